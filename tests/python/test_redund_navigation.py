"""Seed 002's Figs. 9-11 as bench/redund_navigation.py computes them:
the ratio of the non-redundant to the fused position error against the
number of fused X accelerometers follows its closed form
sqrt((Px + Pr) / (Px / n + Pr)) (Px the position variance of the X bias
alone, Pr the rest: the covariance is linear in the bias variances), and
tends to sqrt(n) as the X share tends to 1; the 6 h static errors of the
fused IMU (the average rule) are the mean of the four groups' errors (the
error model is linear and, with seed 002's grouping, the mean of the groups'
biases is the fused bias: each Ax once, Ay1/Ay2 and the gyros twice each)."""
import importlib.util
import os

import numpy as np
import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
spec = importlib.util.spec_from_file_location(
    "redund_navigation", os.path.join(HERE, "..", "..", "bench", "redund_navigation.py"))
rn = importlib.util.module_from_spec(spec)
spec.loader.exec_module(rn)


def test_fig9_ratio_closed_form():
    ep, single, fused, ratios, px, pr = rn.fig9(step=300.0)
    for n, r in zip((1, 2, 3, 4), ratios):
        assert r == pytest.approx(rn.closed_ratio(n, px, pr), rel=1e-8)
    assert ratios[0] == pytest.approx(1.0, rel=1e-12)
    # X dominates: the ratio of 4 fused X is close to, and below, sqrt(4)
    assert 0.85 < px / (px + pr) < 1.0
    assert 1.7 < ratios[3] < 2.0
    # the whole fused IMU: X / 4, Y and Z / 2, gyros / 2
    assert 1.8 < single[-1] / fused[-1] < 2.0
    assert np.all(np.diff(single[1:]) > 0)


def test_static_fused_is_mean_of_groups():
    st = rn.static_errors(hours=2.0)
    groups = [st["group %d" % g] for g in (1, 2, 3, 4)]
    t, de, az = st["fused"]
    np.testing.assert_allclose(de, np.mean([g[1] for g in groups], axis=0), rtol=1e-9,
                               atol=1e-9 * np.max(np.abs(de)))
    np.testing.assert_allclose(az, np.mean([g[2] for g in groups], axis=0), rtol=1e-9,
                               atol=1e-9 * np.max(np.abs(az)))
