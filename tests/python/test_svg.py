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
    np.savetxt(d / "tel.txt", powered_record(), fmt="%.17g")
    np.savetxt(d / "E.txt", E3)
    (d / "fl").mkdir(exist_ok=True)
    assert run(d, "simulate", "--seed", "7", "--save-traj", "--dir", "fl").returncode == 0


def powered_record(duration=10.0, rate=20.0):
    """Strapdown telemetry rows t dv dth of a vehicle climbing at 2 g along
    body x and rolling at 0.05 rad/s (tests/python/test_inserr_li.py's)."""
    n = int(duration * rate) + 1
    tel = np.zeros((n, 7))
    tel[:, 0] = np.arange(n) / rate
    tel[1:, 1] = 2 * 9.80665 / rate
    tel[1:, 4] = 0.05 / rate
    tel[1:, 6] = 0.002 / rate
    return tel


# body x from LI y (up) tipped 20 deg toward LI x (scalar first)
Q0 = "%.17g,0,0,%.17g" % (np.cos((np.pi / 2 - np.radians(20)) / 2),
                          np.sin((np.pi / 2 - np.radians(20)) / 2))
NAV = ["nav", "--lat", "45", "--acc-bias", "1e-4,0,0", "--gyro-drift", "0,4.85e-8,0",
       "--gyro-arw", "2.9e-7,2.9e-7,2.9e-7", "--acc-vrw", "5e-5,5e-5,5e-5"]
NAV_LI = ["nav", "--telemetry", "tel.txt", "--lat", "30", "--lon", "110", "--azimuth", "80",
          "--q0", Q0, "--acc-bias", "1e-3,-2e-3,0", "--gyro-drift", "0,1e-5,0",
          "--gyro-arw", "1e-5,1e-5,2e-5", "--acc-rrw", "1e-5,0,0"]
BURNOUT = "5561563.2,980653.6,3260504.4,-495.5,3461.9,4875.4"
# three 1-sigma burnout errors (x y z vx vy vz by term)
E3 = np.array([[10, 0, 5], [0, 20, 3], [2, 4, 30], [0.01, 0, 0.002], [0, 0.02, 0.001],
               [0.005, 0.001, 0.01]])
IMPACT = ["impact", "--burnout", BURNOUT, "--model", "j2", "--errors", "E.txt", "--names",
          "acc,gyro,align"]
IMPACT_TERMS = ["impact", "--burnout-time", "120", "--traj", "fl/traj.txt", "--lat", "40.96",
                "--lon", "100.29", "--height", "1000", "--azimuth", "30", "--terms", "default"]


PLOTS = {
    "stability": ["stability", "--data", "y.txt", "--fs", "100"],
    "stability_fit": ["stability", "--data", "y.txt", "--fs", "100", "--kind", "oadev", "--fit"],
    "eqerr": EQ + ["--residuals", "res.txt"],
    "montecarlo": ["montecarlo", "--flights", "40"],
    "rls": ["rls", "--S", "Sr.txt", "--dw", "dwr.txt", "--sigma", "0.1", "--every", "0"],
    "fuse": ["redund", "fuse", "--data", "r.txt", "--fs", "100", "--sigma", "0.01"],
    "nav": NAV,
    "nav_li": NAV_LI,
    "impact": IMPACT,
    "impact_terms": IMPACT_TERMS,
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
        fx, fy, fw, fh = frame_box(axes)
        for leg in (e for e in axes.iter() if e.get("class") == "legend"):
            x, y, w, h = box_of(leg.find(NS + "rect"))
            assert fx <= x and x + w <= fx + fw and fy <= y and y + h <= fy + fh


def frame_box(axes):
    """x, y, width, height of a panel's frame."""
    (frame,) = [e for e in axes if e.get("class") == "frame"]
    return box_of(frame)


def box_of(rect):
    return tuple(float(rect.get(k)) for k in ("x", "y", "width", "height"))


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


# ---- igea nav --plot and igea impact --plot --------------------------------

# the factor from SI of each unit an axis label may name (1 rad = 180/pi deg)
UNITS = {"m": 1.0, "km": 1e-3, "m/s": 1.0, "mm/s": 1e3, "arcsec": np.degrees(1.0) * 3600,
         "deg": np.degrees(1.0), "h": 1 / 3600.0, "min": 1 / 60.0, "s": 1.0}


def axis_labels(axes):
    """The x and y axis labels of a panel: the text after the frame and
    the text of the rotated group."""
    kids = list(axes)
    i = next(k for k, e in enumerate(kids) if e.get("class") == "frame")
    assert kids[i + 1].tag == NS + "text" and kids[i + 2].tag == NS + "g"
    return kids[i + 1].text, kids[i + 2].find(NS + "text").text


def unit_of(label):
    m = re.search(r"\(([^,()]+)(,[^()]*)?\)$", label)
    return UNITS[m.group(1)]


def in_axes(axes, cls):
    return [e for e in axes.iter() if e.get("class") == cls]


def inside(p, box):
    x, y, w, h = box
    return (p[:, 0] > x) & (p[:, 0] < x + w) & (p[:, 1] > y) & (p[:, 1] < y + h)


def nav_json(tmp_path, args):
    r = run(tmp_path, *args, "--json", "--plot", "n.svg")
    assert r.returncode == 0, r.stderr
    return json.loads(r.stdout), parse(tmp_path / "n.svg")


def check_nav_panels(root, res, names):
    """Each panel draws the result's errors (in the unit its label names)
    against time, and with a covariance the band x -+ sqrt(P_ii); the
    legend row covers no point of any curve or band."""
    t = np.asarray(res["time"], float)
    cov = np.asarray(res["covariance"]) if "covariance" in res else None
    panels = by_class(root, "axes")
    assert len(panels) == 3 and len(by_class(root, "legend")) == 3
    for q, key in enumerate(("position", "velocity", "attitude")):
        axes, e = panels[q], np.asarray(res[key], float)
        xlab, ylab = axis_labels(axes)
        assert key + " error" in ylab
        tf, f = unit_of(xlab), unit_of(ylab)
        series, bands = in_axes(axes, "series"), in_axes(axes, "band")
        assert len(series) == 3 and len(bands) == (3 if cov is not None else 0)
        for a in range(3):
            pts = points(series[a])
            assert len(pts) == len(t)
            np.testing.assert_allclose(pts[:, 0], predict(axes, False, False, t * tf), atol=0.05)
            np.testing.assert_allclose(pts[:, 1], predict(axes, True, False, f * e[:, a]),
                                       atol=0.05)
            if cov is not None:
                sd = np.sqrt(cov[:, 3 * q + a, 3 * q + a])
                poly = points(bands[a])
                assert len(poly) == 2 * len(t)
                np.testing.assert_allclose(poly[:len(t), 1],
                                           predict(axes, True, False, f * (e[:, a] + sd)),
                                           atol=0.05)
                np.testing.assert_allclose(poly[len(t):, 1],
                                           predict(axes, True, False, f * (e[:, a] - sd))[::-1],
                                           atol=0.05)
        legend = in_axes(axes, "legend")[0]
        texts = [x.text for x in legend.iter(NS + "text")]
        assert texts[:3] == names
        assert ("shaded: \u00b11\u03c3 of the sensor noise" in texts) == (cov is not None)
        box = box_of(legend.find(NS + "rect"))
        for c in series + bands:
            assert not inside(points(c), box).any()


def test_nav_plot_static_with_noise(tmp_path):
    res, root = nav_json(tmp_path, NAV)
    check_nav_panels(root, res, ["north", "east", "down"])
    assert axis_labels(by_class(root, "axes")[0])[0] == "time (h)"   # 6 h


def test_nav_plot_trajectory(tmp_path):
    np.savetxt(tmp_path / "tel.txt", powered_record(), fmt="%.17g")
    res, root = nav_json(tmp_path, NAV_LI + ["--every", "4"])
    check_nav_panels(root, res, ["x", "y", "z"])
    texts = [t.text for t in root.iter(NS + "text")]
    assert "position error, along tel.txt, launch-inertial axes" in texts and "time (s)" in texts
    assert "attitude error, launch-inertial axes" in texts


def test_nav_plot_units_follow_the_size(tmp_path):
    # east and down drifts of 3e-6 rad/s without Earth rate: dN = -R eps (t -
    # sin/ws) reaches 137 km and phi_D = -eps t 0.065 rad (13,400 arcsec): km
    # and deg; no noise, no band
    res, root = nav_json(tmp_path, ["nav", "--lat", "45", "--omega", "0", "--gyro-drift",
                                    "0,3e-6,3e-6"])
    assert "covariance" not in res
    check_nav_panels(root, res, ["north", "east", "down"])
    labels = [axis_labels(a)[1] for a in by_class(root, "axes")]
    assert labels == ["position error (km)", "velocity error (m/s)", "attitude error phi (deg)"]
    # noise alone over 10 min: mm/s and arcsec
    res, root = nav_json(tmp_path, ["nav", "--lat", "45", "--duration", "600", "--gyro-arw",
                                    "1e-7,1e-7,1e-7"])
    check_nav_panels(root, res, ["north", "east", "down"])
    labels = [axis_labels(a) for a in by_class(root, "axes")]
    assert labels[0] == ("time (min)", "position error (m)")
    assert labels[1][1] == "velocity error (mm/s)" and labels[2][1].endswith("(arcsec)")


def test_nav_plot_shows_the_schuler_oscillation(tmp_path):
    """A north accelerometer bias b at rest without Earth rate: dN = (b/g)
    R (1 - cos ws t), dvN = (b/ws) sin ws t, phiE = -(b/g)(1 - cos ws t),
    ws = sqrt(g/R) (docs/inserr.md, closed forms): the drawn curves are
    these to the pixel's rounding, and the velocity's oscillation spans
    most of its panel."""
    b, g, R = 1e-4, 9.80665, 6371008.8
    ws = np.sqrt(g / R)
    r = run(tmp_path, "nav", "--lat", "45", "--omega", "0", "--acc-bias", "%g,0,0" % b,
            "--plot", "s.svg")
    assert r.returncode == 0, r.stderr
    root = parse(tmp_path / "s.svg")
    t = np.linspace(0, 21600, 361)
    want = [(b / g) * R * (1 - np.cos(ws * t)), (b / ws) * np.sin(ws * t),
            -(b / g) * (1 - np.cos(ws * t))]
    for q, (axes, w) in enumerate(zip(by_class(root, "axes"), want)):
        pts = points(in_axes(axes, "series")[0 if q < 2 else 1])   # north, north, east
        f = unit_of(axis_labels(axes)[1])
        np.testing.assert_allclose(pts[:, 1], predict(axes, True, False, f * w), atol=0.05)
    vel = points(in_axes(by_class(root, "axes")[1], "series")[0])
    _, _, _, fh = frame_box(by_class(root, "axes")[1])
    assert np.ptp(vel[:, 1]) > 0.6 * fh
    # four Schuler periods of 84.4 min in 6 h: the velocity changes sign 8 times
    v = want[1][1:]
    assert np.sum(np.diff(np.sign(v)) != 0) == 8


def test_nav_plot_draws_at_most_2000_epochs(tmp_path):
    tel = powered_record(duration=250.0, rate=20.0)       # 5001 records
    np.savetxt(tmp_path / "tel.txt", tel, fmt="%.17g")
    res, root = nav_json(tmp_path, NAV_LI[:15])      # no noise
    t = np.asarray(res["time"])
    assert t.size == 5001
    axes = by_class(root, "axes")[0]
    pts = points(in_axes(axes, "series")[0])
    assert 1000 < len(pts) <= 2000
    drawn_t = (pts[:, 0] - predict(axes, False, False, [0.0])[0]) / \
        (predict(axes, False, False, [1.0])[0] - predict(axes, False, False, [0.0])[0])
    k = np.searchsorted(t, drawn_t - 0.01)       # the epochs drawn, in order
    np.testing.assert_allclose(t[k], drawn_t, atol=0.01)
    assert k[0] == 0 and k[-1] == t.size - 1 and np.all(np.diff(k) > 0)
    e = np.asarray(res["position"])[k, 0]
    np.testing.assert_allclose(pts[:, 1], predict(axes, True, False,
                                                  unit_of(axis_labels(axes)[1]) * e), atol=0.05)


def impact_json(tmp_path, args):
    r = run(tmp_path, *args, "--json", "--plot", "i.svg")
    assert r.returncode == 0, r.stderr
    return json.loads(r.stdout), parse(tmp_path / "i.svg")


def check_impact(root, res):
    """The plane: equal scales; every vertex of the k-sigma ellipse on
    x^T C^-1 x = k^2 (C in crossrange, downrange order), its farthest and
    nearest vertices k sqrt(lambda) along the eigenvectors of C (numpy);
    the circle of radius cep about the mean. The bars: the shares from
    the misses, largest first, the first 15 and the rest summed, split
    into downrange and crossrange parts; names one a bar, not touching."""
    plane, bars = by_class(root, "axes")
    t = tick_map(plane, False, False)
    sx = np.polyfit(t[:, 0], t[:, 1], 1)[0]
    t = tick_map(plane, True, False)
    sy = np.polyfit(t[:, 0], t[:, 1], 1)[0]
    np.testing.assert_allclose(sy, -sx, rtol=1e-4)                  # equal scales
    f = unit_of(axis_labels(plane)[1])
    cd = np.asarray(res["covariance"], float)                        # downrange first
    C = f * f * cd[::-1, ::-1]
    lam, vec = np.linalg.eigh(C)
    x0, y0 = predict(plane, False, False, [0.0])[0], predict(plane, True, False, [0.0])[0]
    ellipses = in_axes(plane, "ellipse")
    assert [float(e.get("data-k")) for e in ellipses] == [1.0, 3.0]
    for e in ellipses:
        k = float(e.get("data-k"))
        p = points(e)
        v = np.column_stack([(p[:, 0] - x0) / sx, (p[:, 1] - y0) / sy])
        np.testing.assert_allclose(np.einsum("ij,jk,ik->i", v, np.linalg.inv(C), v), k * k,
                                   rtol=2e-3)
        d = np.hypot(v[:, 0], v[:, 1])
        np.testing.assert_allclose([d.max(), d.min()], k * np.sqrt(lam[::-1]), rtol=1e-3)
        assert abs(abs(v[d.argmax()] @ vec[:, 1]) / d.max() - 1) < 1e-6
    (circle,) = in_axes(plane, "cep")
    np.testing.assert_allclose([float(circle.get("cx")), float(circle.get("cy"))], [x0, y0],
                               atol=0.01)
    np.testing.assert_allclose(float(circle.get("r")) / sx, f * res["cep"], rtol=1e-4)
    legend = in_axes(plane, "legend")[0]
    box = box_of(legend.find(NS + "rect"))
    for e in ellipses:
        assert not inside(points(e), box).any()
    a = np.linspace(0, 2 * np.pi, 721)
    rr = float(circle.get("r"))
    assert not inside(np.column_stack([x0 + rr * np.cos(a), y0 + rr * np.sin(a)]), box).any()
    # the bars
    miss = np.asarray(res["miss"], float)
    m2 = np.sum(miss ** 2, axis=1)
    share = 100 * m2 / m2.sum()
    down = 100 * miss[:, 0] ** 2 / m2.sum()
    order = np.argsort(-share, kind="stable")
    n = len(share)
    want = [(res["names"][j], share[j], down[j]) for j in order[:15]]
    if n > 15:
        rest = order[15:]
        want.append(("the other %d terms" % (n - 15), share[rest].sum(),
                     down[rest].sum()))
    rects = in_axes(bars, "bar")
    assert len(rects) == 2 * len(want)
    x0 = predict(bars, False, False, [0.0])[0]
    sb = predict(bars, False, False, [1.0])[0] - x0
    fx, fy, fw, fh = frame_box(bars)
    texts = [e for e in bars if e.tag == NS + "text"]
    centres = []
    for i, (name, sh, dn) in enumerate(want):
        rd, rc = rects[2 * i], rects[2 * i + 1]
        assert rd.get("data-part") == "downrange" and rc.get("data-part") == "crossrange"
        xd, _, wd, h = box_of(rd)
        xc, yc, wc, _ = box_of(rc)
        np.testing.assert_allclose([xd, wd / sb, (xc + wc - x0) / sb], [x0, dn, sh],
                                   atol=0.02 / sb + 1e-9 * sh)
        centres.append(yc + h / 2)
        (label,) = [e for e in texts if e.text == name]
        assert float(label.get("x")) < fx and abs(float(label.get("y")) - 4 - yc - h / 2) < 0.02
        assert fy < yc and yc + h < fy + fh
    assert np.all(np.diff(centres) > 14)                    # names do not touch
    box = box_of(in_axes(bars, "legend")[0].find(NS + "rect"))
    for r_ in rects:                                        # the legend covers no bar
        x, y, w, h = box_of(r_)
        assert x + w <= box[0] or y + h <= box[1]
    for e in texts:                                         # the values inside the panel
        if e.text and e.text.endswith(" %"):
            assert float(e.get("x")) + 6.5 * len(e.text) <= fx + fw


def test_impact_plot_errors(tmp_path):
    np.savetxt(tmp_path / "E.txt", E3)
    res, root = impact_json(tmp_path, IMPACT)
    assert res["names"] == ["acc", "gyro", "align"]
    check_impact(root, res)
    texts = [t.text for t in root.iter(NS + "text")]
    assert "CEP %.4g m (50 %%)" % res["cep"] in texts


def test_impact_plot_terms_top_15_and_the_rest(tmp_path):
    (tmp_path / "fl").mkdir()
    assert run(tmp_path, "simulate", "--seed", "7", "--save-traj", "--dir", "fl").returncode == 0
    res, root = impact_json(tmp_path, IMPACT_TERMS + ["--prob", "0.9"])
    assert len(res["names"]) == 21
    check_impact(root, res)
    texts = [t.text for t in root.iter(NS + "text")]
    assert "circle of 90 %%: %.4g m" % res["cep"] in texts
    assert "the other 6 terms" in texts


def test_impact_plot_one_term_is_a_line(tmp_path):
    # one term: the covariance has rank 1, the ellipses are segments along
    # the miss, the circle still drawn
    np.savetxt(tmp_path / "E1.txt", E3[:, :1])
    name = "\u0394v_misalignment_\u00e0_la_pitch_axis"     # 34 characters, UTF-8
    res, root = impact_json(tmp_path, ["impact", "--burnout", BURNOUT, "--errors", "E1.txt",
                                       "--names", name])
    texts = [t.text for t in by_class(root, "axes")[1].iter(NS + "text")]
    assert name[:21] + "..." in texts                # cut to 24 characters
    plane = by_class(root, "axes")[0]
    miss = np.asarray(res["miss"])[0]
    x0, y0 = predict(plane, False, False, [0.0])[0], predict(plane, True, False, [0.0])[0]
    for e in in_axes(plane, "ellipse"):
        p = points(e) - [x0, y0]
        # on the line through the mean along (crossrange, -downrange) in pixels
        np.testing.assert_allclose(p[:, 0] * miss[0] + p[:, 1] * miss[1], 0,
                                   atol=0.02 * np.hypot(*miss))
    assert len(in_axes(plane, "cep")) == 1 and len(in_axes(by_class(root, "axes")[1], "bar")) == 2


def test_impact_plot_needs_a_budget(tmp_path):
    r = run(tmp_path, "impact", "--burnout", BURNOUT, "--plot", "x.svg")
    assert r.returncode == 64 and "--plot" in r.stderr and "--errors" in r.stderr
    assert not (tmp_path / "x.svg").exists()


@pytest.mark.parametrize("kind", ["nav", "impact"])
def test_nav_impact_broken_plot_path(tmp_path, kind):
    np.savetxt(tmp_path / "E.txt", E3)
    args = NAV if kind == "nav" else IMPACT
    r = run(tmp_path, *args, "--out", "rep.txt", "--plot", "no/p.svg")
    assert r.returncode == 74, r.stderr
    assert sorted(os.listdir(tmp_path)) == ["E.txt"]
