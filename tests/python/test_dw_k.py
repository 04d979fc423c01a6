"""K, the covariance of dW, with the tracking position errors' effect through
the gravity integral (igea_dw_compute_k, `igea dw --k-out --xcov-out`,
docs/pipeline.md section 4.2).

The checks are independent of the library's propagation formula:
* an independent linearisation: the Jacobian J of the whole dw map by
  central differences of igea.dw in every tracked value (the map is affine
  in the tracking errors up to gravity's curvature over the steps, which
  central differences cancel to third order), K = J P J' in numpy with P
  the block-diagonal tracking covariance: every block of the library's K,
  diagonal and between epochs, to 1e-8 of the largest entry;
* a numpy Monte Carlo: tracking errors drawn per epoch from P_e by numpy
  (Cholesky), the whole dw recomputed; q = z' K^-1 z of each draw is
  chi-square with 3 n degrees of freedom when K is right, so the sum over
  N draws lies in the central 99.9 % of chi-square(3 n N); K without the
  gravity integral's part lies far outside it;
* the cost of eqerr --cov's block-diagonal K (the diagonal blocks of the
  full K): the chi-square T's mean and variance under the full K
  (trace formulas) and its size by Satterthwaite's approximation, on the
  120-s platform flight of the tutorial (10 m, 0.01 m/s) and at 50 m.
"""
import ctypes
import os
import subprocess

import numpy as np
import pytest
from scipy import stats

import igea
from igea import _lib
from igea.envfun import default_terms
from igea.nav import nav_site

IU = np.triu_indices(6)


def short_flight(sigma_r, sigma_v, frame, duration=40.0):
    """A platform flight of `duration` s at 50 Hz, tracking at 0.9 s from
    0.37 s with a 4-s gap (no epoch on a telemetry record, unequal
    spacing), 28-column tracking with the 6 x 6 covariance of
    igea.track_errors (corr 0.5, cross 0.2), no errors."""
    traj = igea.reference_trajectory(duration, 50.0, system="platform")
    ep = 0.37 + 0.9 * np.arange(int((duration - 1.0) / 0.9))
    ep = ep[(ep < 15.0) | (ep > 19.0)]
    acc, _ = igea.track_errors(np.full(ep.size, sigma_v), sigma_r, corr=0.5, cross=0.2)
    raw = igea.simulate_raw(traj, ["acc_bias_x"], ep, system="platform", x=[0.0], noise=False,
                            frame=frame, acc=acc)
    return raw


def blocks6(trk):
    """The 6 x 6 covariance of each tracking row (columns 7..27)."""
    P = np.zeros((trk.shape[0], 6, 6))
    for e, row in enumerate(trk[:, 7:]):
        B = np.zeros((6, 6))
        B[IU] = row
        P[e] = B + B.T - np.diag(np.diag(B))
    return P


def full_k(d):
    """The full covariance (3 n, 3 n) of the stacked dW from a DwResult:
    cov blocks on the diagonal, xcov[min(e, f)] off it."""
    n = d.n_epochs
    K = np.zeros((3 * n, 3 * n))
    for e, r in enumerate(d.cov):
        K[3 * e:3 * e + 3, 3 * e:3 * e + 3] = [[r[0], r[1], r[2]], [r[1], r[3], r[4]],
                                               [r[2], r[4], r[5]]]
        K[3 * e:3 * e + 3, 3 * e + 3:] = np.tile(d.xcov[e], (1, n - e - 1))
        K[3 * e + 3:, 3 * e:3 * e + 3] = np.tile(d.xcov[e].T, (n - e - 1, 1))
    return K


def old_k(raw, kind=0):
    """The blocks of igea_dw_compute (K without the gravity integral's part)."""
    tel = np.asfortranarray(raw.telemetry)
    trk = np.asfortranarray(raw.tracking)
    n = trk.shape[0]
    site = nav_site(np.radians(raw.lat), np.radians(raw.lon), raw.height,
                    np.radians(raw.azimuth))
    out, cov, bad = np.zeros(3 * n), np.zeros(6 * n), ctypes.c_int()
    fc = 0 if raw.frame == "ecef" else 1
    q = np.array([1.0, 0.0, 0.0, 0.0])
    st = _lib.lib.igea_dw_compute(_lib.dptr(site), 1, kind, _lib.dptr(q), 0.0, tel.shape[0],
                                  _lib.dptr(tel), tel.shape[0], tel.shape[1], fc, n,
                                  _lib.dptr(trk), n, trk.shape[1], _lib.dptr(out),
                                  _lib.dptr(cov), None, ctypes.byref(bad))
    assert st == 0
    K = np.zeros((3 * n, 3 * n))
    for e, r in enumerate(cov.reshape(n, 6)):
        K[3 * e:3 * e + 3, 3 * e:3 * e + 3] = [[r[0], r[1], r[2]], [r[1], r[3], r[4]],
                                               [r[2], r[4], r[5]]]
    return K, out


def jacobian(raw, kw):
    """d dW / d (x y z vx vy vz of every epoch), central differences."""
    trk = raw.tracking
    n = trk.shape[0]
    J = np.zeros((3 * n, 6 * n))
    steps = [10.0] * 3 + [1e-2] * 3
    for e in range(n):
        for c in range(6):
            tp, tm = trk.copy(), trk.copy()
            tp[e, 1 + c] += steps[c]
            tm[e, 1 + c] -= steps[c]
            J[:, 6 * e + c] = (igea.dw(raw.telemetry, tp, **kw).dw -
                               igea.dw(raw.telemetry, tm, **kw).dw) / (2 * steps[c])
    return J


@pytest.mark.parametrize("frame", ["ecef", "le"])
def test_k_against_linearisation(frame):
    """30 m position, 1e-4 m/s velocity sigma (the position's parts, the
    Earth rate's and the gravity integral's, dominate): the library's K,
    every block, equals J P J' to 1e-8 of its largest entry (measured
    2.3e-10); the blocks between epochs (the gravity integral's alone) are
    a sizeable part of it, and K without them is off by as much."""
    raw = short_flight(30.0, 1e-4, frame)
    kw = raw.dw_kwargs()
    d = igea.dw(raw.telemetry, raw.tracking, **kw)
    J = jacobian(raw, kw)
    P = blocks6(raw.tracking)
    n = d.n_epochs
    Pb = np.zeros((6 * n, 6 * n))
    for e in range(n):
        Pb[6 * e:6 * e + 6, 6 * e:6 * e + 6] = P[e]
    K = J @ Pb @ J.T
    Kl = full_k(d)
    big = np.abs(K).max()
    err = np.abs(Kl - K).max() / big
    off = max(np.abs(K[3 * e:3 * e + 3, 3 * e + 3:]).max() for e in range(n - 1)) / big
    Ko, _ = old_k(raw)
    miss = np.abs(Ko - K).max() / big
    print("frame %s: %d epochs, max |K| %.3e, |K_lib - J P J'| %.2e of it; largest block "
          "between epochs %.3f of it; K without the gravity part off by %.3f"
          % (frame, n, big, err, off, miss))
    assert err < 1e-8
    assert off > 0.03 and miss > 0.03
    np.testing.assert_array_equal(d.xcov[-1], 0.0)
    # the navigated kind has no gravity integral: K block-diagonal, J P J'
    kwn = dict(kw, kind="navigated")
    dn = igea.dw(raw.telemetry, raw.tracking, **kwn)
    np.testing.assert_array_equal(dn.xcov, 0.0)
    Jn = jacobian(raw, kwn)
    Kn = Jn @ Pb @ Jn.T
    assert np.abs(full_k(dn) - Kn).max() < 1e-8 * np.abs(Kn).max()


def test_k_monte_carlo():
    """600 draws of the tracking errors by numpy: sum of z' K^-1 z inside
    chi-square(3 n 600)'s central 99.9 % with the library's full K; with
    the blocks of K without the gravity integral's part far outside."""
    raw = short_flight(30.0, 1e-4, "ecef")
    kw = raw.dw_kwargs()
    d = igea.dw(raw.telemetry, raw.tracking, **kw)
    n, N = d.n_epochs, 600
    L = np.linalg.cholesky(blocks6(raw.tracking))
    rng = np.random.default_rng(20240613)
    Ki = np.linalg.inv(full_k(d))
    Koi = np.linalg.inv(old_k(raw)[0])
    q, qo = 0.0, 0.0
    for _ in range(N):
        trk = raw.tracking.copy()
        trk[:, 1:7] += np.einsum("eij,ej->ei", L, rng.standard_normal((n, 6)))
        z = igea.dw(raw.telemetry, trk, **kw).dw - d.dw
        q += z @ Ki @ z
        qo += z @ Koi @ z
    lo, hi = stats.chi2.ppf([0.0005, 0.9995], 3 * n * N)
    print("sum of z' K^-1 z over %d draws: %.0f (full K), %.0f (K without the gravity part); "
          "99.9 %% band [%.0f, %.0f]" % (N, q, qo, lo, hi))
    assert lo < q < hi
    assert not lo < qo < hi


def satterthwaite(S, K, Kj, alpha):
    """Size at nominal alpha of the chi-square T = r' Kj^-1 r (r the GLS
    residual with Kj) when the errors have covariance K: T = sum of
    weighted chi-squares, matched to c chi2(nu) by its mean tr(A) and
    variance 2 tr(A^2), A = R K, R = W - W S (S' W S)^-1 S' W."""
    W = np.linalg.inv(Kj)
    R = W - W @ S @ np.linalg.solve(S.T @ W @ S, S.T @ W)
    A = R @ K
    m, v = np.trace(A), 2 * np.trace(A @ A)
    c, nu = v / (2 * m), 2 * m * m / v
    dof = S.shape[0] - S.shape[1]
    return m, stats.chi2.sf(stats.chi2.ppf(1 - alpha, dof) / c, nu)


@pytest.mark.parametrize("sigma_r,lo,hi", [(10.0, 0.048, 0.051), (50.0, 0.035, 0.048)])
def test_block_diagonal_cost(sigma_r, lo, hi):
    """eqerr --cov takes one 3 x 3 block per epoch: the diagonal blocks of
    the full K. On the tutorial's 120-s platform flight (21 default terms,
    0.01 m/s, correlations 0.5 and 0.2) the chi-square test's size at 5 %
    is then 4.96 % at 10 m and 4.21 % at 50 m (measured; with the full K
    5.00 %): the gravity
    integral's errors form a random walk, mostly absorbed by S's columns,
    so its variance in the diagonal blocks makes the test conservative."""
    traj = igea.reference_trajectory(120.0, 50.0, system="platform")
    ep = np.arange(1.0, 121.0)
    acc, _ = igea.track_errors(np.full(ep.size, 0.01), sigma_r, corr=0.5, cross=0.2)
    raw = igea.simulate_raw(traj, ["acc_bias_x"], ep, system="platform", x=[0.0], noise=False,
                            acc=acc)
    d = igea.dw(raw.telemetry, raw.tracking, **raw.dw_kwargs())
    K = full_k(d)
    Kbd = np.zeros_like(K)
    for e in range(d.n_epochs):
        Kbd[3 * e:3 * e + 3, 3 * e:3 * e + 3] = K[3 * e:3 * e + 3, 3 * e:3 * e + 3]
    site = dict(lat=raw.lat, lon=raw.lon, height=raw.height, azimuth=raw.azimuth)
    S = igea.envfun(traj, default_terms("platform"), ep, system="platform", spec="default",
                    **site)
    mean, size = satterthwaite(S, K, Kbd, 0.05)
    mean_full, size_full = satterthwaite(S, K, K, 0.05)
    print("sigma_r %g m: E T %.2f (dof %d), size at 5 %% %.4f with the diagonal blocks; "
          "%.4f with the full K" % (sigma_r, mean, S.shape[0] - S.shape[1], size, size_full))
    assert abs(size_full - 0.05) < 1e-6
    assert lo < size < hi


def test_driver_xcov(tmp_path):
    """`igea dw --k-out --xcov-out` write the library's blocks (K in eqerr
    --cov's order xx yx yy zx zy zz; X_e row-major)."""
    raw = short_flight(30.0, 1e-3, "ecef", duration=20.0)
    d = igea.dw(raw.telemetry, raw.tracking, **raw.dw_kwargs())
    tel, trk = str(tmp_path / "tel.txt"), str(tmp_path / "trk.txt")
    np.savetxt(tel, raw.telemetry, fmt="%.17g")
    np.savetxt(trk, raw.tracking, fmt="%.17g")
    args = [os.environ["IGEA_DRIVER"], "dw", "--telemetry", tel, "--tracking", trk,
            "--lat", repr(raw.lat), "--lon", repr(raw.lon), "--height", repr(raw.height),
            "--azimuth", repr(raw.azimuth), "--frame", "ecef", "--system", "platform",
            "--out", str(tmp_path / "dw.txt"), "--k-out", str(tmp_path / "K.txt"),
            "--xcov-out", str(tmp_path / "X.txt")]
    r = subprocess.run(args, capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    Kf = np.loadtxt(tmp_path / "K.txt")
    Xf = np.loadtxt(tmp_path / "X.txt")
    np.testing.assert_allclose(Kf, d.cov[:, [0, 1, 3, 2, 4, 5]], rtol=1e-15, atol=0)
    np.testing.assert_allclose(Xf, d.xcov.reshape(-1, 9), rtol=1e-15, atol=0)
    assert np.abs(Xf[:-1]).max() > 0 and not Xf[-1].any()
    head = open(tmp_path / "X.txt").readline()
    assert head.startswith("# names x_xx x_xy x_xz x_yx")
