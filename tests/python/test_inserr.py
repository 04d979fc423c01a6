"""The INS error model with the Earth rate on, against an independent
integration of the same linear equations written here in component form
(the usual phi-angle equations of a stationary INS in north-east-down axes,
e.g. Titterton & Weston, Strapdown Inertial Navigation Technology, 2nd ed.,
ch. 12) by scipy's DOP853 at rtol 1e-12; the Foucault modulation of the
Schuler oscillation; the covariance equation likewise; the driver."""
import json
import math
import os
import subprocess

import numpy as np
import pytest
from scipy import integrate

import igea

R = 6371008.8
G = 9.80665
W = 7.292115e-5
T6H = 21600.0


def stationary_rhs(lat, w=W):
    """d/dt of (dN, dE, dvN, dvE, phiN, phiE, phiD, bN, bE, epsN, epsE, epsD),
    vertical channel aided (dD = dvD = 0), vehicle at rest."""
    s, c, t = math.sin(lat), math.cos(lat), math.tan(lat)

    def rhs(_, y):
        dN, dE, dvN, dvE, pN, pE, pD, bN, bE, eN, eE, eD = y
        return [dvN,
                dvE,
                G * pE + bN - 2 * w * s * dvE,
                -G * pN + bE + 2 * w * s * dvN,
                -w * s * pE - w * s * dN / R + dvE / R - eN,
                w * s * pN + w * c * pD - dvN / R - eE,
                -w * c * pE - w * c * dN / R - dvE * t / R - eD,
                0.0, 0.0, 0.0, 0.0, 0.0]
    return rhs


def reference(lat, acc, gyro, t, w=W):
    y0 = [0, 0, 0, 0, 0, 0, 0, acc[0], acc[1], gyro[0], gyro[1], gyro[2]]
    sol = integrate.solve_ivp(stationary_rhs(lat, w), (0, t[-1]), y0, method="DOP853",
                              t_eval=t, rtol=1e-12, atol=1e-18)
    assert sol.success
    return sol.y


@pytest.mark.parametrize("lat_deg", [45.0, -30.0, 70.0])
def test_earth_rate_against_scipy(lat_deg):
    acc = [1e-4, -5e-5, 2e-4]           # m/s^2 (10 micro-g class)
    gyro = [4.85e-8, -2e-8, 3e-8]       # rad/s (0.01 deg/h class)
    r = igea.nav_errors(lat=lat_deg, duration=T6H, epochs=361, acc_bias=acc,
                        gyro_drift=gyro)
    y = reference(math.radians(lat_deg), acc, gyro, r.time)
    for got, want in ((r.position[:, 0], y[0]), (r.position[:, 1], y[1]),
                      (r.velocity[:, 0], y[2]), (r.velocity[:, 1], y[3]),
                      (r.attitude[:, 0], y[4]), (r.attitude[:, 1], y[5]),
                      (r.attitude[:, 2], y[6])):
        scale = np.max(np.abs(want))
        assert np.max(np.abs(got - want)) <= 1e-6 * scale
    assert np.all(r.position[:, 2] == 0) and np.all(r.velocity[:, 2] == 0)


def test_foucault_modulation():
    """A north accelerometer bias at 45 N: the Schuler oscillation about
    the mean (b / g) R turns from the north channel into the east one at
    the Foucault rate w sin L (period 24 h / sin L = 33.9 h). To first order
    in w / ws (Britting, Inertial Navigation Systems Analysis, sec. 10),
    dN = (b R / g)(1 - cos(ws t) cos(wf t)), dE = -(b R / g) cos(ws t)
    sin(wf t) (the oscillation's plane turns clockwise seen from above in
    the northern hemisphere), plus the slow 24-h mode of relative size
    w / ws = 0.06; checked to 5 % of b R / g over 6 h (seen: 2.7 % north,
    4.2 % east). After 6 h the plane has turned by wf t = 63.8 degrees."""
    lat, b = 45.0, 1e-4
    r = igea.nav_errors(lat=lat, duration=T6H, epochs=721, acc_bias=[b, 0, 0])
    ws, wf = math.sqrt(G / R), W * math.sin(math.radians(lat))
    t, a = r.time, b * R / G
    dn = a * (1 - np.cos(ws * t) * np.cos(wf * t))
    de = -a * np.cos(ws * t) * np.sin(wf * t)
    assert np.max(np.abs(r.position[:, 0] - dn)) <= 0.05 * a
    assert np.max(np.abs(r.position[:, 1] - de)) <= 0.05 * a


def test_covariance_against_scipy():
    """dP/dt = F P + P F^T + Q with F of stationary_rhs (its Jacobian, taken
    column by column) and Q the densities; accelerometer and gyro white
    noise and bias random walks, Earth rate on, 2 h at 30 N."""
    lat = math.radians(30.0)
    idx = [0, 1, 3, 4, 6, 7, 8, 9, 10, 12, 13, 14]  # igea state slots of the 12 here
    f = stationary_rhs(lat)
    F = np.column_stack([f(0, e) for e in np.eye(12)])
    q = np.array([2.5e-9, 1.5e-9, 1e-9, 1e-15, 2e-15, 3e-15, 1e-12, 2e-12, 0.0,
                  1e-20, 0.0, 2e-20])
    Qd = np.zeros(12)
    Qd[2:4] = q[0:2]                      # acc white N E -> dvN dvE
    Qd[4:7] = q[3:6]                      # gyro white -> phi
    Qd[7:9] = q[6:8]                      # acc bias random walk N E
    Qd[9:12] = q[9:12]                    # gyro drift random walk
    P0 = np.zeros((12, 12))
    P0[7, 7] = P0[8, 8] = 1e-8

    def lyap(_, p):
        P = p.reshape(12, 12)
        return (F @ P + P @ F.T + np.diag(Qd)).ravel()

    t = np.linspace(0, 7200.0, 25)
    sol = integrate.solve_ivp(lyap, (0, t[-1]), P0.ravel(), method="DOP853", t_eval=t,
                              rtol=1e-12, atol=1e-30)
    assert sol.success
    p0 = np.zeros((15, 15))
    p0[9, 9] = p0[10, 10] = 1e-8
    r = igea.nav_errors(lat=30.0, duration=7200.0, epochs=25, q=q, p0=p0)
    for k in range(1, 25):
        want = sol.y[:, k].reshape(12, 12)
        got = r.covariance[k][np.ix_(idx, idx)]
        d = np.sqrt(np.outer(np.diag(want), np.diag(want)))
        ok = d > 0
        assert np.max(np.abs(got - want)[ok] / d[ok]) <= 1e-6
        assert np.all(got[~ok] == 0) or np.max(np.abs(got[~ok])) == 0


def test_driver_matches_python():
    out = subprocess.run([os.environ["IGEA_DRIVER"], "nav", "--lat", "45", "--duration", "7200",
                          "--epochs", "13", "--acc-bias", "1e-4,0,0", "--gyro-drift",
                          "0,4.85e-8,0", "--json"], capture_output=True, text=True, check=True)
    j = json.loads(out.stdout)
    r = igea.nav_errors(lat=45, duration=7200, epochs=13, acc_bias=[1e-4, 0, 0],
                        gyro_drift=[0, 4.85e-8, 0])
    assert np.allclose(j["position"], r.position, rtol=1e-14, atol=0)
    assert np.allclose(j["attitude"], r.attitude, rtol=1e-14, atol=0)
    assert j["time"] == list(r.time)
    bad = subprocess.run([os.environ["IGEA_DRIVER"], "nav", "--acc-bias", "1e-4,x,0"],
                         capture_output=True, text=True)
    assert bad.returncode != 0 and "--acc-bias" in bad.stderr


def test_invalid_arguments():
    with pytest.raises(Exception, match="lat"):
        igea.nav_errors(lat=95.0)
    with pytest.raises(Exception):
        igea.nav_errors(epochs=1)
    with pytest.raises(Exception, match="step"):
        igea.nav_errors(step=-1.0)
    with pytest.raises(Exception):
        igea.nav_errors(q=[-1.0] + [0.0] * 11)


def skew(a):
    return np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])


def nonlinear_ned(lat0, ve, f_b, w_b, t):
    """The full NED mechanisation on the sphere, written here: latitude,
    longitude, velocity, body-to-NED matrix C, with dL/dt = v_N / R,
    dlon/dt = v_E / (R cos L), dv/dt = C f_b - (2 W(L) + rho(L, v)) x v +
    (0, 0, g), dC/dt = C [w_b x] - [(W + rho) x] C; height and vertical
    velocity held at 0 (an aided vertical channel)."""
    def rhs(_, y):
        L, v, C = y[0], y[2:5].copy(), y[5:].reshape(3, 3)
        v[2] = 0.0
        Wn = W * np.array([math.cos(L), 0.0, -math.sin(L)])
        rho = np.array([v[1], -v[0], -v[1] * math.tan(L)]) / R
        dv = C @ f_b - np.cross(2 * Wn + rho, v) + np.array([0, 0, G])
        dv[2] = 0.0
        dC = C @ skew(w_b) - skew(Wn + rho) @ C
        return np.concatenate([[v[0] / R, v[1] / (R * math.cos(L))], dv, dC.ravel()])
    y0 = np.concatenate([[lat0, 0.0], [0.0, ve, 0.0], np.eye(3).ravel()])
    sol = integrate.solve_ivp(rhs, (0, t[-1]), y0, method="DOP853", t_eval=t, rtol=1e-13,
                              atol=1e-15)
    assert sol.success
    return sol.y


@pytest.mark.parametrize("scale", [1.0, 0.5])
def test_moving_east_against_nonlinear(scale):
    """A vehicle flying east at 250 m/s along the 40 N parallel (constant
    latitude, so the frozen coefficients are exact): the true body axes
    stay on NED, the true specific force f = (2W + rho) x v - (0, 0, g),
    the true rate W + rho; the same with the sensor errors added, both
    integrated by the nonlinear mechanisation above. The differences
    (dN = R dL, dE = R cos L dlon, dv, phi from C~ C^T = I - [phi x]) match
    the linear model to second order: within 2e-3 of each signal's peak
    over 3 h, and the mismatch halves (x 0.5 +- 0.1) with the errors."""
    lat, ve = math.radians(40.0), 250.0
    acc = scale * np.array([2e-4, -1e-4, 0.0])
    gyro = scale * np.array([5e-8, 8e-8, -4e-8])
    Wn = W * np.array([math.cos(lat), 0.0, -math.sin(lat)])
    v = np.array([0.0, ve, 0.0])
    rho = np.array([ve, 0.0, -ve * math.tan(lat)]) / R
    f_true = np.cross(2 * Wn + rho, v) - np.array([0, 0, G])
    w_true = Wn + rho
    t = np.linspace(0, 10800.0, 37)
    yt = nonlinear_ned(lat, ve, f_true, w_true, t)
    yc = nonlinear_ned(lat, ve, f_true + acc, w_true + gyro, t)
    dN = R * (yc[0] - yt[0])
    dE = R * math.cos(lat) * (yc[1] - yt[1])
    dv = yc[2:4] - yt[2:4]
    phi = np.zeros((3, t.size))
    for k in range(t.size):
        M = yc[5:, k].reshape(3, 3) @ yt[5:, k].reshape(3, 3).T
        A = 0.5 * (M - M.T)                      # = -[phi x] to first order
        phi[:, k] = [-A[2, 1], -A[0, 2], -A[1, 0]]
    r = igea.nav_errors(lat=40.0, ve=ve, duration=10800.0, epochs=37, acc_bias=acc,
                        gyro_drift=gyro)
    worst = 0.0
    for got, want in ((r.position[:, 0], dN), (r.position[:, 1], dE),
                      (r.velocity[:, 0], dv[0]), (r.velocity[:, 1], dv[1]),
                      (r.attitude[:, 0], phi[0]), (r.attitude[:, 1], phi[1]),
                      (r.attitude[:, 2], phi[2])):
        rel = np.max(np.abs(got - want)) / np.max(np.abs(want))
        assert rel <= 2e-3
        worst = max(worst, rel)
    test_moving_east_against_nonlinear.worst[scale] = worst
    if len(test_moving_east_against_nonlinear.worst) == 2:
        ratio = (test_moving_east_against_nonlinear.worst[0.5]
                 / test_moving_east_against_nonlinear.worst[1.0])
        assert 0.4 <= ratio <= 0.6


test_moving_east_against_nonlinear.worst = {}
