"""eqerr with the whole K of igea dw: the diagonal blocks K_ee and the cross
blocks X_e = Cov(dW_e, dW_f), f > e (igea_whiten_accumulate_xcov,
igea_noise_eqerr_xcov, `igea eqerr --cov K --xcov X`, igea.eqerr(cov=,
xcov=); docs/eqerr.md "The whole K of igea dw").

Checked against computations written here: the full K built as a dense
3M x 3M matrix in numpy, its Cholesky factor by numpy, the generalised
least squares and the seed's equivalent errors from numpy's
eigendecomposition; a Monte Carlo of the residual chi-square (the
whitened residual sum of squares of the full-rank fit against
chi2(m - rank)) with tracking errors drawn from the full K, against the
99 % Clopper-Pearson interval."""
import ctypes
import json
import os
import subprocess

import numpy as np
import pytest
from scipy import stats

import igea
from igea import _capi, _lib
from igea.envfun import default_terms
from test_dw_k import full_k, short_flight
from test_eqerr_verdict import clopper_pearson

lib = _lib.lib


def blocks(cov):
    """igea.dw's cov rows (xx xy xz yy yz zz) as 3 x 3 matrices."""
    return np.array([[[r[0], r[1], r[2]], [r[1], r[3], r[4]], [r[2], r[4], r[5]]] for r in cov])


def low6(Kb):
    """3 x 3 blocks as the lower triangles by rows (igea eqerr --cov's order)."""
    return np.stack([Kb[:, 0, 0], Kb[:, 1, 0], Kb[:, 1, 1], Kb[:, 2, 0], Kb[:, 2, 1],
                     Kb[:, 2, 2]], axis=1)


def dense(Kb, X):
    n = len(Kb)
    K = np.zeros((3 * n, 3 * n))
    for e in range(n):
        K[3 * e:3 * e + 3, 3 * e:3 * e + 3] = Kb[e]
        K[3 * e:3 * e + 3, 3 * e + 3:] = np.tile(X[e], (1, n - e - 1))
        K[3 * e + 3:, 3 * e:3 * e + 3] = np.tile(X[e].T, (n - e - 1, 1))
    return K


def random_k(rng, M, walk):
    """A K of igea dw's structure: dW_e = E_e eps_e + sum_(j<e) G_j eps_j,
    eps_j independent with a random 6 x 6 covariance Q_j: K_ee = R_e + E Q E',
    X_e = R_e + E Q G', R_e = sum_(j<e) G_j Q_j G_j' (walk scales G)."""
    Kb, X, R = np.empty((M, 3, 3)), np.empty((M, 3, 3)), np.zeros((3, 3))
    for e in range(M):
        F = rng.normal(size=(6, 6))
        Q = F @ F.T + 0.5 * np.eye(6)
        E, G = rng.normal(size=(3, 6)), walk * rng.normal(size=(3, 6))
        Kb[e] = R + E @ Q @ E.T
        X[e] = R + E @ Q @ G.T
        R = R + G @ Q @ G.T
    return Kb, X


def accumulate(S, dw, Kb, X, spec=None, cuts=(), rowmajor=False, mask=None):
    """igea_whiten_accumulate_xcov over the epoch blocks cut at `cuts`."""
    m, N = S.shape
    M = m // 3
    h = ctypes.c_void_p()
    _lib.call("t", "igea_whiten_create", N, 0, None, 1, ctypes.byref(h))
    A, b, wtw, white = np.zeros((N, N)), np.zeros(N), np.zeros(2), np.zeros((N + 1, m))
    c6, x9 = low6(Kb), X.reshape(M, 9)
    edges = [0, *cuts, M]
    try:
        for e0, e1 in zip(edges[:-1], edges[1:]):
            r0, r1 = 3 * e0, 3 * e1
            Sb = np.ascontiguousarray(S[r0:r1]) if rowmajor else np.asfortranarray(S[r0:r1])
            wb = np.zeros((N + 1, r1 - r0))
            mk = None if mask is None else np.ascontiguousarray(mask[r0:r1], dtype=np.intc)
            _lib.call("t", "igea_whiten_accumulate_xcov", h,
                      _capi.ROWMAJOR if rowmajor else _capi.COLMAJOR, r1 - r0, _lib.dptr(Sb),
                      N if rowmajor else max(1, r1 - r0), _lib.dptr(np.ascontiguousarray(dw[r0:r1])),
                      _lib.dptr(np.ascontiguousarray(c6[e0:e1].ravel())),
                      _lib.dptr(np.ascontiguousarray(x9[e0:e1].ravel())), _lib.iptr(mk),
                      _lib.dptr(spec), _lib.dptr(A), N, _lib.dptr(b), _lib.dptr(wtw),
                      _lib.dptr(wb), None)
            white[:, r0:r1] = wb
    finally:
        lib.igea_whiten_free(h)
    return A, b, wtw, white.T


@pytest.mark.parametrize("seed,walk", [(1, 0.0), (2, 0.4), (3, 2.0), (4, 8.0)])
def test_random_structured_k_equals_dense_gls(seed, walk):
    """Random K of igea dw's structure (the random walk from nothing to far
    beyond the white part): the sums equal S' K^-1 S, S' K^-1 dw,
    dw' K^-1 dw of the dense K to 1e-10, in one block and cut anywhere,
    both layouts, and the whitened rows are L^-1 [S D, dw] with L the
    Cholesky factor of the dense K (the unique lower-triangular whitening
    with a positive diagonal: each epoch's innovation given the earlier)."""
    rng = np.random.default_rng(seed)
    M, N = 31, 5
    m = 3 * M
    Kb, X = random_k(rng, M, walk)
    K = dense(Kb, X)
    S, dw, spec = rng.normal(size=(m, N)), rng.normal(size=m), rng.uniform(0.5, 2, N)
    SD = S * spec
    An, bn, wn = SD.T @ np.linalg.solve(K, SD), SD.T @ np.linalg.solve(K, dw), dw @ np.linalg.solve(K, dw)
    Zn = np.linalg.solve(np.linalg.cholesky(K), np.column_stack([SD, dw]))
    for cuts, rowmajor in [((), False), ((1, 2, 13, 30), False), ((7, 8, 20), True)]:
        A, b, wtw, Z = accumulate(S, dw, Kb, X, spec, cuts, rowmajor)
        np.testing.assert_allclose(A, An, rtol=1e-10, atol=1e-10 * np.abs(An).max())
        np.testing.assert_allclose(b, bn, rtol=1e-10, atol=1e-10 * np.abs(bn).max())
        assert wtw[0] == pytest.approx(wn, rel=1e-10) and wtw[1] == m
        np.testing.assert_allclose(Z, Zn, rtol=1e-10, atol=1e-10 * np.abs(Zn).max())
    # masked rows leave the sums, not the recursion
    mask = np.zeros(m, dtype=int)
    mask[[0, 17, m - 2]] = 1
    A, b, wtw, Z = accumulate(S, dw, Kb, X, spec, (4, 19), mask=mask)
    keep = mask == 0
    np.testing.assert_allclose(A, Zn[keep, :N].T @ Zn[keep, :N], rtol=1e-10,
                               atol=1e-10 * np.abs(An).max())
    assert wtw[0] == pytest.approx(Zn[keep, N] @ Zn[keep, N], rel=1e-10) and wtw[1] == m - 3


def raw_case(tmp_path=None):
    """The short raw flight of test_dw_k (40 s, tracking at 0.9 s with a
    4-s gap, 30 m and 1e-3 m/s, correlations 0.5 and 0.2), its dw, K and
    the 21 default platform terms' S in spec units at the epochs."""
    raw = short_flight(30.0, 1e-3, "ecef")
    d = igea.dw(raw.telemetry, raw.tracking, **raw.dw_kwargs())
    traj = igea.reference_trajectory(40.0, 50.0, system="platform")
    S = igea.envfun(traj, default_terms("platform"), raw.tracking[:, 0], system="platform",
                    spec="default", lat=raw.lat, lon=raw.lon, height=raw.height,
                    azimuth=raw.azimuth)
    return raw, d, S


def numpy_verdict(S, dw, K, lambda_test, alpha):
    """The seed's test (no tracking-accuracy correction) on the GLS with the
    dense K: eigenvalues, |equivalent errors| p_i' b / lambda_i, z and T."""
    L = np.linalg.cholesky(K)
    Sw, ww = np.linalg.solve(L, S), np.linalg.solve(L, dw)
    lam, P = np.linalg.eigh(Sw.T @ Sw)
    lam, P = lam[::-1], P[:, ::-1]
    xh = P.T @ (Sw.T @ ww) / lam
    t = lam >= lambda_test
    z = xh[t] / np.sqrt(1 + 1 / lam[t])
    T = float(z @ z)
    return lam, np.abs(xh), np.abs(z), T, T < stats.chi2.ppf(1 - alpha, t.sum())


def test_raw_flight_verdict_equals_dense_gls(tmp_path):
    """A raw flight whose cross blocks are a tenth of K's largest entries:
    igea.eqerr(cov=, xcov=) and `igea eqerr --cov K.txt --xcov X.txt` (the
    files of igea dw --k-out --xcov-out) give the eigenvalues, equivalent
    errors, z, T and the verdict of the numpy GLS with the dense K, to
    1e-10; with the tracking-accuracy correction on, the same result as
    igea.eqerr on the rows whitened by numpy's Cholesky factor of K."""
    raw, d, S = raw_case()
    Kb = blocks(d.cov)
    K = full_k(d)
    off = max(np.abs(d.xcov[e]).max() for e in range(d.n_epochs - 1)) / np.abs(K).max()
    assert off > 0.05
    # the simulated tracking is exact: errors drawn from K, terms at 0.3 x spec
    L = np.linalg.cholesky(K)
    rng = np.random.default_rng(5)
    dw = d.dw + L @ rng.standard_normal(L.shape[0]) + S @ (0.3 * rng.standard_normal(S.shape[1]))
    # the whitened normal equations
    A, b, wtw, _ = accumulate(S, dw, Kb, d.xcov, cuts=(5, 6, 20))
    An, bn = S.T @ np.linalg.solve(K, S), S.T @ np.linalg.solve(K, dw)
    np.testing.assert_allclose(A, An, rtol=1e-10, atol=1e-10 * np.abs(An).max())
    np.testing.assert_allclose(b, bn, rtol=1e-10, atol=1e-10 * np.abs(bn).max())
    assert wtw[0] == pytest.approx(dw @ np.linalg.solve(K, dw), rel=1e-10)
    lam, axh, az, T, passed = numpy_verdict(S, dw, K, 10.0, 0.01)
    r = igea.eqerr(S, dw, None, cov=Kb, xcov=d.xcov, correction=False)
    np.testing.assert_allclose(r.eigenvalues, lam, rtol=1e-10, atol=1e-10 * lam[0])
    t = lam >= 10.0
    np.testing.assert_allclose(np.abs(r.equiv_err[t]), axh[t], rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(np.abs(r.z), az, rtol=1e-10, atol=1e-12)
    assert r.chi2 == pytest.approx(T, rel=1e-10) and r.passed == passed
    assert r.n_test == t.sum() >= 3
    # the diagonal blocks alone: another GLS (the one the test used to run)
    rb = igea.eqerr(S, dw, None, cov=Kb, correction=False)
    assert abs(rb.chi2 - T) > 1e-6 * T
    # with the correction, as the plain route on numpy's whitened rows; the
    # scale comes from the eight small eigenvalues (down to 1e-8 against
    # lambda_1 = 1.6e13), which either whitening resolves only to about
    # eps lambda_1 / lambda: a few 1e-9 here
    rc = igea.eqerr(S, dw, None, cov=Kb, xcov=d.xcov)
    rd = igea.eqerr(np.linalg.solve(L, S), np.linalg.solve(L, dw), 1.0)
    assert rc.n_small == rd.n_small >= 2 and rc.flag == rd.flag
    for k in ("chi2", "scale", "n_test", "passed"):
        assert getattr(rc, k) == pytest.approx(getattr(rd, k), rel=1e-7), k
    np.testing.assert_allclose(np.abs(rc.z), np.abs(rd.z), rtol=1e-7, atol=1e-12)
    # the driver, from the files igea dw writes
    tel, trk = tmp_path / "tel.txt", tmp_path / "trk.txt"
    np.savetxt(tel, raw.telemetry, fmt="%.17g")
    np.savetxt(trk, raw.tracking, fmt="%.17g")
    np.savetxt(tmp_path / "S.txt", S, fmt="%.17g")
    np.savetxt(tmp_path / "dwx.txt", dw - d.dw, fmt="%.17g")
    drv = os.environ["IGEA_DRIVER"]
    out = subprocess.run([drv, "dw", "--telemetry", str(tel), "--tracking", str(trk),
                          "--lat", repr(raw.lat), "--lon", repr(raw.lon), "--height",
                          repr(raw.height), "--azimuth", repr(raw.azimuth), "--frame", "ecef",
                          "--system", "platform", "--out", str(tmp_path / "dw.txt"), "--k-out",
                          str(tmp_path / "K.txt"), "--xcov-out", str(tmp_path / "X.txt")],
                         capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    dwf = np.loadtxt(tmp_path / "dw.txt") + np.loadtxt(tmp_path / "dwx.txt")
    np.savetxt(tmp_path / "dw2.txt", dwf, fmt="%.17g")
    base = [drv, "eqerr", "--S", str(tmp_path / "S.txt"), "--dw", str(tmp_path / "dw2.txt"),
            "--cov", str(tmp_path / "K.txt"), "--no-correction"]
    out = subprocess.run(base + ["--xcov", str(tmp_path / "X.txt"), "--json"],
                         capture_output=True, text=True)
    assert out.returncode in (0, 1), out.stderr
    doc = json.loads(out.stdout)
    np.testing.assert_allclose(doc["eigenvalues"], lam, rtol=1e-10, atol=1e-10 * lam[0])
    assert doc["chi2"] == pytest.approx(T, rel=1e-10) and doc["passed"] == passed
    out = subprocess.run(base + ["--xcov", str(tmp_path / "X.txt")], capture_output=True,
                         text=True)
    assert "the whole K: cross blocks between epochs from" in out.stdout


def test_refusals(tmp_path):
    """--xcov and xcov= need the diagonal blocks, and are refused with AR
    noise and with groups; a cross-block file in another order than igea dw
    writes (transposed) is refused by its header; the library refuses AR
    options (-9) and a differenced covariance that is not positive definite
    (IGEA_ESINGULAR naming the epoch)."""
    raw, d, S = raw_case()
    Kb = blocks(d.cov)
    with pytest.raises(ValueError, match="xcov: the cross blocks need cov"):
        igea.eqerr(S, d.dw, 0.01, xcov=d.xcov)
    with pytest.raises(ValueError, match="AR noise on top"):
        igea.eqerr(S, d.dw, None, cov=Kb, xcov=d.xcov, ar=1)
    with pytest.raises(ValueError, match="one scale per group"):
        igea.eqerr(S, d.dw, None, cov=Kb, xcov=d.xcov, groups=np.zeros(d.n_epochs, int))
    with pytest.raises(ValueError, match="xcov"):
        igea.eqerr(S, d.dw, None, cov=Kb, xcov=d.xcov[:-1])
    # robust and bias columns combine with the cross blocks: a 30-sigma
    # outlier planted in one row is rejected first; a rejected row is an
    # additive outlier (its dummy column whitened with the data), so the
    # later axes of its epoch, which its innovation reached through the
    # axes' correlation, are clean again (|w| 17-22 when only the whitened
    # row was dropped); any other rejection is a chance one of the 117 rows
    # at |w| > 3.29 (about 11 % of flights), well below the outlier's w
    L = np.linalg.cholesky(full_k(d))
    rng = np.random.default_rng(8)
    dw = d.dw + L @ rng.standard_normal(L.shape[0])
    i = 61
    dw[i] += 30.0 * np.sqrt(Kb[i // 3, i % 3, i % 3])
    r = igea.eqerr(S, dw, None, cov=Kb, xcov=d.xcov, robust=True, group_bias=True)
    assert r.ar_order == 0 and len(r.groups) == 1
    rows = [o["row"] for o in r.rejected_rows]
    assert rows[0] == i and r.rejected_rows[0]["w"] > 15 and i + 1 not in rows
    assert all(abs(o["w"]) < 5 for o in r.rejected_rows[1:])
    np.savetxt(tmp_path / "S.txt", S, fmt="%.17g")
    np.savetxt(tmp_path / "dw.txt", d.dw, fmt="%.17g")
    np.savetxt(tmp_path / "K.txt", low6(Kb), fmt="%.17g")
    X9 = d.xcov.reshape(-1, 9)
    names = "names x_xx x_xy x_xz x_yx x_yy x_yz x_zx x_zy x_zz"
    np.savetxt(tmp_path / "X.txt", X9, fmt="%.17g", header=names)
    np.savetxt(tmp_path / "Xt.txt", d.xcov.transpose(0, 2, 1).reshape(-1, 9), fmt="%.17g",
               header="names x_xx x_yx x_zx x_xy x_yy x_zy x_xz x_yz x_zz")
    drv = os.environ["IGEA_DRIVER"]
    base = [drv, "eqerr", "--S", str(tmp_path / "S.txt"), "--dw", str(tmp_path / "dw.txt")]

    def run(*args):
        return subprocess.run(base + list(args), capture_output=True, text=True)

    out = run("--cov", str(tmp_path / "K.txt"), "--xcov", str(tmp_path / "Xt.txt"))
    assert out.returncode == 65 and "another order than --xcov reads" in out.stderr
    assert "transposed" in out.stderr
    out = run("--sigma", "0.01", "--xcov", str(tmp_path / "X.txt"))
    assert out.returncode == 64 and "--xcov FILE needs --cov" in out.stderr
    out = run("--cov", str(tmp_path / "K.txt"), "--xcov", str(tmp_path / "X.txt"), "--ar", "1")
    assert out.returncode == 64 and "AR noise on top" in out.stderr
    np.savetxt(tmp_path / "g.txt", np.zeros(d.n_epochs, int), fmt="%d")
    out = run("--cov", str(tmp_path / "K.txt"), "--xcov", str(tmp_path / "X.txt"), "--groups",
              str(tmp_path / "g.txt"))
    assert out.returncode == 64 and "--groups" in out.stderr
    out = run("--cov", str(tmp_path / "K.txt"), "--xcov", str(tmp_path / "K.txt"))
    assert out.returncode == 65 and "needs one line of the 9" in out.stderr
    # a cross block too large for one positive definite K: the epoch is named
    bad = X9.copy()
    bad[10] *= 4.0
    np.savetxt(tmp_path / "Xb.txt", bad, fmt="%.17g", header=names)
    out = run("--cov", str(tmp_path / "K.txt"), "--xcov", str(tmp_path / "Xb.txt"))
    assert out.returncode == 65 and "is not positive definite" in out.stderr
    e = int(out.stderr.split("the covariance of epoch ")[1].split()[0])
    assert e >= 11
    # the library: AR options refused
    m, N = S.shape
    opts = _lib.options("eqerr", "t", ("igea_noise_eqerr", "opts"), ar=1)
    outs = [np.zeros(N), np.zeros((N, N)), N, np.zeros(N), np.zeros(N), np.zeros(N, np.intc),
            np.zeros(_capi.STATS_INFO_LEN)]
    st = lib.igea_noise_eqerr_xcov(m, N, _lib.dptr(np.asfortranarray(S)), m, _lib.dptr(d.dw),
                                   _lib.dptr(np.ascontiguousarray(low6(Kb).ravel())),
                                   _lib.dptr(np.ascontiguousarray(X9.ravel())), None,
                                   _lib.dptr(opts), *[o if isinstance(o, int) else
                                                      (_lib.iptr(o) if o.dtype == np.intc
                                                       else _lib.dptr(o)) for o in outs],
                                   None, None, None)
    assert st == -9


def blocks_of(S, dw, Kb, X, whole):
    """The library's sums for one flight: the whole K or the diagonal blocks."""
    m, N = S.shape
    if whole:
        return accumulate(S, dw, Kb, X)[:3]
    h = ctypes.c_void_p()
    _lib.call("t", "igea_whiten_create", N, 0, None, 1, ctypes.byref(h))
    A, b, wtw = np.zeros((N, N)), np.zeros(N), np.zeros(2)
    try:
        _lib.call("t", "igea_whiten_accumulate", h, _capi.COLMAJOR, m,
                  _lib.dptr(np.asfortranarray(S)), m, _lib.dptr(dw), None, 1,
                  _lib.dptr(np.ascontiguousarray(low6(Kb).ravel())), None, None, None,
                  _lib.dptr(A), N, _lib.dptr(b), _lib.dptr(wtw), None, None)
    finally:
        lib.igea_whiten_free(h)
    return A, b, wtw


def test_residual_chi2_size_monte_carlo():
    """The bench/dw_k_cost.py case where the diagonal blocks cost most: the
    120-s platform flight of the tutorial, 21 default terms at their specs,
    tracking 100 m and 0.003 m/s (correlations 0.5 and 0.2). 2,000 flights:
    the terms drawn at their specs, the tracking errors from the full K
    (numpy's Cholesky factor). The residual chi-square T = w~'w~ - b' A^+ b
    of the library's whitened sums against chi2_0.05(m - rank): with the
    whole K its rejection rate's 99 % Clopper-Pearson interval holds 5 %
    (T is then exactly chi-square); with the diagonal blocks the interval
    lies far below (the documented 0.15 % of Satterthwaite's approximation:
    the test is conservative)."""
    traj = igea.reference_trajectory(120.0, 50.0, system="platform")
    ep = np.arange(1.0, 121.0)
    acc, _ = igea.track_errors(np.full(ep.size, 0.003), 100.0, corr=0.5, cross=0.2)
    raw = igea.simulate_raw(traj, ["acc_bias_x"], ep, system="platform", x=[0.0], noise=False,
                            acc=acc)
    d = igea.dw(raw.telemetry, raw.tracking, **raw.dw_kwargs())
    S = igea.envfun(traj, default_terms("platform"), ep, system="platform", spec="default",
                    lat=raw.lat, lon=raw.lon, height=raw.height, azimuth=raw.azimuth)
    Kb = blocks(d.cov)
    L = np.linalg.cholesky(full_k(d))
    m, N = S.shape
    rng = np.random.default_rng(20250612)
    n, rej = 2000, {True: 0, False: 0}
    for _ in range(n):
        dw = S @ rng.standard_normal(N) + L @ rng.standard_normal(m)
        for whole in (True, False):
            A, b, wtw = blocks_of(S, dw, Kb, d.xcov, whole)
            x, _, rank, _ = np.linalg.lstsq(A, b, rcond=1e-12)
            T = wtw[0] - b @ x
            rej[whole] += T >= stats.chi2.ppf(0.95, m - rank)
    lo, hi = clopper_pearson(rej[True], n, 0.99)
    lob, hib = clopper_pearson(rej[False], n, 0.99)
    print("residual chi-square at 5 %%, %d flights: whole K %.4f [%.4f, %.4f], diagonal "
          "blocks %.4f [%.4f, %.4f]" % (n, rej[True] / n, lo, hi, rej[False] / n, lob, hib))
    assert lo <= 0.05 <= hi
    assert hib < 0.02
