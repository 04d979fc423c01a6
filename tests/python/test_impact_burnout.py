"""The burnout from a trajectory and a burnout time (igea.burnout,
igea_impact_burnout; docs/impact.md "From a burnout time"):

- the state against the nav core's navigation of the trajectory's
  trapezoid increments (built here with numpy, a partial last interval
  too), turned into ECEF here from the frame definitions of
  docs/pipeline.md;
- the burnout errors E against finite differences of a nonlinear
  navigation computed here: the nav core flying telemetry to which the
  test adds each error (accelerometer biases, scale factor and
  misalignment, gyro biases and g-sensitive drift, initial attitude as a
  finite rotation; a drifting platform), second order; and against the
  launch-inertial error model (igea.nav_errors_li, another linear model
  along the same reference);
- the miss of each tested component of 'igea eqerr --burnout-time' and
  igea.eqerr(burnout_time=) against numpy's G E p_i x_i, and 'igea impact
  --burnout-time --terms' against igea.burnout and igea.impact_budget."""
import json
import math
import os
import subprocess

import numpy as np
import pytest

import igea
from igea.envfun import default_spec

W_E = 7.292115e-5
LAT, LON, H, AZ = 40.96, 100.29, 1000.0, 30.0
TB = 50.0


def launch_axes(lat, lon, az):
    """Rows: the launch axes x (downrange), y (up, the geodetic normal), z in ECEF."""
    lat, lon, az = np.radians([lat, lon, az])
    n_ = np.array([-np.sin(lat) * np.cos(lon), -np.sin(lat) * np.sin(lon), np.cos(lat)])
    e_ = np.array([-np.sin(lon), np.cos(lon), 0.0])
    u_ = np.array([np.cos(lat) * np.cos(lon), np.cos(lat) * np.sin(lon), np.sin(lat)])
    xa = np.cos(az) * n_ + np.sin(az) * e_
    return np.array([xa, u_, np.cross(xa, u_)])


def rz(u):
    c, s = math.cos(u), math.sin(u)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def li_to_ecef(r, v, t, site):
    """r_E = R(w t)^T (C^T r + r0), v_E = R(w t)^T C^T v - w x r_E."""
    C, r0 = launch_axes(LAT, LON, AZ), site[4:7]
    T = rz(W_E * t).T
    re = T @ (C.T @ r + r0)
    return re, T @ C.T @ v - np.cross([0.0, 0.0, W_E], re)


def increments(traj, system):
    """The trapezoid increments of the sampled f and w (rows t dv [dth])."""
    h = np.diff(traj[:, 0])[:, None]
    cols = 7 if system == "strapdown" else 4
    tel = np.zeros((len(traj), cols))
    tel[:, 0] = traj[:, 0]
    tel[1:, 1:cols] = h * (traj[:-1, 1:cols] + traj[1:, 1:cols]) / 2
    return tel


@pytest.fixture(scope="module")
def flights():
    return {s: np.asarray(igea.reference_trajectory(60.0, 20.0, system=s))
            for s in ("strapdown", "platform")}


def site():
    return igea.nav_site(math.radians(LAT), math.radians(LON), H, math.radians(AZ))


@pytest.mark.parametrize("system", ["strapdown", "platform"])
def test_state_against_nav_core(flights, system):
    traj = flights[system]
    tel = increments(traj, system)
    q0 = traj[0, 7:11] if system == "strapdown" else None
    nav = igea.nav_navigate(site(), tel, system=system, q0=q0)
    for tb in (TB, 60.0, 0.0):
        k = int(round(tb * 20))
        want = np.concatenate(li_to_ecef(nav.r[k], nav.v[k], tb, site()))
        got = igea.burnout(traj, [], tb, lat=LAT, lon=LON, height=H, azimuth=AZ,
                           system=system).burnout
        np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-7)
    # between samples: the last interval cut at tb, f and w interpolated linearly
    tb = 33.337
    k = int(tb * 20)
    s = (tb - traj[k, 0]) / (traj[k + 1, 0] - traj[k, 0])
    end = traj[k] + s * (traj[k + 1] - traj[k])
    part = increments(np.vstack([traj[k], end]), system)[1:]
    part[0, 0] = tb
    nav = igea.nav_navigate(site(), np.vstack([tel[:k + 1], part]), system=system, q0=q0)
    want = np.concatenate(li_to_ecef(nav.r[-1], nav.v[-1], tb, site()))
    got = igea.burnout(traj, [], tb, lat=LAT, lon=LON, height=H, azimuth=AZ,
                       system=system).burnout
    np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-7)


def qmul(a, b):
    return np.array([a[0] * b[0] - a[1:] @ b[1:],
                     *(a[0] * b[1:] + b[0] * a[1:] + np.cross(a[1:], b[1:]))])


def rot(v):
    """exp([v x]) (Rodrigues)."""
    a = np.linalg.norm(v)
    if a == 0:
        return np.eye(3)
    k = np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]]) / a
    return np.eye(3) + math.sin(a) * k + (1 - math.cos(a)) * k @ k


# (term, how the test puts X into the strapdown telemetry); dv, dth the
# error-free increments, h the intervals
STRAPDOWN_TERMS = ["acc_bias_x", "acc_bias_y", "acc_bias_z", "acc_scale_x", "acc_mis_yx",
                   "gyro_bias_x", "gyro_bias_y", "gyro_bias_z", "gyro_g_x", "att0_x", "att0_y",
                   "att0_z"]


def strapdown_burnout(traj, x):
    """The nav core flying the trajectory's increments with the errors x
    {term: X}: the ECEF state at TB."""
    tel = increments(traj, "strapdown")
    h = np.diff(traj[:, 0])
    dv, dth = tel[1:, 1:4].copy(), tel[1:, 4:7].copy()
    for a, ax in enumerate("xyz"):
        tel[1:, 1 + a] += x.get("acc_bias_" + ax, 0.0) * h       # u = e_a
        tel[1:, 4 + a] += x.get("gyro_bias_" + ax, 0.0) * h      # eps = e_a
    tel[1:, 1] += x.get("acc_scale_x", 0.0) * dv[:, 0]           # u = e_x f_x
    tel[1:, 2] += x.get("acc_mis_yx", 0.0) * dv[:, 0]            # u = e_y f_x
    tel[1:, 4] += x.get("gyro_g_x", 0.0) * dv[:, 0]              # eps = e_x f_x
    phi0 = np.array([x.get("att0_" + ax, 0.0) for ax in "xyz"])
    a = np.linalg.norm(phi0)
    qp = np.array([math.cos(a / 2), *(-math.sin(a / 2) * phi0 / a)]) if a > 0 else np.eye(4)[0]
    k = int(round(TB * 20))
    nav = igea.nav_navigate(site(), tel[:k + 1], q0=qmul(qp, traj[0, 7:11]))
    return np.concatenate(li_to_ecef(nav.r[-1], nav.v[-1], TB, site()))


PLATFORM_TERMS = ["acc_bias_x", "acc_bias_y", "acc_bias_z", "gyro_bias_x", "gyro_bias_y",
                  "gyro_bias_z", "align0_x", "align0_y", "align0_z"]


def platform_burnout(traj, x):
    """A platform that starts rotated by alpha0 and drifts at eps:
    alpha(t) = alpha0 + eps t, its accelerometers read R(alpha)^T f + b,
    which the navigator takes as along the launch-inertial axes."""
    tel = increments(traj, "platform")
    h = np.diff(traj[:, 0])
    a0 = np.array([x.get("align0_" + ax, 0.0) for ax in "xyz"])
    eps = np.array([x.get("gyro_bias_" + ax, 0.0) for ax in "xyz"])
    b = np.array([x.get("acc_bias_" + ax, 0.0) for ax in "xyz"])
    for k in range(1, len(tel)):
        tm = 0.5 * (tel[k - 1, 0] + tel[k, 0])
        tel[k, 1:4] = rot(a0 + eps * tm).T @ tel[k, 1:4] + b * h[k - 1]
    k = int(round(TB * 20))
    nav = igea.nav_navigate(site(), tel[:k + 1], system="platform")
    return np.concatenate(li_to_ecef(nav.r[-1], nav.v[-1], TB, site()))


@pytest.mark.parametrize("system", ["strapdown", "platform"])
def test_errors_against_nonlinear_navigation(flights, system):
    """Each term alone at its 1-sigma spec: nonlinear minus reference
    matches E's column to 2e-4 of its largest value (measured at most 6.1e-5
    strapdown, 4.9e-5 platform; the strapdown accelerometer terms keep a
    floor of 1e-5, the two discretisations of the rotating body's force at
    20 Hz, and the platform's are exact to 2e-9); all together at their
    specs (signs +, -, +0.8 in turn) the mismatch is second order: halving
    every error quarters it (measured 4.06 and 4.00)."""
    traj = flights[system]
    terms = STRAPDOWN_TERMS if system == "strapdown" else PLATFORM_TERMS
    fly = strapdown_burnout if system == "strapdown" else platform_burnout
    spec = default_spec(terms, system)
    b = igea.burnout(traj, terms, TB, lat=LAT, lon=LON, height=H, azimuth=AZ, system=system,
                     spec=spec)
    E = b.burnout_errors
    ref = fly(traj, {})
    np.testing.assert_allclose(ref, b.burnout, rtol=1e-12, atol=1e-7)
    worst = 0.0
    for j, name in enumerate(terms):
        d = fly(traj, {name: spec[j]}) - ref
        scale = np.abs(E[:, j]).max()
        worst = max(worst, np.abs(d - E[:, j]).max() / scale)
        assert np.abs(d - E[:, j]).max() < 2e-4 * scale, (name, d, E[:, j])
    sign = np.array([[1.0, -1.0, 0.8][j % 3] for j in range(len(terms))])
    mis = []
    for s in (1.0, 0.5):
        x = s * sign * spec
        d = fly(traj, dict(zip(terms, x))) - ref
        mis.append(np.abs(d - E @ (s * sign)).max())
        assert mis[-1] < 1e-2 * np.abs(E @ (s * sign)).max()
    assert 3.7 < mis[0] / mis[1] < 4.3, mis


@pytest.mark.parametrize("system", ["strapdown", "platform"])
def test_errors_against_li_error_model(flights, system):
    """The columns of the biases, drifts and initial attitude against the
    response of igea.nav_errors_li (the launch-inertial error model along
    the nav core's reference, integrated by its own Runge-Kutta steps),
    turned into ECEF here: agreement to 5e-5 (strapdown; measured 2.5e-5)
    and 5e-6 (platform; measured 2.2e-6) of each column, the two
    discretisations of the same linear model at 20 Hz."""
    traj = flights[system]
    tel = increments(traj, system)
    att = "att0_" if system == "strapdown" else "align0_"
    terms = ([f"acc_bias_{a}" for a in "xyz"] + [f"gyro_bias_{a}" for a in "xyz"]
             + [att + a for a in "xyz"])
    b = igea.burnout(traj, terms, TB, lat=LAT, lon=LON, height=H, azimuth=AZ, system=system)
    slots = [9, 10, 11, 12, 13, 14, 6, 7, 8]
    q0 = traj[0, 7:11] if system == "strapdown" else None
    X = np.eye(15)[slots]
    tol = 5e-5 if system == "strapdown" else 5e-6
    r = [igea.nav_errors_li(site(), tel, system=system, q0=q0, x0=x, epochs=[TB]) for x in X]
    for j, name in enumerate(terms):
        C, T = launch_axes(LAT, LON, AZ), rz(W_E * TB).T
        dr = T @ C.T @ r[j].position[0]
        dv = T @ C.T @ r[j].velocity[0] - np.cross([0, 0, W_E], dr)
        want = np.concatenate([dr, dv])
        got = b.burnout_errors[:, j]
        assert np.abs(got - want).max() < tol * np.abs(want).max(), (name, got, want)


def drv(*args, cwd=None):
    return subprocess.run([os.environ["IGEA_DRIVER"], *map(str, args)], capture_output=True,
                          text=True, cwd=cwd)


SITE_ARGS = ["--lat", LAT, "--lon", LON, "--height", H, "--azimuth", AZ]


@pytest.mark.parametrize("system", ["strapdown", "platform"])
def test_eqerr_component_miss_from_burnout_time(tmp_path, system):
    """igea eqerr --burnout-time: the JSON component_miss of each tested
    component is numpy's G E p_i x_i with G the Kepler miss Jacobian of
    igea.impact at igea.burnout's state and E its errors of S's terms
    (named by S's header) at the specs; igea.eqerr(burnout_time=) gives
    the same, and so does igea.eqerr(burnout=, burnout_errors=)."""
    d = tmp_path
    r = drv("simulate", "--seed", 5, "--system", system, "--save-traj", "--dir", d)
    assert r.returncode == 0, r.stderr
    traj = np.loadtxt(d / "traj.txt")
    fl = igea.simulate(seed=5, system=system)
    args = ["eqerr", "--S", "S.txt", "--dw", "dw.txt", "--sigma", "sigma.txt", "--spec",
            "spec.txt", "--system", system, "--burnout-time", 100, "--traj", "traj.txt",
            *SITE_ARGS]
    r = drv(*args, "--json", cwd=d)
    assert r.returncode in (0, 1), r.stderr
    js = json.loads(r.stdout)
    got = np.array(js["component_miss"])
    res = igea.eqerr(fl.S, fl.dw, fl.sigma, fl.spec)
    n = res.n_test
    b = igea.burnout(traj, list(fl.terms), 100.0, lat=LAT, lon=LON, height=H, azimuth=AZ,
                     system=system, spec=fl.spec)
    G = igea.impact(b.burnout).miss_jacobian
    want = (G @ b.burnout_errors @ res.eigenvectors[:, :n] * res.equiv_err[:n]).T
    assert got.shape == (n, 2) and n >= 3
    np.testing.assert_allclose(got, want, rtol=1e-9, atol=1e-9 * np.abs(want).max())
    np.testing.assert_allclose(js["burnout"], b.burnout, rtol=1e-12)
    assert js["burnout_time"] == 100.0
    assert np.abs(got).max() > 10.0      # metres: a visible miss
    py = igea.eqerr(fl.S, fl.dw, fl.sigma, fl.spec, names=list(fl.terms), burnout_time=100.0,
                    traj=traj, lat=LAT, lon=LON, height=H, azimuth=AZ, system=system)
    np.testing.assert_allclose(py.component_miss, got, rtol=1e-9,
                               atol=1e-9 * np.abs(want).max())
    py2 = igea.eqerr(fl.S, fl.dw, fl.sigma, fl.spec, burnout=b.burnout,
                     burnout_errors=b.burnout_errors)
    np.testing.assert_allclose(py2.component_miss, want, rtol=1e-12,
                               atol=1e-12 * np.abs(want).max())
    assert py.to_dict()["component_miss"] == py.component_miss.tolist()
    assert "component_miss" not in res.to_dict()
    t = drv(*args, cwd=d)
    assert "m downrange" in t.stdout and "burnout at 100 s" in t.stdout


def test_eqerr_burnout_time_refusals(tmp_path):
    d = tmp_path
    assert drv("simulate", "--seed", 2, "--save-traj", "--dir", d).returncode == 0
    base = ["eqerr", "--S", "S.txt", "--dw", "dw.txt", "--sigma", "sigma.txt", "--spec",
            "spec.txt"]
    r = drv(*base, "--burnout-time", 100, "--traj", "traj.txt", "--lat", 40, "--azimuth", 30,
            cwd=d)
    assert r.returncode == 64 and "--lon" in r.stderr
    r = drv(*base, "--burnout-time", 130, "--traj", "traj.txt", *SITE_ARGS, cwd=d)
    assert r.returncode == 64 and "outside the trajectory" in r.stderr
    r = drv(*base, "--burnout-time", 100, "--traj", "traj.txt", *SITE_ARGS, "--burnout",
            "1,2,3,4,5,6", cwd=d)
    assert r.returncode == 64 and "alternatives" in r.stderr
    S = np.loadtxt(d / "S.txt")
    np.savetxt(d / "S2.txt", S)                       # no '# names' header
    r = drv("eqerr", "--S", "S2.txt", *base[3:], "--burnout-time", 100, "--traj", "traj.txt",
            *SITE_ARGS, cwd=d)
    assert r.returncode == 64 and "names" in r.stderr
    names = ",".join(["acc_bias_x"] * 20 + ["time_offset"])
    r = drv("eqerr", "--S", "S2.txt", *base[3:], "--names", names, "--burnout-time", 100,
            "--traj", "traj.txt", *SITE_ARGS, cwd=d)
    assert r.returncode == 64 and "'time_offset'" in r.stderr
    # a part of the burnout options alone is refused, not ignored
    for part in (["--system", "platform"], ["--height", 1000], ["--axes", "0,1,2,1,2,0"]):
        r = drv(*base, *part, cwd=d)
        assert r.returncode == 64 and "--burnout-time is missing" in r.stderr, part
        r = drv("impact", "--burnout", "5561563.2,980653.6,3260504.4,-495.5,3461.9,4875.4",
                *part)
        assert r.returncode == 64 and "--burnout-time is missing" in r.stderr, part
    fl = igea.simulate(seed=2)
    # as the driver's: the trajectory's options without burnout_time refused
    for kw in (dict(system="platform"), dict(height=1000.0),
               dict(traj=np.loadtxt(d / "traj.txt"), lat=LAT, lon=LON, azimuth=AZ)):
        with pytest.raises(ValueError, match="only with burnout_time"):
            igea.eqerr(fl.S, fl.dw, fl.sigma, fl.spec, **kw)
    with pytest.raises(ValueError, match="only with burnout_time"):
        igea.eqerr(fl.S, fl.dw, fl.sigma, fl.spec, burnout=np.ones(6),
                   burnout_errors=np.ones((6, fl.S.shape[1])), lat=LAT)
    with pytest.raises(ValueError, match="names"):
        igea.eqerr(fl.S, fl.dw, fl.sigma, fl.spec, burnout_time=100.0,
                   traj=np.loadtxt(d / "traj.txt"), lat=LAT, lon=LON, azimuth=AZ)
    with pytest.raises(ValueError, match="list of term names"):   # not its letters
        igea.burnout(np.loadtxt(d / "traj.txt"), "acc_bias_x", 100.0, lat=LAT, lon=LON,
                     azimuth=AZ)
    with pytest.raises(igea.IgeaError, match="tb"):
        igea.burnout(np.loadtxt(d / "traj.txt"), ["acc_bias_x"], 121.0, lat=LAT, lon=LON,
                     azimuth=AZ)


def test_impact_budget_from_burnout_time(tmp_path):
    """igea impact --burnout-time --terms default: the burnout, its errors
    and the budget are igea.burnout's, igea.impact's and
    igea.impact_budget's; the shares add to 1."""
    d = tmp_path
    assert drv("simulate", "--seed", 1, "--save-traj", "--dir", d).returncode == 0
    traj = np.loadtxt(d / "traj.txt")
    r = drv("impact", "--burnout-time", 120, "--traj", d / "traj.txt", *SITE_ARGS, "--terms",
            "default", "--model", "j2", "--json")
    assert r.returncode == 0, r.stderr
    js = json.loads(r.stdout)
    b = igea.burnout(traj, "default", 120.0, lat=LAT, lon=LON, height=H, azimuth=AZ,
                     spec="default")
    np.testing.assert_allclose(js["burnout"], b.burnout, rtol=1e-12)
    np.testing.assert_allclose(js["burnout_errors"], b.burnout_errors, rtol=1e-12, atol=1e-300)
    imp = igea.impact(b.burnout, model="j2")
    bud = igea.impact_budget(imp.miss_jacobian, b.burnout_errors, b.terms)
    assert js["names"] == b.terms
    np.testing.assert_allclose(js["miss"], bud.miss, rtol=1e-9, atol=1e-9 * np.abs(bud.miss).max())
    np.testing.assert_allclose(js["cep"], bud.cep, rtol=1e-9)
    assert abs(sum(js["share"]) - 1.0) < 1e-12
    r = drv("impact", "--burnout-time", 120, "--traj", d / "traj.txt", *SITE_ARGS, "--errors",
            "E.txt")
    assert r.returncode == 64 and "alternatives" in r.stderr
    r = drv("impact", "--terms", "default", "--burnout", "1,2,3,4,5,6")
    assert r.returncode == 64 and "--burnout-time" in r.stderr
    r = drv("impact", "--burnout-time", 120, "--traj", d / "traj.txt", *SITE_ARGS, "--spec",
            "default")
    assert r.returncode == 64 and "--terms" in r.stderr
    # the budget's options without a budget are refused, not ignored
    r = drv("impact", "--burnout-time", 120, "--traj", d / "traj.txt", *SITE_ARGS, "--names",
            "a,b")
    assert r.returncode == 64 and "--names" in r.stderr
    r = drv("impact", "--burnout", "1,2,3,4,5,6", "--prob", 0.9)
    assert r.returncode == 64 and "--prob" in r.stderr
    r = drv("impact", "--burnout-time", 120, "--traj", d / "traj.txt", *SITE_ARGS, "--terms",
            "default", "--prob", 0.9)
    assert r.returncode == 0, r.stderr
