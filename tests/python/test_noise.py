"""Tracking noise beyond a diagonal K (igea/noise.h) against independent
computations written here: full-covariance GLS in numpy, the AR(p)
autocovariance from the MA(infinity) weights, OLS of residuals on their
lags, REML of two variance components maximised by scipy."""
import ctypes

import numpy as np
import pytest
from scipy import linalg, optimize, signal

from igea import _capi, _lib

lib = _lib.lib


def whiten(N, p=0, phi=None, G=1):
    h = ctypes.c_void_p()
    ph = None if phi is None else np.ascontiguousarray(phi, dtype=float)
    _lib.call("t", "igea_whiten_create", N, p, _lib.dptr(ph), G, ctypes.byref(h))
    return h


def accumulate(h, S, dw, N, G=1, sigma=None, cov=None, group=None, mask=None, spec=None,
               blocks=(1,)):
    """Stream S (m x N) through the whitener in the given number of epoch blocks."""
    m = S.shape[0]
    A = np.zeros((G, N, N))
    b = np.zeros((G, N))
    wtw = np.zeros(2 * G)
    white = np.zeros((N + 1, m))
    cuts = np.linspace(0, m // 3, blocks[0] + 1).astype(int) * 3
    for r0, r1 in zip(cuts[:-1], cuts[1:]):
        Sb = np.asfortranarray(S[r0:r1])
        d = np.ascontiguousarray(dw[r0:r1])
        sg = None if sigma is None else np.ascontiguousarray(sigma[r0:r1])
        cv = None if cov is None else np.ascontiguousarray(cov[r0 // 3:r1 // 3].ravel())
        gr = None if group is None else np.ascontiguousarray(group[r0 // 3:r1 // 3], dtype=np.int32)
        mk = None if mask is None else np.ascontiguousarray(mask[r0:r1], dtype=np.int32)
        wb = np.zeros((N + 1, r1 - r0))
        _lib.call("t", "igea_whiten_accumulate", h, _capi.COLMAJOR, r1 - r0, _lib.dptr(Sb),
                  max(1, r1 - r0), _lib.dptr(d), _lib.dptr(sg), 1, _lib.dptr(cv), _lib.iptr(gr),
                  _lib.iptr(mk), _lib.dptr(spec), _lib.dptr(A), N, _lib.dptr(b), _lib.dptr(wtw),
                  _lib.dptr(wb), None)
        white[:, r0:r1] = wb
    return A, b, wtw, white.T


def random_cov(rng, M, rmax=0.9):
    """M 3x3 covariances with correlations up to rmax, as 6 lower-triangle values."""
    out = np.empty((M, 6))
    full = np.empty((M, 3, 3))
    for e in range(M):
        sd = rng.uniform(0.5, 2.0, 3)
        r = rng.uniform(-rmax, rmax, 3)
        R = np.array([[1, r[0], r[1]], [r[0], 1, r[2]], [r[1], r[2], 1]])
        while np.linalg.eigvalsh(R).min() <= 0.02:
            r *= 0.9
            R = np.array([[1, r[0], r[1]], [r[0], 1, r[2]], [r[1], r[2], 1]])
        C = R * np.outer(sd, sd)
        full[e] = C
        out[e] = [C[0, 0], C[1, 0], C[1, 1], C[2, 0], C[2, 1], C[2, 2]]
    return out, full


def ar_autocorr(phi, n):
    """Autocorrelation rho_0..rho_(n-1) of a stationary AR(p) from its
    MA(infinity) weights psi (psi_0 = 1, psi_j = sum_k phi_k psi_(j-k)),
    truncated where they are below 1e-17: independent of Yule-Walker."""
    L = 20000
    psi = np.zeros(L)
    psi[0] = 1
    for j in range(1, L):
        psi[j] = sum(phi[k] * psi[j - 1 - k] for k in range(len(phi)) if j - 1 - k >= 0)
    g = np.array([psi[:L - k] @ psi[k:] for k in range(n)])
    return g / g[0]


def test_block_covariance_equals_full_gls():
    rng = np.random.default_rng(1)
    M, N = 40, 5
    m = 3 * M
    S = rng.normal(size=(m, N))
    dw = rng.normal(size=m)
    spec = rng.uniform(0.5, 2, N)
    cov6, full = random_cov(rng, M)
    K = linalg.block_diag(*full)
    Ki = np.linalg.inv(K)
    SD = S * spec
    h = whiten(N)
    A, b, wtw, _ = accumulate(h, S, dw, N, cov=cov6, spec=spec, blocks=(3,))
    lib.igea_whiten_free(h)
    np.testing.assert_allclose(A[0], SD.T @ Ki @ SD, rtol=1e-11, atol=1e-11)
    np.testing.assert_allclose(b[0], SD.T @ Ki @ dw, rtol=1e-11, atol=1e-11)
    assert wtw[0] == pytest.approx(dw @ Ki @ dw, rel=1e-12)
    assert wtw[1] == m


def test_non_positive_definite_block_names_the_epoch():
    rng = np.random.default_rng(2)
    M, N = 6, 2
    S = rng.normal(size=(3 * M, N))
    dw = rng.normal(size=3 * M)
    cov6, _ = random_cov(rng, M)
    cov6[4] = [1, 2, 1, 0, 0, 1]  # |corr| = 2: not positive definite
    h = whiten(N)
    A = np.zeros((N, N)); b = np.zeros(N); wtw = np.zeros(2)
    bad = ctypes.c_int(-1)
    st = lib.igea_whiten_accumulate(h, 0, 3 * M, _lib.dptr(np.asfortranarray(S)), 3 * M,
                                    _lib.dptr(dw), None, 1, _lib.dptr(cov6.ravel().copy()),
                                    None, None, None, _lib.dptr(A), N, _lib.dptr(b),
                                    _lib.dptr(wtw), None, ctypes.byref(bad))
    lib.igea_whiten_free(h)
    assert st == _capi.ESINGULAR and bad.value == 4
    assert not A.any() and not wtw.any()


@pytest.mark.parametrize("phi", [[0.9], [0.5, 0.3], [0.6, -0.2, 0.25]])
def test_prais_winsten_equals_cholesky_of_ar_covariance(phi):
    rng = np.random.default_rng(3)
    p = len(phi)
    M, N = 30, 4
    m = 3 * M
    S = rng.normal(size=(m, N))
    dw = rng.normal(size=m)
    sigma = rng.uniform(0.5, 2, m)
    # axis-dependent coefficients: axis a gets phi scaled by (1 - 0.1 a)
    ph = np.array([[f * (1 - 0.1 * a) for f in phi] for a in range(3)])
    K = np.zeros((m, m))
    for a in range(3):
        rho = ar_autocorr(ph[a], M)
        idx = np.arange(M) * 3 + a
        K[np.ix_(idx, idx)] = linalg.toeplitz(rho)
    K *= np.outer(sigma, sigma)
    # a second segment (group change at epoch 18) is independent of the first
    group = np.zeros(M, dtype=np.int32)
    group[18:] = 1
    same = np.equal.outer(np.repeat(group, 3), np.repeat(group, 3))
    K = K * same  # the filter restarts at a group change
    # ... and the restarted segment's own Toeplitz is the same matrix shifted
    for a in range(3):
        rho = ar_autocorr(ph[a], M)
        idx = 3 * np.arange(18, M) + a
        K[np.ix_(idx, idx)] = linalg.toeplitz(rho[:M - 18]) * np.outer(sigma[idx], sigma[idx])
    Lc = np.linalg.cholesky(K)
    Sw = np.linalg.solve(Lc, S)
    ww = np.linalg.solve(Lc, dw)
    h = whiten(N, p, ph.ravel(), G=2)
    A, b, wtw, white = accumulate(h, S, dw, N, G=2, sigma=sigma, group=group, blocks=(4,))
    lib.igea_whiten_free(h)
    gr = np.repeat(group, 3)
    for g in range(2):
        r = gr == g
        np.testing.assert_allclose(A[g], Sw[r].T @ Sw[r], rtol=1e-9, atol=1e-9)
        np.testing.assert_allclose(b[g], Sw[r].T @ ww[r], rtol=1e-9, atol=1e-9)
        assert wtw[2 * g] == pytest.approx(ww[r] @ ww[r], rel=1e-9)
    # the whitened rows are those of the inverse Cholesky factor (row by row)
    np.testing.assert_allclose(white[:, :N], Sw, rtol=1e-9, atol=1e-9)


def test_non_stationary_phi_refused():
    h = ctypes.c_void_p()
    # AR(1) phi = 1 (a random walk); AR(2) 0.5 + 0.6 > 1 (a root inside the circle)
    for p, phi in ((1, [0.2, 1.0, 0.3]), (2, [0.1, 0.1, 0.5, 0.6, 0.1, 0.1])):
        st = lib.igea_whiten_create(2, p, _lib.dptr(np.array(phi, dtype=float)), 1,
                                    ctypes.byref(h))
        assert st == -3 and not h.value


def test_ar_fit_equals_numpy_ols():
    rng = np.random.default_rng(4)
    M, p = 400, 2
    e = rng.normal(size=(M, 3))
    for t in range(2, M):
        e[t] += 0.5 * e[t - 1] - 0.2 * e[t - 2]
    group = np.zeros(M, dtype=np.int32)
    group[250:] = 1
    mask = np.zeros(3 * M, dtype=np.int32)
    mask[3 * 100 + 1] = 1
    phi = np.zeros(3 * p)
    se = np.zeros(3 * p)
    r = np.ascontiguousarray(e.ravel())
    _lib.call("t", "igea_noise_ar_fit", M, p, _lib.dptr(r), _lib.iptr(group), _lib.iptr(mask),
              _lib.dptr(phi), _lib.dptr(se))
    for a in range(3):
        rows = [t for t in range(M) if t >= p and group[t - p] == group[t]
                and all(not mask[3 * (t - l) + a] for l in range(p + 1))]
        X = np.array([[e[t - 1 - k, a] for k in range(p)] for t in rows])
        y = np.array([e[t, a] for t in rows])
        coef, rss, *_ = np.linalg.lstsq(X, y, rcond=None)
        s2 = rss[0] / (len(y) - p)
        sd = np.sqrt(s2 * np.diag(np.linalg.inv(X.T @ X)))
        np.testing.assert_allclose(phi[a * p:(a + 1) * p], coef, rtol=1e-10)
        np.testing.assert_allclose(se[a * p:(a + 1) * p], sd, rtol=1e-9)


def reml_two_groups(X, y, gr):
    """REML of var(e_i) = c_g(i) for y = X beta + e, maximised by scipy."""
    def nll(t):
        v = np.exp(t)[gr]
        W = 1 / v
        XtWX = X.T @ (X * W[:, None])
        beta = np.linalg.solve(XtWX, X.T @ (W * y))
        r = y - X @ beta
        return 0.5 * (np.sum(np.log(v)) + np.linalg.slogdet(XtWX)[1] + r @ (W * r))
    res = optimize.minimize(nll, np.zeros(2), method="Nelder-Mead",
                            options={"xatol": 1e-10, "fatol": 1e-12, "maxiter": 4000})
    return np.exp(res.x)


def test_vce_two_groups_equals_reml():
    rng = np.random.default_rng(5)
    M, N = 200, 6
    m = 3 * M
    S = rng.normal(size=(m, N))
    group = (np.arange(M) >= 80).astype(np.int32)
    gr = np.repeat(group, 3)
    sd_true = np.where(gr == 0, 1.0, 3.0)  # sigma_w 3x apart
    dw = S @ rng.normal(size=N) + sd_true * rng.normal(size=m)
    h = whiten(N, G=2)
    A, b, wtw, _ = accumulate(h, S, dw, N, G=2, sigma=np.ones(m), group=group)
    lib.igea_whiten_free(h)
    c = np.zeros(2); se = np.zeros(2); red = np.zeros(2); x = np.zeros(N)
    it = ctypes.c_int()
    _lib.call("t", "igea_noise_vce", N, 2, _lib.dptr(A), N, _lib.dptr(b), _lib.dptr(wtw), 1e-12,
              200, _lib.dptr(c), _lib.dptr(se), _lib.dptr(red), _lib.dptr(x), ctypes.byref(it))
    np.testing.assert_allclose(c, reml_two_groups(S, dw, gr), rtol=1e-6)
    assert red.sum() == pytest.approx(m - N, rel=1e-10)  # redundancies add up
    assert abs(c[1] - 9.0) < 3 * se[1] and abs(c[0] - 1.0) < 3 * se[0]


def noise_eqerr(S, dw, sigma=None, cov=None, group=None, G=1, spec=None, phi=None, **slots):
    m, N = S.shape
    opts = _lib.options("eqerr", "t", ("igea_noise_eqerr", "opts"), **slots)
    lam = np.zeros(N); P = np.zeros((N, N)); xh = np.zeros(N); z = np.zeros(N)
    rej = np.zeros(N, dtype=np.int32); info = np.zeros(_capi.STATS_INFO_LEN)
    ar = np.zeros(_capi.NOISE_AR_OUT_LEN); go = np.zeros((G, _capi.NOISE_GROUP_COLS))
    roww = np.zeros(m)
    gr = None if group is None else np.ascontiguousarray(group, dtype=np.int32)
    _lib.call("t", "igea_noise_eqerr", m, N, _lib.dptr(np.asfortranarray(S)), m, _lib.dptr(dw),
              _lib.dptr(sigma), 1, _lib.dptr(None if cov is None else cov.ravel().copy()),
              _lib.iptr(gr), G, _lib.dptr(spec), _lib.dptr(phi), _lib.dptr(opts),
              _lib.dptr(lam), _lib.dptr(P), N, _lib.dptr(xh), _lib.dptr(z), _lib.iptr(rej),
              _lib.dptr(info), _lib.dptr(ar), _lib.dptr(go), _lib.dptr(roww))
    return dict(lam=lam, P=P, xhat=xh, z=z, info=info, ar=ar, groups=go, row_w=roww)


def test_noise_eqerr_cov_and_bias_equals_numpy_gls():
    rng = np.random.default_rng(6)
    M, N = 60, 5
    m = 3 * M
    S = rng.normal(size=(m, N)) * 10
    group = (np.arange(M) >= 25).astype(np.int32)
    cov6, full = random_cov(rng, M)
    dw = rng.normal(size=m)
    r = noise_eqerr(S, dw, cov=cov6, group=group, G=2, correction=0, group_bias=1,
                    lambda_test=1e-3, noise_tol=1e-10)
    # numpy: K block diagonal, bias columns (group, axis) indicators, the
    # bias block eliminated (one group's scale: equal weights)
    gr = np.repeat(group, 3)
    B = np.zeros((m, 6))
    for g in range(2):
        for a in range(3):
            B[(gr == g) & (np.arange(m) % 3 == a), 3 * g + a] = 1
    Ki = np.linalg.inv(linalg.block_diag(*full))
    X = np.hstack([S, B])
    Afull, bfull = X.T @ Ki @ X, X.T @ Ki @ dw
    # the two groups get Helmert scales c_g: weights 1/c_g
    c = r["groups"][:, 0]
    W = np.diag(1 / c[gr])
    Lk = np.linalg.cholesky(np.linalg.inv(Ki))
    Xw, yw = np.linalg.solve(Lk, X), np.linalg.solve(Lk, dw)
    Afull = Xw.T @ W @ Xw
    bfull = Xw.T @ W @ yw
    Att, Atn, Ann = Afull[:N, :N], Afull[:N, N:], Afull[N:, N:]
    Ared = Att - Atn @ np.linalg.solve(Ann, Atn.T)
    bred = bfull[:N] - Atn @ np.linalg.solve(Ann, bfull[N:])
    lam, V = np.linalg.eigh(Ared)
    lam, V = lam[::-1], V[:, ::-1]
    np.testing.assert_allclose(r["lam"], lam, rtol=1e-9)
    np.testing.assert_allclose(np.abs(r["xhat"]), np.abs(V.T @ bred / lam), rtol=1e-7, atol=1e-10)
    # the Helmert scales satisfy the REML/Helmert fixed point in numpy
    beta = np.linalg.lstsq(np.sqrt(W) @ Xw, np.sqrt(W) @ yw, rcond=None)[0]
    H = Xw @ np.linalg.solve(Xw.T @ W @ Xw, Xw.T @ W)
    e = yw - Xw @ beta
    for g in range(2):
        rg = gr == g
        red = rg.sum() - np.trace(H[np.ix_(rg, rg)])
        assert c[g] == pytest.approx(e[rg] @ e[rg] / red, rel=1e-7)
    np.testing.assert_allclose(r["groups"][:, 4:7].ravel(), beta[N:], rtol=1e-7, atol=1e-10)
    assert r["info"][_capi.STATS_INFO_N_NUISANCE] == 6


def test_noise_eqerr_robust_rejects_the_planted_rows():
    rng = np.random.default_rng(7)
    M, N = 300, 6
    m = 3 * M
    S = rng.normal(size=(m, N)) * 5
    dw = S @ rng.normal(size=N) + rng.normal(size=m)
    bad = rng.choice(m, 9, replace=False)
    dw[bad] += 30 * np.where(rng.random(9) < 0.5, -1, 1)
    # alpha_0 = 1e-6 per row: a false rejection among 900 rows has
    # probability below 900e-6
    r = noise_eqerr(S, dw, sigma=np.ones(m), robust=1, robust_alpha=1e-6)
    assert set(np.flatnonzero(r["row_w"])) == set(bad)
    assert np.all(np.abs(r["row_w"][bad]) > r["info"][_capi.STATS_INFO_ROBUST_CRIT])
    # z_(1 - 0.5e-6) = 4.891638475698 (scipy.stats.norm.isf(0.5e-6))
    assert r["info"][_capi.STATS_INFO_ROBUST_CRIT] == pytest.approx(4.891638475698, rel=1e-9)
    # the cleaned fit equals the plain one on the kept rows alone
    keep = np.ones(m, bool)
    keep[bad] = False
    ref = noise_eqerr(S[keep], dw[keep], sigma=np.ones(keep.sum()))
    np.testing.assert_allclose(r["lam"], ref["lam"], rtol=1e-10)
    np.testing.assert_allclose(r["xhat"], ref["xhat"], rtol=1e-8, atol=1e-12)


def test_noise_eqerr_estimates_phi():
    rng = np.random.default_rng(8)
    M, N = 2000, 4
    m = 3 * M
    S = rng.normal(size=(m, N))
    e = rng.normal(size=(M, 3))
    for t in range(1, M):
        e[t] = 0.9 * e[t - 1] + np.sqrt(1 - 0.81) * e[t]
    dw = S @ rng.normal(size=N) + e.ravel()
    r = noise_eqerr(S, dw, sigma=np.ones(m), ar=1, ar_estimate=1)
    phi, se = r["ar"][[0, 3, 6]], r["ar"][[9, 12, 15]]
    assert np.all(np.abs(phi - 0.9) < 4 * se) and np.all(se < 0.02)
    assert r["info"][_capi.STATS_INFO_NOISE_CONVERGED] == 1
    # the same job with phi given as the estimate: the same whitening
    given = noise_eqerr(S, dw, sigma=np.ones(m), phi=np.array([phi[0], phi[1], phi[2]]),
                        ar=1)
    np.testing.assert_allclose(given["lam"], r["lam"], rtol=1e-3)


def test_eqerr_run_refuses_the_noise_options():
    opts = _lib.options("eqerr", "t", ("igea_eqerr_run", "opts"), ar=1)
    assert lib.igea_eqerr_check_opts(_lib.dptr(opts)) == 0
    opts[_capi.EQERR_OPT_AR] = 4
    assert lib.igea_eqerr_check_opts(_lib.dptr(opts)) == 1 + _capi.EQERR_OPT_AR


def test_python_and_driver_cov_equal_numpy_gls(tmp_path):
    import json
    import os
    import subprocess

    import igea
    rng = np.random.default_rng(9)
    M, N = 50, 4
    m = 3 * M
    S = rng.normal(size=(m, N)) * 10
    dw = rng.normal(size=m)
    cov6, full = random_cov(rng, M)
    r = igea.eqerr(S, dw, None, cov=full, correction=False, lambda_test=1e-3)
    Ki = np.linalg.inv(linalg.block_diag(*full))
    lam = np.linalg.eigvalsh(S.T @ Ki @ S)[::-1]
    np.testing.assert_allclose(r.eigenvalues, lam, rtol=1e-10)
    np.savetxt(tmp_path / "S.txt", S)
    np.savetxt(tmp_path / "dw.txt", dw)
    np.savetxt(tmp_path / "cov.txt", cov6)
    out = subprocess.run([os.environ.get("IGEA_DRIVER", "build/bin/igea"), "eqerr", "--S",
                          str(tmp_path / "S.txt"), "--dw", str(tmp_path / "dw.txt"), "--cov",
                          str(tmp_path / "cov.txt"), "--no-correction", "--lambda-test", "1e-3",
                          "--json"], capture_output=True, text=True)
    assert out.returncode in (0, 1), out.stderr
    doc = json.loads(out.stdout)
    np.testing.assert_allclose(doc["eigenvalues"], lam, rtol=1e-10)
    assert doc["passed"] == r.passed and doc["n_test"] == r.n_test
    with pytest.raises(ValueError, match="sigma, cov"):
        igea.eqerr(S, dw, 0.01, cov=full)


def test_montecarlo_two_stations_judged_with_groups():
    import igea
    rng = np.random.default_rng(10)
    m, N = 300, 3
    S = rng.normal(size=(m, N)) * 50
    r = igea.montecarlo(S, 0.01, 200, group_split=0.5, sigma_w=1.0, sigma_w2=3.0,
                        judge_noise=True, threads=1)
    # each flight: two scales, each within 3 se with probability ~0.997;
    # 99 % Wilson interval of 200 flights at p = 0.995 reaches below 0.97
    assert r.scale_covered >= 0.95 * 200
    assert r.flights == 200


def dense_whitening(S, dw, spec, sigma, cov6, group, phi, p):
    """The whitened rows [S~ w~] written densely: stage 1 by each epoch's
    inverse Cholesky factor (or 1/sigma), stage 2 per axis and segment (a
    change of group) by the inverse Cholesky factor of the AR(p) Toeplitz
    autocorrelation (from the MA(infinity) weights)."""
    m = S.shape[0]
    M = m // 3
    Y = np.column_stack([S * spec, dw])
    U = np.empty_like(Y)
    for e in range(M):
        r = slice(3 * e, 3 * e + 3)
        if cov6 is not None:
            c = cov6[e]
            C = np.array([[c[0], c[1], c[3]], [c[1], c[2], c[4]], [c[3], c[4], c[5]]])
            U[r] = np.linalg.solve(np.linalg.cholesky(C), Y[r])
        else:
            U[r] = Y[r] / sigma[r][:, None]
    if p == 0:
        return U
    V = np.empty_like(U)
    seg = np.concatenate([[0], np.cumsum(group[1:] != group[:-1])])
    for a in range(3):
        # MA(infinity) weights: the impulse response of 1 / (1 - sum phi_k B^k)
        psi = signal.lfilter([1.0], np.r_[1.0, -phi[a]], np.r_[1.0, np.zeros(3999)])
        rho = np.array([psi[:4000 - k] @ psi[k:] for k in range(M)])
        rho /= rho[0]
        for s in np.unique(seg):
            e = np.flatnonzero(seg == s)
            i = 3 * e + a
            L = np.linalg.cholesky(linalg.toeplitz(rho[:len(e)]))
            V[i] = np.linalg.solve(L, U[i])
    return V


def test_whitening_random_configurations_equal_dense():
    """Streamed whitening over random configurations (layouts, sigma or 3x3
    covariance, masks, groups coming back, p = 0..3, block splits, specs)
    against the dense transform: sums per group and the whitened rows."""
    rng = np.random.default_rng(42)
    for trial in range(40):
        M = int(rng.integers(2, 40))
        m, N, p, G = 3 * M, int(rng.integers(1, 6)), trial % 4, int(rng.integers(1, 4))
        layout = int(rng.integers(2))
        S = rng.normal(size=(m, N))
        dw = rng.normal(size=m)
        spec = rng.uniform(0.5, 2, N) if rng.random() < 0.5 else None
        use_cov = rng.random() < 0.5
        cov6 = random_cov(rng, M)[0] if use_cov else None
        sigma = None if use_cov else rng.uniform(0.5, 2, m)
        group = np.minimum(np.cumsum(rng.random(M) < 0.1) % G, G - 1).astype(np.int32)
        mask = (rng.random(m) < 0.1).astype(np.int32) if rng.random() < 0.5 else None
        phi = np.array([[0.5, 0.3, -0.2][:p]] * 3) * np.array([[1.0], [0.8], [-0.6]])
        V = dense_whitening(S, dw, np.ones(N) if spec is None else spec, sigma, cov6, group,
                            phi, p)
        h = whiten(N, p, phi.ravel() if p else None, G)
        A = np.zeros((G, N, N)); b = np.zeros((G, N)); wtw = np.zeros(2 * G)
        white = np.zeros((m, N + 1))
        cuts = np.unique(np.r_[0, np.sort(rng.integers(0, M + 1, 3)), M]) * 3
        for r0, r1 in zip(cuts[:-1], cuts[1:]):
            n = r1 - r0
            Sb = S[r0:r1]
            Sb, lds = (np.asfortranarray(Sb), max(1, n)) if layout == 0 else \
                (np.ascontiguousarray(Sb), N)
            wb = np.zeros((N + 1, n))
            _lib.call("t", "igea_whiten_accumulate", h, layout, n, _lib.dptr(Sb), lds,
                      _lib.dptr(np.ascontiguousarray(dw[r0:r1])),
                      _lib.dptr(None if sigma is None else np.ascontiguousarray(sigma[r0:r1])), 1,
                      _lib.dptr(None if cov6 is None else np.ascontiguousarray(cov6[r0 // 3:r1 // 3].ravel())),
                      _lib.iptr(np.ascontiguousarray(group[r0 // 3:r1 // 3])),
                      _lib.iptr(None if mask is None else np.ascontiguousarray(mask[r0:r1])),
                      _lib.dptr(spec), _lib.dptr(A), N, _lib.dptr(b), _lib.dptr(wtw),
                      _lib.dptr(wb), None)
            white[r0:r1] = wb.T
        lib.igea_whiten_free(h)
        np.testing.assert_allclose(white, V, rtol=1e-10, atol=1e-10, err_msg=str(trial))
        keep = np.ones(m, bool) if mask is None else mask == 0
        gr = np.repeat(group, 3)
        for g in range(G):
            r = keep & (gr == g)
            np.testing.assert_allclose(A[g], V[r, :N].T @ V[r, :N], rtol=1e-10, atol=1e-10)
            np.testing.assert_allclose(b[g], V[r, :N].T @ V[r, N], rtol=1e-10, atol=1e-10)
            assert wtw[2 * g] == pytest.approx(V[r, N] @ V[r, N], rel=1e-10, abs=1e-12)
            assert wtw[2 * g + 1] == r.sum()
