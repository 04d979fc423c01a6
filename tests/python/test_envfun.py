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
    """Instrument error per unit coefficient, (n, 3), from the unit errors
    of docs/envfun.md (gyro j: input I(j), spin S(j), output the third)."""
    n = len(f)
    u = np.zeros((n, 3))
    kind, ax = name.rsplit("_", 1)
    if len(ax) == 2:
        j, k = AX.index(ax[0]), AX.index(ax[1])
        if kind == "acc_size":  # centripetal part (w x (w x e_k))_j
            u[:, j] = w[:, j] * w[:, k] - (j == k) * (w * w).sum(axis=1)
        else:
            u[:, j] = {"acc_mis": f[:, k], "acc_cross": f[:, j] * f[:, k],
                       "acc_xsq": f[:, k] ** 2}[kind]
        return u
    j = AX.index(ax)
    fi, fs = f[:, in_ax[j]], f[:, spin_ax[j]]
    fo = f[:, 3 - in_ax[j] - spin_ax[j]]
    k, l = [a for a in range(3) if a != j]
    u[:, j] = {"acc_bias": 1.0, "gyro_bias": 1.0, "acc_scale": f[:, j], "acc_sq": f[:, j] ** 2,
               "gyro_g": f[:, j], "gyro_scale": w[:, j], "gyro_gi": fi, "gyro_gs": fs,
               "gyro_gspin": fs, "gyro_go": fo, "gyro_gii": fi ** 2, "gyro_gss": fs ** 2,
               "gyro_goo": fo ** 2, "gyro_gis": fi * fs, "gyro_gio": fi * fo,
               "gyro_gso": fs * fo, "acc_cube": f[:, j] ** 3, "acc_asym": np.abs(f[:, j]),
               "acc_xprod": f[:, k] * f[:, l]}[kind]
    return u


R_EARTH = 6371000.0


def direct_ref(name, t, W, w, Cq):
    """Velocity functions that are functions of the sample: initial
    attitude W x e_k; launch point theta x W (pos0_x theta = -e_z / R,
    pos0_z theta = e_x / R); lever arm -(C (w x e_k) - the same at t_0)."""
    kind, ax = name.rsplit("_", 1)
    e = np.zeros(3)
    e[AX.index(ax)] = 1.0
    if kind in ("att0", "align0"):
        return np.cross(W, e)
    if kind == "pos0":
        theta = np.array([1.0, 0, 0]) / R_EARTH if ax == "z" else np.array([0, 0, -1.0]) / R_EARTH
        return np.cross(theta, W)
    lv = np.einsum("kij,kj->ki", Cq, np.cross(w, e))
    return -(lv - lv[0])


def envfun_ref(traj, terms, epochs, system):
    t, f, w = traj[:, 0], traj[:, 1:4], traj[:, 4:7]
    Cq = quat_dcm(traj[:, 7:11])
    if system == "strapdown":
        C = Cq
        fa = np.einsum("kij,kj->ki", C, f)
    else:
        C = np.broadcast_to(np.eye(3), (len(t), 3, 3))
        fa = f
    W = cumtrapz(t, fa)
    cols = []
    for name in terms:
        kind = name.rsplit("_", 1)[0]
        if kind in ("att0", "align0", "pos0", "lever"):
            v = direct_ref(name, t, W, w, Cq)
        else:
            cu = np.einsum("kij,kj->ki", C, unit(name, f, w))
            if kind.startswith("acc"):
                v = cumtrapz(t, cu)
            else:
                inner = cumtrapz(t, cu)
                outer = np.cross(inner, fa) if system == "strapdown" else np.cross(fa, inner)
                v = cumtrapz(t, outer)
            if kind == "acc_size":  # tangential: sum of C_mid e_j (dw x e_k)_j
                j, k = AX.index(name[-2]), AX.index(name[-1])
                ek = np.zeros(3)
                ek[k] = 1.0
                tg = np.cross(np.diff(w, axis=0), ek)[:, j]
                cm = 0.5 * (C[1:, :, j] + C[:-1, :, j])
                v = v + np.vstack([np.zeros(3), np.cumsum(cm * tg[:, None], axis=0)])
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
    assert S.shape == (18, len(terms)) and len(terms) == 86
    scale = np.abs(R).max(axis=0)
    assert np.all(scale > 0)
    np.testing.assert_allclose(S / scale, R / scale, rtol=0, atol=1e-12)


def test_platform_all_terms_match_numpy(traj_pf):
    terms = list(TERMS_PLATFORM)
    ep = np.linspace(0.5, 59.5, 7)
    S = igea.envfun(traj_pf, terms, ep, system="platform")
    R = envfun_ref(traj_pf, terms, ep, "platform")
    assert len(terms) == 74  # the size of seed 000's platform model
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


def test_user_terms(traj_sd, traj_pf):
    """A user term whose series is a catalogue term's unit error gives that
    term's column; a thermal-like profile matches the numpy integral."""
    ep = np.linspace(1.0, 59.0, 5)
    for tr, system in ((traj_sd, "strapdown"), (traj_pf, "platform")):
        f, w = tr[:, 1:4], tr[:, 4:7]
        ut = {"acc_k1x": unit("acc_scale_x", f, w), "gyro_gz": unit("gyro_bias_z", f, w),
              "acc_heat": np.outer(np.sin(0.2 * tr[:, 0]), [0.0, 1.0, 0.5])}
        S = igea.envfun(tr, ["acc_scale_x", "gyro_bias_z"], ep, system=system, user_terms=ut)
        assert S.shape == (15, 5)
        sc = np.abs(S[:, :2]).max(axis=0)
        np.testing.assert_allclose(S[:, 2:4] / sc, S[:, :2] / sc, rtol=0, atol=1e-14)
        t = tr[:, 0]
        C = quat_dcm(tr[:, 7:11]) if system == "strapdown" else np.broadcast_to(np.eye(3), (len(t), 3, 3))
        v = cumtrapz(t, np.einsum("kij,kj->ki", C, ut["acc_heat"]))
        want = np.stack([np.interp(ep, t, v[:, a]) for a in range(3)], axis=1).ravel()
        np.testing.assert_allclose(S[:, 4], want, rtol=0, atol=1e-12 * np.abs(want).max())
        # spec: the user columns' default spec is 1
        Sd = igea.envfun(tr, ["acc_scale_x"], ep, system=system, spec="default",
                         user_terms={"acc_heat": ut["acc_heat"]})
        np.testing.assert_allclose(Sd[:, 1], S[:, 4], rtol=1e-15)
        # user terms only
        Su = igea.envfun(tr, [], ep, system=system, user_terms={"acc_heat": ut["acc_heat"]})
        np.testing.assert_allclose(Su[:, 0], S[:, 4], rtol=1e-15)
    with pytest.raises(ValueError, match="user_terms"):
        igea.envfun(traj_sd, [], ep, user_terms={"heat": np.zeros((len(traj_sd), 3))})
    with pytest.raises(ValueError, match="user_terms"):
        igea.envfun(traj_sd, [], ep, user_terms={"acc_bias_x": np.zeros((len(traj_sd), 3))})
    with pytest.raises(ValueError, match="user_terms"):
        igea.envfun(traj_sd, [], ep, user_terms={"acc_t": np.zeros((5, 3))})
    bad = np.zeros((len(traj_sd), 3))
    bad[4, 1] = np.nan
    with pytest.raises(igea.IgeaError):
        igea.envfun(traj_sd, [], ep, user_terms={"acc_t": bad})


def test_nonlinear_new_terms(traj_pf):
    """igea.sim.nonlinear takes every catalogue term: a launch-point error
    of 100 m and a second-order gyro drift agree with S X to second order."""
    ep = np.linspace(0.0, 60.0, 13)
    terms = ["pos0_x", "gyro_gso_y", "lever_z"]
    x = np.array([100.0, 2e-9, 0.5])
    S = igea.envfun(traj_pf, terms, ep, system="platform")
    d = []
    for k in (1.0, 0.5):
        nl = igea.sim.nonlinear(traj_pf, dict(zip(terms, k * x)), ep, system="platform")
        d.append(np.abs(nl - S @ (k * x)).max() / np.abs(nl).max())
    assert d[0] < 1e-4 and 1.8 < d[0] / d[1] < 2.2


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
def test_driver_term_file(tmp_path, traj_pf):
    tf = tmp_path / "traj.txt"
    np.savetxt(tf, traj_pf, fmt="%.17g")
    t = traj_pf[:, 0]
    u = np.column_stack([t, np.sin(0.2 * t), np.zeros_like(t), 0.3 * np.cos(0.1 * t)])
    np.savetxt(tmp_path / "heat.txt", u, fmt="%.17g")
    np.savetxt(tmp_path / "drift.txt", np.column_stack([t, np.ones((len(t), 3))]), fmt="%.17g")
    out = tmp_path / "S.txt"
    r = subprocess.run([DRIVER, "envfun", "--traj", str(tf), "--system", "platform", "--terms",
                        "acc_bias_x", "--term-file",
                        f"acc_heat={tmp_path / 'heat.txt'},gyro_d={tmp_path / 'drift.txt'}",
                        "--epoch-step", "5", "--out", str(out)], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert out.read_text().splitlines()[0] == "# acc_bias_x acc_heat gyro_d"
    ep = np.arange(5.0, 60.0 + 1e-9, 5.0)
    want = igea.envfun(traj_pf, ["acc_bias_x"], ep, system="platform",
                       user_terms={"acc_heat": u[:, 1:], "gyro_d": np.ones((len(t), 3))})
    np.testing.assert_allclose(np.loadtxt(out), want, rtol=1e-15, atol=0)
    # a time column that is not the trajectory's: file:line
    u[7, 0] += 0.01
    np.savetxt(tmp_path / "bad.txt", u, fmt="%.17g")
    r = subprocess.run([DRIVER, "envfun", "--traj", str(tf), "--term-file",
                        f"acc_x1={tmp_path / 'bad.txt'}"], capture_output=True, text=True)
    assert r.returncode == 65 and "bad.txt:8:1" in r.stderr
    r = subprocess.run([DRIVER, "envfun", "--traj", str(tf), "--term-file",
                        f"heat={tmp_path / 'heat.txt'}"], capture_output=True, text=True)
    assert r.returncode == 64 and "--term-file" in r.stderr
    # --terms all: the 74 platform terms
    r = subprocess.run([DRIVER, "envfun", "--traj", str(tf), "--system", "platform", "--terms",
                        "all", "--epoch-step", "20", "--json"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    import json
    assert len(json.loads(r.stdout)["terms"]) == 74


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
