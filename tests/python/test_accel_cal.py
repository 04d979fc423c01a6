"""igea.accel_apply, accel_hysteresis and accel_joint against models and
statistics written here in numpy/scipy."""
import json
import os
import subprocess

import numpy as np
import pytest
from scipy import stats

import igea

ARCSEC = np.pi / 180 / 3600


def exact_pair(K, phi):
    """METHODS 4.2 eqs. (1)-(2): A at phi, B at phi + eta."""
    sa, ca = np.sin(phi), np.cos(phi)
    sb, cb = np.sin(phi + K[4]), np.cos(phi + K[4])
    ya = K[0] + (1 + K[2]) * sa + K[5] * sa ** 2 + K[7] * sa * ca
    yb = K[1] + (1 + K[3]) * cb + K[6] * cb ** 2 - K[8] * cb * sb
    return ya, yb


def test_apply_dual_round_trip():
    K = np.array([2e-3, -1.5e-3, 3e-3, -2e-3, 5e-3, 2e-3, -1e-3, 1e-3, -2e-3])
    phi = np.deg2rad(np.linspace(-170, 175, 40))
    ya, yb = exact_pair(K, phi)
    out = igea.accel_apply(4.0 * ya, K, 4.0 * yb, scale_a=4.0, scale_b=4.0)
    np.testing.assert_allclose(out.u, np.sin(phi), rtol=0, atol=2e-15)
    np.testing.assert_allclose(out.v, np.cos(phi), rtol=0, atol=2e-15)
    # the simulator, noise-free, with an installation angle
    th = igea.accel_schedule(20)
    truth = np.append(K, 1e-3)
    sa, sb = igea.accel_simulate(th, truth, head_sd_arcsec=0, noise_sd=0)
    out = igea.accel_apply(sa, K, sb)
    np.testing.assert_allclose(out.u, np.sin(np.deg2rad(th) + 1e-3), atol=2e-15)


def test_apply_single_and_errors():
    K = np.array([1e-3, -2e-3, 3e-4, 4e-3, -3e-3])
    u = np.linspace(-1, 1, 15)
    v = np.sqrt(1 - u ** 2)
    y = K[0] + (1 + K[1]) * u + K[2] * v + K[3] * u ** 2 + K[4] * u * v
    out = igea.accel_apply(2.5 * y, K, model="single", scale_a=2.5, cross=v)
    np.testing.assert_allclose(out.u, u, atol=2e-15)
    assert out.v is None
    # without the cross axis: the quadratic's root closest to y, numpy
    r = np.array([np.roots([K[3], 1 + K[1], K[0] - yi]) for yi in y])
    want = r[np.arange(len(y)), np.argmin(np.abs(r - y[:, None]), axis=1)].real
    np.testing.assert_allclose(igea.accel_apply(y, K, model="single").u, want, atol=1e-15)
    with pytest.raises(igea.IgeaError):
        igea.accel_apply(y, K, model="single", scale_a=0.0)
    with pytest.raises(ValueError):
        igea.accel_apply(y, np.zeros(9))


def ref_hysteresis(ang, y, d):
    """Pooled-variance F test of zero CW - CCW, numpy/scipy."""
    pos = np.unique(ang)
    diff, w, ss, n = [], [], 0.0, len(y)
    for a in pos:
        cw, ccw = y[(ang == a) & (d > 0)], y[(ang == a) & (d < 0)]
        diff.append(cw.mean() - ccw.mean())
        w.append(1 / len(cw) + 1 / len(ccw))
        ss += ((cw - cw.mean()) ** 2).sum() + ((ccw - ccw.mean()) ** 2).sum()
    df2 = n - 2 * len(pos)
    s2 = ss / df2
    diff, w = np.array(diff), np.array(w)
    F = np.sum(diff ** 2 / (s2 * w)) / len(pos)
    return diff, np.sqrt(s2 * w), F, df2, stats.f.sf(F, len(pos), df2)


def test_hysteresis_against_scipy():
    rng = np.random.default_rng(5)
    ang = np.repeat(np.arange(8) * 45.0, 5)
    d = np.tile([1, 1, -1, -1, -1], 8)
    y = np.sin(np.deg2rad(ang)) + 1e-6 * rng.standard_normal(ang.size) + 2e-6 * (d > 0)
    h = igea.accel_hysteresis(ang, y, d)
    diff, sd, F, df2, p = ref_hysteresis(ang, y, d)
    np.testing.assert_allclose(h.diff, diff, rtol=1e-9, atol=1e-17)
    np.testing.assert_allclose(h.diff_sd, sd, rtol=1e-12)
    assert h.df1 == 8 and h.df2 == df2 == 24
    np.testing.assert_allclose([h.f, h.p], [F, p], rtol=1e-10)
    np.testing.assert_array_equal(h.n_cw, 2)
    np.testing.assert_array_equal(h.n_ccw, 3)


def test_hysteresis_driver(tmp_path):
    """Two runs, 0..360 counter-clockwise then 360..0 clockwise, each
    reading taken twice; the driver infers the directions from the row
    order and agrees with the Python call given them explicitly."""
    th = np.arange(0, 361, 30.0)
    rng = np.random.default_rng(9)
    ang = np.concatenate([np.repeat(th, 2), np.repeat(th[::-1], 2)])
    d = np.concatenate([-np.ones(2 * th.size), np.ones(2 * th.size)])
    ya = np.sin(np.deg2rad(ang)) + 1e-6 * rng.standard_normal(ang.size) + 3e-6 * (d > 0)
    yb = np.cos(np.deg2rad(ang)) + 1e-6 * rng.standard_normal(ang.size)
    f = tmp_path / "run.txt"
    np.savetxt(f, np.column_stack([ang, ya, yb]))
    out = subprocess.run([os.environ.get("IGEA_DRIVER", "igea"), "accel", "--hysteresis",
                          "--json", "--data", str(f)], capture_output=True, text=True, check=True)
    js = json.loads(out.stdout)
    for key, y in (("hysteresis_a", ya), ("hysteresis_b", yb)):
        h = igea.accel_hysteresis(ang, y, d)
        np.testing.assert_allclose(js[key]["diff"], h.diff, rtol=1e-12, atol=1e-18)
        assert js[key]["df2"] == h.df2 == ang.size - 2 * 12
        np.testing.assert_allclose(js[key]["p"], h.p, rtol=1e-12)
    assert js["hysteresis_a"]["p"] < 1e-3 < js["hysteresis_b"]["p"]


TRUTH = np.array([2e-4, -1.5e-4, 3e-4, -2e-4, 5e-5, 2e-5, -1e-5, 1e-5, -2e-5])


def ref_joint(theta, ya, yb):
    """The joint estimator written from docs/accel.md: the radial (g^2)
    equation on the dual design and the tangential equation
    z = c (y_A - s) - s (y_B - c), each with its residual variance from its
    own least squares, stacked by weighted least squares."""
    t = np.deg2rad(theta)
    s, c = np.sin(t), np.cos(t)
    z0 = np.zeros_like(s)
    A1 = np.column_stack([s, c, s * s, c * c, -s * c, s ** 3, c ** 3, s * s * c, -s * c * c, z0])
    A2 = np.column_stack([c, -s, s * c, -s * c, s * s, s * s * c, -s * c * c, s * c * c,
                          s * s * c, np.ones_like(s)])
    y1 = (ya ** 2 + yb ** 2 - 1) / 2
    y2 = c * (ya - s) - s * (yb - c)

    def var(A, y):
        x, _, r, _ = np.linalg.lstsq(A, y, rcond=None)
        return np.sum((y - A @ x) ** 2) / (len(y) - r)
    v1, v2 = var(A1, y1), var(A2, y2)
    A = np.vstack([A1 / np.sqrt(v1), A2 / np.sqrt(v2)])
    y = np.concatenate([y1 / np.sqrt(v1), y2 / np.sqrt(v2)])
    assert np.linalg.matrix_rank(A) == 10
    x = np.linalg.solve(A.T @ A, A.T @ y)
    return x, np.linalg.inv(A.T @ A), np.sqrt([v1, v2])


def test_joint_against_numpy():
    th = igea.accel_schedule(20)
    ya, yb = igea.accel_simulate(th, np.append(TRUTH, 2e-4), head_sd_arcsec=1, noise_sd=1e-6,
                                 seed=11)
    j = igea.accel_joint(th, ya, yb)
    x, cov, comp = ref_joint(th, ya, yb)
    np.testing.assert_allclose(j.coef, x, rtol=1e-6, atol=1e-13)
    np.testing.assert_allclose(j.cov, cov, rtol=1e-6, atol=1e-22)
    np.testing.assert_allclose(j.sd, np.sqrt(np.diag(cov)), rtol=1e-6)
    np.testing.assert_allclose([j.sd_radial, j.sd_angle], comp, rtol=1e-8)
    assert j.rank == 10 and j.dof == 30
    assert j.names[-1] == "delta0"
    # the combinations: C^T x with the dual fit's C
    C = igea.accel_combinations("dual")
    np.testing.assert_allclose(j.comb, C.T @ x[:9], rtol=1e-6, atol=1e-13)
    np.testing.assert_allclose(j.comb_sd, np.sqrt(np.diag(C.T @ cov[:9, :9] @ C)), rtol=1e-6)


def test_joint_driver(tmp_path):
    th = igea.accel_schedule(20)
    ya, yb = igea.accel_simulate(th, np.append(TRUTH, 0), head_sd_arcsec=1, noise_sd=1e-6, seed=4)
    f = tmp_path / "d.txt"
    np.savetxt(f, np.column_stack([th, 2.5 * ya, 2.5 * yb]))
    drv = os.environ.get("IGEA_DRIVER", "igea")
    out = subprocess.run([drv, "accel", "--method", "joint", "--scale-a", "2.5", "--scale-b",
                          "2.5", "--json", "--data", str(f)], capture_output=True, text=True,
                         check=True)
    js = json.loads(out.stdout)
    j = igea.accel_joint(th, ya, yb)
    np.testing.assert_allclose(js["coef"], j.coef, rtol=1e-9, atol=1e-15)  # volts: rounding
    np.testing.assert_allclose(js["sd"], j.sd, rtol=1e-9)
    assert js["flags"] == ["data"] * 10 and js["rank"] == 10
    assert js["names"] == j.names
    np.testing.assert_allclose([js["sd_radial"], js["sd_angle"]], [j.sd_radial, j.sd_angle],
                               rtol=1e-8)
    bad = subprocess.run([drv, "accel", "--method", "joint", "--model", "single", "--data",
                          str(f)], capture_output=True, text=True)
    assert bad.returncode == 64 and "joint" in bad.stderr
