"""The exact Clopper-Pearson interval (igea_sim_interval_cp) against the
beta quantiles of scipy.stats.beta.ppf, and the montecarlo reports
(driver JSON ci99_cp, Python MonteCarloResult.ci99_cp) against the same."""
import ctypes
import json
import os
import subprocess

import numpy as np
import pytest
from scipy import stats

import igea
from igea import _capi, _lib
from igea.sim import interval_cp


def scipy_cp(k, n, level):
    a = 1 - level
    lo = stats.beta.ppf(a / 2, k, n - k + 1) if k > 0 else 0.0
    hi = stats.beta.ppf(1 - a / 2, k + 1, n - k) if k < n else 1.0
    return lo, hi


@pytest.mark.parametrize("k, n", [(0, 1), (1, 1), (0, 10), (3, 10), (10, 10), (17, 2000),
                                  (100, 10000), (9950, 10000), (31, 100000), (1, 4999999), (5000, 10000)])
@pytest.mark.parametrize("level", [0.99, 0.95, 0.5])
def test_cp_equals_scipy_beta_quantiles(k, n, level):
    # the header's accuracy: 1e-11 relative up to 1e5 trials, 1e-9 near the largest n
    np.testing.assert_allclose(interval_cp(k, n, level), scipy_cp(k, n, level),
                               rtol=1e-11 if n <= 1e5 else 1e-9, atol=1e-300)


def test_cp_contains_wilson_center_and_is_wider_at_the_edge():
    # k = 0: the exact upper end is 1 - (0.005)^(1/n) (closed form)
    for n in (5, 60, 2000):
        lo, hi = interval_cp(0, n, 0.99)
        assert lo == 0.0 and hi == pytest.approx(1 - 0.005 ** (1 / n), rel=1e-12)


def test_cp_refuses():
    out = np.array([7.0, 7.0])
    f = _lib.lib.igea_sim_interval_cp
    d = ctypes.c_double
    assert f(d(-1), d(10), d(0.99), _lib.dptr(out)) == -1
    assert f(d(11), d(10), d(0.99), _lib.dptr(out)) == -1
    assert f(d(1.5), d(10), d(0.99), _lib.dptr(out)) == -1
    assert f(d(np.nan), d(10), d(0.99), _lib.dptr(out)) == -1
    assert f(d(0), d(0), d(0.99), _lib.dptr(out)) == -2
    assert f(d(0), d(10.5), d(0.99), _lib.dptr(out)) == -2
    assert f(d(0), d(1e7), d(0.99), _lib.dptr(out)) == -2
    assert f(d(1), d(10), d(1.0), _lib.dptr(out)) == -3
    assert f(d(1), d(10), d(0.0), _lib.dptr(out)) == -3
    assert f(d(1), d(10), d(np.nan), _lib.dptr(out)) == -3
    assert f(d(1), d(10), d(0.99), None) == -4
    assert list(out) == [7.0, 7.0]


def test_montecarlo_python_and_driver_report_cp():
    fl = igea.simulate(seed=1)
    r = igea.montecarlo(fl.S, fl.sigma, 300, spec=fl.spec, threads=1, seed=3)
    for k in ("failed", "chi2_reject", "any_reject", "not_testable"):
        np.testing.assert_allclose(r.ci99_cp[k], scipy_cp(getattr(r, k), 300, 0.99),
                                   rtol=1e-11)
    drv = os.environ.get("IGEA_DRIVER")
    if not drv:
        pytest.skip("IGEA_DRIVER not set")
    d = json.loads(subprocess.run([drv, "montecarlo", "--flights", "300", "--seed", "3",
                                   "--threads", "1", "--json"], check=True,
                                  capture_output=True, text=True).stdout)
    for k in ("failed", "chi2_reject", "any_reject", "not_testable"):
        np.testing.assert_allclose(d[k]["ci99_cp"], scipy_cp(d[k]["count"], 300, 0.99),
                                   rtol=1e-11)
        assert "ci99" in d[k]  # Wilson kept
