"""igea.montecarlo(pool=F) and `igea montecarlo --pool F --json` report the
same pooled verdicts (igea_sim_pool_ex; the seed's rule here, the others in
test_mc_pool_rules.py), and they equal the pooling of the per-flight table
written out here with scipy.stats.chi2 and the Wilson score interval."""
import json
import math
import os
import subprocess

import numpy as np
import pytest
from scipy import stats

import igea

DRIVER = os.environ.get("IGEA_DRIVER")
if DRIVER and not os.path.exists(DRIVER):
    DRIVER = None


def wilson(k, n, conf=0.99):
    z = stats.norm.ppf(0.5 + conf / 2)
    p = k / n
    mid = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z / (1 + z * z / n) * np.sqrt(p * (1 - p) / n + z * z / (4 * n * n))
    return max(0.0, mid - half), min(1.0, mid + half)


def pool_by_hand(r, size, alpha):
    """(pools, failed) of consecutive groups of `size` flights of a result's
    per-flight table: the testable flights of a group pooled, 'out of spec'
    when one has a rejected component or sum chi2 >= chi2.isf(alpha, sum dof);
    a last group of fewer flights left out."""
    pools = r.flights // size
    failed = 0
    for g in range(pools):
        sl = slice(g * size, (g + 1) * size)
        tested = r.dof[sl] > 0
        if not tested.any():
            continue
        dof = int(r.dof[sl][tested].sum())
        if r.n_reject[sl][tested].sum() > 0 or \
                r.chi2[sl][tested].sum() >= stats.chi2.isf(alpha, dof):
            failed += 1
    return pools, failed


@pytest.fixture(scope="module")
def model():
    return igea.simulate(seed=11)


@pytest.mark.parametrize("size, alpha", [(1, 0.01), (3, 0.01), (7, 0.01), (4, 0.05), (13, 0.2)])
def test_pool_against_scipy(model, size, alpha):
    r = igea.montecarlo(model.S, model.sigma, 150, spec=model.spec, seed=6, sigma_w=1.3,
                        correction=False, alpha=alpha, pool=size)
    p = r.pool
    assert isinstance(p, igea.sim.MonteCarloPool)
    assert (p.size, p.pools, p.failed) == (size, *pool_by_hand(r, size, alpha))
    assert p.rate == p.failed / p.pools
    np.testing.assert_allclose(p.ci99, wilson(p.failed, p.pools), rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(p.ci99_cp, [stats.beta.ppf(0.005, p.failed, p.pools - p.failed + 1)
                                           if p.failed else 0.0,
                                           stats.beta.ppf(0.995, p.failed + 1, p.pools - p.failed)
                                           if p.failed < p.pools else 1.0], rtol=1e-9, atol=1e-15)
    if size == 1:  # one flight per group: the flight's own verdict
        assert p.failed == r.failed
    if size == 7:
        assert p.pools == 21 and 0 < p.failed < p.pools  # 150 = 21 x 7 + 3 left out


def test_pool_none_and_no_group(model):
    r = igea.montecarlo(model.S, model.sigma, 20, spec=model.spec, seed=2)
    assert r.pool is None
    assert igea.montecarlo(model.S, model.sigma, 20, spec=model.spec, seed=2, pool=0).pool is None
    # a group larger than the flights leaves no pool (a NaN rate): refused, as by the driver
    with pytest.raises(ValueError, match="pool=21 pools more flights than the 20 judged"):
        igea.montecarlo(model.S, model.sigma, 20, spec=model.spec, seed=2, pool=21)
    if DRIVER:
        r = subprocess.run([DRIVER, "montecarlo", "--flights", "20", "--pool", "21"],
                           capture_output=True, text=True)
        assert r.returncode == 64 and "--pool 21 pools more flights than --flights 20" in r.stderr
        assert r.stdout == ""
    p = igea.montecarlo(model.S, model.sigma, 20, spec=model.spec, seed=2, pool=20).pool
    assert (p.size, p.pools) == (20, 1)
    with pytest.raises(igea.IgeaError) as e:
        igea.montecarlo(model.S, model.sigma, 20, spec=model.spec, seed=2, pool=-1)
    assert e.value.function == "igea_sim_pool_ex" and e.value.argument == "size"


def _driver(*args):
    r = subprocess.run([DRIVER, "montecarlo", *args, "--json"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    return json.loads(r.stdout)


def _as_json(p):
    nan = lambda x: None if math.isnan(x) else x  # noqa: E731 (JSON writes NaN as null)
    return {"size": p.size, "pools": p.pools, "failed": p.failed, "rate": nan(p.rate),
            "ci99": [nan(x) for x in p.ci99], "ci99_cp": [nan(x) for x in p.ci99_cp],
            "mean_size": nan(p.mean_size)}


@pytest.mark.skipif(not DRIVER, reason="IGEA_DRIVER not set")
@pytest.mark.parametrize("flights, size, extra, kw", [
    (150, 3, [], {}),
    (100, 7, ["--sigma-w", "1.3", "--no-correction"], dict(sigma_w=1.3, correction=False)),
    (60, 4, ["--alpha", "0.05", "--first-flight", "5"], dict(alpha=0.05, first_flight=5)),
    (30, 30, [], {}),
])
def test_pool_equals_driver(model, flights, size, extra, kw):
    d = _driver("--flights", str(flights), "--seed", "4", "--pool", str(size), *extra)
    r = igea.montecarlo(model.S, model.sigma, flights, spec=model.spec, seed=4, pool=size, **kw)
    assert d["pool"] == _as_json(r.pool)
    assert set(d["pool"]) == {f for f in igea.sim.MonteCarloPool.__dataclass_fields__}
    assert d["failed"]["count"] == r.failed


@pytest.mark.skipif(not DRIVER, reason="IGEA_DRIVER not set")
def test_driver_pool_text_and_chunks(model):
    """More flights than one of the driver's progress chunks (1000): the
    table is pooled whole, groups straddling the chunk boundary included."""
    d = _driver("--flights", "1003", "--seed", "3", "--pool", "6", "--threads", "2")
    r = igea.montecarlo(model.S, model.sigma, 1003, spec=model.spec, seed=3, pool=6, threads=2)
    assert d["pool"] == _as_json(r.pool)
    assert (r.pool.pools, r.pool.failed) == pool_by_hand(r, 6, 0.01)
    t = subprocess.run([DRIVER, "montecarlo", "--flights", "1003", "--seed", "3", "--pool", "6"],
                       capture_output=True, text=True)
    assert t.returncode == 0, t.stderr
    lo, hi = r.pool.ci99
    assert ("pooled over 6 flights: %d of %d pools 'out of spec' (%.4f, 99%% interval "
            "[%.4f, %.4f], exact [%.4f, %.4f]); verdict rule seed: mean overall size of the "
            "pooled rule %.6f" % (r.pool.failed, r.pool.pools, r.pool.rate, lo, hi,
                                  *r.pool.ci99_cp, r.pool.mean_size)) in t.stdout
