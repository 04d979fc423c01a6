"""igea.simulate / igea.montecarlo: per-flight verdicts against a numpy
implementation of the seed-000 test (no sigma_w correction), small size and
misstated-sigma studies with binomial bounds at 1e-6 (cannot flake), thread
independence, and the `igea montecarlo` command."""
import json
import os
import subprocess

import numpy as np
import pytest
from scipy import stats

import igea


@pytest.fixture(scope="module")
def model():
    return igea.simulate(seed=11)


def numpy_test(S, dw, sigma, spec, alpha=0.01, lambda_test=10.0):
    """METHODS 1.2 steps 1, 2, 4, 5 with c = 1, in numpy."""
    St = S * spec / sigma[:, None]
    A = St.T @ St
    b = St.T @ (dw / sigma)
    lam, P = np.linalg.eigh(A)
    lam, P = lam[::-1], P[:, ::-1]
    t = lam >= lambda_test
    xhat = (P[:, t].T @ b) / lam[t]
    z = xhat / np.sqrt(1 + 1 / lam[t])
    zc = stats.norm.ppf(1 - alpha / 2)
    T = float(np.sum(z ** 2))
    crit = stats.chi2.isf(alpha, t.sum())
    return T, int(t.sum()), int(np.sum(np.abs(z) > zc)), T >= crit


def test_flights_match_numpy_test(model):
    S, sig, spec = model.S, model.sigma, model.spec
    r = igea.montecarlo(S, sig, 12, spec=spec, seed=5, correction=False, threads=2)
    for f in range(12):
        fl = igea.simulate(seed=5, flight=f)
        T, dof, nrej, chi_rej = numpy_test(fl.S, fl.dw, fl.sigma, fl.spec)
        assert r.chi2[f] == pytest.approx(T, rel=1e-7)
        assert r.dof[f] == dof
        assert r.n_reject[f] == nrej
    assert r.scale.tolist() == [1.0] * 12


def test_simulate_truth(model):
    fl = igea.simulate(seed=11, x={"gyro_bias_y": 3.0}, sigma=1e-9)
    assert fl.x_true[model.terms.index("gyro_bias_y")] == 3.0
    np.testing.assert_allclose(fl.dw, fl.S @ (fl.spec * fl.x_true), rtol=0,
                               atol=1e-6 * np.abs(fl.dw).max())
    other = igea.simulate(seed=11, sigma=1e-9)
    keep = [i for i, t in enumerate(model.terms) if t != "gyro_bias_y"]
    np.testing.assert_array_equal(fl.x_true[keep], other.x_true[keep])
    assert "flight" in fl.summary()
    with pytest.raises(ValueError, match="x"):
        igea.simulate(x={"nope": 1.0})
    with pytest.raises(igea.IgeaError):
        igea.simulate(ar1=1.5)


def test_nonlinear_truth(model):
    lin = igea.simulate(seed=11, sigma=1e-9)
    nl = igea.simulate(seed=11, sigma=1e-9, nonlinear_truth=True)
    d = np.abs(nl.dw - lin.dw).max() / np.abs(nl.dw).max()
    assert 1e-7 < d < 1e-3          # second order, not zero
    # a platform accelerometer bias is exactly linear: t e_x per m/s^2
    tr = igea.reference_trajectory(10.0, 10.0, system="platform")
    out = igea.sim.nonlinear(tr, {"acc_bias_x": 0.01}, [2.0, 5.0], system="platform")
    np.testing.assert_allclose(out, [0.02, 0, 0, 0.05, 0, 0], rtol=1e-13, atol=1e-15)
    with pytest.raises(ValueError, match="terms"):
        igea.sim.nonlinear(tr, {"att0_x": 1e-4}, [1.0], system="platform")
    with pytest.raises(igea.IgeaError, match="epochs"):
        igea.sim.nonlinear(tr, {}, [20.0], system="platform")


def binom_ok(k, n, p):
    d = stats.binom(n, p)
    return d.cdf(k) > 0.5e-6 and d.sf(k - 1) > 0.5e-6


def test_size_small(model):
    """sigma_w = 1, no correction, alpha = 0.1: exact size alpha for the
    chi-square test and each component test."""
    n = 400
    r = igea.montecarlo(model.S, model.sigma, n, spec=model.spec, seed=21, alpha=0.1,
                        correction=False)
    assert binom_ok(r.chi2_reject, n, 0.1)
    tested = r.comp_tested > 0
    assert tested.sum() == 7
    for k in r.comp_reject[tested]:
        assert binom_ok(int(k), n, 0.1)
    # the verdict combines 7 component tests and the chi-square test: its size
    # is at least that of one test and at most the union bound
    assert r.failed >= r.chi2_reject
    assert stats.binom(n, 1 - 0.9 ** 7 + 0.1).cdf(r.failed) > 1e-6
    assert r.mean_scale == 1.0


def test_misstated_sigma_small(model):
    n = 300
    un = igea.montecarlo(model.S, model.sigma, n, spec=model.spec, seed=22, sigma_w=10.0,
                         alpha=0.1, correction=False)
    co = igea.montecarlo(model.S, model.sigma, n, spec=model.spec, seed=22, sigma_w=10.0,
                         alpha=0.1, correction=True)
    # weakest tested component, exact rejection probability without correction
    St = model.S * model.spec / model.sigma[:, None]
    lam = np.sort(np.linalg.eigvalsh(St.T @ St))[::-1]
    i = int(np.sum(lam >= 10.0)) - 1
    sd = np.sqrt((1 + 100 / lam[i]) / (1 + 1 / lam[i]))
    p = 2 * stats.norm.sf(stats.norm.ppf(0.95) / sd)
    assert p > 0.3
    assert binom_ok(int(un.comp_reject[i]), n, p)
    assert co.mean_scale == pytest.approx(100.0, rel=0.15)
    assert co.failed < 0.75 * un.failed


def test_threads_and_chunks_identical(model):
    a = igea.montecarlo(model.S, model.sigma, 200, spec=model.spec, seed=3, threads=1)
    b = igea.montecarlo(model.S, model.sigma, 200, spec=model.spec, seed=3, threads=2)
    c = igea.montecarlo(model.S, model.sigma, 100, spec=model.spec, seed=3, threads=2,
                        first_flight=100)
    np.testing.assert_array_equal(a.chi2, b.chi2)
    np.testing.assert_array_equal(a.comp_reject, b.comp_reject)
    assert (a.failed, a.mean_scale) == (b.failed, b.mean_scale)
    np.testing.assert_array_equal(a.chi2[100:], c.chi2)
    assert "flights" in a.summary()


def test_montecarlo_errors(model):
    with pytest.raises(ValueError, match="sigma"):
        igea.montecarlo(model.S, np.ones(5), 10)
    with pytest.raises(ValueError, match="spec"):
        igea.montecarlo(model.S, 0.01, 10, spec=np.ones(3))
    with pytest.raises(ValueError, match="flights"):
        igea.montecarlo(model.S, 0.01, 0)
    with pytest.raises(igea.IgeaError, match="opts"):
        igea.montecarlo(model.S, 0.01, 10, sigma_w=-1.0)
    with pytest.raises(igea.IgeaError, match="seed"):
        igea.montecarlo(model.S, 0.01, 10, seed=-1)


DRIVER = os.environ.get("IGEA_DRIVER")


@pytest.mark.skipif(not DRIVER, reason="IGEA_DRIVER not set")
def test_driver_montecarlo_files(model, tmp_path):
    # a geometry of one's own: S, sigma, spec from files (here a shorter flight)
    fl = igea.simulate(igea.reference_trajectory(60.0, 20.0), seed=2, sigma=0.02)
    np.savetxt(tmp_path / "S.txt", fl.S, fmt="%.17g")
    np.savetxt(tmp_path / "sigma.txt", fl.sigma, fmt="%.17g")
    np.savetxt(tmp_path / "spec.txt", fl.spec, fmt="%.17g")
    r = subprocess.run([DRIVER, "montecarlo", "--S", "S.txt", "--sigma", "sigma.txt",
                        "--spec", "spec.txt", "--flights", "120", "--seed", "8",
                        "--json", "--no-correction"], cwd=tmp_path, capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    d = json.loads(r.stdout)
    py = igea.montecarlo(fl.S, fl.sigma, 120, spec=fl.spec, seed=8, correction=False)
    assert d["failed"]["count"] == py.failed
    assert d["comp_tested"] == py.comp_tested.tolist()
    r = subprocess.run([DRIVER, "montecarlo", "--S", "S.txt", "--flights", "5"], cwd=tmp_path,
                       capture_output=True, text=True)
    assert r.returncode == 64


@pytest.mark.skipif(not DRIVER, reason="IGEA_DRIVER not set")
def test_driver_montecarlo(model):
    r = subprocess.run([DRIVER, "montecarlo", "--flights", "150", "--seed", "4", "--json",
                        "--pool", "3"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    d = json.loads(r.stdout)
    py = igea.montecarlo(model.S, model.sigma, 150, spec=model.spec, seed=4)
    assert d["failed"]["count"] == py.failed
    assert d["chi2_reject"]["count"] == py.chi2_reject
    assert d["comp_reject"] == py.comp_reject.tolist()
    lo, hi = d["failed"]["ci99"]
    assert lo <= d["failed"]["rate"] <= hi
    assert d["pool"]["pools"] == 50
    r = subprocess.run([DRIVER, "montecarlo", "--flights", "x"], capture_output=True, text=True)
    assert r.returncode == 64
    r = subprocess.run([DRIVER, "montecarlo", "--help"], capture_output=True, text=True)
    assert r.returncode == 0 and "example" in r.stdout
