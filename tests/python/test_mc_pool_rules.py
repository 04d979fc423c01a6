"""The Monte Carlo's pooled verdicts by every verdict rule (igea_sim_pool_ex,
igea.montecarlo(pool=F, verdict=...), `igea montecarlo --pool F --verdict`),
checked against what is written here: each flight's largest |z| from a numpy
judge of the flight's own draws, the pooled verdicts by hand with scipy's
thresholds (the exact rule's common level read back from its a), the
pooled exact rule's size within the 99 % Clopper-Pearson interval around
alpha, and a numpy Monte Carlo of the pooled z under the same thresholds."""
import ctypes
import json
import math
import os
import subprocess

import numpy as np
import pytest
from scipy import stats

import igea
from igea import _capi, _lib
from test_eqerr_verdict import clopper_pearson, independent_thresholds, union_mc

DRIVER = os.environ.get("IGEA_DRIVER")
if DRIVER and not os.path.exists(DRIVER):
    DRIVER = None
RULES = ["seed", "chi2", "exact", "sidak"]
ALPHA = 0.01


@pytest.fixture(scope="module")
def model():
    return igea.simulate(seed=11)


def thresholds(rule, n, alpha=ALPHA):
    """(a, b) of the rule for n pooled components: scipy's, the exact
    rule's common level taken from the library's a (checked below)."""
    a_exact = igea.verdict_thresholds("exact", n, alpha)[0] if rule == "exact" else None
    a, b = independent_thresholds(rule, n, alpha, a_exact)
    return (math.inf if a is None else a), b


def pool_by_hand(r, size, rule, alpha=ALPHA):
    """(pools, failed) of consecutive groups of `size` flights: the testable
    flights pooled, 'out of spec' when a flight's largest |z| exceeds a or
    the summed chi2 reaches b, a and b the rule's for the summed dof."""
    pools, failed = r.flights // size, 0
    for g in range(pools):
        sl = slice(g * size, (g + 1) * size)
        t = r.dof[sl] > 0
        if not t.any():
            continue
        a, b = thresholds(rule, int(r.dof[sl][t].sum()), alpha)
        failed += bool(r.zmax[sl][t].max() > a or r.chi2[sl][t].sum() >= b)
    return pools, failed


def test_zmax_is_the_flights_largest_z(model):
    """zmax from the flights' own draws (igea.simulate of the same seed and
    flight) judged in numpy with the correction off: z_i = (p_i' b / l_i) /
    sqrt(1 + 1 / l_i) for l_i >= 10."""
    r = igea.montecarlo(model.S, model.sigma, 12, spec=model.spec, seed=7, sigma_w=1.2,
                        correction=False, threads=2)
    Sw = model.S * model.spec / model.sigma[:, None]
    lam, P = np.linalg.eigh(Sw.T @ Sw)
    tested = lam >= 10.0
    for f in range(12):
        dw = igea.simulate(seed=7, flight=f, sigma_w=1.2).dw
        x = (P.T @ (Sw.T @ (dw / model.sigma)))[tested] / lam[tested]
        z = x / np.sqrt(1 + 1 / lam[tested])
        assert r.zmax[f] == pytest.approx(np.abs(z).max(), rel=1e-9)
        assert r.dof[f] == tested.sum() and r.chi2[f] == pytest.approx((z * z).sum(), rel=1e-9)
    # the seed's per-flight rejection is zmax > z_{0.995}
    big = igea.montecarlo(model.S, model.sigma, 400, spec=model.spec, seed=3, sigma_w=1.3)
    np.testing.assert_array_equal(big.n_reject > 0, big.zmax > stats.norm.isf(ALPHA / 2))
    assert 0 < np.count_nonzero(big.n_reject) < 400


@pytest.mark.parametrize("rule", RULES)
@pytest.mark.parametrize("size", [1, 3, 7])
def test_pool_rule_by_hand(model, rule, size):
    r = igea.montecarlo(model.S, model.sigma, 210, spec=model.spec, seed=5, correction=False,
                        terms=model.terms, x={"gyro_bias_y": 2.5}, verdict=rule, pool=size)
    p = r.pool
    assert (p.pools, p.failed) == pool_by_hand(r, size, rule)
    assert 0 < p.failed < p.pools
    if size == 1:  # one flight per group: the flight's own verdict by the rule
        assert p.failed == r.failed
    n = 7 * size  # every flight tests 7 components (correction off)
    if rule in ("chi2", "exact"):
        assert p.mean_size == pytest.approx(ALPHA, rel=1e-9)
    else:
        a, b = thresholds(rule, n)
        k, draws = union_mc(n, a, b, 200000, seed=40 + size)
        lo, hi = clopper_pearson(k, draws, 0.999)
        assert lo <= p.mean_size <= hi, (rule, size, p.mean_size, k / draws)


@pytest.mark.parametrize("rule", ["exact", "sidak"])
def test_pool_on_the_flight_by_flight_path(model, rule):
    """The robust judge runs flight by flight: its zmax and pools are the
    same bits on 1 and 2 threads and pool as by hand."""
    kw = dict(spec=model.spec, seed=8, correction=False, terms=model.terms,
              x={"gyro_bias_y": 2.5}, robust=True, verdict=rule, pool=3)
    with igea.blas_threads(1):
        one = igea.montecarlo(model.S, model.sigma, 60, threads=1, **kw)
        two = igea.montecarlo(model.S, model.sigma, 60, threads=2, **kw)
    np.testing.assert_array_equal(one.zmax, two.zmax)
    assert one.pool == two.pool
    assert (one.pool.pools, one.pool.failed) == pool_by_hand(one, 3, rule)
    assert 0 < one.pool.failed < one.pool.pools


def test_exact_thresholds_are_one_level_of_size_alpha():
    """The pooled exact rule's (a, b) at one common level g, its union size
    alpha by brute force (scipy and numpy only)."""
    for n, seed in ((14, 1), (35, 2)):
        a, b = thresholds("exact", n)
        g = 2 * stats.norm.sf(a)
        assert stats.chi2.sf(b, n) == pytest.approx(g, rel=1e-9) and g < ALPHA
        k, draws = union_mc(n, a, b, 400000, seed=seed)
        lo, hi = clopper_pearson(k, draws, 0.999)
        assert lo <= ALPHA <= hi, (n, k / draws)


@pytest.mark.parametrize("F", [2, 5, 10])
def test_pooled_exact_size(model, F):
    """4,000 pools of F flights in spec (sigma_w 1, X ~ N(0, I)), the
    correction off: the pooled exact verdict's rate within the 99 %
    Clopper-Pearson interval around alpha, and within that of a numpy
    Monte Carlo of 4,000 x F x 7 standard normal z under the same
    thresholds; the seed's pooled rate beside its union size."""
    pools = 4000
    kw = dict(spec=model.spec, seed=900 + F, correction=False, generator="xoshiro", pool=F)
    r = igea.montecarlo(model.S, model.sigma, pools * F, verdict="exact", **kw)
    assert r.pool.pools == pools and (r.dof == 7).all()
    lo, hi = clopper_pearson(r.pool.failed, pools, 0.99)
    assert lo <= ALPHA <= hi, (F, r.pool.failed)
    assert tuple(r.pool.ci99_cp) == pytest.approx((lo, hi), rel=1e-9)
    a, b = thresholds("exact", 7 * F)
    z = np.random.default_rng(F).standard_normal((pools, 7 * F))
    k = int(np.count_nonzero((np.abs(z).max(1) > a) | ((z * z).sum(1) >= b)))
    lo, hi = clopper_pearson(k, pools, 0.99)
    assert lo <= r.pool.rate <= hi and lo <= ALPHA <= hi, (F, k, r.pool.failed)
    # the seed's rule pools the same flights' z: its rate is its union size
    s = igea.montecarlo(model.S, model.sigma, pools * F, verdict="seed", **kw).pool
    lo, hi = clopper_pearson(s.failed, pools, 0.99)
    assert lo <= s.mean_size <= hi, (F, s.failed, s.mean_size)
    assert s.mean_size == pytest.approx(igea.union_size(7 * F, *thresholds("seed", 7 * F)),
                                        rel=1e-12)


# ---- the library function's arguments --------------------------------------

def pool_ex(table, size, eq=None, ldt=None):
    n = table.shape[0]
    out = np.full(_capi.SIM_POOL_LEN, -7.0)
    st = _lib.lib.igea_sim_pool_ex(n, _lib.dptr(table), n if ldt is None else ldt, size,
                                   _lib.dptr(eq), _lib.dptr(out))
    return st, out


def eq_opts(**slots):
    eq = np.zeros(_capi.EQERR_OPT_LEN)
    _lib.lib.igea_eqerr_defaults(_lib.dptr(eq))
    for k, v in slots.items():
        eq[getattr(_capi, "EQERR_OPT_" + k.upper())] = v
    return eq


def table_of(r):
    t = np.zeros((r.flights, _capi.SIM_MC_TABLE_COLS_Z), order="F")
    for k in ("chi2", "dof", "n_reject", "scale", "zmax"):
        t[:, getattr(_capi, "SIM_MC_TABLE_" + k.upper())] = getattr(r, k)
    return t


def test_seed_rule_equals_igea_sim_pool(model):
    r = igea.montecarlo(model.S, model.sigma, 300, spec=model.spec, seed=2, sigma_w=1.2)
    t = table_of(r)
    for size in (1, 4, 9, 301):
        old = np.zeros(_capi.SIM_POOL_LEN)
        assert _lib.lib.igea_sim_pool(300, _lib.dptr(t), 300, size, ctypes.c_double(ALPHA),
                                      _lib.dptr(old)) == 0
        st, new = pool_ex(t, size, eq_opts(overall_size=1))
        assert st == 0
        np.testing.assert_array_equal(new[:5], old[:5])
        assert (new[6:] == 0).all() and (old[5:] == 0).all()
        if size == 301:
            assert math.isnan(new[_capi.SIM_POOL_MEAN_SIZE])
    # the size is computed only when asked for (seed, sidak), as for a flight
    assert pool_ex(t, 4, eq_opts(overall_size=0))[1][_capi.SIM_POOL_MEAN_SIZE] == 0.0
    assert pool_ex(t, 4, None)[1][_capi.SIM_POOL_MEAN_SIZE] == 0.0
    assert pool_ex(t, 4, eq_opts(verdict=_capi.STATS_VERDICT_CHI2))[1][
        _capi.SIM_POOL_MEAN_SIZE] == pytest.approx(ALPHA, rel=1e-14)


def test_arguments_and_table_checked(model):
    r = igea.montecarlo(model.S, model.sigma, 40, spec=model.spec, seed=2)
    t = table_of(r)
    Z, D = _capi.SIM_MC_TABLE_ZMAX, _capi.SIM_MC_TABLE_DOF
    lib = _lib.lib
    out = np.zeros(_capi.SIM_POOL_LEN)
    assert lib.igea_sim_pool_ex(0, _lib.dptr(t), 40, 2, None, _lib.dptr(out)) == -1
    assert lib.igea_sim_pool_ex(40, None, 40, 2, None, _lib.dptr(out)) == -2
    assert pool_ex(t, 2, ldt=39)[0] == -3
    assert pool_ex(t, 0)[0] == -4
    assert pool_ex(t, 2, eq_opts(alpha=1.5))[0] == -5
    assert lib.igea_sim_pool_ex(40, _lib.dptr(t), 40, 2, None, None) == -6
    for col, row, v, st in ((Z, 3, -1.0, -2), (Z, 3, np.nan, _capi.ENONFINITE),
                            (D, 3, 2.5, -2), (D, 3, 0.0, -2)):  # dof 0 needs chi2 and zmax 0
        bad = t.copy()
        bad[row, col] = v
        s, o = pool_ex(bad, 2)
        assert s == st and (o == -7.0).all(), (col, v)
    # the exact rule beyond IGEA_STATS_UNION_N_MAX pooled components
    assert (r.dof >= 7).all()  # 29 flights: more than 200 components
    assert pool_ex(t, 29, eq_opts(verdict=_capi.STATS_VERDICT_EXACT))[0] == _capi.EVERDICT
    # igea_sim_montecarlo_ex: 4 or 5 columns, the first four those of igea_sim_montecarlo
    h = ctypes.c_void_p()
    S = np.asfortranarray(model.S)
    m, N = S.shape
    lib.igea_sim_model_create(m, N, _lib.dptr(S), m, ctypes.byref(h))
    try:
        c4, c5 = np.zeros(_capi.SIM_MC_LEN), np.zeros(_capi.SIM_MC_LEN)
        t4, t5 = np.zeros((30, 4), order="F"), np.zeros((30, 5), order="F")
        assert lib.igea_sim_montecarlo(h, None, 1, 0, 30, 1, _lib.dptr(c4), None, None, None,
                                       _lib.dptr(t4), 30) == 0
        assert lib.igea_sim_montecarlo_ex(h, None, 1, 0, 30, 2, _lib.dptr(c5), None, None, None,
                                          _lib.dptr(t5), 30, 5) == 0
        np.testing.assert_array_equal(t5[:, :4], t4)
        np.testing.assert_array_equal(c5, c4)
        for bad in (3, 6):
            assert lib.igea_sim_montecarlo_ex(h, None, 1, 0, 30, 1, _lib.dptr(c5), None, None,
                                              None, _lib.dptr(t5), 30, bad) == -13
        assert lib.igea_sim_montecarlo_ex(h, None, 1, 0, 30, 1, _lib.dptr(c5), None, None,
                                          None, None, 0, 0) == 0  # ncols ignored without table
    finally:
        lib.igea_sim_model_free(h)


@pytest.mark.skipif(not DRIVER, reason="IGEA_DRIVER not set")
@pytest.mark.parametrize("rule", ["exact", "sidak", "chi2"])
def test_driver_pools_by_the_rule(model, rule):
    c = subprocess.run([DRIVER, "montecarlo", "--flights", "120", "--seed", "4", "--pool", "4",
                        "--verdict", rule, "--sigma-w", "1.3", "--json"],
                       capture_output=True, text=True)
    assert c.returncode == 0, c.stderr
    d = json.loads(c.stdout)["pool"]
    r = igea.montecarlo(model.S, model.sigma, 120, spec=model.spec, seed=4, sigma_w=1.3,
                        verdict=rule, pool=4)
    assert (d["pools"], d["failed"]) == (r.pool.pools, r.pool.failed) == (30, r.pool.failed)
    assert d["mean_size"] == pytest.approx(r.pool.mean_size, rel=1e-15)
    assert d["ci99_cp"] == pytest.approx(list(r.pool.ci99_cp), rel=1e-15)
    assert (r.pool.pools, r.pool.failed) == pool_by_hand(r, 4, rule)
