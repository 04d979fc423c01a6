"""Overall size of the verdict (igea.union_size, igea.verdict_thresholds)
against scipy quadrature of the acceptance region and brute-force Monte
Carlo of independent N(0, 1) components."""
import math

import numpy as np
import pytest
from scipy import integrate, special, stats

import igea

SQ2 = math.sqrt(2.0)


def ref_size2(a, b):
    """1 - P(|z1|, |z2| <= a, z1^2 + z2^2 <= b) by scipy.integrate.quad."""
    top = min(a, math.sqrt(b))

    def f(z):
        r = b - z * z
        return 0.0 if r <= 0 else stats.norm.pdf(z) * special.erf(min(a, math.sqrt(r)) / SQ2)

    pts = [math.sqrt(b - a * a)] if a * a < b < 2 * a * a else None
    v, _ = integrate.quad(f, 0.0, top, points=pts, epsabs=1e-14, epsrel=1e-13, limit=200)
    return 1.0 - 2.0 * v


def ref_size3(a, b):
    """The same for n = 3: nested scipy quadrature over z1 >= 0, z2 >= 0,
    the z3 integral in closed form, split where min(a, sqrt(.)) switches."""
    def inner(z1):
        r1 = b - z1 * z1
        if r1 <= 0:
            return 0.0
        top = min(a, math.sqrt(r1))

        def g(z2):
            r = r1 - z2 * z2
            return 0.0 if r <= 0 else stats.norm.pdf(z2) * special.erf(min(a, math.sqrt(r)) / SQ2)

        c = r1 - a * a
        pts = [math.sqrt(c)] if 0 < c < top * top else None
        v, _ = integrate.quad(g, 0.0, top, points=pts, epsabs=1e-13, epsrel=1e-12, limit=200)
        return stats.norm.pdf(z1) * 2.0 * v

    top = min(a, math.sqrt(b))
    pts = [math.sqrt(b - j * a * a) for j in (1, 2) if 0 < b - j * a * a < top * top]
    v, _ = integrate.quad(inner, 0.0, top, points=pts or None, epsabs=1e-12, epsrel=1e-11,
                          limit=200)
    return 1.0 - 2.0 * v


def seed_thresholds(n, alpha):
    return stats.norm.isf(alpha / 2), stats.chi2.isf(alpha, n)


@pytest.mark.parametrize("a,b", [(2.5758, 9.21), (2.0, 5.0), (1.0, 1.5), (3.0, 17.0),
                                 (2.0, 3.0), (1.0, 3.0)])
def test_union_n2_scipy(a, b):
    assert abs(igea.union_size(2, a, b) - ref_size2(a, b)) <= 1e-10


@pytest.mark.parametrize("a,b", [(2.5758, 11.34), (2.0, 7.0), (1.5, 5.0), (1.2, 2.0)])
def test_union_n3_scipy(a, b):
    assert abs(igea.union_size(3, a, b) - ref_size3(a, b)) <= 1e-9


def test_union_limits():
    assert igea.union_size(5, math.inf, 15.0) == pytest.approx(stats.chi2.sf(15.0, 5), rel=1e-12)
    assert igea.union_size(5, 2.5, math.inf) == pytest.approx(
        1 - (1 - 2 * stats.norm.sf(2.5)) ** 5, rel=1e-12)
    assert igea.union_size(1, 2.0, 3.0) == pytest.approx(2 * stats.norm.sf(math.sqrt(3.0)),
                                                         rel=1e-12)
    with pytest.raises(igea.IgeaError):
        igea.union_size(0, 2.0, 3.0)
    with pytest.raises(igea.IgeaError):
        igea.union_size(3, -1.0, 3.0)
    with pytest.raises(ValueError):
        igea.verdict_thresholds("bonferroni", 3, 0.01)


def mc_reject(n_max, draws, rules, seed=20261201, chunk=200000):
    """Monte Carlo rejection counts: rules is a list of (n, a, b)."""
    rng = np.random.default_rng(seed)
    counts = np.zeros(len(rules), dtype=np.int64)
    done = 0
    while done < draws:
        m = min(chunk, draws - done)
        z = rng.standard_normal((m, n_max))
        cmax = np.maximum.accumulate(np.abs(z), axis=1)
        csum = np.cumsum(z * z, axis=1)
        for i, (n, a, b) in enumerate(rules):
            counts[i] += np.count_nonzero((cmax[:, n - 1] > a) | (csum[:, n - 1] > b))
        done += m
    return counts / draws


def within(p_mc, p, draws, k=4.5):
    """|MC - p| within k binomial standard deviations sqrt(p (1 - p) / N)."""
    return abs(p_mc - p) <= k * math.sqrt(p * (1 - p) / draws)


def test_union_monte_carlo_small_n():
    draws = 10 ** 6
    rules = []
    for n in (5, 7, 11):
        for alpha in (0.01, 0.05):
            a, b = seed_thresholds(n, alpha)
            rules.append((n, a, b))
        rules.append((n, 1.5, 0.9 * n))
    rates = mc_reject(11, draws, rules)
    for (n, a, b), r in zip(rules, rates):
        p = igea.union_size(n, a, b)
        assert within(r, p, draws), (n, a, b, r, p)


def test_seed_size_n7_printed():
    a, b, s = igea.verdict_thresholds("seed", 7, 0.01)
    assert a == pytest.approx(stats.norm.isf(0.005), rel=1e-13)
    assert b == pytest.approx(stats.chi2.isf(0.01, 7), rel=1e-12)
    print("seed verdict, n = 7, alpha = 0.01: true size %.6f" % s)
    assert 0.05 < s < 0.09


@pytest.mark.parametrize("alpha", [0.01, 0.05])
def test_exact_rule_reproduces_alpha(alpha):
    rules = []
    for n in range(1, 21):
        a, b, s = igea.verdict_thresholds("exact", n, alpha)
        assert s == pytest.approx(alpha, rel=1e-9)
        g = 2 * stats.norm.sf(a)  # the common level
        assert alpha / (n + 1) <= g <= alpha * (1 + 1e-12)
        assert stats.chi2.sf(b, n) == pytest.approx(g, rel=1e-8)
        if n == 1:
            assert g == pytest.approx(alpha, rel=1e-12)
        elif n == 2:
            assert abs(ref_size2(a, b) - alpha) <= 1e-9
        elif n == 3:
            assert abs(ref_size3(a, b) - alpha) <= 1e-9
        else:
            rules.append((n, a, b))
    draws = 10 ** 6
    rates = mc_reject(20, draws, rules, seed=7 if alpha == 0.01 else 8)
    for (n, a, b), r in zip(rules, rates):
        assert within(r, alpha, draws), (n, r, alpha)


def test_sidak_and_chi2_rules():
    alpha = 0.01
    for n in (2, 3, 7):
        a, b, s = igea.verdict_thresholds("sidak", n, alpha)
        gs = 1 - (1 - alpha) ** (1.0 / n)
        assert 2 * stats.norm.sf(a) == pytest.approx(gs, rel=1e-10)
        assert b == pytest.approx(stats.chi2.isf(alpha, n), rel=1e-12)
        if n == 2:
            assert abs(s - ref_size2(a, b)) <= 1e-10
        if n == 3:
            assert abs(s - ref_size3(a, b)) <= 1e-9
        assert alpha < s < 2 * alpha
        a, b, s = igea.verdict_thresholds("chi2", n, alpha)
        assert math.isinf(a) and s == alpha
        assert stats.chi2.sf(b, n) == pytest.approx(alpha, rel=1e-10)


# Larger n, where igea_stats_union_size takes the inclusion-exclusion route
# (n - floor(b / a^2) >= 8, docs/eqerr.md): values of the other algorithm,
# the recursion over k of D_k(s) on Gauss-Legendre panels (the route of
# every size before; itself checked above against scipy quadrature and
# Monte Carlo), computed with it to its 1e-12 accuracy and tabulated here.
RECURSION = [
    (20, 3.0, 37.566, 0.056966125194669065),
    (50, 2.5, 76.154, 0.464911253974377),
    (74, 3.0, 105.202, 0.18445488632216792),
    (74, 2.0, 105.202, 0.9681279406320181),
    (100, 3.5, 135.807, 0.052831162124960945),
    (150, 3.0, 193.208, 0.3354748426242239),
    (200, 3.2, 249.445, 0.2441569172131647),
    # terms C(n, j) eps^j up to 5e3: the cancellation the route allows
    (150, 1.8, 193.20768638551058, 0.9999861331224572),
]


@pytest.mark.parametrize("n, a, b, size", RECURSION)
def test_union_large_n_against_the_recursion(n, a, b, size):
    assert igea.union_size(n, a, b) == pytest.approx(size, abs=1e-11, rel=0)


def test_union_large_n_monte_carlo():
    """n = 74 at the seed's thresholds (alpha 0.01, z 3): 200,000 draws of 74
    independent N(0, 1); the size inside the 99.9 % binomial interval."""
    n, a = 74, 3.0
    b = stats.chi2.isf(0.01, n)
    rng = np.random.default_rng(74)
    hits = 0
    for _ in range(20):
        z = rng.standard_normal((10000, n))
        hits += int(np.count_nonzero((np.abs(z).max(axis=1) > a) | ((z * z).sum(axis=1) > b)))
    p = igea.union_size(n, a, b)
    lo, hi = stats.binom.interval(0.999, 200000, p)
    assert lo <= hits <= hi, (hits, 200000 * p)
