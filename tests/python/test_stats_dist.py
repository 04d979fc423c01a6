"""Python wrappers of the distribution functions against mpmath values.

References: mpmath 1.3.0, mp.dps = 50 (the script is in tests/test_stats.c):
  P = z**a * exp(-z) / gamma(a + 1) * hyp1f1(1, a + 1, z), z = x / 2, a = dof / 2;
  Q = gammainc(a, z, inf, regularized=True); normal tail erfc(x / sqrt(2)) / 2.
"""
import math

import pytest

import igea


@pytest.mark.parametrize("x, dof, p, q", [
    (9891, 1e4, 2.209922655604454e-1, 7.790077344395546e-1),
    (103000, 1e5, 9.9999999998471087e-1, 1.5289130117302352e-11),
    (9.99e6, 1e7, 1.2654131885775518e-2, 9.8734586811422448e-1),
])
def test_chi2_mpmath(x, dof, p, q):
    tol = 1e-14 if dof <= 1e5 else 1e-13
    assert igea.chi2_cdf(x, dof) == pytest.approx(p, rel=tol)
    assert igea.chi2_sf(x, dof) == pytest.approx(q, rel=tol)


def test_chi2_quantile_mpmath():
    assert igea.chi2_upper(1e-10, 1e5) == pytest.approx(1.0287124188112092e+5, rel=1e-14)
    assert igea.chi2_quantile(0.5, 1e7) == pytest.approx(9.9999993333333412e+6, rel=1e-13)


def test_normal_sf():
    assert igea.normal_sf(8.3) == pytest.approx(5.205569744890254e-17, rel=1e-15)
    assert igea.normal_sf(38) == 2.8854283600687843e-316   # subnormal, correctly rounded
    assert igea.normal_sf(-1.5) == pytest.approx(9.3319279873114193e-1, rel=1e-15)
    assert igea.normal_sf(math.inf) == 0.0
    with pytest.raises(igea.IgeaError):
        igea.normal_sf(math.nan)


def test_t_f_against_scipy_and_mpmath():
    """mpmath 1.3.0 values (tests/test_stats.c) and scipy.stats at moderate dof."""
    from scipy import stats
    assert igea.t_sf(2.0, 10) == pytest.approx(3.6694017385370183e-2, rel=1e-13)
    assert igea.t_quantile(0.975, 10) == pytest.approx(2.2281388519862742, rel=1e-14)
    assert igea.f_sf(3.0, 2, 10) == pytest.approx(1.6 ** -5, rel=1e-14)  # closed form
    for t, n in [(-2.5, 3), (0.7, 17), (4.0, 250)]:
        assert igea.t_sf(t, n) == pytest.approx(stats.t.sf(t, n), rel=1e-12)
    for f, a, b in [(0.8, 4, 9), (2.5, 12, 40)]:
        assert igea.f_sf(f, a, b) == pytest.approx(stats.f.sf(f, a, b), rel=1e-12)
