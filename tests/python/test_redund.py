"""igea.redund against independent numpy/scipy implementations (METHODS 3.1-3.3)."""
import itertools
import math

import numpy as np
import pytest
from scipy import special, stats

import igea

S2 = math.sqrt(0.5)
X_TV = np.array([1.000010, 1.000018, 0.999995, 1.000004])


# ---- references ------------------------------------------------------------

def ref_cdm(x, sigma):
    x = np.asarray(x, float)
    s = np.broadcast_to(np.asarray(sigma, float), x.shape)
    return np.abs(special.erf((x[None, :] - x[:, None]) / (math.sqrt(2) * s[:, None])))


def ref_fusion(D, alpha, iterative=True):
    n = D.shape[0]
    A = np.broadcast_to(alpha, (n, n))
    r = (D <= A)
    np.fill_diagonal(r, False)
    F = list(range(n))
    if not iterative:
        need = math.ceil((n - 1) / 2)
        return np.array([r[:, j].sum() >= need for j in range(n)])
    while True:
        need = math.ceil((len(F) - 1) / 2)
        sup = {j: sum(r[i, j] for i in F if i != j) for j in F}
        mn = min(sup.values())
        if mn >= need:
            break
        cands = [j for j in F if sup[j] == mn]
        dsum = {j: sum(D[i, j] for i in F if i != j) for j in cands}
        mx = max(dsum.values())
        worst = max(j for j in cands if dsum[j] == mx)
        F.remove(worst)
    return np.array([j in F for j in range(n)])


def ref_geometry(axes, R):
    axes = np.asarray(axes, float)
    axes = axes / np.linalg.norm(axes, axis=1)[:, None]
    n = len(R)
    span = det = iso = 0.0
    for mask in itertools.product([0, 1], repeat=n):
        idx = [k for k in range(n) if mask[k]]
        w = np.prod([R[k] if mask[k] else 1 - R[k] for k in range(n)])
        if len(idx) < 3:
            continue
        H = axes[idx]
        if np.linalg.matrix_rank(H, tol=1e-9) < 3:
            continue
        span += w
        if len(idx) < 4:
            continue
        P = np.eye(len(idx)) - H @ np.linalg.pinv(H)
        d = np.diag(P)
        if np.all(d > 1e-9):
            det += w
            ok = all(P[i, j] ** 2 < (1 - 1e-9) * d[i] * d[j]
                     for i in range(len(idx)) for j in range(i + 1, len(idx)))
            iso += w if ok else 0.0
    return span, det, iso


# ---- reliability -------------------------------------------------------------

def test_seed002_figures():
    r = igea.reliability_seed002(0.992, 0.995)
    assert r.non_redundant == pytest.approx(0.9616217080, abs=5e-11)
    assert r.system_without_skew == pytest.approx(0.9997580219, abs=5e-11)
    assert r.system_eq7 == pytest.approx(0.9998077617, abs=5e-11)
    assert r.system_exact == pytest.approx(0.9998077611, abs=5e-11)
    assert "0.9998077611" in r.summary()


def test_series_parallel_kofn_diagram():
    R = np.array([0.9, 0.8, 0.95, 0.7, 0.99])
    assert igea.reliability_series(R) == pytest.approx(np.prod(R), rel=1e-15)
    assert igea.reliability_parallel(R) == pytest.approx(1 - np.prod(1 - R), rel=1e-15)
    for k in range(1, 6):
        want = sum(np.prod([R[i] if m[i] else 1 - R[i] for i in range(5)])
                   for m in itertools.product([0, 1], repeat=5) if sum(m) >= k)
        assert igea.reliability_kofn(R, k) == pytest.approx(want, rel=1e-13)
    # seed 002 eq. (7) as a diagram: X4 || ; (Y || Y) (Z || Z) series, || D
    Rs = np.full(9, 0.995)
    blocks = [("parallel", [0, 1, 2, 3]), ("parallel", [4, 5]), ("parallel", [6, 7]),
              ("series", [10, 11]), ("parallel", [8, 12]), ("series", [9, 13])]
    out = igea.reliability_diagram(Rs, blocks)
    assert out[-1] == pytest.approx(0.999999749378, abs=5e-13)
    assert igea.reliability_diagram(R[:3], [("kofn", [0, 1, 2], 2)])[0] == pytest.approx(
        igea.reliability_kofn(R[:3], 2), rel=1e-15)
    R0, mtbf = igea.reliability_exponential(1e-4, 100.0)
    assert R0 == pytest.approx(math.exp(-1e-2)) and mtbf == pytest.approx(1e4)
    with pytest.raises(igea.IgeaError, match="invalid argument 2 \\(k\\)"):
        igea.reliability_kofn(R, 7)
    with pytest.raises(igea.IgeaError):
        igea.reliability_series([0.5, 1.5])
    with pytest.raises(igea.IgeaError):
        igea.reliability_diagram(R, [("series", [0, 0])])
    with pytest.raises(ValueError, match="blocks"):
        igea.reliability_diagram(R, [("mixed", [0])])
    with pytest.raises(ValueError, match="R"):
        igea.reliability_series(np.ones((2, 2)))


def test_geometry_against_enumeration():
    s = S2
    ax = [[1, 0, 0]] * 4 + [[0, 1, 0]] * 2 + [[0, 0, 1]] * 2 + [[0, s, s]]
    g = igea.reliability_geometry(ax, 0.995)
    assert g.span == pytest.approx(0.999999748756, abs=5e-13)
    want = ref_geometry(ax, np.full(9, 0.995))
    assert (g.span, g.detect, g.isolate) == pytest.approx(want, rel=1e-12)
    assert g.classes == 4
    rng = np.random.default_rng(5)
    axes = rng.normal(size=(7, 3))
    axes[3] = axes[0] * -2.0   # a parallel pair
    R = rng.uniform(0.8, 0.99, 7)
    g = igea.reliability_geometry(axes, R)
    assert (g.span, g.detect, g.isolate) == pytest.approx(ref_geometry(axes, R), rel=1e-12)
    assert math.isnan(igea.reliability_geometry(axes, R, fdi=False).detect)
    with pytest.raises(ValueError, match="axes"):
        igea.reliability_geometry(np.ones((4, 2)), 0.9)
    with pytest.raises(ValueError, match="R"):
        igea.reliability_geometry(axes, np.ones(3))
    with pytest.raises(igea.IgeaError):
        igea.reliability_geometry(np.zeros((4, 3)), 0.9)


# ---- consistency ----------------------------------------------------------------

def test_erfinv_against_scipy():
    for y in np.concatenate([np.linspace(-0.999999, 0.999999, 101), [1 - 1e-13, -1e-300]]):
        assert igea.erfinv(y) == pytest.approx(special.erfinv(y), rel=2e-15, abs=1e-300)
    with pytest.raises(igea.IgeaError):
        igea.erfinv(1.0)


def test_confidence_distance_test_vector():
    D = igea.confidence_distance(X_TV, 20e-6)
    want = [[0, .3108, .5467, .2358], [.3108, 0, .7499, .5161],
            [.5467, .7499, 0, .3473], [.2358, .5161, .3473, 0]]
    np.testing.assert_allclose(D, want, atol=5e-5)
    sig = np.array([1.0, 2.0, 0.5, 3.0])
    x = np.array([0.1, 1.4, -0.7, 2.2])
    np.testing.assert_allclose(igea.confidence_distance(x, sig), ref_cdm(x, sig), rtol=1e-14,
                               atol=1e-16)
    with pytest.raises(ValueError, match="sigma"):
        igea.confidence_distance(x, [1.0, 2.0])
    with pytest.raises(igea.IgeaError):
        igea.confidence_distance(x, [1.0, 0.0, 1.0, 1.0])
    with pytest.raises(igea.IgeaError):
        igea.confidence_distance([1.0, np.nan], 1.0)


def test_relation_thresholds_fusion():
    D = igea.confidence_distance(X_TV, 20e-6)
    r = igea.relation(D, 0.7)
    np.testing.assert_array_equal(r, [[1, 1, 1, 1], [1, 1, 0, 1], [1, 0, 1, 1], [1, 1, 1, 1]])
    delta = igea.thresholds(np.full(4, 20e-6), 0.7)
    np.testing.assert_allclose(delta, math.sqrt(2) * 20e-6 * special.erfinv(0.7), rtol=1e-15)
    phys = (np.abs(X_TV[None, :] - X_TV[:, None]) <= delta).astype(int)
    np.testing.assert_array_equal(phys, r)
    assert igea.fusion_set(D).all()
    x = X_TV.copy()
    x[3] += 0.010
    D = igea.confidence_distance(x, 20e-6)
    np.testing.assert_array_equal(igea.fusion_set(D), [True, True, True, False])
    np.testing.assert_array_equal(igea.fusion_set(D, one_shot=True), [True, False, False, False])
    np.testing.assert_array_equal(igea.support(D), [2, 1, 1, 0])
    v, s = igea.fuse(x, 20e-6, igea.fusion_set(D))
    assert v == pytest.approx(1.0000077, abs=5e-8)
    assert s == pytest.approx(20e-6 / math.sqrt(3), rel=1e-14)
    # random sets against the reference algorithm, alpha as a matrix too
    rng = np.random.default_rng(9)
    for trial in range(200):
        n = rng.integers(2, 8)
        xs = rng.normal(size=n) * rng.uniform(0.5, 3)
        sg = rng.uniform(0.5, 2.0, n)
        alpha = rng.uniform(0.3, 0.95, (n, n)) if trial % 2 else 0.7
        D = igea.confidence_distance(xs, sg)
        np.testing.assert_array_equal(ref_cdm(xs, sg) <= np.broadcast_to(alpha, (n, n)),
                                      igea.relation(D, alpha).astype(bool) | np.eye(n, dtype=bool))
        for it in (True, False):
            np.testing.assert_array_equal(igea.fusion_set(D, alpha, one_shot=not it),
                                          ref_fusion(D, alpha, it))
    with pytest.raises(ValueError, match="alpha"):
        igea.fusion_set(D, np.ones((2, 2)) * 0.5)
    with pytest.raises(ValueError, match="D"):
        igea.fusion_set(np.zeros((2, 3)))
    with pytest.raises(igea.IgeaError):
        igea.relation(D, 1.5)


def test_fuse_and_false_alarm():
    x = np.array([1.0, 2.0, 4.0])
    s = np.array([1.0, 2.0, 4.0])
    w = s ** -2
    v, fs = igea.fuse(x, s)
    assert v == pytest.approx((w * x).sum() / w.sum(), rel=1e-15)
    assert fs == pytest.approx(w.sum() ** -0.5, rel=1e-15)
    v, fs = igea.fuse(x, s, [True, False, True], average=True)
    assert v == pytest.approx(2.5) and fs == pytest.approx(math.sqrt(17) / 2)
    with pytest.raises(igea.IgeaError):
        igea.fuse(x, s, [False, False, False])
    with pytest.raises(ValueError, match="mask"):
        igea.fuse(x, s, [True])
    for k, want in ((1, 0.464), (3, 0.028)):
        assert igea.false_alarm(k, 1.0) == pytest.approx(want, abs=5e-4)
    # Monte Carlo-free check: P(|N(0, a^2 + b^2)| > delta)
    delta = math.sqrt(2) * 2.0 * special.erfinv(0.8)
    assert igea.false_alarm(2.0, 0.7, 1.1, 0.8) == pytest.approx(
        2 * stats.norm.sf(delta / math.hypot(0.7, 1.1)), rel=1e-12)


def test_transform():
    rng = np.random.default_rng(2)
    C = rng.normal(size=(3, 3, 3))
    v = rng.normal(size=(3, 3))
    np.testing.assert_allclose(igea.transform(C, v), np.einsum("gij,gj->gi", C, v), rtol=1e-14)
    with pytest.raises(ValueError, match="v"):
        igea.transform(C, v[:2])


# ---- parity space -----------------------------------------------------------------

def cone(n):
    c, s = 1 / math.sqrt(3), math.sqrt(2 / 3)
    az = 2 * np.pi * np.arange(n) / n + 0.1 * np.arange(n) ** 2
    return np.column_stack([s * np.cos(az), s * np.sin(az), np.full(n, c)])


def test_parity_and_fdi():
    H = cone(6)
    V = igea.parity_matrix(H)
    np.testing.assert_allclose(V @ H, 0, atol=1e-14)
    np.testing.assert_allclose(V @ V.T, np.eye(3), atol=1e-14)
    # same row space as scipy's null space of H^T
    N = __import__("scipy.linalg", fromlist=["null_space"]).null_space(H.T)
    np.testing.assert_allclose(V.T @ V, N @ N.T, atol=1e-13)
    sig = 1e-3 * (1 + 0.2 * np.arange(6))
    y = H @ np.array([0.1, -0.2, 9.8])
    r = igea.fdi(H, y, sig, 0.01)
    assert not r.detected and r.isolated == -1 and r.isolable
    assert r.threshold == pytest.approx(stats.chi2.isf(0.01, 3), rel=1e-12)
    for k in range(6):
        yf = y.copy()
        yf[k] += 8 * sig[k]
        r = igea.fdi(H, yf, sig, 0.01)
        Hw = H / sig[:, None]
        P = np.eye(6) - Hw @ np.linalg.pinv(Hw)
        e = (yf - y) / sig
        assert r.statistic == pytest.approx(e @ P @ e, rel=1e-10)
        assert r.p_value == pytest.approx(stats.chi2.sf(e @ P @ e, 3), rel=1e-8)
        assert r.detected and r.isolated == k
    with pytest.raises(ValueError, match="H"):
        igea.fdi(H[:3], y[:3], sig[:3])
    with pytest.raises(ValueError, match="y"):
        igea.fdi(H, y[:5], sig)
    with pytest.raises(igea.IgeaError):
        igea.fdi(H, y, sig, 1.5)
    Hp = H.copy()
    Hp[:, 2] = Hp[:, 0]
    with pytest.raises(igea.IgeaError):
        igea.parity_matrix(Hp)


def test_skew_check():
    s2 = math.sqrt(0.5)
    ay = np.array([0.3, 0.31])
    az = np.array([-0.2, -0.2])
    sg = np.full(2, 1e-3)
    ad = (0.3 - 0.2) * s2
    r = igea.skew_check(ay, sg, az, sg, ad, 1e-3)
    np.testing.assert_allclose(r.residual, ad - s2 * (ay[:, None] + az[None, :]), atol=1e-16)
    thr = 3 * np.sqrt(1e-6 + 0.5 * sg[:, None] ** 2 + 0.5 * sg[None, :] ** 2)
    fails = np.abs(r.residual) > thr
    np.testing.assert_array_equal(r.faulty_y, fails.all(axis=1))
    assert list(r.faulty_y) == [False, True] and not r.faulty_z.any() and not r.faulty_d
    assert r.summary() == "faulty: Y2"
    assert igea.skew_check(ay[:1], sg[:1], az, sg, ad + 0.05, 1e-3).faulty_d
    with pytest.raises(ValueError, match="sz"):
        igea.skew_check(ay, sg, az, sg[:1], ad, 1e-3)
    with pytest.raises(igea.IgeaError):
        igea.skew_check(ay, sg, az, sg, ad, 1e-3, kappa=0.0)


# ---- the seed's experiment ------------------------------------------------------------

def test_series_check_seed_experiment():
    fs, T = 100, 200
    level = [1.000004, 1.000001, 0.999998, 1.000003]
    y = igea.simulate_redundant(fs * T, fs, level, 30e-6, fault_sensor=3, t0=100, t1=120,
                                bias=0.010, seed=2024)
    r = igea.series_check(y, fs, 1.0, 20e-6, 0.7)
    assert r.intervals() == [(3, 100.0, 120.0)]
    assert "sensor 3 excluded from 100 s to 120 s" in r.summary()
    # the window means and the fused values against numpy
    means = y.reshape(T, fs, 4).mean(axis=1)
    np.testing.assert_allclose(r.means, means, rtol=1e-14)
    for w in (0, 50, 110, 150):
        m = ~r.excluded[w]
        np.testing.assert_allclose(r.fused[w], means[w, m].mean(), rtol=1e-14)
    # the same record again with a numpy generator: same decisions
    rng = np.random.default_rng(4)
    y2 = np.array(level) + rng.normal(0, 30e-6, (fs * T, 4))
    y2[100 * fs:120 * fs, 3] += 0.010
    assert igea.series_check(y2, fs, 1.0, 20e-6).intervals() == [(3, 100.0, 120.0)]
    with pytest.raises(ValueError, match="sigma"):
        igea.series_check(y, fs, 1.0, [1, 2])
    with pytest.raises(igea.IgeaError, match="window"):
        igea.series_check(y, fs, 0.0, 20e-6)


# ---- the driver ----------------------------------------------------------------------

def _drive(*args, cwd=None):
    import os
    import subprocess
    return subprocess.run([os.environ["IGEA_DRIVER"], "redund", *args], capture_output=True,
                          text=True, cwd=cwd)


def test_driver_redund(tmp_path):
    import json
    r = _drive("reliability", "--json")
    assert r.returncode == 0, r.stderr
    d = json.loads(r.stdout)
    assert d["system_exact"] == pytest.approx(0.9998077611, abs=5e-11)
    assert d["system_without_skew_eq10"] == pytest.approx(0.9997580219, abs=5e-11)
    x = X_TV.copy()
    x[3] += 0.010
    np.savetxt(tmp_path / "x.txt", x)
    r = _drive("consistency", "--x", "x.txt", "--sigma", "20e-6", "--json", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    d = json.loads(r.stdout)
    np.testing.assert_allclose(d["D"], ref_cdm(x, 20e-6), rtol=1e-15, atol=1e-300)
    assert d["support"] == [2, 1, 1, 0] and d["fusion_set"] == [1, 1, 1, 0]
    assert d["fusion_set_one_shot"] == [1, 0, 0, 0]
    assert d["fused"] == pytest.approx(1.0000077, abs=5e-8)
    y = igea.simulate_redundant(20000, 100, [1.000004, 1.000001, 0.999998, 1.000003], 30e-6,
                                fault_sensor=3, t0=100, t1=120, bias=0.010, seed=2024)
    np.save(tmp_path / "rec.npy", y)
    r = _drive("fuse", "--data", "rec.npy", "--fs", "100", "--sigma", "20e-6", "--json",
               "--out", "fuse.json", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    d = json.loads((tmp_path / "fuse.json").read_text())
    assert d["exclusions"] == [{"sensor": 3, "from": 100, "to": 120}]
    np.testing.assert_allclose(d["fused"], igea.series_check(y, 100, 1.0, 20e-6).fused,
                               rtol=1e-15)
    H = cone(6)
    yy = H @ [0.1, 0.2, 9.8]
    yy[2] += 0.05
    np.savetxt(tmp_path / "H.txt", H)
    np.savetxt(tmp_path / "y.txt", yy)
    r = _drive("fdi", "--H", "H.txt", "--y", "y.txt", "--sigma", "0.005", "--json", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    d = json.loads(r.stdout)
    ref = igea.fdi(H, yy, np.full(6, 0.005))
    assert d["detected"] and d["isolated"] == 2 and ref.isolated == 2
    assert d["statistic"] == pytest.approx(ref.statistic, rel=1e-12)
    assert _drive("--help").returncode == 0 and "example" in _drive("--help").stdout
    assert _drive("consistency", "--x", "x.txt", "--sigma", "1", "--alpha", "2",
                  cwd=tmp_path).returncode == 64
    assert _drive("consistency", "--bogus").returncode == 64
    assert _drive("consistency", "--x", "missing.txt", "--sigma", "1",
                  cwd=tmp_path).returncode == 66
    (tmp_path / "bad.txt").write_text("1.0\n2.x\n")
    r = _drive("consistency", "--x", "bad.txt", "--sigma", "1", cwd=tmp_path)
    assert r.returncode == 65 and "bad.txt:2" in r.stderr


def test_series_check_window_used_and_the_driver_spelling():
    """The window used is round(window fs) samples with halves away from
    zero (C's lround; Python's round(2.5) is 2): window 2.5 s at 1 Hz is 3
    samples, so 30 samples give 10 windows starting every 3 s. one_shot=/
    average= are the driver's --one-shot/--average; the old iterative=/
    weighted= (their negations) give the same result with a warning."""
    rng = np.random.default_rng(4)
    y = 1.0 + 1e-6 * rng.standard_normal((30, 4))
    r = igea.series_check(y, 1.0, 2.5, 20e-6)
    assert r.window == 3.0 and r.fused.size == 10
    np.testing.assert_array_equal(r.t, 3.0 * np.arange(10))
    np.testing.assert_allclose(r.means[0], y[:3].mean(axis=0), rtol=1e-15)
    new = igea.series_check(y, 1.0, 2.5, 20e-6, one_shot=True, average=True)
    np.testing.assert_allclose(new.fused, y.reshape(10, 3, 4).mean(axis=(1, 2)), rtol=1e-14)
    with pytest.warns(DeprecationWarning, match="iterative= is now one_shot="):
        old = igea.series_check(y, 1.0, 2.5, 20e-6, iterative=False, weighted=False)
    np.testing.assert_array_equal(old.fused, new.fused)
    with pytest.raises(TypeError, match="give average= only"):
        igea.fuse([1.0, 2.0], [1.0, 1.0], average=True, weighted=True)
