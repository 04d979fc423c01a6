"""The miss distance of each equivalent-error component
(igea_impact_component_miss): a simulated flight judged by igea.eqerr, the
position and velocity environment functions at a burnout time turned into
ECEF here (numpy, from the frame definitions of docs/pipeline.md 1.2), the
impact Jacobian of igea.impact applied by numpy: G E p_i x_i."""
import numpy as np
import pytest

import igea
from igea.envfun import default_terms

W_E = 7.292115e-5
BURNOUT = [5561563.2, 980653.6, 3260504.4, -495.5, 3461.9, 4875.4]


def launch_axes(lat, lon, az):
    lat, lon, az = np.radians([lat, lon, az])
    n_ = np.array([-np.sin(lat) * np.cos(lon), -np.sin(lat) * np.sin(lon), np.cos(lat)])
    e_ = np.array([-np.sin(lon), np.cos(lon), 0.0])
    u_ = np.array([np.cos(lat) * np.cos(lon), np.cos(lat) * np.sin(lon), np.sin(lat)])
    xa = np.cos(az) * n_ + np.sin(az) * e_
    return np.array([xa, u_, np.cross(xa, u_)])


def burnout_errors(fl, tb, system):
    """E (6, N): the LI position and velocity functions at tb (spec units)
    in ECEF: dr_E = R^T C^T dr_LI, dv_E = R^T C^T dv_LI - w x dr_E."""
    traj = igea.reference_trajectory(system=system)
    terms = list(fl.terms)
    Sr = igea.envfun(traj, terms, [tb], system=system, spec=fl.spec, output="position")
    Sv = igea.envfun(traj, terms, [tb], system=system, spec=fl.spec, output="velocity")
    C = launch_axes(40.96, 100.29, 30.0)
    c, s = np.cos(W_E * tb), np.sin(W_E * tb)
    R = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
    T = R.T @ C.T
    dr = T @ Sr
    dv = T @ Sv - np.cross([0, 0, W_E], dr.T).T
    return np.vstack([dr, dv])


@pytest.mark.parametrize("system", ["strapdown", "platform"])
def test_component_miss(system):
    fl = igea.simulate(system=system, seed=4, flight=1)
    res = igea.eqerr(fl.S, fl.dw, fl.sigma, fl.spec)
    n = res.n_test
    assert n >= 3
    P, x = res.eigenvectors[:, :n], res.equiv_err[:n]
    E = burnout_errors(fl, 100.0, system)
    G = igea.impact(BURNOUT).miss_jacobian
    miss = igea.component_miss(G, E, P, x)
    want = (G @ E @ P * x).T
    np.testing.assert_allclose(miss, want, rtol=1e-12, atol=1e-12 * np.abs(want).max())
    assert np.abs(miss).max() > 1.0            # metres: a visible miss


def test_component_miss_refusals():
    G = np.ones((2, 6))
    with pytest.raises(ValueError):
        igea.component_miss(G, np.ones((6, 3)), np.ones((2, 1)), [1.0])
    with pytest.raises(ValueError):
        igea.component_miss(G, np.ones((6, 3)), np.ones((3, 2)), [1.0])
    E = np.ones((6, 3))
    E[2, 1] = np.inf
    with pytest.raises(igea.IgeaError):
        igea.component_miss(G, E, np.ones((3, 1)), [1.0])


def test_eqerr_report_component_miss(tmp_path):
    """igea eqerr --burnout --burnout-errors (opt-in): the JSON component_miss
    of each tested component equals numpy's G E p_i x_i, G the Kepler miss
    Jacobian of igea.impact, p_i and x_i of igea.eqerr on the same files;
    the text report prints the lines; one option alone is refused."""
    import json
    import os
    import subprocess
    driver = os.environ["IGEA_DRIVER"]
    d = str(tmp_path)
    fl = igea.simulate(system="platform", seed=7)
    for name, a in (("S", fl.S), ("dw", fl.dw), ("sigma", fl.sigma), ("spec", fl.spec)):
        np.savetxt(os.path.join(d, name + ".txt"), a)
    E = burnout_errors(fl, 100.0, "platform")
    np.savetxt(os.path.join(d, "E.txt"), E)
    b = ",".join(repr(v) for v in BURNOUT)
    args = [driver, "eqerr", "--S", "S.txt", "--dw", "dw.txt", "--sigma", "sigma.txt", "--spec",
            "spec.txt", "--burnout", b, "--burnout-errors", "E.txt"]
    r = subprocess.run(args + ["--json"], cwd=d, capture_output=True, text=True)
    assert r.returncode in (0, 1), r.stderr
    got = np.array(json.loads(r.stdout)["component_miss"])
    res = igea.eqerr(fl.S, fl.dw, fl.sigma, fl.spec)
    n = res.n_test
    G = igea.impact(BURNOUT).miss_jacobian
    want = (G @ np.loadtxt(os.path.join(d, "E.txt")) @ res.eigenvectors[:, :n]
            * res.equiv_err[:n]).T
    assert got.shape == (n, 2)
    np.testing.assert_allclose(got, want, rtol=1e-9, atol=1e-9 * np.abs(want).max())
    t = subprocess.run(args, cwd=d, capture_output=True, text=True)
    assert "m downrange" in t.stdout and "m crossrange" in t.stdout
    r = subprocess.run(args[:-2], cwd=d, capture_output=True, text=True)
    assert r.returncode == 64 and "--burnout-errors" in r.stderr
