"""The batched Monte Carlo (IGEA_SIM_OPT_BATCH >= 2 or automatic) against
the flight-by-flight path (IGEA_SIM_OPT_BATCH = 1) on the same flights:
both judge the same draws, so the counts, the per-flight degrees of
freedom, rejections and verdicts are equal and T and c agree to rounding
(1e-12 relative); and the batched results are bit-identical for every
block size and thread count (each flight's dgemm columns have the same
shape whatever block it falls in)."""
import ctypes

import numpy as np
import pytest

from igea import _capi, _lib

lib = _lib.lib


def run(S, sigma, spec=None, nflights=150, seed=3, first=5, threads=1, eq=None, **slots):
    """igea_sim_montecarlo_ex on the model S, sigma (one value), spec with the
    simulation slots given: (counts, rates, comp_tested, comp_reject, table
    with the ZMAX column)."""
    S = np.asfortranarray(S, dtype=float)
    m, N = S.shape
    h = ctypes.c_void_p()
    _lib.call("t", "igea_sim_model_create", m, N, _lib.dptr(S), m, ctypes.byref(h))
    try:
        _lib.call("t", "igea_sim_model_set_sigma", h, _lib.dptr(np.array([sigma])), 0, 0.0)
        if spec is not None:
            _lib.call("t", "igea_sim_model_set_spec", h, _lib.dptr(np.asarray(spec, float)))
        opts = np.zeros(_capi.SIM_OPT_LEN)
        lib.igea_sim_defaults(_lib.dptr(opts))
        for k, v in slots.items():
            opts[getattr(_capi, "SIM_OPT_" + k.upper())] = v
        _lib.call("t", "igea_sim_model_set_noise", h, _lib.dptr(opts))
        eqo = np.zeros(_capi.EQERR_OPT_LEN)
        lib.igea_eqerr_defaults(_lib.dptr(eqo))
        for k, v in (eq or {}).items():
            eqo[getattr(_capi, "EQERR_OPT_" + k.upper())] = v
        counts, rates = np.zeros(_capi.SIM_MC_LEN), np.zeros(_capi.SIM_MC_RATES_LEN)
        ct, cr = np.zeros(N, dtype=np.intc), np.zeros(N, dtype=np.intc)
        table = np.zeros((nflights, _capi.SIM_MC_TABLE_COLS_Z), order="F")
        _lib.call("t", "igea_sim_montecarlo_ex", h, _lib.dptr(eqo), seed, first, nflights,
                  threads, _lib.dptr(counts), _lib.dptr(rates), _lib.iptr(ct), _lib.iptr(cr),
                  _lib.dptr(table), nflights, _capi.SIM_MC_TABLE_COLS_Z)
    finally:
        lib.igea_sim_model_free(h)
    return counts, rates, ct, cr, table


def graded(m, N, seed, spread):
    """A random S (m x N) whose column norms span 10^-spread .. 10^spread."""
    rng = np.random.default_rng(seed)
    return rng.standard_normal((m, N)) * np.logspace(-spread, spread, N)


# (name, S, sigma, spec, simulation slots, eqerr slots)
MODELS = [
    ("120x21", graded(360, 21, 1, 1.5), 0.01, None, dict(sigma_w=1.3), {}),
    ("120x21 spec", graded(360, 21, 2, 1.0), 0.02, np.linspace(0.5, 2.0, 21),
     dict(sigma_w=0.8, ar1=0.4, growth=0.5, outlier_prob=0.01), {}),
    ("40x74 sidak", graded(120, 74, 3, 1.5), 0.01, None, dict(sigma_w=1.1),
     dict(verdict=_capi.STATS_VERDICT_SIDAK, overall_size=1)),
    ("60x12 exact", graded(180, 12, 4, 2.0), 0.01, None, dict(sigma_w=1.0, corr=0.3),
     dict(verdict=_capi.STATS_VERDICT_EXACT)),
    ("nothing testable", graded(30, 6, 5, 0.0) * 1e-3, 1.0, None, {}, {}),
]


def assert_same_study(a, b, rtol):
    ca, ra, cta, cra, ta = a
    cb, rb, ctb, crb, tb = b
    ints = [_capi.SIM_MC_FLIGHTS, _capi.SIM_MC_FAILED, _capi.SIM_MC_CHI2_REJECT,
            _capi.SIM_MC_ANY_REJECT, _capi.SIM_MC_NOT_TESTABLE]
    np.testing.assert_array_equal(ca[ints], cb[ints])
    np.testing.assert_allclose(ca, cb, rtol=rtol, atol=0)
    np.testing.assert_allclose(ra, rb, rtol=rtol, atol=0)
    np.testing.assert_array_equal(cta, ctb)
    np.testing.assert_array_equal(cra, crb)
    for col in (_capi.SIM_MC_TABLE_DOF, _capi.SIM_MC_TABLE_N_REJECT):
        np.testing.assert_array_equal(ta[:, col], tb[:, col])
    for col in (_capi.SIM_MC_TABLE_CHI2, _capi.SIM_MC_TABLE_SCALE, _capi.SIM_MC_TABLE_ZMAX):
        np.testing.assert_allclose(ta[:, col], tb[:, col], rtol=rtol, atol=0)


@pytest.mark.parametrize("name,S,sigma,spec,slots,eq", MODELS, ids=[m[0] for m in MODELS])
def test_batched_equals_per_flight(name, S, sigma, spec, slots, eq):
    one = run(S, sigma, spec, eq=eq, batch=1, **slots)
    assert one[0][_capi.SIM_MC_FLIGHTS] == 150
    if name == "nothing testable":
        assert one[0][_capi.SIM_MC_NOT_TESTABLE] == 150
    else:  # a study that exercises the tests: some flights pass, some fail
        assert 0 < one[0][_capi.SIM_MC_FAILED] < 150
    assert_same_study(run(S, sigma, spec, eq=eq, **slots), one, 1e-12)


@pytest.mark.parametrize("name,S,sigma,spec,slots,eq", MODELS[:3], ids=[m[0] for m in MODELS[:3]])
def test_bit_identical_blocks_threads(name, S, sigma, spec, slots, eq):
    ref = run(S, sigma, spec, eq=eq, batch=2, threads=1, **slots)
    for batch, threads in ((7, 1), (0, 2), (64, 3), (1000, 2), (150, 1), (33, 4)):
        got = run(S, sigma, spec, eq=eq, batch=batch, threads=threads, **slots)
        for a, b in zip(ref, got):
            np.testing.assert_array_equal(a, b)


@pytest.mark.parametrize("name,S,sigma,spec,slots,eq", [MODELS[2], MODELS[1]],
                         ids=[MODELS[2][0], MODELS[1][0]])
def test_flight_by_flight_bit_identical_threads(name, S, sigma, spec, slots, eq):
    """The flight-by-flight path (batch 1; also the noise judge's) shares
    its flights out among the threads as they come free: every output,
    mean_size included (summed in flight order), is the same bits for
    1 .. 5 threads (BLAS on one thread, as the driver runs them: each
    flight's dsyevd would otherwise wake OpenBLAS's own pool from every
    thread)."""
    import igea
    eq = dict(eq, overall_size=1)
    with igea.blas_threads(1):
        ref = run(S, sigma, spec, eq=eq, batch=1, threads=1, **slots)
        assert ref[0][_capi.SIM_MC_MEAN_SIZE] > 0
        for threads in (2, 3, 5):
            got = run(S, sigma, spec, eq=eq, batch=1, threads=threads, **slots)
            for a, b in zip(ref, got):
                np.testing.assert_array_equal(a, b)
        robust = dict(eq, robust=1)
        ref = run(S, sigma, spec, eq=robust, nflights=40, threads=1, **slots)
        for threads in (2, 4):
            got = run(S, sigma, spec, eq=robust, nflights=40, threads=threads, **slots)
            for a, b in zip(ref, got):
                np.testing.assert_array_equal(a, b)


def test_model_keeps_its_setup():
    """A model's first run keeps its decomposition for the later runs (the
    driver's and Python's chunks): runs on one model, in turn and from
    four threads at once, equal runs on fresh models bit for bit, and a
    new sigma or spec drops what was kept."""
    import threading
    S, sigma = MODELS[2][1], MODELS[2][2]
    m, N = S.shape
    S = np.asfortranarray(S)

    def new_model(sig, spec=None):
        h = ctypes.c_void_p()
        _lib.call("t", "igea_sim_model_create", m, N, _lib.dptr(S), m, ctypes.byref(h))
        _lib.call("t", "igea_sim_model_set_sigma", h, _lib.dptr(np.array([sig])), 0, 0.0)
        if spec is not None:
            _lib.call("t", "igea_sim_model_set_spec", h, _lib.dptr(spec))
        return h

    def mc(h, first, n, batch=0, threads=1):
        opts = np.zeros(_capi.SIM_OPT_LEN)
        lib.igea_sim_defaults(_lib.dptr(opts))
        opts[_capi.SIM_OPT_SIGMA_W], opts[_capi.SIM_OPT_BATCH] = 1.1, batch
        _lib.call("t", "igea_sim_model_set_noise", h, _lib.dptr(opts))
        counts, table = np.zeros(_capi.SIM_MC_LEN), np.zeros((n, 5), order="F")
        _lib.call("t", "igea_sim_montecarlo_ex", h, None, 3, first, n, threads,
                  _lib.dptr(counts), None, None, None, _lib.dptr(table), n, 5)
        return counts, table

    spec = np.linspace(0.5, 1.5, N)
    fresh = {}
    for key, sig, sp, batch in (("a", sigma, None, 0), ("a1", sigma, None, 1),
                                ("b", 2 * sigma, None, 0), ("c", 2 * sigma, spec, 0)):
        h = new_model(sig, sp)
        fresh[key] = mc(h, 0, 120, batch)[1]
        lib.igea_sim_model_free(h)
    h = new_model(sigma)
    try:
        for batch in (0, 1, 0):  # the flight-by-flight path reads the same set-up
            got = np.vstack([mc(h, 0, 50, batch)[1], mc(h, 50, 70, batch, 2)[1]])
            np.testing.assert_array_equal(got, fresh["a1" if batch else "a"])
        out = [None] * 4

        def work(i):
            out[i] = mc(h, 0, 120, 0, 1 + i % 2)[1]
        ths = [threading.Thread(target=work, args=(i,)) for i in range(4)]
        for t in ths:
            t.start()
        for t in ths:
            t.join()
        for o in out:
            np.testing.assert_array_equal(o, fresh["a"])
        _lib.call("t", "igea_sim_model_set_sigma", h, _lib.dptr(np.array([2 * sigma])), 0, 0.0)
        np.testing.assert_array_equal(mc(h, 0, 120)[1], fresh["b"])
        _lib.call("t", "igea_sim_model_set_spec", h, _lib.dptr(spec))
        np.testing.assert_array_equal(mc(h, 0, 120)[1], fresh["c"])
        assert not np.array_equal(fresh["a"], fresh["b"])
        assert not np.array_equal(fresh["b"], fresh["c"])
    finally:
        lib.igea_sim_model_free(h)


@pytest.mark.parametrize("cut", [80, 37, 1])
def test_sub_range_is_the_same_flights(cut):
    """Flights 5 .. 154 run as 5 .. 4 + cut and 5 + cut .. 154 (each flight
    at another column of the products): the same table rows, bit for bit."""
    S, sigma, slots = MODELS[2][1], MODELS[2][2], MODELS[2][4]
    whole = run(S, sigma, first=5, nflights=150, **slots)[4]
    a = run(S, sigma, first=5, nflights=cut, **slots)[4]
    b = run(S, sigma, first=5 + cut, nflights=150 - cut, threads=2, **slots)[4]
    np.testing.assert_array_equal(whole, np.vstack([a, b]))


@pytest.mark.parametrize("bad", [-1.0, 1.5, _capi.SIM_BATCH_MAX + 1.0])
def test_batch_slot_checked(bad):
    opts = np.zeros(_capi.SIM_OPT_LEN)
    lib.igea_sim_defaults(_lib.dptr(opts))
    opts[_capi.SIM_OPT_BATCH] = bad
    assert lib.igea_sim_check_opts(_lib.dptr(opts)) == 1 + _capi.SIM_OPT_BATCH
    assert lib.igea_opt_name(_capi.MODULE_SIM, _capi.SIM_OPT_BATCH).decode() == "batch"


# ---- campaigns: chunks by first_flight, merged (python/igea/campaign.py) ----

class SerialClient:
    """The two Client methods campaign_montecarlo uses, run here, in an
    order that is not the flights' (the merge must not depend on it)."""

    def __init__(self):
        self.calls = 0

    def submit(self, fn, *args, pure=True, retries=None, **kwargs):
        self.calls += 1
        return (fn, args, kwargs)

    def gather(self, futures):
        done = {i: f[0](*f[1], **f[2]) for i, f in reversed(list(enumerate(futures)))}
        return [done[i] for i in range(len(futures))]


def assert_same_result(a, b, size_rtol=1e-12):
    for k, v in vars(a).items():
        w = getattr(b, k)
        if k == "mean_size":  # rebuilt from the chunks' means: to rounding
            assert v == pytest.approx(w, rel=size_rtol, abs=0), k
        elif isinstance(v, np.ndarray):
            np.testing.assert_array_equal(v, w, err_msg=k)
        elif isinstance(v, float) and np.isnan(v):
            assert np.isnan(w), k
        else:
            assert v == w, k


CAMPAIGN = dict(S=MODELS[0][1], sigma=0.01, flights=203, sigma_w=1.3, seed=4, first_flight=11)


@pytest.mark.parametrize("chunk", [1000, 64, 50, 7])
def test_campaign_equals_single_run(chunk):
    import igea
    with igea.blas_threads(1):  # as every chunk runs (python/igea/campaign.py)
        whole = igea.montecarlo(**CAMPAIGN, pool=10)
    client = SerialClient()
    got = igea.campaign_montecarlo(client, chunk, **CAMPAIGN, pool=10)
    assert client.calls == -(-203 // chunk)
    assert 0 < whole.failed < whole.flights and got.pool.pools == 20
    assert_same_result(got, whole)


def test_campaign_noise_judge_and_not_testable():
    import igea
    kw = dict(S=MODELS[3][1], sigma=0.01, flights=60, robust=True, seed=2)
    with igea.blas_threads(1):
        whole = igea.montecarlo(**kw)
    assert_same_result(igea.campaign_montecarlo(SerialClient(), 13, **kw), whole)
    kw = dict(S=MODELS[4][1], sigma=1.0, flights=30)
    got = igea.campaign_montecarlo(SerialClient(), 8, **kw)
    assert got.not_testable == 30 and np.isnan(got.mean_scale)
    with igea.blas_threads(1):
        assert_same_result(got, igea.montecarlo(**kw))


def test_campaign_arguments():
    import igea
    with pytest.raises(ValueError, match="chunk"):
        igea.campaign_montecarlo(SerialClient(), 0, **CAMPAIGN)
    with pytest.raises(ValueError, match="client"):
        igea.campaign_montecarlo(None, 10, **CAMPAIGN)
    with pytest.raises(TypeError, match="client"):
        igea.campaign_montecarlo(object(), 10, **CAMPAIGN)
    # pooled by another rule than the seed's (igea_sim_pool_ex): merged alike
    kw = dict(CAMPAIGN, pool=5, verdict="sidak")
    with igea.blas_threads(1):
        whole = igea.montecarlo(**kw)
    assert_same_result(igea.campaign_montecarlo(SerialClient(), 10, **kw), whole)
