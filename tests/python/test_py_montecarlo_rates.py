"""igea.montecarlo's rates and 99 % intervals are the library's, checked
here against the Wilson score interval written out in numpy/scipy."""
import numpy as np
from scipy import stats

import igea


def wilson(k, n, conf=0.99):
    z = stats.norm.ppf(0.5 + conf / 2)
    p = k / n
    mid = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z / (1 + z * z / n) * np.sqrt(p * (1 - p) / n + z * z / (4 * n * n))
    return max(0.0, mid - half), min(1.0, mid + half)


def test_rates_and_intervals():
    fl = igea.simulate(igea.reference_trajectory(40.0, 10.0), seed=4)
    r = igea.montecarlo(fl.S, fl.sigma, 60, spec=fl.spec, seed=8, sigma_w=1.6, correction=False)
    assert r.failed > 0
    for name in ("failed", "chi2_reject", "any_reject", "not_testable"):
        k = getattr(r, name)
        assert r.rate(name) == k / 60
        np.testing.assert_allclose(r.ci99[name], wilson(k, 60), rtol=1e-12, atol=1e-15)
    assert len(r.scale) == 60 and np.all(r.dof >= 0)
