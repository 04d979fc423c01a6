"""Sensor noise along a trajectory (igea.nav_errors_li with acc_noise,
gyro_noise, acc_tc, gyro_tc; igea_inserr_li_noise_covariance): white noise
N, bias instability B as a stationary Gauss-Markov bias of correlation time
T and standard deviation s = B sqrt(2 ln 2 / pi) / 0.61736 (the peak of a
Gauss-Markov Allan deviation, computed here), rate random walk K, per
instrument axis, against a Monte Carlo of the launch-inertial error model
written here from its equations (docs/inserr.md, "Along a trajectory"):

    d(dr)/dt = dv,  d(dv)/dt = f x phi + C (b + w_a) + G dr,
    d(phi)/dt = -C (eps + w_g)   (strapdown),   +(eps + w_g)   (platform),

along the reference that the nav core flies (igea.nav_navigate of the
trajectory's trapezoid increments: f from its apparent velocity, C from
the mean quaternion of each interval, G the point-mass gravity gradient
written here), each bias the sum of an exactly discretised Gauss-Markov
process started stationary and a random walk, the state by Euler-Maruyama
at the telemetry interval. The variance of each of the nine navigation
errors at 20, 40, 60 s, estimated with the known mean 0, satisfies
M s2 / sigma^2 ~ chi^2(M): the two-sided 1e-4 interval by the
Wilson-Hilferty approximation."""
import json
import math
import os
import subprocess

import numpy as np
import pytest
from scipy import optimize

import igea

GM = 3.986004418e14
LAT, LON, AZ = 35.0, 110.0, 70.0


def gm_peak():
    """max over x = tau / T of a unit Gauss-Markov's Allan deviation."""
    f = lambda x: -math.sqrt(2 / x**2 * (x - (3 - 4 * math.exp(-x) + math.exp(-2 * x)) / 2))  # noqa: E731
    r = optimize.minimize_scalar(f, bounds=(0.5, 5.0), method="bounded",
                                 options=dict(xatol=1e-10))
    return -r.fun


def dcm(q):
    a, b, c, d = q / np.linalg.norm(q)
    return np.array([[a*a + b*b - c*c - d*d, 2*(b*c - a*d), 2*(b*d + a*c)],
                     [2*(b*c + a*d), a*a - b*b + c*c - d*d, 2*(c*d - a*b)],
                     [2*(b*d - a*c), 2*(c*d + a*b), a*a - b*b - c*c + d*d]])


def skew(v):
    return np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])


def reference(system):
    """The telemetry (trapezoid increments of the reference boost, 60 s at
    20 Hz), its site and q0, and per interval f, C, G of the model."""
    traj = np.asarray(igea.reference_trajectory(60.0, 20.0, system=system))
    cols = 7 if system == "strapdown" else 4
    h = np.diff(traj[:, 0])
    tel = np.zeros((len(traj), cols))
    tel[:, 0] = traj[:, 0]
    tel[1:, 1:cols] = h[:, None] * (traj[:-1, 1:cols] + traj[1:, 1:cols]) / 2
    site = igea.nav_site(math.radians(LAT), math.radians(LON), 0.0, math.radians(AZ))
    q0 = traj[0, 7:11] if system == "strapdown" else None
    nav = igea.nav_navigate(site, tel, system=system, gravity="point_mass", q0=q0)
    Cs = site[7:16].reshape(3, 3)          # LE axes in ECEF (rows)
    r0 = site[4:7]
    f = np.diff(nav.w, axis=0) / h[:, None]
    C = [dcm(nav.q[k - 1] + nav.q[k]) if system == "strapdown" else np.eye(3)
         for k in range(1, len(tel))]
    G = []
    for k in range(1, len(tel)):
        p = Cs.T @ (0.5 * (nav.r[k - 1] + nav.r[k])) + r0      # Earth-centred, inertial
        n = np.linalg.norm(p)
        Gi = GM / n**3 * (3 * np.outer(p, p) / n**2 - np.eye(3))
        G.append(Cs @ Gi @ Cs.T)
    return tel, site, q0, h, f, C, G


ACC = np.array([[1e-3, 2e-3, 1.5e-3], [6e-4, 3e-4, 9e-4], [2e-5, 1e-5, 3e-5]])   # N B K by axis
GYRO = np.array([[2e-5, 1e-5, 3e-5], [3e-6, 6e-6, 4.5e-6], [1e-7, 2e-7, 1e-7]])
TA, TG = 20.0, 30.0


@pytest.mark.parametrize("system", ["strapdown", "platform"])
def test_noise_covariance_montecarlo(system):
    tel, site, q0, h, f, C, G = reference(system)
    ep = np.array([20.0, 40.0, 60.0])
    r = igea.nav_errors_li(site, tel, system=system, gravity="point_mass", q0=q0, epochs=ep,
                           acc_noise=ACC, gyro_noise=GYRO, acc_tc=TA, gyro_tc=TG)
    P = r.covariance
    s = math.sqrt(2 * math.log(2) / math.pi) / gm_peak()
    sa, sg = s * ACC[1], s * GYRO[1]
    # the bias block: the stationary Gauss-Markov variance plus K^2 t
    for k, t in enumerate(ep):
        np.testing.assert_allclose(np.diag(P[k])[9:12], sa**2 + ACC[2]**2 * t, rtol=1e-9)
        np.testing.assert_allclose(np.diag(P[k])[12:15], sg**2 + GYRO[2]**2 * t, rtol=1e-9)
    M = 2000
    rng = np.random.default_rng(18 if system == "strapdown" else 19)
    x = np.zeros((9, M))
    gma = sa[:, None] * rng.standard_normal((3, M))     # stationary at t = 0
    gmg = sg[:, None] * rng.standard_normal((3, M))
    rwa, rwg = np.zeros((3, M)), np.zeros((3, M))
    sign = -1.0 if system == "strapdown" else 1.0
    z, c = 3.8906, 2.0 / (9.0 * M)
    lo, hi = (1 - c - z * math.sqrt(c)) ** 3, (1 - c + z * math.sqrt(c)) ** 3
    check = {int(round(t * 20)): k for k, t in enumerate(ep)}
    seen, ratios = 0, []
    for k in range(len(h)):
        dt, Ck = h[k], C[k]
        ba, bg = gma + rwa, gmg + rwg
        dx = np.zeros_like(x)
        dx[0:3] = x[3:6]
        dx[3:6] = skew(f[k]) @ x[6:9] + Ck @ ba + G[k] @ x[0:3]
        dx[6:9] = sign * (Ck @ bg)
        x = x + dt * dx
        x[3:6] += Ck @ (ACC[0, :, None] * math.sqrt(dt) * rng.standard_normal((3, M)))
        x[6:9] += sign * (Ck @ (GYRO[0, :, None] * math.sqrt(dt) * rng.standard_normal((3, M))))
        fa, fg = math.exp(-dt / TA), math.exp(-dt / TG)
        gma = fa * gma + sa[:, None] * math.sqrt(1 - fa * fa) * rng.standard_normal((3, M))
        gmg = fg * gmg + sg[:, None] * math.sqrt(1 - fg * fg) * rng.standard_normal((3, M))
        rwa += ACC[2, :, None] * math.sqrt(dt) * rng.standard_normal((3, M))
        rwg += GYRO[2, :, None] * math.sqrt(dt) * rng.standard_normal((3, M))
        if k + 1 in check:
            j = check[k + 1]
            for i in range(9):
                ratio = np.mean(x[i] ** 2) / P[j][i, i]
                ratios.append(ratio)
                assert lo < ratio < hi, (j, i, ratio, lo, hi)
                seen += 1
    assert seen == 27
    # the Gauss-Markov part is not negligible: without B each of the nine
    # variances at 60 s falls by more than 30 % (37 % .. 91 %)
    nob = ACC.copy(), GYRO.copy()
    nob[0][1] = nob[1][1] = 0.0
    r0 = igea.nav_errors_li(site, tel, system=system, gravity="point_mass", q0=q0, epochs=ep,
                            acc_noise=nob[0], gyro_noise=nob[1])
    share = 1 - np.diag(r0.covariance[-1])[:9] / np.diag(P[-1])[:9]
    assert share.min() > 0.3, share
    if os.environ.get("IGEA_TEST_VERBOSE"):
        print(system, "MC variance / covariance %.3f .. %.3f in (%.3f, %.3f)"
              % (min(ratios), max(ratios), lo, hi))


def test_gauss_markov_response_decays():
    """With acc_tc and gyro_tc an initial bias decays as b0 e^(-t / T) in
    the response's bias states, and the velocity error of an accelerometer
    bias alone (gyros quiet, a non-rotating platform: dv' = b + G dr) is
    b0 T (1 - e^(-t / T)) to the gravity-gradient coupling (3.2e-3 here)."""
    tel, site, q0, *_ = reference("platform")
    b0 = np.array([1e-3, -2e-3, 5e-4])
    r = igea.nav_errors_li(site, tel, system="platform", acc_bias=b0,
                           gyro_drift=[1e-5, 0, 0], acc_tc=TA, gyro_tc=TG)
    t = r.time
    np.testing.assert_allclose(r.acc_bias, np.outer(np.exp(-t / TA), b0), rtol=1e-10)
    np.testing.assert_allclose(r.gyro_drift[:, 0], 1e-5 * np.exp(-t / TG), rtol=1e-10)
    r = igea.nav_errors_li(site, tel, system="platform", acc_bias=b0, acc_tc=TA)
    want = np.outer(TA * (1 - np.exp(-t / TA)), b0)
    assert np.abs(r.velocity - want).max() < 5e-3 * np.abs(want).max()


def test_driver_bias_instability(tmp_path):
    """igea nav --telemetry --gyro-bi --gyro-tc --acc-bi --acc-tc: the JSON
    is igea.nav_errors_li's with the same noise fit; a bias instability
    without its correlation time is refused naming both options."""
    tel, site, q0, *_ = reference("strapdown")
    np.savetxt(tmp_path / "tel.txt", tel, fmt="%.17g")
    drv = os.environ["IGEA_DRIVER"]
    base = [drv, "nav", "--telemetry", str(tmp_path / "tel.txt"), "--lat", str(LAT), "--lon",
            str(LON), "--azimuth", str(AZ), "--gravity", "point_mass", "--q0",
            ",".join("%.17g" % v for v in q0)]
    opts = ["--acc-vrw", "1e-3,2e-3,1.5e-3", "--acc-bi", "2e-4,1e-4,3e-4", "--acc-tc", "20",
            "--gyro-bi", "1e-6,2e-6,1.5e-6", "--gyro-tc", "30", "--gyro-rrw", "1e-7,2e-7,1e-7",
            "--acc-bias", "1e-3,0,0", "--every", "200", "--json"]
    out = subprocess.run(base + opts, capture_output=True, text=True, check=True)
    js = json.loads(out.stdout)
    acc = np.array([[1e-3, 2e-3, 1.5e-3], [2e-4, 1e-4, 3e-4], [0, 0, 0]])
    gyro = np.array([[0, 0, 0], [1e-6, 2e-6, 1.5e-6], [1e-7, 2e-7, 1e-7]])
    r = igea.nav_errors_li(site, tel, gravity="point_mass", q0=q0, epochs=tel[::200, 0],
                           acc_bias=[1e-3, 0, 0], acc_noise=acc, gyro_noise=gyro, acc_tc=20.0,
                           gyro_tc=30.0)
    for key in ("position", "velocity", "attitude", "covariance"):
        np.testing.assert_allclose(np.array(js[key]), getattr(r, key), rtol=1e-12, atol=1e-300)
    bad = subprocess.run(base + ["--acc-bi", "1e-4,0,0"], capture_output=True, text=True)
    assert bad.returncode == 64 and "--acc-bi" in bad.stderr and "--acc-tc" in bad.stderr
    # each mode refuses the other's options rather than ignore them
    for opt, val in (("--step", "5"), ("--duration", "60"), ("--epochs", "3"),
                     ("--radius", "6.4e6"), ("--g", "9.8"), ("--omega", "0"), ("--vn", "1"),
                     ("--ve", "1"), ("--vertical", "1")):
        bad = subprocess.run(base + [opt, val], capture_output=True, text=True)
        assert bad.returncode == 64 and opt in bad.stderr and "static" in bad.stderr, opt
    for opt, val in (("--lon", "100"), ("--height", "10"), ("--azimuth", "30"),
                     ("--system", "platform"), ("--gravity", "j2"), ("--q0", "1,0,0,0"),
                     ("--every", "2"), ("--pos0", "1,0,0"), ("--vel0", "1,0,0"),
                     ("--att0", "1e-4,0,0")):
        bad = subprocess.run([drv, "nav", "--lat", "45", opt, val], capture_output=True,
                             text=True)
        assert bad.returncode == 64 and opt in bad.stderr and "--telemetry" in bad.stderr, opt
    with pytest.raises(ValueError, match="not both"):
        igea.nav_errors_li(site, tel, q0=q0, q=np.zeros(12), acc_noise=acc)
    with pytest.raises(igea.IgeaError):
        igea.nav_errors_li(site, tel, q0=q0, gyro_noise=gyro)      # B > 0 without gyro_tc


def test_gauss_markov_long_telemetry_interval():
    """A telemetry record at 2-s intervals (the 50-Hz record's increments
    summed) with correlation times of 1 and 1.5 s: each interval is cut into
    steps of a quarter of the shortest correlation time (one RK4 step of
    2 s diverges on -b / T: the bias grew 6-fold per interval). The bias
    states are b0 e^(-t / T) (closed form) and the navigation errors those
    of the 50-Hz record at the same epochs to 2e-3 of their largest."""
    traj = igea.reference_trajectory(40.0, 50.0, system="platform")
    raw = igea.simulate_raw(traj, ["acc_bias_x"], np.arange(1.0, 40.0), system="platform",
                            x=[0.0], noise=False)
    site = igea.nav_site(math.radians(raw.lat), math.radians(raw.lon), raw.height,
                         math.radians(raw.azimuth))
    tel = raw.telemetry
    idx = np.arange(0, len(tel), 100)
    coarse = np.zeros((len(idx), tel.shape[1]))
    coarse[:, 0] = tel[idx, 0]
    coarse[1:, 1:] = np.diff(np.cumsum(tel[:, 1:], axis=0)[idx], axis=0)
    ep = coarse[:, 0]
    kw = dict(system="platform", acc_bias=[1e-3, 2e-3, 0.0], gyro_drift=[0.0, 0.0, 1e-5],
              acc_tc=1.0, gyro_tc=1.5, epochs=ep)
    fine = igea.nav_errors_li(site, tel, **kw)
    got = igea.nav_errors_li(site, coarse, **kw)
    t = ep - ep[0]
    np.testing.assert_allclose(got.acc_bias[:, :2], np.outer(np.exp(-t), [1e-3, 2e-3]),
                               rtol=1e-3, atol=1e-9)
    np.testing.assert_allclose(got.gyro_drift[:, 2], 1e-5 * np.exp(-t / 1.5), rtol=1e-3,
                               atol=1e-11)
    for key in ("position", "velocity", "attitude"):
        a, b = getattr(fine, key), getattr(got, key)
        assert np.abs(a - b).max() < 2e-3 * np.abs(a).max(), key
