"""Sensor noise from IEEE Std 952 coefficients (igea.nav_errors with
acc_noise, gyro_noise: white noise N, bias instability B as a Gauss-Markov
bias of correlation time T, rate random walk K) against a Monte Carlo of
the same linear model written here: the stationary phi-angle equations in
north-east-down axes (vertical channel aided; Titterton & Weston, Strapdown
Inertial Navigation Technology, 2nd ed., ch. 12), each bias the sum of an
exactly discretised Gauss-Markov process of standard deviation
s = B sqrt(2 ln 2 / pi) / 0.61736 (the peak of a Gauss-Markov Allan
deviation, computed here) started stationary, and a random walk; white
noise and the state by Euler-Maruyama at 1 s over 1 h (the Schuler period
is 5064 s). The variance of each checked error at each checked epoch,
estimated with the known mean 0, satisfies M s2 / sigma^2 ~ chi^2(M): the
two-sided 1e-4 interval by the Wilson-Hilferty approximation."""
import math

import numpy as np
import pytest
from scipy import optimize

import igea

R, G, W = 6371008.8, 9.80665, 7.292115e-5


def gm_peak():
    """max over x = tau / T of a unit Gauss-Markov's Allan deviation."""
    f = lambda x: -math.sqrt(2 / x**2 * (x - (3 - 4 * math.exp(-x) + math.exp(-2 * x)) / 2))  # noqa: E731
    r = optimize.minimize_scalar(f, bounds=(0.5, 5.0), method="bounded",
                                 options=dict(xatol=1e-10))
    return -r.fun


def nav_matrix(lat):
    """A of d/dt (dN, dE, dvN, dvE, phiN, phiE, phiD) = A x + Bb (bN, bE) +
    Be (eN, eE, eD) (the stationary equations, vehicle at rest)."""
    s, c = math.sin(lat), math.cos(lat)
    A = np.zeros((7, 7))
    A[0, 2] = A[1, 3] = 1.0
    A[2, 5], A[2, 3] = G, -2 * W * s
    A[3, 4], A[3, 2] = -G, 2 * W * s
    A[4, 5], A[4, 0], A[4, 3] = -W * s, -W * s / R, 1 / R
    A[5, 4], A[5, 6], A[5, 2] = W * s, W * c, -1 / R
    A[6, 5], A[6, 0], A[6, 3] = -W * c, -W * c / R, -math.tan(lat) / R
    return A


def test_noise_fit_covariance_montecarlo():
    lat = math.radians(45.0)
    acc = np.array([[2e-4, 2e-4, 0.0], [5e-5, 3e-5, 0.0], [2e-6, 1e-6, 0.0]])   # N B K by axis
    gyro = np.array([[3e-6, 2e-6, 4e-6], [1e-7, 2e-7, 1e-7], [2e-9, 1e-9, 2e-9]])
    ta, tg = 300.0, 900.0
    dur, nep = 3600.0, 4
    r = igea.nav_errors(lat=45.0, duration=dur, epochs=nep, acc_noise=acc, gyro_noise=gyro,
                        acc_tc=ta, gyro_tc=tg)
    P = r.covariance
    sa = acc[1] * math.sqrt(2 * math.log(2) / math.pi) / gm_peak()
    sg = gyro[1] * math.sqrt(2 * math.log(2) / math.pi) / gm_peak()
    # the bias block: the stationary Gauss-Markov variance plus K^2 t
    for k in range(nep):
        t = k * dur / (nep - 1)
        np.testing.assert_allclose(np.diag(P[k])[9:11], sa[:2] ** 2 + acc[2, :2] ** 2 * t,
                                   rtol=1e-9)
        np.testing.assert_allclose(np.diag(P[k])[12:15], sg ** 2 + gyro[2] ** 2 * t, rtol=1e-9)
    M, h = 2000, 1.0
    rng = np.random.default_rng(18)
    A = nav_matrix(lat)
    x = np.zeros((7, M))
    gma = sa[:2, None] * rng.standard_normal((2, M))
    gmg = sg[:, None] * rng.standard_normal((3, M))
    rwa, rwg = np.zeros((2, M)), np.zeros((3, M))
    fa, fg = math.exp(-h / ta), math.exp(-h / tg)
    steps = int(dur / h)
    check = {int(k * dur / (nep - 1) / h): k for k in range(1, nep)}
    z, c = 3.8906, 2.0 / (9.0 * M)
    lo, hi = (1 - c - z * math.sqrt(c)) ** 3, (1 - c + z * math.sqrt(c)) ** 3
    seen = 0
    for s in range(1, steps + 1):
        ba, bg = gma + rwa, gmg + rwg
        dx = A @ x
        dx[2:4] += ba
        dx[4:7] -= bg
        x = x + h * dx
        x[2:4] += acc[0, :2, None] * math.sqrt(h) * rng.standard_normal((2, M))
        x[4:7] -= gyro[0, :, None] * math.sqrt(h) * rng.standard_normal((3, M))
        gma = fa * gma + sa[:2, None] * math.sqrt(1 - fa * fa) * rng.standard_normal((2, M))
        gmg = fg * gmg + sg[:, None] * math.sqrt(1 - fg * fg) * rng.standard_normal((3, M))
        rwa += acc[2, :2, None] * math.sqrt(h) * rng.standard_normal((2, M))
        rwg += gyro[2, :, None] * math.sqrt(h) * rng.standard_normal((3, M))
        if s in check:
            k = check[s]
            # state slots of igea: dN 0, dE 1, dvN 3, dvE 4, phiN 6, phiE 7, phiD 8
            for mine, slot in ((0, 0), (1, 1), (2, 3), (3, 4), (4, 6), (5, 7), (6, 8)):
                ratio = np.mean(x[mine] ** 2) / P[k][slot, slot]
                assert lo < ratio < hi, (k, slot, ratio, lo, hi)
                seen += 1
    assert seen == 7 * (nep - 1)


def test_noise_parts_add():
    """White, Gauss-Markov and random-walk parts: the covariance of all
    three is the sum of the three alone (the model is linear), and each
    part is not negligible in the east-west position here."""
    kw = dict(lat=30.0, duration=7200.0, epochs=5, acc_tc=200.0, gyro_tc=600.0)
    parts = []
    for i in range(3):
        a = np.zeros((3, 3))
        g = np.zeros((3, 3))
        a[i] = [1e-4, 2e-5, 1e-6][i]
        g[i] = [1e-6, 5e-8, 1e-9][i]
        parts.append(igea.nav_errors(acc_noise=a, gyro_noise=g, **kw).covariance)
    a = np.array([[1e-4] * 3, [2e-5] * 3, [1e-6] * 3])
    g = np.array([[1e-6] * 3, [5e-8] * 3, [1e-9] * 3])
    tot = igea.nav_errors(acc_noise=a, gyro_noise=g, **kw).covariance
    np.testing.assert_allclose(tot, sum(parts), rtol=1e-10, atol=1e-300)
    for p in parts:
        assert p[-1][1, 1] > 0.01 * tot[-1][1, 1]


def test_noise_fit_object_and_refusals():
    fit = igea.NoiseFit(("quantization", "random_walk", "bias_instability",
                         "rate_random_walk", "rate_ramp"),
                        np.array([0.0, 1e-6, 5e-8, 1e-9, 0.0]), np.zeros(5),
                        np.ones(5, dtype=bool), 0.0)
    r1 = igea.nav_errors(lat=10.0, duration=600.0, epochs=3, gyro_noise=fit, gyro_tc=100.0)
    r2 = igea.nav_errors(lat=10.0, duration=600.0, epochs=3, gyro_noise=[1e-6, 5e-8, 1e-9],
                         gyro_tc=100.0)
    np.testing.assert_array_equal(r1.covariance, r2.covariance)
    with pytest.raises(igea.IgeaError):   # B > 0 needs its correlation time
        igea.nav_errors(duration=600.0, epochs=3, gyro_noise=[1e-6, 5e-8, 0.0])
    with pytest.raises(ValueError, match="acc_noise"):
        igea.nav_errors(duration=600.0, epochs=3, acc_noise=[1.0, 2.0])
    with pytest.raises(ValueError, match="not both"):
        igea.nav_errors(duration=600.0, epochs=3, acc_noise=[1e-4, 0, 0], q=np.zeros(12))
    with pytest.raises(igea.IgeaError, match="acc_tc"):
        igea.nav_errors(duration=600.0, epochs=3, acc_tc=0.5)


def test_driver_noise_options():
    """igea nav --gyro-arw/--gyro-bi/--gyro-tc/--acc-vrw: the JSON covariance
    is the one igea.nav_errors gives for the same coefficients; a bias
    instability without its correlation time is refused naming the option."""
    import json
    import os
    import subprocess
    drv = os.environ["IGEA_DRIVER"]
    out = subprocess.run([drv, "nav", "--lat", "30", "--duration", "1800", "--epochs", "4",
                          "--acc-vrw", "1e-4,2e-4,0", "--gyro-arw", "1e-6,1e-6,2e-6",
                          "--gyro-bi", "5e-8,5e-8,5e-8", "--gyro-tc", "600", "--json"],
                         capture_output=True, text=True, check=True)
    js = json.loads(out.stdout)
    r = igea.nav_errors(lat=30.0, duration=1800.0, epochs=4,
                        acc_noise=[[1e-4, 2e-4, 0], [0, 0, 0], [0, 0, 0]],
                        gyro_noise=[[1e-6, 1e-6, 2e-6], [5e-8] * 3, [0, 0, 0]], gyro_tc=600.0)
    np.testing.assert_allclose(np.array(js["covariance"]), r.covariance, rtol=1e-12, atol=0)
    bad = subprocess.run([drv, "nav", "--gyro-bi", "1e-8,0,0"], capture_output=True, text=True)
    assert bad.returncode == 64 and "--gyro-bi" in bad.stderr and "--gyro-tc" in bad.stderr
    bad = subprocess.run([drv, "nav", "--acc-rrw", "1e-6,-1,0"], capture_output=True, text=True)
    assert bad.returncode == 64 and "--acc-rrw" in bad.stderr
