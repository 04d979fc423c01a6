"""--plot FILE.svg: the driver's SVG pictures are well-formed XML with axes, a
legend and one polyline / marker per datum fed, their pixel coordinates map
the data monotonically (linearly in the value or its log10), text is escaped
for XML, NaN and Inf are never written, and a broken path is exit 74 with
no file left behind. Rendered to PNG with rsvg-convert when it is installed
(the tests that need it are skipped otherwise)."""
import json
import os
import re
import shutil
import subprocess
import xml.etree.ElementTree as ET

import numpy as np
import pytest

DRIVER = os.environ["IGEA_DRIVER"]
REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
FLIGHT = os.path.join(REPO, "examples", "flight")
NS = "{http://www.w3.org/2000/svg}"
EQ = ["eqerr", "--S", "S.txt", "--dw", "dw.txt", "--sigma", "sigma.txt", "--spec", "spec.txt"]


def run(cwd, *args):
    return subprocess.run([DRIVER, *args], cwd=cwd, capture_output=True, text=True, timeout=120)


def parse(path):
    text = open(path, encoding="utf-8").read()
    low = text.lower()
    assert "nan" not in low and "inf" not in low.replace("information", "")
    return ET.fromstring(text)


def by_class(root, cls):
    return [e for e in root.iter() if e.get("class") == cls]


def points(poly):
    return np.array([[float(v) for v in p.split(",")] for p in poly.get("points").split()])


def assert_linear(u, p, tol=0.02):
    """Pixels p are an affine map of the values u (rounded to 0.01 px)."""
    u, p = np.asarray(u, float), np.asarray(p, float)
    A = np.column_stack([u, np.ones_like(u)])
    coef, *_ = np.linalg.lstsq(A, p, rcond=None)
    assert np.max(np.abs(A @ coef - p)) < tol, np.max(np.abs(A @ coef - p))
    return coef[0]


def tick_map(axes, vertical, log):
    """The tick labels' values (log10 on a log axis) and their pixels."""
    kids, out = list(axes), []
    for i, e in enumerate(kids):
        if e.get("class") != "tick":
            continue
        horiz = e.get("y1") == e.get("y2")
        if horiz == vertical:
            v = float(kids[i + 1].text)
            out.append((np.log10(v) if log else v, float(e.get("y1" if vertical else "x1"))))
    assert len(out) >= 2
    return np.array(out)


def predict(axes, vertical, log, values):
    """Pixels of values read off the axis's own tick labels."""
    t = tick_map(axes, vertical, log)
    slope, icpt = np.polyfit(t[:, 0], t[:, 1], 1)
    assert np.max(np.abs(slope * t[:, 0] + icpt - t[:, 1])) < 0.02  # ticks on one map
    v = np.log10(values) if log else np.asarray(values, float)
    return slope * v + icpt


def oadev(y, fs, m):
    """Overlapping Allan deviation of rate samples y at tau = m / fs (IEEE
    Std 952 / NIST SP 1065 eq. 14 on the phase x = cumsum(y) / fs)."""
    x = np.concatenate([[0.0], np.cumsum(y)]) / fs
    d = x[2 * m:] - 2 * x[m:-m] + x[:-2 * m]
    tau = m / fs
    return np.sqrt(np.sum(d ** 2) / (2 * tau ** 2 * d.size))


@pytest.fixture
def record(tmp_path):
    rng = np.random.default_rng(7)
    y = rng.standard_normal(4096)
    np.savetxt(tmp_path / "y.txt", y)
    ms = np.array([1, 2, 4, 8, 16, 32, 64])
    np.savetxt(tmp_path / "taus.txt", ms / 10.0)
    return tmp_path, y, ms


def test_stability_plot_log_log(record):
    d, y, ms = record
    r = run(d, "stability", "--data", "y.txt", "--fs", "10", "--taus", "taus.txt", "--plot",
            "a.svg")
    assert r.returncode == 0, r.stderr
    root = parse(d / "a.svg")
    assert root.tag == NS + "svg"
    assert len(by_class(root, "axes")) == 1 and len(by_class(root, "legend")) == 1
    (line,) = by_class(root, "series")
    pts = points(line)
    assert len(pts) == len(ms) and len(by_class(root, "marker")) == len(ms)
    assert len(by_class(root, "errbar")) == len(ms)
    # x: linear in log10(tau), increasing; y: linear in log10 of the deviation
    # computed here, decreasing upwards (SVG y grows downwards)
    assert assert_linear(np.log10(ms / 10.0), pts[:, 0]) > 0
    dev = [oadev(y, 10.0, m) for m in ms]
    assert assert_linear(np.log10(dev), pts[:, 1], tol=0.05) < 0
    # and where the tick labels say: tau and the deviation in absolute terms
    (axes,) = by_class(root, "axes")
    np.testing.assert_allclose(pts[:, 0], predict(axes, False, True, ms / 10.0), atol=0.05)
    np.testing.assert_allclose(pts[:, 1], predict(axes, True, True, dev), atol=0.05)
    texts = "".join(t.text or "" for t in root.iter(NS + "text"))
    assert "tau (s)" in texts and "y.txt" in texts


def test_stability_fit_terms_shown(record):
    d, _, _ = record
    r = run(d, "stability", "--data", "y.txt", "--fs", "10", "--kind", "adev", "--fit", "--plot",
            "f.svg")
    assert r.returncode == 0, r.stderr
    texts = [t.text for t in parse(d / "f.svg").iter(NS + "text")]
    assert sum(1 for t in texts if t and t.startswith("IEEE 952 ")) == 5


def test_text_escaped_and_utf8_kept(record):
    d, y, _ = record
    name = "a&b<c>\"'\u00e9.txt"
    shutil.copy(d / "y.txt", d / name)
    r = run(d, "stability", "--data", name, "--fs", "10", "--plot", "e.svg")
    assert r.returncode == 0, r.stderr
    root = parse(d / "e.svg")
    assert root.find(NS + "title").text.startswith(name + ":")
    raw = b"bad\xff.txt"
    with open(os.path.join(os.fsencode(str(d)), raw), "wb") as f:
        f.write(open(d / "y.txt", "rb").read())
    r = subprocess.run([os.fsencode(DRIVER), b"stability", b"--data", raw, b"--fs", b"10",
                        b"--plot", b"u.svg"], cwd=d, capture_output=True, timeout=120)
    assert r.returncode == 0, r.stderr
    assert parse(d / "u.svg").find(NS + "title").text.startswith("bad?.txt:")


@pytest.mark.parametrize("target", ["missing_dir/p.svg", "."])
def test_broken_path_is_74_and_no_file(record, target):
    d, _, _ = record
    r = run(d, "stability", "--data", "y.txt", "--fs", "10", "--out", "rep.txt", "--plot", target)
    assert r.returncode == 74, r.stderr
    assert not (d / "rep.txt").exists() and not (d / "missing_dir").exists()
    assert [p for p in os.listdir(d) if ".tmp." in p] == []


def eqerr_plot(tmp_path, *extra):
    for f in ("S.txt", "dw.txt", "sigma.txt", "spec.txt"):
        shutil.copy(os.path.join(FLIGHT, f), tmp_path / f)
    r = run(tmp_path, *EQ, "--json", "--out", "r.json", "--plot", "e.svg", *extra)
    assert r.returncode in (0, 1), r.stderr
    return parse(tmp_path / "e.svg"), json.load(open(tmp_path / "r.json"))


@pytest.mark.parametrize("with_file", [False, True])
def test_eqerr_residuals_and_spectrum(tmp_path, with_file):
    root, res = eqerr_plot(tmp_path, *(["--residuals", "res.txt"] if with_file else []))
    m = np.loadtxt(tmp_path / "dw.txt").size
    assert len(by_class(root, "axes")) == 2 and len(by_class(root, "legend")) == 2
    series = by_class(root, "series")
    assert len(series) == 3
    e = np.asarray(res["residual"], float)
    assert e.size == m
    for k, s in enumerate(series):
        pts = points(s)
        assert len(pts) == len(e[k::3])
        assert assert_linear(np.arange(len(pts)), pts[:, 0]) > 0
        assert assert_linear(e[k::3], pts[:, 1]) < 0
        np.testing.assert_allclose(pts[:, 1], predict(by_class(root, "axes")[0], True, False,
                                                      e[k::3]), atol=0.05)
    if with_file:
        np.testing.assert_array_equal(np.loadtxt(tmp_path / "res.txt")[:, 2], e)  # epoch axis residual
    # the spectrum: one marker per positive eigenvalue, linear in log10
    lam = np.asarray(res["eigenvalues"], float)
    pos = lam > 0
    marks = by_class(root, "marker")
    assert len(marks) == pos.sum()
    cy = np.array([float(c.get("cy")) for c in marks])
    cx = np.array([float(c.get("cx")) for c in marks])
    slope = assert_linear(np.log10(lam[pos]), cy)
    np.testing.assert_allclose(cy, predict(by_class(root, "axes")[1], True, True, lam[pos]),
                               atol=0.05)
    assert slope < 0 and assert_linear(np.flatnonzero(pos), cx) > 0
    # lambda_test = 10 and lambda_small = 0.1 (the library's defaults) on the same map
    hl = by_class(root, "hline")
    assert len(hl) == 2
    hy = [float(h.get("y1")) for h in hl]
    assert_linear(np.concatenate([np.log10(lam[pos]), [1.0, -1.0]]), np.concatenate([cy, hy]))
    texts = " ".join(t.text or "" for t in root.iter(NS + "text"))
    assert "lambda_test = 10" in texts and "lambda_small = 0.1" in texts


def test_eqerr_plot_refused_with_noise_models(tmp_path):
    for f in ("S.txt", "dw.txt", "sigma.txt", "spec.txt"):
        shutil.copy(os.path.join(FLIGHT, f), tmp_path / f)
    r = run(tmp_path, *EQ, "--robust", "--plot", "e.svg")
    assert r.returncode == 64 and "--plot" in r.stderr
    assert not (tmp_path / "e.svg").exists()


def test_eqerr_broken_plot_path(tmp_path):
    for f in ("S.txt", "dw.txt", "sigma.txt", "spec.txt"):
        shutil.copy(os.path.join(FLIGHT, f), tmp_path / f)
    r = run(tmp_path, *EQ, "--out", "rep.txt", "--residuals", "res.txt", "--plot", "no/e.svg")
    assert r.returncode == 74, r.stderr
    assert sorted(os.listdir(tmp_path)) == ["S.txt", "dw.txt", "sigma.txt", "spec.txt"]


def _plot_inputs(d):
    """The inputs of one picture of every --plot kind in d."""
    rng = np.random.default_rng(7)
    np.savetxt(d / "y.txt", rng.standard_normal(20000) * 1e-3
               + np.cumsum(rng.standard_normal(20000)) * 2e-6)
    for f in ("S.txt", "dw.txt", "sigma.txt", "spec.txt"):
        shutil.copy(os.path.join(FLIGHT, f), d / f)
    r = rng.normal(0, 1e-3, (1000, 3))
    r[300:600, 2] += 0.5
    np.savetxt(d / "r.txt", r)
    S = rng.standard_normal((60, 2))
    np.savetxt(d / "Sr.txt", S)
    np.savetxt(d / "dwr.txt", S @ [1.0, -2.0] + 0.1 * rng.standard_normal(60))


PLOTS = {
    "stability": ["stability", "--data", "y.txt", "--fs", "100"],
    "stability_fit": ["stability", "--data", "y.txt", "--fs", "100", "--kind", "oadev", "--fit"],
    "eqerr": EQ + ["--residuals", "res.txt"],
    "montecarlo": ["montecarlo", "--flights", "40"],
    "rls": ["rls", "--S", "Sr.txt", "--dw", "dwr.txt", "--sigma", "0.1", "--every", "0"],
    "fuse": ["redund", "fuse", "--data", "r.txt", "--fs", "100", "--sigma", "0.01"],
}


def png_size(path):
    """Width and height from the PNG's IHDR chunk."""
    head = open(path, "rb").read(24)
    assert head[:8] == b"\x89PNG\r\n\x1a\n" and head[12:16] == b"IHDR"
    return int.from_bytes(head[16:20], "big"), int.from_bytes(head[20:24], "big")


@pytest.mark.skipif(shutil.which("rsvg-convert") is None, reason="rsvg-convert not installed")
@pytest.mark.parametrize("kind", sorted(PLOTS))
def test_renders_to_png(tmp_path, kind):
    _plot_inputs(tmp_path)
    r = run(tmp_path, *PLOTS[kind], "--plot", "p.svg")
    assert r.returncode in (0, 1), r.stderr
    root = parse(tmp_path / "p.svg")
    png = str(tmp_path / "p.png")
    r = subprocess.run(["rsvg-convert", "-o", png, str(tmp_path / "p.svg")], capture_output=True,
                       timeout=60)
    assert r.returncode == 0 and r.stderr == b"", r.stderr
    assert png_size(png) == (int(root.get("width")), int(root.get("height")))
    try:
        from matplotlib.image import imread
    except ImportError:
        return
    img = imread(png)[:, :, :3]
    ink = np.any(img < 0.9, axis=2)
    assert 0.01 < ink.mean() < 0.6          # drawn, and not a filled page
    for axes in by_class(root, "axes"):      # the legend box is inside its panel
        (frame,) = [e for e in axes if e.get("class") == "frame"]
        fx, fw = float(frame.get("x")), float(frame.get("width"))
        for leg in (e for e in root.iter() if e.get("class") == "legend"):
            box = leg.find(NS + "rect")
            if abs(float(box.get("y")) - float(frame.get("y")) - 6) < 1e-6:
                assert fx <= float(box.get("x")) and \
                    float(box.get("x")) + float(box.get("width")) <= fx + fw


def test_legend_is_wide_enough_for_its_labels(tmp_path):
    """Every label fits in its box at 6.5 px a character (DejaVu Sans at
    12 px averages about 6.2 px on lower-case text)."""
    _plot_inputs(tmp_path)
    for kind in ("stability_fit", "montecarlo"):
        assert run(tmp_path, *PLOTS[kind], "--plot", kind + ".svg").returncode == 0
        for leg in by_class(parse(tmp_path / (kind + ".svg")), "legend"):
            box = leg.find(NS + "rect")
            right = float(box.get("x")) + float(box.get("width"))
            for t in leg.iter(NS + "text"):
                assert float(t.get("x")) + 6.5 * len(t.text) <= right, t.text


def test_stability_fit_lines(tmp_path):
    """--fit draws each supported IEEE Std 952 term, sigma_k(tau) =
    sqrt(c_k f_k(tau)) with f = 3Q^2/tau^2, N^2/tau, (2 ln 2/pi) B^2,
    K^2 tau/3, R^2 tau^2/2 (IEEE Std 952-1997 Annex C), and their sum."""
    rng = np.random.default_rng(7)   # white noise and a random walk: N, B and K supported
    np.save(tmp_path / "y.npy", rng.standard_normal(200000) * 1e-3
            + np.cumsum(rng.standard_normal(200000)) * 2e-6)
    r = run(tmp_path, "stability", "--data", "y.npy", "--fs", "100", "--kind", "oadev", "--fit",
            "--json", "--plot", "f.svg")
    assert r.returncode == 0, r.stderr
    res = json.loads(r.stdout)
    tau = np.asarray(res["taus"])
    val, sup = np.asarray(res["fit"]["value"]), np.asarray(res["fit"]["supported"])
    f = np.array([3 / tau ** 2, 1 / tau, np.full_like(tau, 2 * np.log(2) / np.pi), tau / 3,
                  tau ** 2 / 2])
    terms = (val[:, None] ** 2) * f
    root = parse(tmp_path / "f.svg")
    (axes,) = by_class(root, "axes")
    lines = by_class(root, "fit")
    assert len(lines) == 1 + sup.sum() and sup.sum() >= 2
    want = [np.sqrt(terms[sup].sum(axis=0))] + [np.sqrt(terms[k]) for k in np.flatnonzero(sup)]
    for line, w in zip(lines, want):
        pts = points(line)
        py = predict(axes, True, True, w)
        keep = np.isfinite(py) & (np.abs(py) < 1e7)
        assert len(pts) == keep.sum()
        np.testing.assert_allclose(pts[:, 1], py[keep], atol=0.05)
        np.testing.assert_allclose(pts[:, 0], predict(axes, False, True, tau[keep]), atol=0.05)
    legend = [t.text for t in by_class(root, "legend")[0].iter(NS + "text")]
    assert "fit: the sum of the terms" in legend


def wilson99(k, n):
    """The 99 % Wilson score interval (z = Phi^-1(0.995) = 2.5758293035489004)."""
    z, p = 2.5758293035489004, k / n
    c = (p + z * z / (2 * n)) / (1 + z * z / n)
    h = z / (1 + z * z / n) * np.sqrt(p * (1 - p) / n + z * z / (4 * n * n))
    return max(c - h, 0.0), min(c + h, 1.0)


def test_montecarlo_component_rates(tmp_path):
    r = run(tmp_path, "montecarlo", "--flights", "60", "--json", "--plot", "m.svg")
    assert r.returncode == 0, r.stderr
    res = json.loads(r.stdout)
    ct, cr = np.array(res["comp_tested"]), np.array(res["comp_reject"])
    root = parse(tmp_path / "m.svg")
    (axes,) = by_class(root, "axes")
    assert len(by_class(root, "legend")) == 1
    tested = np.flatnonzero(ct > 0)
    marks, bars = by_class(root, "marker"), by_class(root, "errbar")
    assert len(marks) == len(bars) == len(tested) > 0
    cx = np.array([float(c.get("cx")) for c in marks])
    cy = np.array([float(c.get("cy")) for c in marks])
    np.testing.assert_allclose(cx, predict(axes, False, False, tested), atol=0.05)
    np.testing.assert_allclose(cy, predict(axes, True, False, cr[tested] / ct[tested]), atol=0.05)
    for b, j in zip(bars, tested):
        _, y_lo, y_hi = map(float, re.match(r"M([-\d.]+) ([-\d.]+)V([-\d.]+)", b.get("d")).groups())
        lo, hi = wilson99(cr[j], ct[j])
        np.testing.assert_allclose([y_lo, y_hi], predict(axes, True, False, [lo, hi]), atol=0.05)
    (hl,) = by_class(root, "hline")  # alpha = 0.01, the library's default
    np.testing.assert_allclose(float(hl.get("y1")), predict(axes, True, False, [0.01])[0],
                               atol=0.05)


def test_redund_fuse_timeline(tmp_path):
    # sensor 2 carries a 0.5 bias from 3 s to 6 s: excluded exactly then
    rng = np.random.default_rng(3)
    y = rng.normal(0, 1e-3, (1000, 3))
    y[300:600, 2] += 0.5
    np.savetxt(tmp_path / "r.txt", y)
    r = run(tmp_path, "redund", "fuse", "--data", "r.txt", "--fs", "100", "--sigma", "0.01",
            "--json", "--plot", "f.svg")
    assert r.returncode == 0, r.stderr
    res = json.loads(r.stdout)
    root = parse(tmp_path / "f.svg")
    axes = by_class(root, "axes")
    assert len(axes) == 2 and len(by_class(root, "legend")) == 2
    (bar,) = by_class(root, "interval")
    x0, w = float(bar.get("x")), float(bar.get("width"))
    np.testing.assert_allclose([x0, x0 + w], predict(axes[1], False, False, [3.0, 6.0]), atol=0.05)
    yc = float(bar.get("y")) + float(bar.get("height")) / 2
    np.testing.assert_allclose(yc, predict(axes[1], True, False, [2.0])[0], atol=0.05)
    (line,) = by_class(root, "series")
    pts = points(line)
    assert len(pts) == 10 and len(by_class(root, "band")) == 1
    np.testing.assert_allclose(pts[:, 0], predict(axes[0], False, False, np.arange(10.0)),
                               atol=0.05)
    # the fused value of a window without exclusion: the mean of its 3 x 100 samples
    want = [y[100 * w:100 * w + 100].mean() for w in (0, 1, 2, 6, 7, 8, 9)]
    np.testing.assert_allclose(pts[[0, 1, 2, 6, 7, 8, 9], 1],
                               predict(axes[0], True, False, want), atol=0.05)
    assert res["exclusions"] == [{"sensor": 2, "from": 3, "to": 6}]
    # the sensor axis: a tick at each sensor, no fractional ones, and the
    # bar of the last sensor inside the panel
    t = tick_map(axes[1], True, False)
    assert list(t[:, 0]) == [0.0, 1.0, 2.0]
    (frame,) = [e for e in axes[1] if e.get("class") == "frame"]
    top = float(frame.get("y"))
    assert top < float(bar.get("y")) and \
        float(bar.get("y")) + float(bar.get("height")) < top + float(frame.get("height"))


def test_redund_plot_only_for_fuse(tmp_path):
    r = run(tmp_path, "redund", "reliability", "--plot", "x.svg")
    assert r.returncode == 64 and "--plot" in r.stderr and not (tmp_path / "x.svg").exists()


def test_rls_estimates_and_bands(tmp_path):
    # standard RLS from a diffuse start is batch least squares on the epochs so
    # far (METHODS 2): x_e and its sd from numpy at every epoch
    rng = np.random.default_rng(5)
    ne, k, sig = 40, 3, 0.1
    S = rng.standard_normal((ne * k, 2))
    dw = S @ np.array([1.0, -2.0]) + sig * rng.standard_normal(ne * k)
    np.savetxt(tmp_path / "S.txt", S)
    np.savetxt(tmp_path / "dw.txt", dw)
    r = run(tmp_path, "rls", "--S", "S.txt", "--dw", "dw.txt", "--sigma", str(sig), "--every",
            "0", "--plot", "r.svg")
    assert r.returncode == 0, r.stderr
    root = parse(tmp_path / "r.svg")
    axes = by_class(root, "axes")
    assert len(axes) == 2 and len(by_class(root, "legend")) == 2
    series, bands = by_class(root, "series"), by_class(root, "band")
    assert len(series) == 2 and len(bands) == 2
    est, sd = [], []
    for e in range(ne):
        A, b = S[:k * (e + 1)] / sig, dw[:k * (e + 1)] / sig
        N = A.T @ A + np.eye(2) / 1e6  # the prior Gamma0 = 1e6 I (whitened)
        est.append(np.linalg.solve(N, A.T @ b))
        sd.append(np.sqrt(np.diag(np.linalg.inv(N))))
    est, sd = np.array(est), np.array(sd)
    for i in range(2):
        pts = points(series[i])
        assert len(pts) == ne
        np.testing.assert_allclose(pts[:, 0], predict(axes[i], False, False, np.arange(ne)),
                                   atol=0.05)
        np.testing.assert_allclose(pts[:, 1], predict(axes[i], True, False, est[:, i]), atol=0.05)
        poly = points(bands[i])
        assert len(poly) == 2 * ne
        np.testing.assert_allclose(poly[:ne, 1], predict(axes[i], True, False,
                                                         est[:, i] + 3 * sd[:, i]), atol=0.05)
        np.testing.assert_allclose(poly[ne:, 1], predict(axes[i], True, False,
                                                         (est[:, i] - 3 * sd[:, i])[::-1]),
                                   atol=0.05)


def test_rls_broken_plot_path(tmp_path):
    np.savetxt(tmp_path / "S.txt", np.eye(3))
    np.savetxt(tmp_path / "dw.txt", np.ones(3))
    r = run(tmp_path, "rls", "--S", "S.txt", "--dw", "dw.txt", "--out", "o.txt", "--plot",
            "no/r.svg")
    assert r.returncode == 74 and sorted(os.listdir(tmp_path)) == ["S.txt", "dw.txt"]


def test_eqerr_residuals_to_stdout_not_drawn(tmp_path):
    for f in ("S.txt", "dw.txt", "sigma.txt", "spec.txt"):
        shutil.copy(os.path.join(FLIGHT, f), tmp_path / f)
    r = run(tmp_path, *EQ, "--out", "rep.txt", "--residuals", "-", "--plot", "e.svg")
    assert r.returncode in (0, 1), r.stderr
    root = parse(tmp_path / "e.svg")
    assert len(by_class(root, "axes")) == 1 and by_class(root, "series") == []
    assert any("residuals not drawn" in (t.text or "") for t in root.iter(NS + "text"))


def test_montecarlo_nothing_tested_is_an_empty_picture(tmp_path):
    # lambda_test = 1e30: no component is ever tested, every rate is missing
    r = run(tmp_path, "montecarlo", "--flights", "3", "--lambda-test", "1e30", "--json",
            "--plot", "m.svg")
    assert r.returncode == 0, r.stderr
    assert sum(json.loads(r.stdout)["comp_tested"]) == 0
    root = parse(tmp_path / "m.svg")
    assert len(by_class(root, "axes")) == 1 and len(by_class(root, "legend")) == 1
    assert by_class(root, "marker") == [] and by_class(root, "errbar") == []
    assert len(by_class(root, "hline")) == 1
