"""The biased CEP: the circle about the aim point holding 50 % of a miss
with a mean offset (igea_impact_circle_prob_offset, igea_impact_cep_offset).
Checked against the closed form of a circular normal (the Rice
distribution of scipy: P(|x| <= r) = rice.cdf(r / s, d / s)), against the
zero-mean functions, a degenerate closed form written here, and Monte Carlo
(numpy draws) within 1 %."""
import numpy as np
import pytest
from scipy import stats

import igea


@pytest.mark.parametrize("s,d", [(3.0, 4.0), (10.0, 0.5), (1.0, 6.0), (2.0, 0.0)])
def test_rice(s, d):
    cov = np.diag([s * s, s * s])
    mean = d * np.array([0.6, -0.8])
    for r in (0.1 * s, s, 2.5 * s, d + 3 * s):
        np.testing.assert_allclose(igea.circle_prob(cov, r, mean=mean),
                                   stats.rice.cdf(r / s, d / s), rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(igea.cep(cov, mean=mean), s * stats.rice.ppf(0.5, d / s),
                               rtol=1e-9)
    np.testing.assert_allclose(igea.cep(cov, 0.9, mean=mean), s * stats.rice.ppf(0.9, d / s),
                               rtol=1e-9)


def test_zero_mean_and_degenerate():
    cov = np.array([[400.0, 120.0], [120.0, 90.0]])
    for r in (3.0, 17.0, 60.0):
        np.testing.assert_allclose(igea.circle_prob(cov, r, mean=[0, 0]),
                                   igea.circle_prob(cov, r), rtol=1e-13)
    np.testing.assert_allclose(igea.cep(cov, mean=[0, 0]), igea.cep(cov), rtol=1e-13)
    assert igea.cep(np.zeros((2, 2)), mean=[3.0, 4.0]) == 5.0
    # x2 fixed at m2 = 30 (variance 0 along y): P = P(|x1| <= sqrt(r^2 - 30^2))
    c = np.diag([25.0, 0.0])
    for r in (31.0, 40.0):
        h = np.sqrt(r * r - 900.0)
        want = stats.norm.cdf(h, 2.0, 5.0) - stats.norm.cdf(-h, 2.0, 5.0)
        np.testing.assert_allclose(igea.circle_prob(c, r, mean=[2.0, 30.0]), want, rtol=1e-13)
    assert igea.circle_prob(c, 29.0, mean=[2.0, 30.0]) == 0.0


def test_monte_carlo():
    """400,000 draws (numpy) of an elliptical miss (sigmas 20.8 and 8.8 m,
    correlated) offset by (35, -10) m: the fraction inside the exact biased
    CEP is 0.5 within 1 % (its binomial sd is 0.16 %), and the draws'
    median distance from the aim point is the CEP within 1 %; the unbiased
    CEP (about the mean) is far from it."""
    cov = np.array([[400.0, 120.0], [120.0, 90.0]])
    mean = np.array([35.0, -10.0])
    c = igea.cep(cov, mean=mean)
    x = np.random.default_rng(11).multivariate_normal(mean, cov, 400_000)
    dist = np.hypot(x[:, 0], x[:, 1])
    assert abs(np.mean(dist <= c) - 0.5) < 0.005
    assert abs(np.median(dist) / c - 1.0) < 0.01
    assert igea.cep(cov) < 0.6 * c


def test_refusals():
    cov = np.eye(2)
    with pytest.raises(ValueError):
        igea.cep(cov, mean=[1.0, 2.0, 3.0])
    with pytest.raises(igea.IgeaError):
        igea.cep(cov, mean=[np.nan, 0.0])
    with pytest.raises(igea.IgeaError):
        igea.cep(cov, 1.0, mean=[1.0, 0.0])
    with pytest.raises(igea.IgeaError):
        igea.circle_prob(cov, -1.0, mean=[1.0, 0.0])
    with pytest.raises(igea.IgeaError):
        igea.circle_prob([[1.0, 2.0], [2.0, 1.0]], 1.0, mean=[1.0, 0.0])   # not PSD
