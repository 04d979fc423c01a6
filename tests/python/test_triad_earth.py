"""The Earth's rate in the gyro triad calibration (docs/calibration.md,
"The Earth's rate"): records of a navigation-grade IMU simulated here at
latitude 45 deg, whose gyros see the Earth's rotation in every static
attitude and during every turn, with a random heading; the biases, the
scale factors and misalignments, the horizontal Earth rate and the heading
within 3 sd of the truth with lat=, and the biases off by many sd without
it (the static mean holds the Earth's rate projected on each attitude)."""
import math

import numpy as np
import pytest
from scipy import stats
from scipy.spatial.transform import Rotation as Rot

import igea

G = 9.80665
FS = 100.0
W = 7.292115e-5
ACC = np.array([0.02, -0.015, 0.01, 1.0005, 0.9996, 1.0003, 2.0e-4, -1.5e-4, 1.0e-4])
GYR = np.array([3e-5, -2e-5, 1.5e-5,                       # biases, rad/s (~6 deg/h)
                1.0004, 0.9997, 1.0002,                    # scale factors
                2.0e-4, -1.5e-4, 1.0e-4, 2.5e-4, -0.8e-4, 1.2e-4])


def gyro_S(theta):
    k, m = theta[3:6], theta[6:]
    M = np.array([[1, m[0], m[1]], [m[2], 1, m[3]], [m[4], m[5], 1]])
    return M * k


def simulate(rng, lat_deg, attitudes=30, static=5.0, move=2.0, init=30.0, an=5e-5,
             gn=3e-6):
    """An IMU at rest on the Earth at lat_deg (local frame east, north, up):
    an initial static period at a random heading, then `attitudes` random
    attitudes held `static` s, each reached by a turn about a body-fixed
    axis with a (1 - cos) rate profile over `move` s. The accelerometers
    read the specific force (g up); the gyros the turn's rate plus the
    Earth's rate (0, W cos lat, W sin lat) in the body axes, in the static
    periods and during the turns. Returns raw acc, raw gyro (n, 3) and the
    heading of the body x axis in the first period (deg from north towards
    east)."""
    lat = math.radians(lat_deg)
    wn = np.array([0.0, W * math.cos(lat), W * math.sin(lat)])
    C0 = Rot.from_euler("z", rng.uniform(0, 360), degrees=True)
    C = Rot.concatenate([C0, Rot.random(attitudes, random_state=rng)])
    f, w = [], []
    for i in range(attitudes + 1):
        n = int((init if i == 0 else static) * FS)
        f.append(np.tile(C[i].inv().apply([0, 0, G]), (n, 1)))
        w.append(np.tile(C[i].inv().apply(wn), (n, 1)))
        if i < attitudes:
            d = (C[i].inv() * C[i + 1]).as_rotvec()
            phi = np.linalg.norm(d)
            u = d / phi
            nm = int(move * FS)
            s = np.arange(1, nm + 1) / (nm + 1)
            ang = phi * (s - np.sin(2 * np.pi * s) / (2 * np.pi))
            rate = phi * FS / (nm + 1) * (1 - np.cos(2 * np.pi * s))
            body = C[i] * Rot.from_rotvec(np.outer(ang, u))
            f.append(body.inv().apply([0, 0, G]) + 0.05 * rng.normal(size=(nm, 3)))
            w.append(np.outer(rate, u) + body.inv().apply(wn))
    f, w = np.vstack(f), np.vstack(w)
    b, k, (tyx, tzx, tzy) = ACC[:3], ACC[3:6], ACC[6:]
    T = np.array([[1, 0, 0], [tyx, 1, 0], [tzx, tzy, 1]])
    raw_a = np.linalg.solve(T, f.T).T / k + b + an * rng.normal(size=f.shape)
    raw_g = np.linalg.solve(gyro_S(GYR), w.T).T + GYR[:3] + gn * rng.normal(size=w.shape)
    x_enu = C0.apply([1.0, 0.0, 0.0])
    return raw_a, raw_g, math.degrees(math.atan2(x_enu[0], x_enu[1])) % 360.0


def test_biases_within_3_sd_at_45_deg_and_not_without_the_earth_rate():
    rng = np.random.default_rng(45)
    raw_a, raw_g, heading = simulate(rng, 45.0)
    r = igea.triad_calibrate(raw_a, FS, gyro=raw_g, lat=45.0)
    g = r.gyro
    z = (g.theta - GYR) / g.sd
    assert np.all(np.abs(z[:3]) < 3), z[:3]           # the biases
    assert np.all(np.abs(z[3:]) < 3), z[3:]           # scale factors, misalignments
    # the horizontal Earth rate and the heading the static intervals show
    assert abs(g.earth_h - W * math.cos(math.radians(45))) < 3 * g.earth_h_sd
    dpsi = (g.heading - heading + 180.0) % 360.0 - 180.0
    assert abs(dpsi) < 3 * g.heading_sd, (g.heading, heading, g.heading_sd)
    assert g.heading_sd < 2.0                          # a gyrocompass to a degree or two
    # without the Earth's rate the static mean holds it: biases off by many sd
    r0 = igea.triad_calibrate(raw_a, FS, gyro=raw_g)
    z0 = (r0.gyro.theta[:3] - GYR[:3]) / r0.gyro.sd[:3]
    assert np.max(np.abs(z0)) > 10, z0
    assert r0.gyro.earth_h is None


def test_within_3_sd_over_records():
    """RECORDS records at 45 deg: the 12 gyro parameters' standardised
    errors within 3 sd at the normal rate 0.9973 less 3.1 binomial sds
    (a 99.9 % bound; the biases' sds rest on thousands of samples, the
    others on 2 x 30 - 9 = 51 dof, P(|t51| < 3) = 0.9958), and no
    parameter's mean standardised error beyond 3.3 / sqrt(RECORDS)."""
    RECORDS = 12
    rng = np.random.default_rng(46)
    z = []
    for _ in range(RECORDS):
        raw_a, raw_g, _ = simulate(rng, 45.0)
        g = igea.triad_calibrate(raw_a, FS, gyro=raw_g, lat=45.0).gyro
        z.append((g.theta - GYR) / g.sd)
    z = np.array(z)
    p = 1 - 2 * stats.t.sf(3, 51)
    assert np.mean(np.abs(z) < 3) >= p - 3.1 * math.sqrt(p * (1 - p) / z.size)
    assert np.all(np.abs(z.mean(axis=0)) < 3.3 / math.sqrt(RECORDS)), z.mean(axis=0)


def test_the_vertical_component_alone_is_not_enough():
    """Subtracting only W sin(lat) along gravity leaves the horizontal part,
    W cos(lat) projected on each attitude's horizontal plane, in the
    static means: the mean of the static samples minus the vertical part
    misses the biases by up to W cos(lat) (|bias error| well above 3 sd
    here), which is why igea estimates the horizontal part too."""
    rng = np.random.default_rng(47)
    raw_a, raw_g, _ = simulate(rng, 45.0)
    r = igea.triad_calibrate(raw_a, FS, gyro=raw_g, lat=45.0)
    iv = r.static_intervals
    acc_cal = r.apply(raw_a)
    sl = math.sin(math.radians(45.0))
    resid = []
    for s, e in iv:
        v = acc_cal[s:e].mean(axis=0)
        v /= np.linalg.norm(v)
        vert = np.linalg.solve(gyro_S(r.gyro.theta), W * sl * v)
        resid.append((raw_g[s:e] - vert).mean(axis=0))
    n = np.array([e - s for s, e in iv])
    b_vert = (np.array(resid) * n[:, None]).sum(axis=0) / n.sum()
    assert np.max(np.abs(b_vert - GYR[:3]) / r.gyro.sd[:3]) > 3
    assert np.max(np.abs(b_vert - GYR[:3])) < W * math.cos(math.radians(45.0))


def test_no_earth_rate_is_the_old_fit():
    """earth_rate 0 (at any latitude) is igea_triad_gyro_fit's model: the
    same numbers; lat without earth_rate takes EARTH_RATE; earth_rate
    without lat and latitudes beyond 90 deg are refused."""
    rng = np.random.default_rng(48)
    raw_a, raw_g, _ = simulate(rng, 30.0, attitudes=16)
    acc = igea.triad_calibrate(raw_a, FS)
    iv, means = igea.triad_static(raw_a, FS, threshold=acc.threshold)
    a = igea.triad_gyro_fit(raw_g, FS, iv, means, acc.theta, cov_a=acc.covariance)
    b = igea.triad_gyro_fit(raw_g, FS, iv, means, acc.theta, cov_a=acc.covariance, lat=30.0,
                            earth_rate=0.0)
    np.testing.assert_array_equal(a.theta, b.theta)
    np.testing.assert_array_equal(a.covariance, b.covariance)
    c = igea.triad_gyro_fit(raw_g, FS, iv, means, acc.theta, cov_a=acc.covariance, lat=30.0)
    d = igea.triad_gyro_fit(raw_g, FS, iv, means, acc.theta, cov_a=acc.covariance, lat=30.0,
                            earth_rate=igea.triad.EARTH_RATE)
    np.testing.assert_array_equal(c.theta, d.theta)
    assert abs(c.theta[0] - a.theta[0]) > 1e-6
    with pytest.raises(ValueError, match="earth_rate"):
        igea.triad_gyro_fit(raw_g, FS, iv, means, acc.theta, earth_rate=W)
    with pytest.raises(igea.IgeaError, match="lat"):
        igea.triad_gyro_fit(raw_g, FS, iv, means, acc.theta, lat=91.0)
    with pytest.raises(igea.IgeaError, match="lat"):
        igea.triad_calibrate(raw_a, FS, gyro=raw_g, lat=-90.5)


# ---- the driver ------------------------------------------------------------------
import json  # noqa: E402
import os  # noqa: E402
import subprocess  # noqa: E402

DRIVER = os.environ.get("IGEA_DRIVER")


@pytest.mark.skipif(not DRIVER or not os.path.exists(DRIVER), reason="IGEA_DRIVER not set")
def test_driver_lat_is_the_python_result(tmp_path):
    """igea triad --lat 45 --json gives igea.triad_calibrate(lat=45)'s gyro
    fields (earth_h, heading and their sds, lat, earth_rate); without --lat
    they are null; --earth-rate needs --lat, --lat needs --gyro."""
    rng = np.random.default_rng(49)
    raw_a, raw_g, heading = simulate(rng, 45.0, attitudes=16)
    t = np.arange(len(raw_a)) / FS
    fa, fg = tmp_path / "acc.npy", tmp_path / "gyro.npy"
    np.save(fa, np.c_[t, raw_a])
    np.save(fg, np.c_[t, raw_g])
    p = subprocess.run([DRIVER, "triad", "--acc", str(fa), "--gyro", str(fg), "--lat", "45",
                        "--json"], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    d = json.loads(p.stdout)["gyro"]
    r = igea.triad_calibrate(raw_a, FS, gyro=raw_g, lat=45.0).gyro.to_dict()
    assert set(d) == set(r)
    np.testing.assert_allclose(d["theta"], r["theta"], rtol=1e-9)
    for key in ("earth_h", "earth_h_sd", "heading", "heading_sd", "lat", "earth_rate"):
        assert d[key] == pytest.approx(r[key], rel=1e-9), key
    assert abs((d["heading"] - heading + 180) % 360 - 180) < 3 * d["heading_sd"]
    text = subprocess.run([DRIVER, "triad", "--acc", str(fa), "--gyro", str(fg), "--lat", "45"],
                          capture_output=True, text=True)
    assert text.returncode == 0 and "heading of the x axis" in text.stdout
    p = subprocess.run([DRIVER, "triad", "--acc", str(fa), "--gyro", str(fg), "--json"],
                       capture_output=True, text=True)
    assert json.loads(p.stdout)["gyro"]["heading"] is None
    p = subprocess.run([DRIVER, "triad", "--acc", str(fa), "--gyro", str(fg), "--earth-rate",
                        "7.3e-5"], capture_output=True, text=True)
    assert p.returncode == 64 and "--earth-rate needs --lat" in p.stderr
    p = subprocess.run([DRIVER, "triad", "--acc", str(fa), "--lat", "45"], capture_output=True,
                       text=True)
    assert p.returncode == 64 and "--lat needs --gyro" in p.stderr
    p = subprocess.run([DRIVER, "triad", "--acc", str(fa), "--gyro", str(fg), "--lat", "95"],
                       capture_output=True, text=True)
    assert p.returncode == 64 and "lat" in p.stderr
