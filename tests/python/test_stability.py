"""igea.stability against independent numpy/scipy implementations and the
published NBS test-suite values (METHODS 3.4)."""
import math

import numpy as np
import pytest
from scipy import stats

import igea


def nbs1000():
    x = [1234567890]
    for _ in range(999):
        x.append(16807 * x[-1] % 2147483647)
    return np.array(x, float) / 2147483647


def ref_oadev(y, m):
    x = np.concatenate([[0.0], np.cumsum(y - y.mean(), dtype=np.longdouble)])
    d = x[2 * m:] - 2 * x[m:-m] + x[:-2 * m]
    return float(np.sqrt(np.mean(d * d) / (2.0 * m * m)))


def ref_mdev(y, m):
    x = np.concatenate([[0.0], np.cumsum(y - y.mean(), dtype=np.longdouble)])
    d = x[2 * m:] - 2 * x[m:-m] + x[:-2 * m]          # n - 2m + 1 second differences
    c = np.concatenate([[0.0], np.cumsum(d)])
    s = c[m:] - c[:-m]                                  # n - 3m + 2 sums of m
    return float(np.sqrt(np.mean(s * s) / (2.0 * m ** 4)))


def ref_adev(y, m):
    b = len(y) // m
    means = y[:b * m].reshape(b, m).mean(axis=1)
    return float(np.sqrt(np.mean(np.diff(means) ** 2) / 2))


def test_nbs_published_values():
    y = nbs1000()
    want = {"overlapping": [2.922319e-01, 9.159953e-02, 3.241343e-02],
            "modified": [2.922319e-01, 6.172376e-02, 2.170921e-02],
            "nonoverlapping": [2.922319e-01, 9.965736e-02, 3.897804e-02]}
    for kind, w in want.items():
        r = igea.allan(y, 1.0, [1, 10, 100], kind=kind)
        np.testing.assert_allclose(r.dev, w, rtol=2e-7)
    f = [892, 809, 823, 798, 671, 644, 883, 903, 677]
    np.testing.assert_allclose(igea.allan(f, 1.0, [1, 2]).dev, [91.22945, 85.95287], rtol=5e-7)
    np.testing.assert_allclose(igea.allan(f, 1.0, [1, 2], kind="modified").dev,
                               [91.22945, 74.78849], rtol=5e-7)


def test_against_numpy_and_intervals():
    rng = np.random.default_rng(3)
    n, fs = 20000, 50.0
    y = 9.8 + rng.normal(0, 1e-3, n) + np.cumsum(rng.normal(0, 1e-6, n)) + 1e-7 * np.arange(n)
    for kind, ref in (("overlapping", ref_oadev), ("modified", ref_mdev),
                      ("nonoverlapping", ref_adev)):
        r = igea.allan(y, fs, None, kind=kind, noise="wfm", conf=0.9)
        m = np.round(r.taus * fs).astype(int)
        assert m[0] == 1 and np.all(np.diff(m) == m[:-1])     # octaves
        np.testing.assert_allclose(r.dev, [ref(y, k) for k in m], rtol=1e-9)
        e = r.edf
        np.testing.assert_allclose(r.lo, r.dev * np.sqrt(e / stats.chi2.ppf(0.95, e)), rtol=1e-10)
        np.testing.assert_allclose(r.hi, r.dev * np.sqrt(e / stats.chi2.ppf(0.05, e)), rtol=1e-10)
        if kind == "overlapping":
            N = n + 1.0
            np.testing.assert_allclose(
                e, np.maximum(1.0, (3 * (N - 1) / (2 * m) - 2 * (N - 2) / N) * 4 * m * m /
                              (4 * m * m + 5)), rtol=1e-13)
    assert "overlapping Allan deviation" in igea.allan(y, fs).summary()


def test_modified_when_the_phase_fills_its_last_block():
    """n + 1 rate samples' phase points (or n phase points) a multiple of the
    pass's block of 1024: the last running sum W_N lies in an empty block
    after a full one; the short taus' terms there against the definition."""
    rng = np.random.default_rng(5)
    for n in (1023, 2047, 4095):
        y = 3.0 + rng.normal(0, 1.0, n) + np.cumsum(rng.normal(0, 0.05, n))
        for noise in ("wfm", "auto"):
            r = igea.allan(y, 1.0, [1, 2, 4, 8, 64, 256], kind="modified", noise=noise)
            np.testing.assert_allclose(r.dev, [ref_mdev(y, m) for m in (1, 2, 4, 8, 64, 256)],
                                       rtol=1e-11)
    x = np.cumsum(rng.normal(0, 1.0, 2048))               # phase, 2048 points
    r = igea.stability(x, 1.0, [1, 2, 8, 100], kind="mdev", data_type="phase", noise="wfm")
    np.testing.assert_allclose(r.dev, [ref_mdev(np.diff(x), m) for m in (1, 2, 8, 100)],
                               rtol=1e-11)


def exact_edf(n, m, kind, noise):
    """EDF = tr(C)^2 / |C|_F^2 of the estimator's terms z = A w for white w
    (independent of the library: direct matrix algebra)."""
    if noise == "wpm":
        X = np.eye(n + 1)                                     # phase white
    elif noise == "wfm":
        X = np.tril(np.ones((n + 1, n)), -1)                  # x = cumsum(y), y white
    else:
        X = np.tril(np.ones((n + 1, n)), -1) @ np.tril(np.ones((n, n)))  # y random walk
    d = X[2 * m:] - 2 * X[m:-m] + X[:-2 * m]
    if kind == "modified":
        c = np.vstack([np.zeros(X.shape[1]), np.cumsum(d, axis=0)])
        d = c[m:] - c[:-m]
    C = d @ d.T
    return np.trace(C) ** 2 / np.sum(C * C)


def test_edf_against_exact():
    n = 240
    y = np.random.default_rng(2).normal(size=n)
    for noise, code in (("wfm", "wfm"), ("wpm", "wpm"), ("rwfm", "rwfm")):
        for m in (8, 16, 30):
            got = igea.allan(y, 1.0, [m], kind="modified", noise=code).edf[0]
            assert got == pytest.approx(exact_edf(n, m, "modified", noise), rel=0.03), (noise, m)
    # the overlapping white-FM formula of SP 1065 is close to exact
    for m in (1, 4, 16):
        got = igea.allan(y, 1.0, [m], noise="wfm").edf[0]
        assert got == pytest.approx(exact_edf(n, m, "overlapping", "wfm"), rel=0.05)


def test_white_noise_closed_form_and_noise_id():
    # white rate noise: sigma(tau) = s / sqrt(tau fs) (expectation); the
    # random walk coefficient N = s / sqrt(fs)
    rng = np.random.default_rng(8)
    fs, s = 100.0, 0.02
    y = rng.normal(0, s, 400000)
    r = igea.allan(y, fs, [0.01, 0.1, 1.0])
    np.testing.assert_allclose(r.dev, s / np.sqrt(np.array([1, 10, 100])), rtol=0.05)
    assert np.all((r.lo < r.dev) & (r.dev < r.hi))
    full = igea.allan(y, fs)
    terms = igea.noise_id(full.taus, full.dev)
    assert terms.random_walk == pytest.approx(s / math.sqrt(fs), rel=0.05)
    # a synthetic gyro curve
    tau = 4.0 ** np.arange(-2, 14)
    dev = np.sqrt(1e-6 / tau + 0.4412712 * 1e-8 + 1e-14 * tau / 3)
    t = igea.noise_id(tau, dev)
    assert t.random_walk == pytest.approx(1e-3, rel=0.02)
    assert t.bias_instability == pytest.approx(1e-4, rel=0.1)
    assert t.rate_random_walk == pytest.approx(1e-7, rel=0.1)
    assert math.isnan(t.quantization)
    assert "bias instability" in t.summary()
    with pytest.raises(ValueError, match="adev"):
        igea.noise_id(tau, dev[:3])
    with pytest.raises(igea.IgeaError):
        igea.noise_id(tau[::-1], dev)


def test_ramp_closed_form():
    fs, R = 10.0, 2e-3
    y = 5.0 + R * np.arange(5000) / fs
    for kind in ("overlapping", "modified", "nonoverlapping"):
        r = igea.allan(y, fs, [0.1, 1.0, 10.0, 100.0], kind=kind, noise="rwfm")
        np.testing.assert_allclose(r.dev, R * r.taus / math.sqrt(2), rtol=1e-8)


def test_auto_noise_on_a_noiseless_ramp():
    # the m-means of a ramp lie on a line: r1/(1 + r1) of the means is about
    # 1/2, their first differences are constant (r1 = 0 in exact arithmetic),
    # so the lag-1 method gives alpha = -2 (random-walk FM) at every tau
    taus = [1, 2, 4, 8, 64, 1024]
    for scale, offset in ((1e-3, 0.0), (1.0, 1e6), (1e3, 1.0)):
        y = offset + scale * (3.0 + 1e-3 * np.arange(70001))
        for kind in ("overlapping", "modified"):
            auto = igea.allan(y, 1.0, taus, kind=kind, noise="auto")
            rwfm = igea.allan(y, 1.0, taus, kind=kind, noise="rwfm")
            np.testing.assert_array_equal(auto.edf, rwfm.edf)


def test_block_3sigma():
    y = np.concatenate([np.full(100, v) for v in (1.0, 2.0, 3.0)] + [np.zeros(40)])
    y[:300] += np.where(np.arange(300) % 2, -0.5, 0.5)
    b = igea.block_3sigma(y, 1.0, 100.0)
    assert b.three_sigma == pytest.approx(3.0, rel=1e-15)
    assert b.nblock == 3 and b.block_samples == 100
    assert b.adev == pytest.approx(math.sqrt(0.5), rel=1e-15)
    rng = np.random.default_rng(12)
    w = 1.0 + rng.normal(0, 1e-5, 216000)
    b = igea.block_3sigma(w, 10.0)
    means = w.reshape(216, 1000).mean(axis=1)
    assert b.sigma == pytest.approx(np.std(means, ddof=1), rel=1e-9)
    assert b.three_sigma == pytest.approx(3e-5 / math.sqrt(1000), rel=0.2)
    with pytest.raises(igea.IgeaError):
        igea.block_3sigma(w, 10.0, 1e6)
    with pytest.raises(ValueError, match="y"):
        igea.block_3sigma(np.ones((3, 3)), 1.0)


def test_allan_errors():
    y = np.random.default_rng(0).normal(size=100)
    with pytest.raises(ValueError, match="kind"):
        igea.allan(y, 1.0, [1], kind="hadamard")
    with pytest.raises(ValueError, match="noise"):
        igea.allan(y, 1.0, [1], noise="pink")
    with pytest.raises(igea.IgeaError, match="tau"):
        igea.allan(y, 1.0, [60])
    with pytest.raises(igea.IgeaError):
        igea.allan(np.r_[y, np.nan], 1.0, [1])
    with pytest.raises(ValueError, match="y"):
        igea.allan([1.0], 1.0, [1])


def test_driver_stability(tmp_path):
    import json
    import os
    import subprocess
    rng = np.random.default_rng(21)
    y = 0.5 + rng.normal(0, 0.01, 30000)
    np.save(tmp_path / "g.npy", y)
    drv = os.environ["IGEA_DRIVER"]
    r = subprocess.run([drv, "stability", "--data", "g.npy", "--fs", "100", "--block", "10", "--json"],
                       capture_output=True, text=True, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    d = json.loads(r.stdout)
    ref = igea.allan(y, 100.0)
    np.testing.assert_allclose(d["taus"], ref.taus, rtol=1e-15)
    np.testing.assert_allclose(d["dev"], ref.dev, rtol=1e-15)
    np.testing.assert_allclose(d["hi"], ref.hi, rtol=1e-15)
    b = igea.block_3sigma(y, 100.0, 10.0)
    assert d["block"]["three_sigma"] == pytest.approx(b.three_sigma, rel=1e-15)
    assert d["noise"]["random_walk"] == pytest.approx(0.001, rel=0.05)
    np.savetxt(tmp_path / "two.txt", np.column_stack([y[:500], y[:500] * 2]))
    r = subprocess.run([drv, "stability", "--data", "two.txt", "--fs", "1", "--column", "1", "--kind",
                        "modified", "--json"], capture_output=True, text=True, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    d = json.loads(r.stdout)
    np.testing.assert_allclose(d["dev"], igea.allan(y[:500] * 2, 1.0, kind="modified").dev,
                               rtol=1e-14)
    assert d["block"] is not None
    h = subprocess.run([drv, "stability", "--help"], capture_output=True, text=True)
    assert h.returncode == 0 and "example" in h.stdout
    for bad in (["--data", "g.npy"], ["--data", "g.npy", "--fs", "1", "--kind", "x"],
                ["--data", "g.npy", "--fs", "x"], ["--data", "g.npy", "--fs", "1", "--nope"]):
        assert subprocess.run([drv, "stability", *bad], capture_output=True,
                              cwd=tmp_path).returncode == 64
    assert subprocess.run([drv, "stability", "--data", "none.npy", "--fs", "1"], capture_output=True,
                          cwd=tmp_path).returncode == 66


def test_block_seconds_and_taus_used_are_the_drivers():
    """Block3Sigma.seconds is the JSON block.seconds (round(block fs) / fs);
    the taus reported are those on the sample grid, lround(tau fs) / fs,
    for the driver and Python alike (a 2.5-sample tau is 3 samples)."""
    import json
    import subprocess
    y = np.random.default_rng(8).standard_normal(4000)
    b = igea.block_3sigma(y, 10.0, block=2.46)
    assert b.block_samples == 25 and b.seconds == 2.5
    r = igea.allan(y, 10.0, [0.25, 0.35, 1.0])
    np.testing.assert_array_equal(r.taus, [0.3, 0.4, 1.0])
    import os
    import tempfile
    with tempfile.TemporaryDirectory() as d:
        np.savetxt(os.path.join(d, "y.txt"), y)
        np.savetxt(os.path.join(d, "t.txt"), [0.25, 0.35, 1.0])
        out = subprocess.run([os.environ["IGEA_DRIVER"], "stability", "--data",
                              os.path.join(d, "y.txt"), "--fs", "10", "--block", "2.46",
                              "--taus", os.path.join(d, "t.txt"), "--json"],
                             capture_output=True, text=True, check=True).stdout
    j = json.loads(out)
    assert j["block"]["seconds"] == b.seconds
    assert j["taus"] == list(r.taus)


def _lag1_alpha(y, m):
    """Riley and Greenhall's lag-1 autocorrelation identification written
    here: non-overlapping m-means, differenced until delta < 0.25."""
    z = y[:y.size // m * m].reshape(-1, m).mean(axis=1)
    for d in range(3):
        u = z - z.mean()
        r1 = np.dot(u[:-1], u[1:]) / np.dot(u, u)
        delta = r1 / (1 + r1)
        if delta < 0.25 or d == 2:
            return int(max(-2, min(2, round(-2 * (delta + d)))))
        z = np.diff(z)


def test_auto_noise_from_the_deviation_pass():
    # the noise type found inside the deviation's pass is the lag-1 type of
    # the m-means (numpy above): the EDF equals that of the type given
    rng = np.random.default_rng(5)
    names = {2: "wpm", 1: "fpm", 0: "wfm", -1: "ffm", -2: "rwfm"}
    n = 20000
    for y in (rng.standard_normal(n), np.cumsum(rng.standard_normal(n)),
              np.diff(rng.standard_normal(n + 1))):
        for kind in ("overlapping", "modified", "nonoverlapping"):
            t = igea.octave_taus(n, 1.0, kind)
            t = t[n // np.round(t).astype(int) >= 32]
            auto = igea.allan(y, 1.0, t, kind=kind)
            for j, m in enumerate(np.round(t).astype(int)):
                a = _lag1_alpha(y - y.mean(), m)
                fixed = igea.allan(y, 1.0, [m], kind=kind, noise=names[a])
                assert auto.edf[j] == pytest.approx(fixed.edf[0], rel=1e-14), (kind, m, a)
