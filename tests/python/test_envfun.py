"""igea.envfun and igea.reference_trajectory against an independent numpy
implementation of METHODS 5.2/5.3 (cumulative trapezoid, np.interp), and
the `igea envfun` / `igea simulate` driver commands."""
import os
import subprocess

import numpy as np
import pytest

import igea
from igea.envfun import STRAPDOWN_21, TERMS_PLATFORM, TERMS_STRAPDOWN, default_spec

AX = "xyz"


def quat_dcm(q):
    q = q / np.linalg.norm(q, axis=1)[:, None]
    a, b, c, d = q.T
    C = np.empty((len(q), 3, 3))
    C[:, 0, 0] = a * a + b * b - c * c - d * d
    C[:, 0, 1] = 2 * (b * c - a * d)
    C[:, 0, 2] = 2 * (b * d + a * c)
    C[:, 1, 0] = 2 * (b * c + a * d)
    C[:, 1, 1] = a * a - b * b + c * c - d * d
    C[:, 1, 2] = 2 * (c * d - a * b)
    C[:, 2, 0] = 2 * (b * d - a * c)
    C[:, 2, 1] = 2 * (c * d + a * b)
    C[:, 2, 2] = a * a - b * b - c * c + d * d
    return C


def cumtrapz(t, y):
    out = np.zeros_like(y)
    out[1:] = np.cumsum(0.5 * np.diff(t)[:, None] * (y[1:] + y[:-1]), axis=0)
    return out


def unit(name, f, w, in_ax=(0, 1, 2), spin_ax=(1, 2, 0)):
    """Instrument error per unit coefficient, (n, 3)."""
    n = len(f)
    u = np.zeros((n, 3))
    kind, ax = name.rsplit("_", 1)
    if kind == "acc_mis":
        j, k = AX.index(ax[0]), AX.index(ax[1])
        u[:, j] = f[:, k]
        return u
    j = AX.index(ax)
    u[:, j] = {"acc_bias": 1.0, "gyro_bias": 1.0, "acc_scale": f[:, j], "acc_sq": f[:, j] ** 2,
               "gyro_g": f[:, j], "gyro_scale": w[:, j], "gyro_gi": f[:, in_ax[j]],
               "gyro_gs": f[:, spin_ax[j]]}[kind]
    return u


def envfun_ref(traj, terms, epochs, system):
    t, f, w = traj[:, 0], traj[:, 1:4], traj[:, 4:7]
    if system == "strapdown":
        C = quat_dcm(traj[:, 7:11])
        fa = np.einsum("kij,kj->ki", C, f)
    else:
        C = np.broadcast_to(np.eye(3), (len(t), 3, 3))
        fa = f
    W = cumtrapz(t, fa)
    cols = []
    for name in terms:
        kind = name.rsplit("_", 1)[0]
        if kind in ("att0", "align0"):
            e = np.zeros(3)
            e[AX.index(name[-1])] = 1.0
            v = np.cross(W, e)
        else:
            cu = np.einsum("kij,kj->ki", C, unit(name, f, w))
            if kind.startswith("acc"):
                v = cumtrapz(t, cu)
            else:
                inner = cumtrapz(t, cu)
                outer = np.cross(inner, fa) if system == "strapdown" else np.cross(fa, inner)
                v = cumtrapz(t, outer)
        cols.append(np.stack([np.interp(epochs, t, v[:, a]) for a in range(3)], axis=1).ravel())
    return np.stack(cols, axis=1)


@pytest.fixture(scope="module")
def traj_sd():
    return igea.reference_trajectory(60.0, 20.0, system="strapdown")


@pytest.fixture(scope="module")
def traj_pf():
    return igea.reference_trajectory(60.0, 20.0, system="platform")


def test_reference_trajectory_consistent():
    """The body rates match the attitude: w = 2 Im(q* dq/dt) by central
    differences of the quaternions (test-only differentiation), and the
    platform force is the rotated body force."""
    tr = igea.reference_trajectory(120.0, 50.0)
    t, q, w = tr[:, 0], tr[:, 7:11], tr[:, 4:7]
    np.testing.assert_allclose(np.linalg.norm(q, axis=1), 1.0, atol=1e-13)
    def rate(step):
        """2 Im(conj(q) dq/dt), central differences over +-step samples."""
        sl = slice(2, -2)
        dq = (np.roll(q, -step, 0) - np.roll(q, step, 0))[sl] / (2 * step * (t[1] - t[0]))
        a, b, c, d = q[sl].T
        da, db, dc, dd = dq.T
        return 2 * np.stack([a * db - b * da - c * dd + d * dc,
                             a * dc + b * dd - c * da - d * db,
                             a * dd - b * dc + c * db - d * da], axis=1)
    est = (4 * rate(1) - rate(2)) / 3          # Richardson: O(h^4)
    assert np.abs(est - w[2:-2]).max() < 1e-6 * np.abs(w).max()
    pf = igea.reference_trajectory(120.0, 50.0, system="platform")
    fa = np.einsum("kij,kj->ki", quat_dcm(q), tr[:, 1:4])
    np.testing.assert_allclose(pf[:, 1:4], fa, rtol=0, atol=1e-12)
    # pitch-over: thrust axis starts vertical, ends 30 deg above the horizon
    assert np.degrees(np.arctan2(fa[-1, 1], fa[-1, 0])) == pytest.approx(30.0, abs=2.0)
    with pytest.raises(igea.IgeaError, match="rate"):
        igea.reference_trajectory(10.0, 0.0)


def test_strapdown_all_terms_match_numpy(traj_sd):
    terms = list(TERMS_STRAPDOWN)
    ep = np.array([0.0, 0.77, 13.3, 30.0, 59.99, 60.0])
    S = igea.envfun(traj_sd, terms, ep)
    R = envfun_ref(traj_sd, terms, ep, "strapdown")
    assert S.shape == (18, len(terms))
    scale = np.abs(R).max(axis=0)
    assert np.all(scale > 0)
    np.testing.assert_allclose(S / scale, R / scale, rtol=0, atol=1e-12)


def test_platform_all_terms_match_numpy(traj_pf):
    terms = list(TERMS_PLATFORM)
    ep = np.linspace(0.5, 59.5, 7)
    S = igea.envfun(traj_pf, terms, ep, system="platform")
    R = envfun_ref(traj_pf, terms, ep, "platform")
    scale = np.abs(R).max(axis=0)
    np.testing.assert_allclose(S / scale, R / scale, rtol=0, atol=1e-12)


def test_spec_scaling_and_position(traj_sd):
    terms = STRAPDOWN_21
    ep = np.arange(1.0, 61.0)
    S = igea.envfun(traj_sd, terms, ep)
    Sd = igea.envfun(traj_sd, terms, ep, spec="default")
    spec = default_spec(terms)
    np.testing.assert_allclose(Sd, S * spec, rtol=1e-15, atol=0)
    # position = integral of velocity (on the sample grid)
    tgrid = traj_sd[:, 0]
    V = igea.envfun(traj_sd, terms[:4], tgrid)
    P = igea.envfun(traj_sd, terms[:4], tgrid, output="position")
    for j in range(4):
        v = V[:, j].reshape(-1, 3)
        p = P[:, j].reshape(-1, 3)
        np.testing.assert_allclose(p, cumtrapz(tgrid, v), rtol=1e-12,
                                   atol=1e-12 * np.abs(p).max())
    # gravity coupling changes position by a small but visible amount
    Pg = igea.envfun(traj_sd, terms[:1], ep, output="position_g")
    P1 = igea.envfun(traj_sd, terms[:1], ep, output="position")
    rel = np.abs(Pg - P1).max() / np.abs(P1).max()
    assert 1e-5 < rel < 1e-2


def test_platform_axes(traj_pf):
    ep = np.array([10.0, 40.0])
    a = igea.envfun(traj_pf, ["gyro_gi_x", "gyro_gs_x"], ep, system="platform",
                    axes=[2, 1, 0, 1, 2, 0])
    R = envfun_ref(traj_pf, ["gyro_gs_x"], ep, "platform")  # spin (1) = default spin of x
    # input axis of gyro x is z now: equals a gyro_gi term computed with in_ax (2, 1, 0)
    t, f = traj_pf[:, 0], traj_pf[:, 1:4]
    u = np.zeros((len(t), 3))
    u[:, 0] = f[:, 2]
    v = cumtrapz(t, np.cross(f, cumtrapz(t, u)))
    want = np.stack([np.interp(ep, t, v[:, k]) for k in range(3)], axis=1).ravel()
    np.testing.assert_allclose(a[:, 0], want, rtol=1e-12, atol=1e-12 * np.abs(want).max())
    np.testing.assert_allclose(a[:, 1], R[:, 0], rtol=1e-12, atol=1e-12 * np.abs(R).max())


def test_errors(traj_sd):
    ep = np.array([1.0, 2.0])
    with pytest.raises(ValueError, match="traj"):
        igea.envfun(traj_sd[:, :10], ["acc_bias_x"], ep)
    with pytest.raises(ValueError, match="terms"):
        igea.envfun(traj_sd, ["acc_bias_q"], ep)
    with pytest.raises(ValueError, match="terms"):
        igea.envfun(traj_sd, ["align0_x"], ep)  # a platform term
    with pytest.raises(ValueError, match="system"):
        igea.envfun(traj_sd, ["acc_bias_x"], ep, system="gimbal")
    with pytest.raises(ValueError, match="spec"):
        igea.envfun(traj_sd, ["acc_bias_x"], ep, spec=[1.0, 2.0])
    with pytest.raises(ValueError, match="epochs"):
        igea.envfun(traj_sd, ["acc_bias_x"], np.ones((2, 2)))
    with pytest.raises(igea.IgeaError, match="epochs"):
        igea.envfun(traj_sd, ["acc_bias_x"], [2.0, 1.0])
    with pytest.raises(igea.IgeaError, match="epochs"):
        igea.envfun(traj_sd, ["acc_bias_x"], [100.0])
    bad = traj_sd.copy()
    bad[3, 2] = np.nan
    with pytest.raises(igea.IgeaError) as ei:
        igea.envfun(bad, ["acc_bias_x"], ep)
    assert ei.value.code == -1011
    with pytest.raises(igea.IgeaError) as ei:
        igea.envfun(traj_sd, ["acc_bias_x"], ep, spec=[-1.0])
    assert ei.value.code == -1012


# ---- driver ----------------------------------------------------------------
DRIVER = os.environ.get("IGEA_DRIVER")
needs_driver = pytest.mark.skipif(not DRIVER, reason="IGEA_DRIVER not set")


@needs_driver
def test_driver_envfun_matches_python(tmp_path, traj_sd):
    tf = tmp_path / "traj.txt"
    np.savetxt(tf, traj_sd, fmt="%.17g")
    out = tmp_path / "S.txt"
    r = subprocess.run([DRIVER, "envfun", "--traj", str(tf), "--terms", "acc_bias_x,gyro_g_z,att0_y",
                        "--epoch-step", "2", "--out", str(out)], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    first = out.read_text().splitlines()[0]
    assert first == "# acc_bias_x gyro_g_z att0_y"
    S = np.loadtxt(out)
    ep = np.arange(2.0, 60.0 + 1e-9, 2.0)
    want = igea.envfun(traj_sd, ["acc_bias_x", "gyro_g_z", "att0_y"], ep)
    np.testing.assert_allclose(S, want, rtol=1e-15, atol=0)
    # usage errors
    r = subprocess.run([DRIVER, "envfun", "--traj", str(tf), "--terms", "nope"], capture_output=True,
                       text=True)
    assert r.returncode == 64 and "nope" in r.stderr
    r = subprocess.run([DRIVER, "envfun", "--traj", str(tf), "--terms", "acc_bias_x", "--epochs",
                        str(tmp_path / "missing.txt")], capture_output=True, text=True)
    assert r.returncode == 66
    r = subprocess.run([DRIVER, "envfun", "--help"], capture_output=True, text=True)
    assert r.returncode == 0 and "example" in r.stdout


@needs_driver
def test_driver_simulate_then_eqerr(tmp_path):
    r = subprocess.run([DRIVER, "simulate", "--seed", "3", "--flight", "2", "--sigma-w", "1.8",
                        "--dir", str(tmp_path), "--json"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    fl = igea.simulate(seed=3, flight=2, sigma_w=1.8)
    np.testing.assert_allclose(np.loadtxt(tmp_path / "dw.txt"), fl.dw, rtol=1e-15, atol=1e-17)
    np.testing.assert_allclose(np.loadtxt(tmp_path / "S.txt"), fl.S, rtol=1e-15, atol=0)
    np.testing.assert_allclose(np.loadtxt(tmp_path / "spec.txt"), fl.spec, rtol=1e-15)
    np.testing.assert_allclose(np.loadtxt(tmp_path / "X.txt", usecols=0), fl.x_true,
                               rtol=1e-15)
    r = subprocess.run([DRIVER, "eqerr", "--S", "S.txt", "--dw", "dw.txt", "--sigma",
                        "sigma.txt", "--spec", "spec.txt"], cwd=tmp_path, capture_output=True,
                       text=True)
    assert r.returncode in (0, 1), r.stderr
    assert "verdict" in r.stdout


@needs_driver
def test_driver_simulate_nonlinear_truth(tmp_path):
    r = subprocess.run([DRIVER, "simulate", "--seed", "5", "--nonlinear-truth", "--dir",
                        str(tmp_path)], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    fl = igea.simulate(seed=5, nonlinear_truth=True)
    np.testing.assert_allclose(np.loadtxt(tmp_path / "dw.txt"), fl.dw, rtol=1e-12,
                               atol=1e-14)
    lin = igea.simulate(seed=5)
    assert np.abs(fl.dw - lin.dw).max() > 1e-7
