"""igea.dw and `igea dw` closing the loop on a reference flight integrated
here with scipy (solve_ivp, DOP853, in ECEF with J2 gravity, Coriolis and
centrifugal terms): ideal increments and ideal tracking give dW = 0; the
driver and the Python function agree; bad records are refused naming the
epoch."""
import os
import subprocess

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import igea

# WGS-84, NIMA TR8350.2 (3rd ed.) tables 3.1, 3.3
A, F, GM, WE, J2 = 6378137.0, 1 / 298.257223563, 3.986004418e14, 7.292115e-5, 1.082629821313e-3
LAT, LON, HGT, AZ = 28.25, -80.6, 20.0, 95.0  # degrees, m
RATE, DUR = 50, 60.0


def frames():
    la, lo, az = np.radians([LAT, LON, AZ])
    e2 = F * (2 - F)
    N = A / np.sqrt(1 - e2 * np.sin(la) ** 2)
    r0 = np.array([(N + HGT) * np.cos(la) * np.cos(lo), (N + HGT) * np.cos(la) * np.sin(lo),
                   (N * (1 - e2) + HGT) * np.sin(la)])
    east = np.array([-np.sin(lo), np.cos(lo), 0])
    north = np.array([-np.sin(la) * np.cos(lo), -np.sin(la) * np.sin(lo), np.cos(la)])
    up = np.array([np.cos(la) * np.cos(lo), np.cos(la) * np.sin(lo), np.sin(la)])
    x = np.cos(az) * north + np.sin(az) * east
    return np.array([x, up, np.cross(x, up)]), r0


def grav(r):
    r2 = r @ r
    k, zz = 1.5 * J2 * A * A / r2, r[2] ** 2 / r2
    return -GM / r2 ** 1.5 * r * np.array([1 + k * (1 - 5 * zz), 1 + k * (1 - 5 * zz),
                                            1 + k * (3 - 5 * zz)])


def omega_b(t):
    return np.array([0.02 * np.sin(0.7 * t), 0.01 * np.cos(1.1 * t), -0.01])


def omega_int(a, b):
    return np.array([0.02 * (np.cos(0.7 * a) - np.cos(0.7 * b)) / 0.7,
                     0.01 * (np.sin(1.1 * b) - np.sin(1.1 * a)) / 1.1, -0.01 * (b - a)])


def force_b(t):
    return np.array([25.0 + 2.0 * t / DUR, 0.4 * np.sin(1.9 * t), 0.0])


def force_int(a, b):
    return np.array([25.0 * (b - a) + (b * b - a * a) / DUR,
                     0.4 * (np.cos(1.9 * a) - np.cos(1.9 * b)) / 1.9, 0.0])


def dcm(q):
    a, b, c, d = q / np.linalg.norm(q)
    return np.array([[a*a + b*b - c*c - d*d, 2*(b*c - a*d), 2*(b*d + a*c)],
                     [2*(b*c + a*d), a*a - b*b + c*c - d*d, 2*(c*d - a*b)],
                     [2*(b*d - a*c), 2*(c*d + a*b), a*a - b*b - c*c + d*d]])


Q0 = np.array([np.cos(np.pi / 4), 0, 0, np.sin(np.pi / 4)])  # body x up


@pytest.fixture(scope="module")
def flight():
    C, r0 = frames()
    w = np.array([0, 0, WE])

    def rhs(t, x):
        r, v, q = x[:3], x[3:6], x[6:10]
        wx, wy, wz = omega_b(t)
        dq = 0.5 * np.array([-q[1]*wx - q[2]*wy - q[3]*wz, q[0]*wx + q[2]*wz - q[3]*wy,
                             q[0]*wy - q[1]*wz + q[3]*wx, q[0]*wz + q[1]*wy - q[2]*wx])
        fli = dcm(q) @ force_b(t)
        c, s = np.cos(WE * t), np.sin(WE * t)
        fE = np.array([[c, s, 0], [-s, c, 0], [0, 0, 1]]) @ (C.T @ fli)
        a = fE + grav(r) - 2 * np.cross(w, v) - np.cross(w, np.cross(w, r))
        return np.concatenate([v, a, dq, fli])

    x0 = np.concatenate([r0, np.zeros(3), Q0, np.zeros(3)])
    sol = solve_ivp(rhs, (0, DUR), x0, method="DOP853", rtol=1e-13, atol=1e-9,
                    dense_output=True)
    t = np.arange(int(RATE * DUR) + 1) / RATE
    tel = np.zeros((t.size, 7))
    tel[:, 0] = t
    for k in range(1, t.size):
        tel[k, 1:4] = force_int(t[k - 1], t[k])
        tel[k, 4:7] = omega_int(t[k - 1], t[k])
    X = sol.sol(t)
    plat = np.zeros((t.size, 4))
    plat[:, 0] = t
    plat[1:, 1:4] = np.diff(X[10:13], axis=1).T
    # unequal epochs with a gap, some between telemetry records
    ep = np.concatenate([[0.5], np.arange(1.0, 20.0), [20.013, 23.5], np.arange(27.0, 60.0, 0.8),
                         [59.99]])
    Y = sol.sol(ep)
    trk_ecef = np.column_stack([ep, Y[0:3].T, Y[3:6].T, np.full(ep.size, 0.02)])
    rle = (C @ (Y[0:3] - r0[:, None])).T
    vle = (C @ Y[3:6]).T
    trk_le = np.column_stack([ep, rle, vle, np.full((ep.size, 3), [0.01, 0.02, 0.03])])
    return dict(tel=tel, plat=plat, ecef=trk_ecef, le=trk_le, C=C)


KW = dict(lat=LAT, lon=LON, height=HGT, azimuth=AZ)


@pytest.mark.parametrize("frame", ["ecef", "le"])
def test_closed_loop_strapdown(flight, frame):
    res = igea.dw(flight["tel"], flight[frame], frame=frame, q0=Q0, **KW)
    assert res.max_abs < 1e-6
    assert res.n_epochs == flight[frame].shape[0] and res.rows == 3 * res.n_epochs
    assert res.samples == flight["tel"].shape[0]


@pytest.mark.parametrize("system", ["strapdown", "platform"])
def test_closed_loop_navigated(flight, system):
    tel = flight["tel"] if system == "strapdown" else flight["plat"]
    res = igea.dw(tel, flight["le"], frame="le", system=system, kind="navigated", q0=Q0, **KW)
    assert res.max_abs < 1e-6


def test_closed_loop_platform(flight):
    res = igea.dw(flight["plat"], flight["ecef"], frame="ecef", system="platform", **KW)
    assert res.max_abs < 1e-6
    # an isotropic sigma stays isotropic in LI
    np.testing.assert_allclose(res.sigma, 0.02, rtol=1e-12)


def test_covariance_le_to_li(flight):
    """diag(0.01, 0.02, 0.03)^2 in LE, rotated by M = C R(w t) C^T."""
    res = igea.dw(flight["tel"], flight["le"], frame="le", q0=Q0, **KW)
    C, P = flight["C"], np.diag([1e-4, 4e-4, 9e-4])
    for e, t in enumerate(flight["le"][:, 0]):
        c, s = np.cos(WE * t), np.sin(WE * t)
        M = C @ np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]]) @ C.T
        Q = M @ P @ M.T
        np.testing.assert_allclose(res.cov[e], Q[[0, 0, 0, 1, 1, 2], [0, 1, 2, 1, 2, 2]],
                                   rtol=1e-9, atol=1e-18)


def test_clock_offset_column(flight):
    """A 5 ms offset: dW = dw_dtau tau to second order, recovered by least
    squares; dw_dtau's leading term is the specific force."""
    tel = flight["tel"].copy()
    tel[:, 0] -= 5e-3
    trk = flight["ecef"][flight["ecef"][:, 0] < DUR - 0.01]
    res = igea.dw(tel, trk, frame="ecef", q0=Q0, **KW)
    tau = res.dw_dtau @ res.dw / (res.dw_dtau @ res.dw_dtau)
    assert abs(tau - 5e-3) < 5e-3 * 1e-3
    np.testing.assert_allclose(res.dw, res.dw_dtau * 5e-3, atol=2e-5)
    again = igea.dw(tel, trk, frame="ecef", q0=Q0, time_offset=5e-3, **KW)
    assert again.max_abs < 1e-6


def test_refusals(flight):
    trk = flight["ecef"].copy()
    trk[-1, 0] = DUR + 1.0
    with pytest.raises(igea.IgeaError, match="epoch %d" % (trk.shape[0] - 1)):
        igea.dw(flight["tel"], trk, frame="ecef", q0=Q0, **KW)
    with pytest.raises(ValueError, match="frame"):
        igea.dw(flight["tel"], trk, frame="eci", **KW)


def _driver(*args, cwd):
    return subprocess.run([os.environ["IGEA_DRIVER"], "dw", *args], cwd=cwd,
                          capture_output=True, text=True)


def test_driver_matches_python(flight, tmp_path):
    np.savetxt(tmp_path / "tel.txt", flight["tel"], fmt="%.17g")
    np.savetxt(tmp_path / "trk.txt", flight["le"], fmt="%.17g")
    q = ",".join("%.17g" % x for x in Q0)
    p = _driver("--telemetry", "tel.txt", "--tracking", "trk.txt", "--lat", str(LAT), "--lon",
                str(LON), "--height", str(HGT), "--azimuth", str(AZ), "--frame", "le", "--q0", q,
                "--out", "dw.txt", "--cov-out", "cov.txt", "--sigma-out", "sigma.txt",
                "--time-offset-out", "tau.txt", "--json", cwd=tmp_path)
    assert p.returncode == 0, p.stderr
    res = igea.dw(flight["tel"], flight["le"], frame="le", q0=Q0, **KW)
    text = (tmp_path / "dw.txt").read_text()
    assert text.startswith("# names dw\n# units m/s\n")
    np.testing.assert_array_equal(np.loadtxt(tmp_path / "dw.txt"), res.dw)
    np.testing.assert_array_equal(np.loadtxt(tmp_path / "cov.txt"), res.cov)
    np.testing.assert_array_equal(np.loadtxt(tmp_path / "sigma.txt"), res.sigma)
    np.testing.assert_array_equal(np.loadtxt(tmp_path / "tau.txt"), res.dw_dtau)
    import json
    j = json.loads(p.stdout)
    assert j["n_epochs"] == res.n_epochs and j["rows"] == res.rows
    assert j["max_abs"] == res.max_abs
    np.testing.assert_allclose(j["rms"], res.rms, rtol=1e-12)


def test_driver_refuses_epoch_outside(flight, tmp_path):
    trk = flight["le"].copy()
    trk[3, 0], trk[4, 0] = 100.0, 101.0  # out of order and beyond the record
    np.savetxt(tmp_path / "tel.txt", flight["tel"])
    np.savetxt(tmp_path / "trk.txt", trk)
    p = _driver("--telemetry", "tel.txt", "--tracking", "trk.txt", "--lat", "1", "--lon", "2",
                "--azimuth", "3", "--out", "dw.txt", cwd=tmp_path)
    assert p.returncode == 65
    assert "trk.txt: data row 6 (epoch 5)" in p.stderr  # 5 s after 101 s
    assert not (tmp_path / "dw.txt").exists()
    trk = flight["le"].copy()
    trk[-1, 0] = 70.0
    np.savetxt(tmp_path / "trk.txt", trk)
    p = _driver("--telemetry", "tel.txt", "--tracking", "trk.txt", "--lat", "1", "--lon", "2",
                "--azimuth", "3", "--out", "dw.txt", cwd=tmp_path)
    assert p.returncode == 65
    assert "outside the telemetry span" in p.stderr and "epoch %d" % (trk.shape[0] - 1) in p.stderr


def test_driver_navigated_and_usage(flight, tmp_path):
    np.savetxt(tmp_path / "tel.txt", flight["plat"], fmt="%.17g")
    np.savetxt(tmp_path / "trk.txt", flight["ecef"], fmt="%.17g")
    base = ["--telemetry", "tel.txt", "--tracking", "trk.txt", "--lat", str(LAT), "--lon",
            str(LON), "--height", str(HGT), "--azimuth", str(AZ), "--system", "platform",
            "--out", "dv.txt"]
    p = _driver(*base, "--frame", "ecef", "--kind", "navigated", cwd=tmp_path)
    assert p.returncode == 0, p.stderr
    res = igea.dw(flight["plat"], flight["ecef"], frame="ecef", system="platform",
                  kind="navigated", **KW)
    np.testing.assert_array_equal(np.loadtxt(tmp_path / "dv.txt"), res.dw)
    assert res.max_abs < 1e-6
    p = _driver(*base, "--frame", "li", cwd=tmp_path)
    assert p.returncode == 64 and "--frame" in p.stderr
    p = _driver(*base[:-2], cwd=tmp_path)  # no --out
    assert p.returncode == 64 and "--out" in p.stderr


def test_summary_is_the_librarys_and_equals_numpy():
    """igea_dw_summary (the driver's and Python's one summary): sigma the
    square roots of each epoch's xx, yy, zz, the largest |dW| and the rms
    per axis, against numpy."""
    import ctypes
    from igea import _lib
    rng = np.random.default_rng(12)
    dw = rng.normal(size=12) * 1e-3
    cov = np.zeros((4, 6))
    cov[:, [0, 3, 5]] = rng.uniform(1e-6, 4e-6, size=(4, 3))
    sig, mx, rms = np.empty(12), ctypes.c_double(), np.empty(3)
    _lib.call("t", "igea_dw_summary", 4, _lib.dptr(dw), _lib.dptr(cov.ravel()), _lib.dptr(sig),
              ctypes.byref(mx), _lib.dptr(rms))
    np.testing.assert_allclose(sig, np.sqrt(cov[:, [0, 3, 5]]).ravel(), rtol=1e-15)
    assert mx.value == np.max(np.abs(dw))
    np.testing.assert_allclose(rms, np.sqrt(np.mean(dw.reshape(4, 3) ** 2, axis=0)), rtol=1e-14)
    bad = cov.copy()
    bad[2, 3] = -1e-9
    with pytest.raises(igea.IgeaError) as e:
        _lib.call("t", "igea_dw_summary", 4, _lib.dptr(dw), _lib.dptr(bad.ravel()), _lib.dptr(sig),
                  None, None)
    assert e.value.code == -1012
