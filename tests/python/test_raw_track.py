"""Tracking errors and accuracy columns in the raw records
(igea_sim_raw_track): position and velocity errors with a full per-epoch
6 x 6 covariance in the tracking frame, propagated by igea dw into the
launch-inertial block covariance K that eqerr's noise model (cov=) reads.
The frame change is written here from its definition (docs/pipeline.md
1.2: v_LI = C R(w t) (v_E + w x r_E)), not taken from igea; the Monte Carlo
interval is the binomial one of scipy."""
import os
import subprocess

import numpy as np
import pytest
from scipy import stats

import igea
from igea import simulate_raw

W_E = 7.292115e-5
DRIVER = os.environ.get("IGEA_DRIVER")


def launch_axes(lat, lon, az):
    lat, lon, az = np.radians([lat, lon, az])
    n_ = np.array([-np.sin(lat) * np.cos(lon), -np.sin(lat) * np.sin(lon), np.cos(lat)])
    e_ = np.array([-np.sin(lon), np.cos(lon), 0.0])
    u_ = np.array([np.cos(lat) * np.cos(lon), np.cos(lat) * np.sin(lon), np.sin(lat)])
    xa = np.cos(az) * n_ + np.sin(az) * e_
    return np.array([xa, u_, np.cross(xa, u_)])


def cov6(e, ne, sr=50.0, sv=0.01, rho=0.6, c=0.3):
    """The tracking covariance of epoch e (ECEF): axis correlation
    [[1 r r^2][r 1 r][r^2 r 1]], position-velocity correlation c, the
    sigmas growing by half over the flight."""
    R = np.array([[1, rho, rho ** 2], [rho, 1, rho], [rho ** 2, rho, 1]])
    g = 1.0 + 0.5 * e / max(ne - 1, 1)
    s = np.concatenate([np.full(3, sr * g), np.full(3, sv * g)])
    Cr = np.block([[R, c * R], [c * R, R]])
    return Cr * np.outer(s, s)


def upper(P):
    return np.concatenate([P[i, i:] for i in range(6)])


def records(flight, ne_expected=None, seed=3, **kw):
    rng = np.random.default_rng(1000 + flight)
    fl = igea.simulate(system="platform", seed=seed, flight=flight)
    ne = fl.epochs.size
    P = [cov6(e, ne) for e in range(ne)]
    err = np.array([np.linalg.cholesky(p) @ rng.standard_normal(6) for p in P])
    acc = np.array([upper(p) for p in P])
    raw = simulate_raw(system="platform", seed=seed, flight=flight, trk_err=err, acc=acc, **kw)
    return raw, P


def test_covariance_propagation():
    """dw's LI velocity covariance of a 28-column record equals A P A^T,
    A = [M [w x], M], M = C R(w t) (ECEF), to 1e-12 relative; the velocity
    block alone (13 columns) misses the position's w x dr part. The
    navigated kind's (the frame change alone; the apparent kind adds the
    gravity integral's part, tests/python/test_dw_k.py)."""
    raw, P = records(0)
    d = igea.dw(raw.telemetry, raw.tracking, **dict(raw.dw_kwargs(), kind="navigated"))
    C = launch_axes(raw.lat, raw.lon, raw.azimuth)
    wx = np.array([[0, -W_E, 0], [W_E, 0, 0], [0, 0, 0]])
    for e in (0, 57, raw.tracking.shape[0] - 1):
        t = raw.tracking[e, 0]
        Rz = np.array([[np.cos(W_E * t), -np.sin(W_E * t), 0],
                       [np.sin(W_E * t), np.cos(W_E * t), 0], [0, 0, 1]])
        M = C @ Rz
        A = np.hstack([M @ wx, M])
        K = A @ P[e] @ A.T
        got = d.cov[e]
        want = K[[0, 0, 0, 1, 1, 2], [0, 1, 2, 1, 2, 2]]
        np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-12 * np.abs(want).max())
        Kv = M @ P[e][3:, 3:] @ M.T
        assert np.max(np.abs(np.diag(K - Kv)) / np.diag(Kv)) > 0.05   # sizeable position part


def test_refusals():
    raw, _ = records(1)
    with pytest.raises(ValueError):
        simulate_raw(system="platform", seed=3, flight=1, acc=np.zeros((3, 21)))
    with pytest.raises(igea.IgeaError):
        simulate_raw(system="platform", seed=3, flight=1, acc=np.zeros((raw.tracking.shape[0], 5)))
    bad = np.zeros((raw.tracking.shape[0], 6))
    bad[4, 2] = np.nan
    with pytest.raises(igea.IgeaError):
        simulate_raw(system="platform", seed=3, flight=1, trk_err=bad)


FLIGHTS = int(os.environ.get("IGEA_RAW_TRACK_FLIGHTS", "240"))


def test_chi2_size_correlated_tracking():
    """FLIGHTS raw platform flights (21 terms, X ~ N(0, I)) whose tracking
    has correlated position and velocity errors (50 m, 0.01 m/s, axis
    correlation 0.6, position-velocity 0.3, growing by half): judged with
    dw's K (cov=, no sigma_w correction) at alpha = 0.2 the chi-square
    rejects at its size: the count lies in Binomial(F, 0.2)'s central 99 %
    (measured 49/240, band 33..64; rerun larger: IGEA_RAW_TRACK_FLIGHTS=2000)."""
    rej = 0
    for f in range(FLIGHTS):
        raw, P = records(f)
        fl = raw.flight
        d = igea.dw(raw.telemetry, raw.tracking, **raw.dw_kwargs())
        c = d.cov
        K = np.array([[[r[0], r[1], r[2]], [r[1], r[3], r[4]], [r[2], r[4], r[5]]] for r in c])
        res = igea.eqerr(fl.S, d.dw, None, fl.spec, cov=K, alpha=0.2, correction=0)
        rej += res.chi2 >= res.chi2_crit
    lo, hi = stats.binom.ppf([0.005, 0.995], FLIGHTS, 0.2)
    print(f"chi2 rejections at alpha 0.2: {rej}/{FLIGHTS} (99 % band {lo:.0f}..{hi:.0f})")
    assert lo <= rej <= hi


def test_track_errors_model():
    """igea.track_errors: acc holds the covariance written here (cov6 with
    constant sigmas), and 6000 draws have that covariance (each entry within
    5 of its standard errors, (P_ii P_jj + P_ij^2) / n)."""
    n = 6000
    acc, err = igea.track_errors(np.full(n, 0.02), 40.0, corr=0.5, cross=-0.4, seed=5, flight=2)
    P = cov6(0, 1, sr=40.0, sv=0.02, rho=0.5, c=-0.4)
    np.testing.assert_allclose(acc, np.tile(upper(P), (n, 1)), rtol=1e-14)
    emp = err.T @ err / n
    se = np.sqrt((np.outer(np.diag(P), np.diag(P)) + P ** 2) / n)
    assert np.all(np.abs(emp - P) < 5 * se)
    a2, e2 = igea.track_errors(np.full(n, 0.02), 40.0, corr=0.5, cross=-0.4, seed=5, flight=2)
    np.testing.assert_array_equal(e2, err)                       # the same stream
    _, e3 = igea.track_errors(np.full(n, 0.02), 40.0, corr=0.5, cross=-0.4, seed=5, flight=3)
    assert not np.array_equal(e3, err)
    for kw in (dict(corr=1.0), dict(cross=-1.0)):
        with pytest.raises(igea.IgeaError):
            igea.track_errors(np.full(3, 0.02), 40.0, **kw)
    with pytest.raises(igea.IgeaError):
        igea.track_errors(np.array([0.02, 0.0]), 40.0)


@pytest.mark.skipif(not DRIVER, reason="the driver")
def test_driver_track_pipeline(tmp_path):
    """simulate --raw --track-sigma-r: tracking.txt holds 28 columns whose
    covariance columns are cov6's with the stated sigma; dw --k-out writes K
    in eqerr --cov's order (xx yx yy zx zy zz), the transpose-free
    rearrangement of --cov-out; eqerr --cov K judges the flight."""
    d = str(tmp_path)

    def run(*a):
        return subprocess.run([DRIVER, *a], cwd=d, capture_output=True, text=True)
    r = run("simulate", "--raw", "--system", "platform", "--seed", "7", "--track-sigma-r", "50",
            "--track-corr", "0.6", "--track-cross", "0.3", "--dir", ".")
    assert r.returncode == 0, r.stderr
    trk = np.loadtxt(os.path.join(d, "tracking.txt"), ndmin=2)
    sig = np.loadtxt(os.path.join(d, "sigma.txt"))[0::3]
    assert trk.shape[1] == 28
    for e in (0, len(trk) - 1):
        P = cov6(0, 1, sr=50.0, sv=sig[e], rho=0.6, c=0.3)
        np.testing.assert_allclose(trk[e, 7:], upper(P), rtol=1e-14)
    args = open(os.path.join(d, "dw_args.txt")).read().split()
    r = run("dw", *args, "--telemetry", "telemetry.txt", "--tracking", "tracking.txt",
            "--out", "dw_raw.txt", "--cov-out", "cov.txt", "--k-out", "K.txt")
    assert r.returncode == 0, r.stderr
    cov, K = np.loadtxt(os.path.join(d, "cov.txt")), np.loadtxt(os.path.join(d, "K.txt"))
    np.testing.assert_array_equal(K, cov[:, [0, 1, 3, 2, 4, 5]])
    sa = open(os.path.join(d, "site_args.txt")).read().split()
    r = run("envfun", *sa, "--traj", "traj.txt", "--terms", "default", "--system", "platform",
            "--out", "S_raw.txt")
    assert r.returncode == 0, r.stderr
    r = run("eqerr", "--json", "--S", "S_raw.txt", "--dw", "dw_raw.txt", "--cov", "K.txt",
            "--spec", "spec.txt")
    assert r.returncode in (0, 1), r.stderr
    r = run("simulate", "--raw", "--track-sigma-r", "5", "--track-corr", "1", "--dir", ".")
    assert r.returncode == 64 and "--track-corr" in r.stderr
    bad = trk.copy()
    bad[5, 7] = -1.0                                   # c_x_x < 0: not positive definite
    np.savetxt(os.path.join(d, "bad.txt"), bad)
    r = run("dw", *args, "--telemetry", "telemetry.txt", "--tracking", "bad.txt", "--out", "x.txt")
    assert r.returncode == 65 and "bad.txt" in r.stderr and "positive definite" in r.stderr
    assert not os.path.exists(os.path.join(d, "x.txt"))
