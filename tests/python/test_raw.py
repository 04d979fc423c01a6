"""The raw pipeline of a simulated flight: igea simulate --raw -> igea dw ->
igea envfun -> igea eqerr judges the flight as the simulator's own dw and S
do. The comparison is the test's own: the difference of the two dw, whitened
by the stated sigma, projected on the orthonormal principal directions of
the whitened S diag(spec) (numpy's SVD, written here) is the change of each
estimated component in units of its standard error; "equal to the noise"
means every such change is far below 1."""
import json
import os
import subprocess

import numpy as np
import pytest

import igea
from igea import simulate_raw

DRIVER = os.environ["IGEA_DRIVER"]


def run(*args, cwd):
    return subprocess.run([DRIVER, *args], cwd=cwd, capture_output=True, text=True)


def table(path):
    return np.loadtxt(path, comments="#", ndmin=2)


def component_changes(S, spec, sigma, dw_a, dw_b):
    """U^T (dw_a - dw_b) / sigma, U the left singular vectors of the whitened
    S diag(spec) with singular value above 1e-10 of the largest."""
    A = S * spec / sigma[:, None]
    U, s, _ = np.linalg.svd(A, full_matrices=False)
    U = U[:, s > 1e-10 * s[0]]
    return U.T @ ((dw_a - dw_b) / sigma)


def raw_pipeline(d, system, *extra, site=False):
    """simulate --raw (all terms, seed 7) -> dw -> envfun in directory d
    (with site: envfun given the stated launch point of site_args.txt):
    (S, S_raw, spec, sigma, sigma_raw, dw, dw_raw, X true in spec units)."""
    r = run("simulate", "--raw", "--system", system, "--terms", "all", "--seed", "7",
            "--dir", ".", *extra, cwd=d)
    assert r.returncode == 0, r.stderr
    args = open(os.path.join(d, "dw_args.txt")).read().split()
    r = run("dw", *args, "--telemetry", "telemetry.txt", "--tracking", "tracking.txt",
            "--out", "dw_raw.txt", "--sigma-out", "sigma_raw.txt", cwd=d)
    assert r.returncode == 0, r.stderr
    sa = open(os.path.join(d, "site_args.txt")).read().split() if site else []
    r = run("envfun", "--traj", "traj.txt", "--terms", "all", "--system", system, *sa,
            "--out", "S_raw.txt", cwd=d)
    assert r.returncode == 0, r.stderr
    t = {k: table(os.path.join(d, k + ".txt")) for k in
         ("S", "S_raw", "spec", "sigma", "sigma_raw", "dw", "dw_raw")}
    x = np.array([float(line.split()[0]) for line in open(os.path.join(d, "X.txt"))
                  if not line.startswith("#")])
    return ([t["S"], t["S_raw"]] + [t[k].ravel() for k in
            ("spec", "sigma", "sigma_raw", "dw", "dw_raw")] + [x])


def judge(d, S, dw, sigma):
    e = run("eqerr", "--json", "--S", S, "--dw", dw, "--sigma", sigma, "--spec", "spec.txt",
            cwd=d)
    assert e.returncode in (0, 1), e.stderr
    return json.loads(e.stdout)


NO_SITE_TERMS = "pos0_x=0,pos0_z=0,lever_x=0,lever_y=0,lever_z=0"


@pytest.mark.parametrize("system", ["platform", "strapdown"])
def test_driver_pipeline_equals_simulator(tmp_path, system):
    """Every instrument term drawn (69 platform, 81 strapdown), the
    simulator's nonlinear truth: the raw route gives the simulator's dw to
    1e-6 m/s (measured 3.7e-8, 8.4e-8), hence the same X and verdict."""
    d = str(tmp_path)
    S, S_raw, spec, sig, sig_raw, dw, dw_raw, _ = raw_pipeline(
        d, system, "--nonlinear-truth", "--x", NO_SITE_TERMS)
    np.testing.assert_array_equal(S, S_raw)      # the same trajectory and epochs
    np.testing.assert_allclose(sig_raw, sig, rtol=1e-12)  # 1 cm/s rotated into LI
    assert np.max(np.abs(dw_raw - dw)) < 1e-6
    assert np.max(np.abs(component_changes(S, spec, sig, dw_raw, dw))) < 1e-3
    a = judge(d, "S.txt", "dw.txt", "sigma.txt")
    b = judge(d, "S_raw.txt", "dw_raw.txt", "sigma_raw.txt")
    assert a["n_test"] == b["n_test"] and a["passed"] == b["passed"]
    np.testing.assert_allclose(b["z"], a["z"], atol=1e-3)
    np.testing.assert_allclose(b["chi2"], a["chi2"], rtol=1e-3)


def test_launch_point_error_pad_velocity(tmp_path):
    """All 74 platform terms: the launch-point errors pos0_x, pos0_z (10 m
    spec) also shift the stated pad velocity, w x (r0' - r0): a constant
    C (w_E x C^T (dx, 0, dz)) in dW. The simulator's own S and truth (a
    rotation of the launch frame only) leave it out; envfun given the
    stated launch point (site_args.txt) holds it: its pos0 columns exceed
    the simulator's by w_L x e_k (numpy closed form here, within 5 %: the
    rest is the ellipsoid's frame rotation and the tracking's first gravity
    interval), and dW_raw - dW = (S_raw - S) X to 5e-5 m/s; no estimated
    component moves by more than its standard error."""
    d = str(tmp_path)
    S, S_raw, spec, sig, _, dw, dw_raw, x = raw_pipeline(d, "platform", "--nonlinear-truth",
                                                         site=True)
    names = [line.split("#")[1].strip() for line in open(os.path.join(d, "X.txt"))
             if not line.startswith("#")]
    ix, iz = (names.index(n) for n in ("pos0_x", "pos0_z"))
    dx, dz = x[ix] * spec[ix], x[iz] * spec[iz]
    lat, lon, az = np.radians([40.96, 100.29, 30.0])
    n_ = np.array([-np.sin(lat) * np.cos(lon), -np.sin(lat) * np.sin(lon), np.cos(lat)])
    e_ = np.array([-np.sin(lon), np.cos(lon), 0.0])
    u_ = np.array([np.cos(lat) * np.cos(lon), np.cos(lat) * np.sin(lon), np.sin(lat)])
    xa = np.cos(az) * n_ + np.sin(az) * e_
    C = np.array([xa, u_, np.cross(xa, u_)])
    w = np.array([0.0, 0.0, 7.292115e-5])
    offset = C @ np.cross(w, C.T @ np.array([dx, 0.0, dz]))
    diff = (dw_raw - dw).reshape(-1, 3)
    assert np.linalg.norm(offset) > 3e-4          # the flight has a sizeable error
    assert np.max(np.abs(diff - offset)) < 5e-5   # the simulator's S lacks the offset
    wl = C @ w
    for i, ek in ((ix, [1.0, 0, 0]), (iz, [0, 0, 1.0])):
        extra = (S_raw[:, i] - S[:, i]).reshape(-1, 3)
        np.testing.assert_allclose(extra, np.tile(np.cross(wl, ek), (len(extra), 1)),
                                   rtol=0, atol=0.05 * np.linalg.norm(wl))
    xs = x * spec
    assert np.max(np.abs((dw_raw - dw) - (S_raw - S) @ xs)) < 5e-5
    assert np.max(np.abs(component_changes(S_raw, spec, sig, dw_raw, dw + (S_raw - S) @ xs))) < 1.0


@pytest.mark.parametrize("system", ["platform", "strapdown"])
@pytest.mark.parametrize("frame", ["ecef", "le"])
def test_no_errors_no_noise(system, frame):
    from igea.envfun import default_terms
    t = default_terms(system)
    raw = simulate_raw(system=system, terms=t, x=np.zeros(len(t)), noise=False, frame=frame)
    d = igea.dw(raw.telemetry, raw.tracking, **raw.dw_kwargs())
    assert d.max_abs < 1e-6


def test_same_flight_and_noise():
    """The raw records carry the simulator's flight: same X, and the noise of
    the flight comes back in dW (X = 0: dW is the noise alone)."""
    from igea.envfun import default_terms
    t = default_terms("strapdown")
    raw = simulate_raw(terms=t, seed=11, flight=3, x=np.zeros(len(t)))
    fl = igea.simulate(terms=t, seed=11, flight=3, x=np.zeros(len(t)))
    np.testing.assert_array_equal(raw.flight.dw, fl.dw)
    d = igea.dw(raw.telemetry, raw.tracking, **raw.dw_kwargs())
    np.testing.assert_allclose(d.dw, fl.dw, rtol=0, atol=1e-6)
    np.testing.assert_allclose(raw.tracking[:, 7], fl.sigma[0::3])


def test_driver_refusals(tmp_path):
    d = str(tmp_path)
    r = run("simulate", "--raw", "--frame", "li", "--dir", ".", cwd=d)
    assert r.returncode == 64 and "--frame" in r.stderr
    r = run("simulate", "--raw", "--lat", "95", "--dir", ".", cwd=d)
    assert r.returncode == 64 and "--lat" in r.stderr
    assert not os.path.exists(os.path.join(d, "telemetry.txt"))


@pytest.mark.parametrize("system", ["platform", "strapdown"])
def test_envfun_site_python(system):
    """igea.envfun with the stated launch point (lat, lon, height, azimuth
    of the records): the raw records of a launch point off by 2 x spec
    downrange and -1.5 x spec cross-range (no other error, no noise) give
    dW = S X to 1e-6 m/s (dw's floor); without the site the pad velocity's
    error w_L x d (9.5e-4 m/s measured) is left."""
    terms = ["pos0_x", "pos0_z"]
    x = np.array([2.0, -1.5])
    raw = simulate_raw(system=system, terms=terms, x=x, noise=False)
    fl = raw.flight
    d = igea.dw(raw.telemetry, raw.tracking, **raw.dw_kwargs())
    traj = igea.reference_trajectory(system=system)
    site = dict(lat=raw.lat, lon=raw.lon, height=raw.height, azimuth=raw.azimuth)
    S = igea.envfun(traj, terms, fl.epochs, system=system, **site)
    S0 = igea.envfun(traj, terms, fl.epochs, system=system)
    xs = x * fl.spec
    assert np.max(np.abs(d.dw - S @ xs)) < 1e-6
    assert np.max(np.abs(d.dw - S0 @ xs)) > 5e-4
    with pytest.raises(ValueError, match="lat, lon, azimuth"):
        igea.envfun(traj, terms, fl.epochs, system=system, lat=raw.lat)
