"""igea.ls / ebr / ridge / pce / bayes / collinearity against an independent
numpy/scipy implementation written here (METHODS 0.3, 4.3)."""
import dataclasses

import numpy as np
import pytest
from scipy.optimize import brentq, minimize_scalar

import igea

# ---- designs ---------------------------------------------------------------


def dual_design():
    """METHODS 4.2: the 20-position dual-accelerometer design (rank 7)."""
    th = np.deg2rad(18.0 * np.arange(20))
    s, c = np.sin(th), np.cos(th)
    A = np.column_stack([s, c, s * s, c * c, -s * c, s ** 3, c ** 3, s * s * c, -s * c * c])
    return th, A


BETA_TRUE = np.array([2, -1.5, 3, -2, 0.5, 0.2, -0.1, 0.1, -0.2]) * 1e-4


def ebr_data(a):
    th, A = dual_design()
    return A, A @ BETA_TRUE + a * np.cos(7 * th + 0.3) + a / 2 * np.sin(5 * th)


def random_problem(m=30, N=5, seed=1, collinear=True):
    rng = np.random.default_rng(seed)
    A = rng.standard_normal((m, N))
    if collinear:
        A[:, -1] = A[:, 0] + 1e-3 * rng.standard_normal(m)
    x = rng.standard_normal(N)
    y = A @ x + 0.1 * rng.standard_normal(m)
    return A, y, x


# ---- independent reference implementations ---------------------------------


def ref_canon(A, y, scale=None):
    As = A if scale is None else A * scale
    U, s, Vt = np.linalg.svd(As, full_matrices=True)
    m, N = A.shape
    r = int(np.sum(s > max(m, N) * np.finfo(float).eps * s[0]))
    z = U[:, :r].T @ y
    S = float(np.sum((y - U[:, :r] @ z) ** 2))
    return U, s, Vt.T, r, z, S


def ref_ebr(A, y, rule="sc", scale=None, lam_floor=0.0):
    m, N = A.shape
    U, s, V, r, z, S = ref_canon(A, y, scale)
    d = s[:r] ** 2
    s2 = S / (m - r)
    if rule in ("sc", "mm"):
        rhs = (r - 2) * S / (m - r + 2) if rule == "sc" else r * S / (m - r)
        f = lambda lam: np.sum(z * z / (1 + lam * d)) - rhs  # noqa: E731
        if f(0.0) <= 0:
            lam = 0.0
        else:
            hi = 1.0
            while f(hi) > 0:
                hi *= 10
            lam = brentq(f, 0.0, hi, xtol=1e-300, rtol=1e-15)
    else:
        nll = lambda t: np.sum(np.log1p(np.exp(t) * d) + z * z / (s2 * (1 + np.exp(t) * d)))  # noqa
        ts = np.linspace(-40, 40, 4001)
        vals = np.array([nll(t) for t in ts])
        i = int(np.argmin(vals))
        res = minimize_scalar(nll, bracket=(ts[max(i - 1, 0)], ts[i], ts[min(i + 1, 4000)]),
                              tol=1e-12)
        lam = float(np.exp(res.x))
        if np.sum(z * z) / s2 <= np.sum(np.ones(r)) and nll(-40) <= nll(res.x):
            lam = 0.0
    lam = max(lam, lam_floor)
    sh = lam * d / (1 + lam * d)
    D = np.ones(N) if scale is None else scale
    beta = D * (V[:, :r] @ (sh * z / s[:r]))
    dall = np.concatenate([d, np.zeros(N - r)])
    post = s2 * (D[:, None] * V) @ np.diag(lam / (1 + lam * dall)) @ (D[:, None] * V).T
    freq = s2 * (D[:, None] * V[:, :r]) @ np.diag(lam ** 2 * d / (1 + lam * d) ** 2) @ \
        (D[:, None] * V[:, :r]).T
    return lam, r, sh, beta, np.sqrt(np.diag(post)), np.sqrt(np.diag(freq))


# ---- least squares ---------------------------------------------------------


def test_ls_weighted_against_lstsq():
    A, y, _ = random_problem(collinear=False)
    sg = np.linspace(0.05, 0.3, len(y))
    r = igea.ls(A, y, sigma=sg)
    Aw, yw = A / sg[:, None], y / sg
    x, rss, rank, _ = np.linalg.lstsq(Aw, yw, rcond=None)
    s2 = rss[0] / (len(y) - rank)
    np.testing.assert_allclose(r.x, x, rtol=1e-12)
    assert r.rank == rank == 5
    np.testing.assert_allclose(r.sigma2, s2, rtol=1e-11)
    np.testing.assert_allclose(r.cov, s2 * np.linalg.inv(Aw.T @ Aw), rtol=1e-10)
    np.testing.assert_allclose(r.residual, y - A @ x, rtol=1e-9, atol=1e-13)
    # a scalar sigma is a constant weight
    r1 = igea.ls(A, y, sigma=0.2)
    np.testing.assert_allclose(r1.x, np.linalg.lstsq(A, y, rcond=None)[0], rtol=1e-12)


def test_ls_rank_deficient_min_norm():
    A, y = ebr_data(3e-5)
    r = igea.ls(A, y)
    assert r.rank == 7
    np.testing.assert_allclose(r.x, np.linalg.pinv(A) @ y, rtol=1e-10, atol=1e-18)
    np.testing.assert_allclose(r.sigma2, 12.5 * 9e-10 / 13, rtol=1e-9)
    # METHODS 4.3 table: LS minimum-norm K_A0 = 1.467e-4, K_A2 = 7.3e-5
    assert round(r.x[0], 7) == 1.467e-4 and round(r.x[5], 6) == 7.3e-5


def test_ls_longley_certified():
    # NIST StRD Longley, certified by NIST (see tests/test_regress.c)
    data = np.array([
        [60323, 83.0, 234289, 2356, 1590, 107608, 1947], [61122, 88.5, 259426, 2325, 1456, 108632, 1948],
        [60171, 88.2, 258054, 3682, 1616, 109773, 1949], [61187, 89.5, 284599, 3351, 1650, 110929, 1950],
        [63221, 96.2, 328975, 2099, 3099, 112075, 1951], [63639, 98.1, 346999, 1932, 3594, 113270, 1952],
        [64989, 99.0, 365385, 1870, 3547, 115094, 1953], [63761, 100.0, 363112, 3578, 3350, 116219, 1954],
        [66019, 101.2, 397469, 2904, 3048, 117388, 1955], [67857, 104.6, 419180, 2822, 2857, 118734, 1956],
        [68169, 108.4, 442769, 2936, 2798, 120445, 1957], [66513, 110.8, 444546, 4681, 2637, 121950, 1958],
        [68655, 112.6, 482704, 3813, 2552, 123366, 1959], [69564, 114.2, 502601, 3931, 2514, 125368, 1960],
        [69331, 115.7, 518173, 4806, 2572, 127852, 1961], [70551, 116.9, 554894, 4007, 2827, 130081, 1962]])
    A = np.column_stack([np.ones(16), data[:, 1:]])
    cert = [-3482258.63459582, 15.0618722713733, -0.358191792925910e-01, -2.02022980381683,
            -1.03322686717359, -0.511041056535807e-01, 1829.15146461355]
    r = igea.ls(A, data[:, 0])
    np.testing.assert_allclose(r.x, cert, rtol=1e-10)
    np.testing.assert_allclose(np.sqrt(r.sigma2), 304.854073561965, rtol=1e-10)


def test_ls_shapes_and_errors():
    A, y, _ = random_problem()
    with pytest.raises(ValueError, match="y"):
        igea.ls(A, y[:-1])
    with pytest.raises(ValueError, match="A"):
        igea.ls(A[:, 0], y)
    with pytest.raises(ValueError, match="sigma"):
        igea.ls(A, y, sigma=np.ones(3))
    y2 = y.copy()
    y2[3] = np.nan
    with pytest.raises(igea.IgeaError) as e:
        igea.ls(A, y2)
    assert e.value.code == -1011
    with pytest.raises(igea.IgeaError) as e:
        igea.ls(A, y, sigma=np.zeros(len(y)))
    assert e.value.code == -1012
    with pytest.raises(igea.IgeaError, match="rcond"):
        igea.ls(A, y, rcond=2.0)


# ---- EBR ---------------------------------------------------------------------


def test_ebr_methods_vector():
    """METHODS 4.3 test vector, to the digits shown."""
    lstar = {1e-6: 4.3191821286e+04, 3e-5: 4.7812680709e+01, 3e-4: 3.1903350644e-01}
    for a, want in lstar.items():
        A, y = ebr_data(a)
        r = igea.ebr(A, y)
        assert r.rank == 7
        # a = 1e-6: the exact-S root is 4.319182128821e4 (see test_regress.c)
        digits = 10 if a == 1e-6 else 11
        assert float("%.*e" % (digits - 1, r.lam)) == float("%.*e" % (digits - 1, want))
    np.testing.assert_array_equal(np.round(r.shrink[:7], 5),
                                  [0.83916, 0.83916, 0.76136, 0.61467, 0.44370, 0.26782, 0.26782])
    assert np.all(r.shrink[7:] == 0)
    want = [1.156185e-4, -8.07093e-5, 1.917349e-4, -1.155993e-4, 2.21849e-5, 7.84732e-5,
            -5.76305e-5, -2.30789e-5, -3.71453e-5]
    for got, w in zip(r.x, want):
        assert float("%.6e" % got) == pytest.approx(w, rel=1e-12, abs=0) or \
            float("%.5e" % got) == pytest.approx(w, rel=1e-12, abs=0)


@pytest.mark.parametrize("rule", ["sc", "mm", "ml2"])
@pytest.mark.parametrize("case", ["dual", "random"])
def test_ebr_against_reference(rule, case):
    if case == "dual":
        A, y = ebr_data(1e-4)
    else:
        A, y, _ = random_problem(m=25, N=6, seed=7)
        y = y + 2.0 * np.random.default_rng(3).standard_normal(len(y))
    lam, r, sh, beta, sdp, sdf = ref_ebr(A, y, rule)
    got = igea.ebr(A, y, rule=rule)
    assert got.rank == r
    np.testing.assert_allclose(got.lam, lam, rtol=1e-7 if rule == "ml2" else 1e-12)
    np.testing.assert_allclose(got.shrink[:r], sh, rtol=1e-7)
    np.testing.assert_allclose(got.x, beta, rtol=1e-6, atol=1e-12 * np.max(np.abs(beta)))
    np.testing.assert_allclose(got.sd, sdp, rtol=1e-6)
    np.testing.assert_allclose(got.sd_frequentist, sdf, rtol=1e-6)


def test_ebr_prior_scale_and_floor():
    A, y = ebr_data(3e-5)
    scale = np.array([1e-4, 1e-4, 3e-4, 3e-4, 1e-4, 2e-5, 2e-5, 2e-5, 2e-5])
    lam, r, sh, beta, sdp, sdf = ref_ebr(A, y, "sc", scale=scale)
    got = igea.ebr(A, y, spec=scale)
    np.testing.assert_allclose(got.lam, lam, rtol=1e-11)
    np.testing.assert_allclose(got.x, beta, rtol=1e-8)
    np.testing.assert_allclose(got.sd, sdp, rtol=1e-8)
    fl = igea.ebr(A, y, lam_floor=10 * got.lam * 1e8)
    assert fl.lam == 10 * got.lam * 1e8


def test_ebr_errors():
    A, y = ebr_data(1e-5)
    with pytest.raises(ValueError, match="rule"):
        igea.ebr(A, y, rule="xx")
    with pytest.raises(ValueError, match="spec"):
        igea.ebr(A, y, spec=np.ones(3))
    with pytest.raises(igea.IgeaError) as e:
        igea.ebr(A[:, :2], y)
    assert e.value.code == -1014
    with pytest.raises(igea.IgeaError, match="lam_floor"):
        igea.ebr(A, y, lam_floor=-1.0)
    with pytest.raises(igea.IgeaError) as e:
        igea.ebr(np.eye(3), np.ones(3))
    assert e.value.code == -1017


# ---- ridge, PCE, Bayes -------------------------------------------------------


def ridge_ref(A, y, k):
    N = A.shape[1]
    return np.linalg.solve(A.T @ A + k * np.eye(N), A.T @ y)


def test_ridge_fixed_and_rules():
    A, y, _ = random_problem(m=30, N=5, seed=11)
    sg = np.linspace(0.5, 1.5, 30)
    Aw, yw = A / sg[:, None], y / sg
    r = igea.ridge(A, y, sigma=sg, k=0.3)
    np.testing.assert_allclose(r.x, ridge_ref(Aw, yw, 0.3), rtol=1e-10)
    ls = igea.ls(A, y, sigma=sg)
    M = np.linalg.inv(Aw.T @ Aw + 0.3 * np.eye(5))
    np.testing.assert_allclose(r.cov, ls.sigma2 * M @ Aw.T @ Aw @ M, rtol=1e-9)
    assert igea.ridge(A, y, sigma=sg, rule="hkb").k == pytest.approx(
        5 * ls.sigma2 / np.sum(ls.x ** 2), rel=1e-10)
    assert igea.ridge(A, y, sigma=sg, rule="lw").k == pytest.approx(
        5 * ls.sigma2 / np.sum((Aw @ ls.x) ** 2), rel=1e-10)

    def gcv(t):
        k = 10.0 ** t
        H = Aw @ np.linalg.solve(Aw.T @ Aw + k * np.eye(5), Aw.T)
        e = yw - H @ yw
        return 30 * e @ e / (30 - np.trace(H)) ** 2

    def loo(t):
        k = 10.0 ** t
        H = Aw @ np.linalg.solve(Aw.T @ Aw + k * np.eye(5), Aw.T)
        e = yw - H @ yw
        return np.sum((e / (1 - np.diag(H))) ** 2)

    for rule, f in (("gcv", gcv), ("loo", loo)):
        got = igea.ridge(A, y, sigma=sg, rule=rule)
        ts = np.linspace(-10, 4, 1401)
        best = min(f(t) for t in ts)
        assert f(np.log10(got.k)) <= best * (1 + 1e-9)
        np.testing.assert_allclose(got.x, ridge_ref(Aw, yw, got.k), rtol=1e-9)


def test_ridge_trace_and_errors():
    A, y, _ = random_problem(seed=5)
    ks = np.array([0.0, 0.01, 1.0, 100.0])
    tr = igea.ridge_trace(A, y, ks)
    assert tr.X.shape == (5, 4)
    np.testing.assert_allclose(tr.X[:, 0], np.linalg.lstsq(A, y, rcond=None)[0], rtol=1e-8)
    for j in range(1, 4):
        np.testing.assert_allclose(tr.X[:, j], ridge_ref(A, y, ks[j]), rtol=1e-9)
    d = np.linalg.svd(A, compute_uv=False) ** 2
    np.testing.assert_allclose(tr.edf, [np.sum(d / (d + k)) for k in ks], rtol=1e-12)
    with pytest.raises(ValueError, match="k, rule"):
        igea.ridge(A, y)
    with pytest.raises(ValueError, match="rule"):
        igea.ridge(A, y, rule="nope")
    with pytest.raises(igea.IgeaError, match="k"):
        igea.ridge(A, y, k=-1.0)
    with pytest.raises(igea.IgeaError, match="k"):
        igea.ridge_trace(A, y, [-1.0])


def test_pce():
    A, y, _ = random_problem(seed=9)
    U, s, Vt = np.linalg.svd(A, full_matrices=False)
    for n in (1, 3, 5):
        got = igea.pce(A, y, ncomp=n)
        assert got.ncomp == n
        ref = Vt[:n].T @ ((U[:, :n].T @ y) / s[:n])
        np.testing.assert_allclose(got.x, ref, rtol=1e-9, atol=1e-12)
    got = igea.pce(A, y, eig_min=s[2] ** 2 * 0.999)
    assert got.ncomp == 3
    with pytest.raises(ValueError, match="ncomp"):
        igea.pce(A, y)
    with pytest.raises(ValueError, match="ncomp"):
        igea.pce(A, y, ncomp=0)


def test_bayes_closed_form():
    A, y = ebr_data(2e-5)
    sg = np.full(20, 1e-5)
    rng = np.random.default_rng(2)
    L = rng.standard_normal((9, 9)) * 1e-5
    P = L @ L.T + 1e-10 * np.eye(9)
    mu = rng.standard_normal(9) * 1e-4
    got = igea.bayes(A, y, P, prior_mean=mu, sigma=sg)
    W = np.diag(1 / sg ** 2)
    Pi = np.linalg.inv(P)
    C = np.linalg.inv(A.T @ W @ A + Pi)
    np.testing.assert_allclose(got.x, C @ (A.T @ W @ y + Pi @ mu), rtol=1e-6,
                               atol=1e-9 * np.max(np.abs(mu)))
    np.testing.assert_allclose(got.cov, C, rtol=1e-6, atol=1e-8 * np.max(np.abs(C)))
    with pytest.raises(igea.IgeaError) as e:
        igea.bayes(A, y, -np.eye(9))
    assert e.value.code == -1013
    with pytest.raises(ValueError, match="prior_cov"):
        igea.bayes(A, y, np.eye(3))


# ---- diagnostics -------------------------------------------------------------


def test_collinearity_dual_design():
    A, y = ebr_data(4e-5)
    c = igea.collinearity(A, y, names=["KA0", "KB0", "kA1", "kB1", "eta", "KA2", "KB2", "KAix",
                                       "KBix"])
    assert c.rank == 7
    ev = np.linalg.eigvalsh(A.T @ A)[::-1]
    np.testing.assert_allclose(c.eigenvalues[:7], ev[:7], rtol=1e-12)
    assert list(c.prior_determined) == [True, True, False, False, False, True, True, True, True]
    B = A.T @ A
    vif = np.diag(B) * np.diag(np.linalg.pinv(B))
    np.testing.assert_allclose(c.vif[2:5], vif[2:5], rtol=1e-10)
    assert np.all(np.isinf(c.vif[c.prior_determined]))
    # the null space is exactly n1 and n2 of METHODS 4.2
    n1 = np.array([-1, 0, 0, 0, 0, 1, 0, 0, -1]) / np.sqrt(3)
    n2 = np.array([0, -1, 0, 0, 0, 0, 1, 1, 0]) / np.sqrt(3)
    Z = c.null_space
    for n in (n1, n2):
        np.testing.assert_allclose(np.sum((Z.T @ n) ** 2), 1.0, rtol=1e-12)
    s = np.sqrt(12.5 * 16e-10 / 13)
    np.testing.assert_allclose(c.sd_comb[:7], s / np.sqrt(c.eigenvalues[:7]), rtol=1e-9)
    text = c.summary()
    assert "PRIOR" in text and "KBix" in text


def test_bias_mse_and_dataclasses():
    A, y, x = random_problem(collinear=False, seed=4)
    bias, mse = igea.bias_mse(lambda v: igea.ls(A, v).x, A, x, 0.1)
    np.testing.assert_allclose(bias, 0, atol=1e-12)
    np.testing.assert_allclose(mse, 0.01 * np.diag(np.linalg.inv(A.T @ A)), rtol=1e-9)
    k = 2.0
    bias, mse = igea.bias_mse(lambda v: igea.ridge(A, v, k=k).x, A, x, 0.1)
    M = np.linalg.inv(A.T @ A + k * np.eye(5))
    np.testing.assert_allclose(bias, -k * M @ x, rtol=1e-9)
    for res in (igea.ls(A, y), igea.ebr(A, y), igea.ridge(A, y, k=1.0), igea.pce(A, y, ncomp=2),
                igea.bayes(A, y, np.eye(5)), igea.collinearity(A)):
        assert isinstance(res.summary(), str) and res.summary()
        with pytest.raises(dataclasses.FrozenInstanceError):
            res.x = None


# ---- driver ----------------------------------------------------------------

def _driver():
    import os
    exe = os.environ.get("IGEA_DRIVER")
    if not exe or not os.path.exists(exe):
        pytest.skip("IGEA_DRIVER not set")
    return exe


def _write_flight(tmp_path):
    A, y, _ = random_problem(m=40, N=6, seed=21)
    sg = np.linspace(0.05, 0.2, 40)
    spec = np.array([1.0, 2.0, 0.5, 1.0, 3.0, 1.0])
    np.savetxt(tmp_path / "S.txt", A)
    np.savetxt(tmp_path / "dw.txt", y)
    np.savetxt(tmp_path / "sigma.txt", sg)
    np.savetxt(tmp_path / "spec.txt", spec)
    return A, y, sg, spec


def test_driver_json_matches_python(tmp_path):
    import json
    import subprocess
    exe = _driver()
    A, y, sg, spec = _write_flight(tmp_path)
    base = [exe, "regress", "--S", str(tmp_path / "S.txt"), "--dw", str(tmp_path / "dw.txt"),
            "--sigma", str(tmp_path / "sigma.txt"), "--spec", str(tmp_path / "spec.txt"), "--json"]
    As = A * spec
    cases = {
        ("ls",): lambda: (igea.ls(A, y, sigma=sg).x, igea.ls(A, y, sigma=sg).sd),
        ("ridge", "--k", "0.5"): lambda: (spec * igea.ridge(As, y, sigma=sg, k=0.5).x,
                                          spec * igea.ridge(As, y, sigma=sg, k=0.5).sd),
        ("pce", "--ncomp", "3"): lambda: (spec * igea.pce(As, y, sigma=sg, ncomp=3).x,
                                          spec * igea.pce(As, y, sigma=sg, ncomp=3).sd),
        ("bayes",): lambda: (spec * igea.bayes(As, y, np.eye(6), sigma=sg).x,
                             spec * igea.bayes(As, y, np.eye(6), sigma=sg).sd),
        ("ebr", "--rule", "mm"): lambda: (
            spec * igea.ebr(As / sg[:, None], y / sg, rule="mm").x,
            spec * igea.ebr(As / sg[:, None], y / sg, rule="mm").sd),
    }
    for args, ref in cases.items():
        out = subprocess.run(base + ["--method", *args], capture_output=True, text=True)
        assert out.returncode == 0, out.stderr
        js = json.loads(out.stdout)
        x, sd = ref()
        np.testing.assert_allclose(js["x"], x, rtol=1e-12, atol=1e-15)
        np.testing.assert_allclose(js["sd"], sd, rtol=1e-12)
        assert js["rank"] == 6 and len(js["prior_determined"]) == 6


def test_driver_usage(tmp_path):
    import subprocess
    exe = _driver()
    _write_flight(tmp_path)
    h = subprocess.run([exe, "regress", "--help"], capture_output=True, text=True)
    assert h.returncode == 0 and "example" in h.stdout
    base = [exe, "regress", "--S", str(tmp_path / "S.txt"), "--dw", str(tmp_path / "dw.txt")]
    for bad in (["--method", "xx"], ["--method", "ridge", "--rule", "sc"], ["--method", "bayes"],
                ["--method", "ls", "--bogus"], ["--method", "pce", "--ncomp", "0"]):
        r = subprocess.run(base + bad, capture_output=True, text=True)
        assert r.returncode == 64, (bad, r.stderr)
    r = subprocess.run([exe, "regress", "--method", "ls", "--S", str(tmp_path / "nope.txt"),
                        "--dw", str(tmp_path / "dw.txt")], capture_output=True, text=True)
    assert r.returncode == 66
    # EBR on two terms: rank < 3 -> data that cannot be used (65, igea_status_class DATA)
    np.savetxt(tmp_path / "S2.txt", np.loadtxt(tmp_path / "S.txt")[:, :2])
    r = subprocess.run([exe, "regress", "--method", "ebr", "--S", str(tmp_path / "S2.txt"),
                        "--dw", str(tmp_path / "dw.txt")], capture_output=True, text=True)
    assert r.returncode == 65


def test_ridge_published_mass_longley():
    """MASS::lm.ridge(Employed ~ ., longley) + select(): modified HKB
    0.004275357, modified L-W 0.03229531 (printed output, Faraway's book and
    course notes). MASS centres, scales columns by sqrt(mean(x^2)), uses
    s2 = RSS/(n-p-1), (p-2) and an extra n for L-W."""
    L = np.array([
        [60323, 83.0, 234289, 2356, 1590, 107608, 1947], [61122, 88.5, 259426, 2325, 1456, 108632, 1948],
        [60171, 88.2, 258054, 3682, 1616, 109773, 1949], [61187, 89.5, 284599, 3351, 1650, 110929, 1950],
        [63221, 96.2, 328975, 2099, 3099, 112075, 1951], [63639, 98.1, 346999, 1932, 3594, 113270, 1952],
        [64989, 99.0, 365385, 1870, 3547, 115094, 1953], [63761, 100.0, 363112, 3578, 3350, 116219, 1954],
        [66019, 101.2, 397469, 2904, 3048, 117388, 1955], [67857, 104.6, 419180, 2822, 2857, 118734, 1956],
        [68169, 108.4, 442769, 2936, 2798, 120445, 1957], [66513, 110.8, 444546, 4681, 2637, 121950, 1958],
        [68655, 112.6, 482704, 3813, 2552, 123366, 1959], [69564, 114.2, 502601, 3931, 2514, 125368, 1960],
        [69331, 115.7, 518173, 4806, 2572, 127852, 1961], [70551, 116.9, 554894, 4007, 2827, 130081, 1962]])
    n, p = 16, 6
    X = L[:, 1:] - L[:, 1:].mean(0)
    X = X / np.sqrt((X ** 2).mean(0))
    y = L[:, 0] - L[:, 0].mean()
    f = (p - 2) / p * (n - p) / (n - p - 1)
    assert float("%.6e" % (igea.ridge(X, y, rule="hkb").k * f)) == 4.275357e-3
    assert float("%.6e" % (igea.ridge(X, y, rule="lw").k * f * n)) == 3.229531e-2
