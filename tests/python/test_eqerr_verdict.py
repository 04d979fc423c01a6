"""The overall verdict rules (IGEA_EQERR_OPT_VERDICT) in igea.eqerr,
igea.accuracy_test, igea.pool, igea.montecarlo and the driver, checked
against scipy's normal and chi-square quantiles written here and against
brute-force Monte Carlo of the union probability with Clopper-Pearson
intervals (scipy.stats.beta)."""
import json
import os
import subprocess

import numpy as np
import pytest
from scipy import stats

import igea
from test_eqerr import flight

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
FLIGHT = os.path.join(REPO, "examples", "flight")
RULES = ["seed", "chi2", "exact", "sidak"]


def driver(*args, cwd=None):
    return subprocess.run([os.environ["IGEA_DRIVER"], *map(str, args)], capture_output=True,
                          text=True, cwd=cwd)


def clopper_pearson(k, n, conf):
    """Exact binomial interval of k successes in n trials."""
    a = 1 - conf
    lo = stats.beta.ppf(a / 2, k, n - k + 1) if k > 0 else 0.0
    hi = stats.beta.ppf(1 - a / 2, k + 1, n - k) if k < n else 1.0
    return lo, hi


def union_mc(n, a, b, draws, seed):
    """P(max |z_i| > a or sum z_i^2 > b) by brute force: (count, draws)."""
    rng = np.random.default_rng(seed)
    k = 0
    for _ in range(draws // 100000):
        z = rng.standard_normal((100000, n))
        k += int(np.count_nonzero((np.abs(z).max(axis=1) > a) | ((z * z).sum(axis=1) > b)))
    return k, draws


def independent_thresholds(rule, n, alpha, a_exact=None):
    """(a, b) from scipy; for exact the common level g is read back from a."""
    if rule == "seed":
        return stats.norm.isf(alpha / 2), stats.chi2.isf(alpha, n)
    if rule == "chi2":
        return None, stats.chi2.isf(alpha, n)
    if rule == "sidak":
        g = 1 - (1 - alpha) ** (1 / n)
        return stats.norm.isf(g / 2), stats.chi2.isf(alpha, n)
    g = 2 * stats.norm.sf(a_exact)
    return a_exact, stats.chi2.isf(g, n)


# Brute-force Monte Carlo of the union size for small n: 400,000 draws per
# case; the library's size must lie in the 99.9 % Clopper-Pearson interval
# of the count (a false failure in 1 of 1000 runs per case, fixed seeds).
@pytest.mark.parametrize("n", [1, 2, 3, 5])
@pytest.mark.parametrize("rule", ["seed", "exact", "sidak"])
def test_union_size_by_brute_force(n, rule):
    a, b, size = igea.verdict_thresholds(rule, n, 0.01)
    k, draws = union_mc(n, a, b, 400000, seed=1000 * n + RULES.index(rule))
    lo, hi = clopper_pearson(k, draws, 0.999)
    assert lo <= size <= hi, (rule, n, k / draws, size, lo, hi)


@pytest.mark.parametrize("rule", RULES)
def test_eqerr_rules_on_a_flight(rule):
    S, dw, sigma, spec, _ = flight(5, x=[3.2, -2.9, 0.5] + [0.0] * 11)
    r = igea.eqerr(S, dw, sigma, spec, verdict=rule)
    seed = igea.eqerr(S, dw, sigma, spec)
    # the estimates do not depend on the rule, nor do the seed's level-alpha fields
    for k in ("eigenvalues", "equiv_err", "z"):
        np.testing.assert_array_equal(getattr(r, k), getattr(seed, k))
    assert (r.chi2_crit, r.z_crit, r.p_value) == (seed.chi2_crit, seed.z_crit, seed.p_value)
    n = r.n_test
    a, b = independent_thresholds(rule, n, 0.01, r.verdict_z_crit)
    assert r.verdict == rule
    assert r.verdict_chi2_crit == pytest.approx(b, rel=1e-9)
    if a is None:
        assert r.verdict_z_crit is None and not r.reject.any()
    else:
        assert r.verdict_z_crit == pytest.approx(a, rel=1e-9)
        np.testing.assert_array_equal(r.reject, np.abs(r.z) > a)
    assert r.passed == (not r.reject.any() and r.chi2 < b)
    assert r.n_reject == int(np.count_nonzero(r.reject))
    if rule in ("chi2", "exact"):
        assert r.overall_size == pytest.approx(0.01, rel=1e-9)
    assert "overall size" in r.summary() and rule in r.summary()
    if rule == "seed":
        assert (r.passed, r.n_reject, r.verdict_z_crit) == (seed.passed, seed.n_reject, seed.z_crit)


def test_rules_change_the_verdict():
    # |z| about 2.9 > z_0.995 = 2.576 but below the exact rule's 3.2 for n = 7
    S, dw, sigma, spec, _ = flight(5, x=[3.2, -2.9, 0.5] + [0.0] * 11)
    seed = igea.eqerr(S, dw, sigma, spec)
    exact = igea.eqerr(S, dw, sigma, spec, verdict="exact")
    zmax = np.abs(seed.z).max()
    assert seed.verdict_z_crit < zmax or exact.verdict_z_crit > zmax
    assert exact.verdict_z_crit > seed.verdict_z_crit
    assert exact.verdict_chi2_crit > seed.verdict_chi2_crit


@pytest.mark.parametrize("rule", ["exact", "sidak"])
def test_svd_route_same_verdict(rule):
    S, dw, sigma, spec, _ = flight(6, x=[3.1, -2.9, 0.5] + [0.0] * 11)
    e = igea.eqerr(S, dw, sigma, spec, verdict=rule)
    s = igea.eqerr(S, dw, sigma, spec, verdict=rule, route="svd")
    assert (s.n_test, s.passed, list(s.reject)) == (e.n_test, e.passed, list(e.reject))
    for k in ("verdict_z_crit", "verdict_chi2_crit", "overall_size"):
        assert getattr(s, k) == pytest.approx(getattr(e, k), rel=1e-12)


def test_options_checked():
    S, dw, sigma, spec, _ = flight(2)
    with pytest.raises(ValueError):
        igea.eqerr(S, dw, sigma, spec, verdict="bonferroni")
    with pytest.raises(igea.IgeaError, match="verdict"):
        igea.eqerr(S, dw, sigma, spec, verdict="exact", z_crit=2.58)
    r = igea.eqerr(S, dw, sigma, spec, z_crit=2.58)
    assert r.verdict_z_crit == 2.58


@pytest.mark.parametrize("rule", RULES)
def test_pool_rules(rule):
    res = [igea.eqerr(*flight(s)[:4]) for s in (11, 12, 13)]
    p = igea.pool(res, verdict=rule)
    n = sum(r.dof for r in res)
    z = np.concatenate([r.z for r in res])
    assert p.dof == n and p.chi2 == pytest.approx(sum(r.chi2 for r in res), rel=1e-12)
    a, b = independent_thresholds(rule, n, 0.01, p.verdict_z_crit)
    assert p.verdict_chi2_crit == pytest.approx(b, rel=1e-9)
    if a is not None:
        np.testing.assert_array_equal(p.reject, np.abs(z) > a)
    assert p.passed == (not p.reject.any() and p.chi2 < b)
    if rule == "seed":
        old = igea.pool(res)
        assert (old.passed, old.chi2, old.dof) == (p.passed, p.chi2, p.dof)
        assert p.overall_size == pytest.approx(igea.union_size(n, a, b), rel=1e-12)


def test_accuracy_test_rule_and_driver_table(tmp_path):
    x = np.array([2.9, -0.4, 1.1, 0.3, -2.7])
    lam = np.array([4e3, 900.0, 120.0, 15.0, 2.0])
    t = igea.accuracy_test(x, lam, verdict="exact")
    assert t.n_test == 4
    z = x[:4] / np.sqrt(1 + 1 / lam[:4])
    np.testing.assert_array_equal(t.reject, np.abs(z) > t.verdict_z_crit)
    np.savetxt(tmp_path / "t.txt", np.c_[x, lam])
    c = driver("test", "--table", "t.txt", "--verdict", "exact", "--json", cwd=tmp_path)
    j = json.loads(c.stdout)
    assert j["verdict"] == "exact"
    assert j["verdict_z_crit"] == pytest.approx(t.verdict_z_crit, rel=1e-12)
    assert j["overall_size"] == pytest.approx(0.01, rel=1e-9)
    assert j["reject"] == list(t.reject)
    c = driver("test", "--table", "t.txt", "--verdict", "exact", "--z-crit", "2.58",
               cwd=tmp_path)
    assert c.returncode == 64 and "--z-crit" in c.stderr


def test_driver_eqerr_and_pool_equal_python(tmp_path):
    files = []
    res = []
    for s in (21, 22):
        S, dw, sigma, spec, _ = flight(s)
        d = tmp_path / str(s)
        d.mkdir()
        for k, v in dict(S=S, dw=dw, sigma=sigma, spec=spec).items():
            np.savetxt(d / (k + ".txt"), v)
        c = driver("eqerr", "--S", "S.txt", "--dw", "dw.txt", "--sigma", "sigma.txt", "--spec",
                   "spec.txt", "--verdict", "sidak", "--json", "--out", "r.json", cwd=d)
        assert c.returncode in (0, 1), c.stderr
        j = json.load(open(d / "r.json"))
        r = igea.eqerr(S, dw, sigma, spec, verdict="sidak")
        for k in ("verdict_z_crit", "verdict_chi2_crit", "overall_size"):
            assert j[k] == pytest.approx(getattr(r, k), rel=1e-12), k
        assert j["verdict"] == "sidak" and j["passed"] == r.passed
        files.append(str(d / "r.json"))
        res.append(r)
    for rule in ("exact", "seed"):
        c = driver("test", "--results", ",".join(files), "--verdict", rule, "--json")
        j = json.loads(c.stdout)
        p = igea.pool(res, verdict=rule)
        assert j["passed"] == p.passed and j["n_reject"] == p.n_reject
        assert j["overall_size"] == pytest.approx(p.overall_size, rel=1e-12)
        assert j["verdict_chi2_crit"] == pytest.approx(p.verdict_chi2_crit, rel=1e-12)
    # a result without "z" cannot be pooled by another rule than the seed's
    bare = tmp_path / "bare.json"
    bare.write_text('{"chi2": 3.0, "dof": 2, "n_reject": 0}')
    c = driver("test", "--results", str(bare), "--verdict", "exact")
    assert c.returncode == 65 and '"z"' in c.stderr
    assert driver("test", "--results", str(bare)).returncode == 0


def test_montecarlo_counts_the_rule():
    base = ["montecarlo", "--flights", 1500, "--seed", 3, "--threads", 1, "--json"]
    out = {}
    for rule in RULES:
        c = driver(*base, "--verdict", rule, cwd=FLIGHT)
        assert c.returncode == 0, c.stderr
        out[rule] = json.loads(c.stdout)
        assert out[rule]["verdict"] == rule
    # chi2: no component test; its overall size is alpha
    assert out["chi2"]["any_reject"]["count"] == 0
    assert out["chi2"]["failed"]["count"] == out["chi2"]["chi2_reject"]["count"]
    assert out["chi2"]["mean_size"] == pytest.approx(0.01, rel=1e-9)
    assert out["exact"]["mean_size"] == pytest.approx(0.01, rel=1e-9)
    # the seed's verdict is unchanged by the option: the default run's counts
    c = driver(*base, cwd=FLIGHT)
    assert json.loads(c.stdout)["failed"] == out["seed"]["failed"]
    # the seed's 7-component size is about 0.07 (docs/validation.md): the
    # exact rule's failures are fewer than the seed's, and each rule's
    # count lies in the 99.9 % interval of its mean overall size
    for rule in ("seed", "exact", "sidak"):
        k = out[rule]["failed"]["count"]
        lo, hi = clopper_pearson(k, 1500, 0.999)
        assert lo <= out[rule]["mean_size"] <= hi, (rule, k, out[rule]["mean_size"])
    assert out["exact"]["failed"]["count"] < out["seed"]["failed"]["count"]
    r = igea.montecarlo(*_example_geometry(), 300, verdict="exact", threads=1, pool=3)
    assert r.verdict == "exact" and r.mean_size == pytest.approx(0.01, rel=1e-9)
    # pooled by the same rule (tests/python/test_mc_pool_rules.py): its size is alpha
    assert r.pool.pools == 100 and r.pool.mean_size == pytest.approx(0.01, rel=1e-9)
    c = driver("montecarlo", "--flights", 300, "--seed", 3, "--json", "--verdict", "exact",
               "--pool", 3, cwd=FLIGHT)
    assert c.returncode == 0, c.stderr
    assert json.loads(c.stdout)["pool"]["mean_size"] == pytest.approx(0.01, rel=1e-9)


def _example_geometry():
    S = np.loadtxt(os.path.join(FLIGHT, "S.txt"))
    sigma = np.loadtxt(os.path.join(FLIGHT, "sigma.txt"))
    return S, sigma
