"""The launch-inertial error model along a trajectory (igea.nav_errors_li)
against the full nonlinear navigation of the nav core (igea.nav_navigate)
with the same errors on a powered record: the difference is second order
(halving every error quarters it); the covariance of random constant
biases against the response columns, P(t) = X(t) P0 X(t)^T with X the
responses to unit errors (linearity of the propagation)."""
import math

import numpy as np
import pytest

import igea

DEG = math.pi / 180.0


def powered_record(duration=40.0, rate=25.0):
    """A strapdown telemetry record of a vehicle climbing at 2 g along body
    x, pitched 30 deg from the local vertical and rolling at 0.05 rad/s:
    trapezoid increments of the constant force and rate (rows t dv dth)."""
    n = int(duration * rate) + 1
    t = np.arange(n) / rate
    tel = np.zeros((n, 7))
    tel[:, 0] = t
    tel[1:, 1] = 2 * 9.80665 / rate
    tel[1:, 4] = 0.05 / rate
    tel[1:, 6] = 0.002 / rate
    return tel


def q_pitch(a):
    """body x from LI y (up) tipped by a toward LI x: rotation about LI z by
    90 deg - a (scalar first)."""
    u = (math.pi / 2 - a) / 2
    return np.array([math.cos(u), 0, 0, math.sin(u)])


def qmul(a, b):
    return np.array([a[0] * b[0] - a[1:] @ b[1:],
                     *(a[0] * b[1:] + b[0] * a[1:] + np.cross(a[1:], b[1:]))])


def dcm(q):
    a, b, c, d = q / np.linalg.norm(q)
    return np.array([[a*a + b*b - c*c - d*d, 2*(b*c - a*d), 2*(b*d + a*c)],
                     [2*(b*c + a*d), a*a - b*b + c*c - d*d, 2*(c*d - a*b)],
                     [2*(b*d - a*c), 2*(c*d + a*b), a*a - b*b - c*c + d*d]])


def nonlinear(site, tel, q0, e, gravity):
    """The nonlinear navigation with the errors e (x0 layout) minus the one
    without, at every sample: dr, dv and phi (C_e C^T = I - [phi x])."""
    ref = igea.nav_navigate(site, tel, q0=q0, gravity=gravity)
    phi0 = np.asarray(e[6:9])
    a = np.linalg.norm(phi0)
    qp = np.array([math.cos(a / 2), *(-math.sin(a / 2) * phi0 / a)]) if a > 0 else np.eye(4)[0]
    te = tel.copy()
    h = np.diff(tel[:, 0])
    te[1:, 1:4] += np.outer(h, e[9:12])
    te[1:, 4:7] += np.outer(h, e[12:15])
    err = igea.nav_navigate(site, te, q0=qmul(qp, q0), r0=ref.r[0] + e[0:3],
                            v0=ref.v[0] + e[3:6], gravity=gravity)
    phi = np.zeros_like(ref.r)
    for k in range(len(phi)):
        M = dcm(err.q[k]) @ dcm(ref.q[k]).T
        phi[k] = [(M[1, 2] - M[2, 1]) / 2, (M[2, 0] - M[0, 2]) / 2, (M[0, 1] - M[1, 0]) / 2]
    return err.r - ref.r, err.v - ref.v, phi


E = np.array([3.0, -2.0, 1.0, 0.05, -0.02, 0.04, 2e-4, -1e-4, 1.5e-4,
              1e-3, -2e-3, 1.5e-3, 2e-5, -1e-5, 1e-5])


@pytest.mark.parametrize("gravity", ["j2", "point_mass"])
def test_second_order_against_nonlinear(gravity):
    site = igea.nav_site(30 * DEG, 110 * DEG, 0.0, 80 * DEG)
    tel, q0 = powered_record(), q_pitch(30 * DEG)
    d = []
    for s in (1.0, 0.5):
        lin = igea.nav_errors_li(site, tel, q0=q0, x0=s * E, gravity=gravity)
        dr, dv, phi = nonlinear(site, tel, q0, s * E, gravity)
        d.append([np.max(np.abs(dr - lin.position)), np.max(np.abs(dv - lin.velocity)),
                  np.max(np.abs(phi - lin.attitude)), np.max(np.abs(lin.position)),
                  np.max(np.abs(lin.velocity)), np.max(np.abs(lin.attitude))])
    for b in range(3):
        assert d[0][b] < 1e-2 * d[0][b + 3]
        assert 3.8 < d[0][b] / d[1][b] < 4.2


def test_covariance_of_constant_biases():
    site = igea.nav_site(-20 * DEG, 10 * DEG, 200.0, -30 * DEG)
    tel, q0 = powered_record(20.0, 20.0), q_pitch(10 * DEG)
    ep = tel[::80, 0]
    sig = np.array([1.0, 0.5, 0.2, 0.1, 0.05, 0.02, 1e-4, 2e-4, 3e-4,
                    1e-3, 2e-3, 3e-3, 1e-5, 2e-5, 3e-5])
    X = np.stack([igea.nav_errors_li(site, tel, q0=q0, epochs=ep, x0=np.eye(15)[j]).position
                  for j in range(15)], axis=-1)           # (n, 3, 15)
    r = igea.nav_errors_li(site, tel, q0=q0, epochs=ep, q=np.zeros(12),
                           p0=np.diag(sig ** 2))
    want = np.einsum("nij,j,nkj->nik", X, sig ** 2, X)
    # RK4 of the covariance equation and the RK4 transition applied on both
    # sides agree up to the truncation of each step: 1e-7 relative
    np.testing.assert_allclose(r.covariance[:, 0:3, 0:3], want, rtol=1e-7,
                               atol=1e-10 * np.max(np.abs(want)))
    np.testing.assert_allclose(r.covariance[:, 9:15, 9:15],
                               np.broadcast_to(np.diag(sig[9:] ** 2), (len(ep), 6, 6)))


def test_refusals():
    site = igea.nav_site(0.5, 1.0, 0.0, 0.2)
    tel = powered_record(2.0, 10.0)
    with pytest.raises(ValueError, match="epochs"):
        igea.nav_errors_li(site, tel, epochs=[0.0, 0.15])
    with pytest.raises(ValueError, match="telemetry"):
        igea.nav_errors_li(site, tel[:, :4])
    bad = tel.copy()
    bad[3, 2] = np.nan
    with pytest.raises(ValueError):
        igea.nav_errors_li(site, bad)


def test_driver_trajectory(tmp_path):
    """igea nav --telemetry: the JSON is igea.nav_errors_li's for the same
    record, site, errors and noise; refusals name the option."""
    import json
    import os
    import subprocess
    tel, q0 = powered_record(10.0, 20.0), q_pitch(20 * DEG)
    np.savetxt(tmp_path / "tel.txt", tel, fmt="%.17g")
    drv = os.environ["IGEA_DRIVER"]
    base = [drv, "nav", "--telemetry", str(tmp_path / "tel.txt"), "--lat", "30", "--lon", "110",
            "--azimuth", "80", "--q0", ",".join("%.17g" % v for v in q0)]
    out = subprocess.run(base + ["--acc-bias", "1e-3,-2e-3,0", "--gyro-drift", "0,1e-5,0",
                                 "--pos0", "1,2,3", "--att0", "1e-4,0,0", "--every", "40",
                                 "--gyro-arw", "1e-5,1e-5,2e-5", "--acc-rrw", "1e-5,0,0",
                                 "--json"], capture_output=True, text=True, check=True)
    js = json.loads(out.stdout)
    site = igea.nav_site(30 * DEG, 110 * DEG, 0.0, 80 * DEG)
    x0 = np.zeros(15)
    x0[0:3], x0[6] = [1, 2, 3], 1e-4
    q = np.zeros(12)
    q[3:6] = [1e-10, 1e-10, 4e-10]
    q[6] = 1e-10
    r = igea.nav_errors_li(site, tel, q0=q0, epochs=tel[::40, 0], x0=x0,
                           acc_bias=[1e-3, -2e-3, 0], gyro_drift=[0, 1e-5, 0], q=q)
    np.testing.assert_allclose(js["time"], r.time)
    for key in ("position", "velocity", "attitude", "covariance"):
        np.testing.assert_allclose(np.array(js[key]), getattr(r, key), rtol=1e-12, atol=1e-300)
    bad = subprocess.run(base + ["--gyro-bi", "1e-8,0,0"], capture_output=True, text=True)
    assert bad.returncode == 64 and "--gyro-bi" in bad.stderr and "--gyro-tc" in bad.stderr
    bad = subprocess.run(base + ["--system", "platform"], capture_output=True, text=True)
    assert bad.returncode == 65 and "columns" in bad.stderr


def rot(v):
    """exp([v x]) (Rodrigues)."""
    a = np.linalg.norm(v)
    if a == 0:
        return np.eye(3)
    k = np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]]) / a
    return np.eye(3) + math.sin(a) * k + (1 - math.cos(a)) * k @ k


def test_platform_against_nonlinear():
    """A platform system: the accelerometers sit on a platform that drifts
    from the launch-inertial axes by alpha(t) = alpha0 + eps t (the gyro
    drift), so they read R(alpha)^T f + b; the navigator takes that as f.
    The model's phi is alpha exactly, and its position and velocity errors
    match the nonlinear navigation of those readings to second order."""
    site = igea.nav_site(35 * DEG, 120 * DEG, 0.0, 45 * DEG)
    tr = np.asarray(igea.reference_trajectory(60.0, 20.0, system="platform"))
    h = np.diff(tr[:, 0])
    tel = np.zeros((len(tr), 4))
    tel[:, 0] = tr[:, 0]
    tel[1:, 1:4] = h[:, None] * (tr[:-1, 1:4] + tr[1:, 1:4]) / 2
    e = np.array([2.0, -1.0, 0.5, 0.02, 0.01, -0.03, 2e-4, -1e-4, 3e-4,
                  1e-3, 5e-4, -2e-3, 2e-5, -3e-5, 1e-5])
    d = []
    for s in (1.0, 0.5):
        x = s * e
        lin = igea.nav_errors_li(site, tel, system="platform", x0=x)
        ref = igea.nav_navigate(site, tel, system="platform")
        te = tel.copy()
        for k in range(1, len(tel)):
            tm = 0.5 * (tel[k - 1, 0] + tel[k, 0])
            te[k, 1:4] = rot(x[6:9] + x[12:15] * tm).T @ tel[k, 1:4] + x[9:12] * h[k - 1]
        err = igea.nav_navigate(site, te, system="platform", r0=ref.r[0] + x[0:3],
                                v0=ref.v[0] + x[3:6])
        np.testing.assert_allclose(lin.attitude, x[6:9] + np.outer(tel[:, 0], x[12:15]),
                                   rtol=1e-12, atol=1e-18)
        d.append([np.max(np.abs(err.r - ref.r - lin.position)),
                  np.max(np.abs(err.v - ref.v - lin.velocity)),
                  np.max(np.abs(lin.position)), np.max(np.abs(lin.velocity))])
    for b in range(2):
        assert d[0][b] < 1e-2 * d[0][b + 2]
        assert 3.8 < d[0][b] / d[1][b] < 4.2, (b, d[0][b] / d[1][b])
