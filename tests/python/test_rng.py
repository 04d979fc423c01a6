"""igea's keyed streams (generator "xoshiro", IGEA_SIM_XOSHIRO):
xoshiro256++ seeded per (seed, flight) by SplitMix64 and Doornik's
ziggurat normal (src/rng.c, docs/speed.md).

Statistical sanity against scipy's normal: moments with their large-sample
standard errors, Kolmogorov-Smirnov, the ziggurat's tail beyond R =
3.442619855899 (its base layer) with a binomial interval, and no
correlation between the flights of a stream, between streams, or along a
stream. The streams being fixed, each check is one draw of a test of size
about 1e-4 or smaller (stated at each); a defect of the generator or the
transform (a wrong table, a biased layer, overlapping streams) moves the
statistics by many standard errors. Then the Monte Carlo on these streams:
batched equal to flight by flight (to rounding), bit-identical for any
block size, thread count and split of the flight range."""
import ctypes

import numpy as np
import pytest
from scipy import stats

from igea import _capi, _lib
from test_mc_batch import MODELS, assert_same_study, run

lib = _lib.lib
XO = _capi.SIM_XOSHIRO
Z4 = 4.0  # two-sided normal quantile of size 6e-5


def flights(nflights, m=30, N=40, seed=7, first=0, sigma=0.5, sigma_w=2.0, **slots):
    """x_true (nflights x N) and dw / (sigma_w sigma) (nflights x m) of
    igea_sim_flight with S = 0 on the keyed streams: the truth's and the
    noise's standard normals."""
    S = np.zeros((m, N), order="F")
    h = ctypes.c_void_p()
    _lib.call("t", "igea_sim_model_create", m, N, _lib.dptr(S), m, ctypes.byref(h))
    try:
        _lib.call("t", "igea_sim_model_set_sigma", h, _lib.dptr(np.array([sigma])), 0, 0.0)
        opts = np.zeros(_capi.SIM_OPT_LEN)
        lib.igea_sim_defaults(_lib.dptr(opts))
        opts[_capi.SIM_OPT_GENERATOR] = XO
        opts[_capi.SIM_OPT_SIGMA_W] = sigma_w
        for k, v in slots.items():
            opts[getattr(_capi, "SIM_OPT_" + k.upper())] = v
        _lib.call("t", "igea_sim_model_set_noise", h, _lib.dptr(opts))
        X, W = np.zeros((nflights, N)), np.zeros((nflights, m))
        x, dw = np.zeros(N), np.zeros(m)
        for f in range(nflights):
            _lib.call("t", "igea_sim_flight", h, seed, first + f, _lib.dptr(x), _lib.dptr(dw))
            X[f], W[f] = x, dw / (sigma_w * sigma)
    finally:
        lib.igea_sim_model_free(h)
    return X, W


@pytest.fixture(scope="module")
def draws():
    X, W = flights(2500)
    return X, W, np.concatenate([X.ravel(), W.ravel()])  # 175,000 normals


def test_moments(draws):
    z = draws[2]
    n = z.size
    # standard errors of the sample mean, variance, skewness, excess kurtosis
    # of n standard normals: 1, sqrt(2), sqrt(6), sqrt(24) over sqrt(n)
    assert abs(z.mean()) < Z4 / np.sqrt(n)
    assert abs(z.var() - 1.0) < Z4 * np.sqrt(2.0 / n)
    assert abs(stats.skew(z)) < Z4 * np.sqrt(6.0 / n)
    assert abs(stats.kurtosis(z)) < Z4 * np.sqrt(24.0 / n)


def test_kolmogorov_smirnov(draws):
    X, W, z = draws
    for sample in (X.ravel(), W.ravel(), z):
        assert stats.kstest(sample, "norm").pvalue > 1e-4


def test_tail_and_layers(draws):
    """The base layer's tail |z| > R and the far tail |z| > 4.5 occur at the
    normal's rates (binomial, 4 sd); the 128 equiprobable layers of the
    ziggurat leave no trace in the counts of 200 equiprobable bins (chi2)."""
    z = draws[2]
    n = z.size
    for r in (3.442619855899, 4.5):
        p = 2 * stats.norm.sf(r)
        k = np.sum(np.abs(z) > r)
        assert abs(k - n * p) <= Z4 * np.sqrt(n * p * (1 - p)) + 1, r
    edges = stats.norm.ppf(np.linspace(0, 1, 201))
    counts = np.histogram(z, edges)[0]
    assert stats.chisquare(counts).pvalue > 1e-4


def test_no_correlation_between_flights_and_streams(draws):
    """Sample correlations of n pairs are N(0, 1/n) under independence: the
    same draw index in consecutive flights, in the same flight of two seeds
    (and of seeds differing by one with flights differing by one: keys
    seed * 2^32 + flight), and consecutive draws along a stream."""
    X, W, _ = draws
    rows = np.hstack([X, W])
    X2, W2 = flights(2500, seed=8)
    X3, W3 = flights(2500, seed=6, first=1)
    other, shifted = np.hstack([X2, W2]), np.hstack([X3, W3])
    pairs = [(rows[:-1], rows[1:]), (rows, other), (rows, shifted), (rows[:, :-1], rows[:, 1:])]
    for a, b in pairs:
        n = a.size
        r = np.corrcoef(a.ravel(), b.ravel())[0, 1]
        assert abs(r) < Z4 / np.sqrt(n)
    # each draw index across flights: 70 correlations of 2500 pairs, the largest
    # within the Bonferroni bound of size 1e-3
    rr = [np.corrcoef(rows[:-1, j], rows[1:, j])[0, 1] for j in range(rows.shape[1])]
    assert np.max(np.abs(rr)) < stats.norm.isf(1e-3 / 2 / len(rr)) / np.sqrt(2499)


def test_flights_are_keyed_and_reproducible():
    """A flight is the same whatever was drawn before (its key, not a
    position in a sequence), different for another flight or seed, and the
    default generator's flights are not these."""
    a = flights(3, first=10)
    b = flights(1, first=12)
    np.testing.assert_array_equal(a[0][2], b[0][0])
    np.testing.assert_array_equal(a[1][2], b[1][0])
    assert not np.any(a[0][0] == a[0][1])
    c = flights(1, first=10, seed=8)
    assert not np.any(c[0][0] == a[0][0])


def test_noise_models_on_the_keyed_streams():
    """AR(1): lag-1 correlation phi along the epochs of an axis; outliers at
    their probability (binomial, 4 sd) and scale; the general noise rows
    (corr: sim_noise.c through the GSL face of the generator) still
    standard normal per row after the 3x3 correlation is undone."""
    phi = 0.6
    _, W = flights(400, m=60, ar1=phi)
    e = W.reshape(400, 20, 3)
    a, b = e[:, :-1, :].ravel(), e[:, 1:, :].ravel()
    r = np.corrcoef(a, b)[0, 1]
    assert abs(r - phi) < Z4 * (1 - phi ** 2) / np.sqrt(a.size)
    _, W = flights(2000, m=30, outlier_prob=0.05, outlier_scale=10.0)
    z = W.ravel()
    n, p = z.size, 0.05
    k = np.sum(np.abs(z) > 6.0)  # an outlier adds N(0, 100): |z| > 6 w.p. 2 sf(6 / sqrt(101))
    pk = p * 2 * stats.norm.sf(6.0 / np.sqrt(101.0)) + (1 - p) * 2 * stats.norm.sf(6.0)
    assert abs(k - n * pk) <= Z4 * np.sqrt(n * pk * (1 - pk)) + 1
    _, W = flights(2000, m=30, corr=0.5)
    # corr ramps 0 .. 0.5 along the epochs: the first epoch's rows are independent
    first = W[:, :3].ravel()
    assert stats.kstest(first, "norm").pvalue > 1e-4


KEYED = [(n, S, sg, sp, dict(sl, generator=XO), eq) for n, S, sg, sp, sl, eq in MODELS]


@pytest.mark.parametrize("name,S,sigma,spec,slots,eq", KEYED, ids=[m[0] for m in KEYED])
def test_batched_equals_per_flight(name, S, sigma, spec, slots, eq):
    """The batched keyed path forms diag(lam0) V^T X + Q^T E where the
    flight-by-flight path forms Q^T ((S D X + E) / sigma): equal to rounding.
    The latter's rounding on component i is about eps ||Sw x|| ~ eps
    sqrt(lam_max) against a component of size sqrt(lam_i) >= sqrt(10) (the
    tested ones): a relative 1e-12 sqrt(lam_max / 10) (1e-12 for eps times a
    margin for m-term sums)."""
    one = run(S, sigma, spec, eq=eq, batch=1, **slots)
    if name != "nothing testable":
        assert 0 < one[0][_capi.SIM_MC_FAILED] < 150
    Sw = np.asarray(S) * (1.0 if spec is None else np.asarray(spec)) / sigma
    rtol = 1e-12 * max(1.0, np.sqrt(np.linalg.norm(Sw, 2) ** 2 / 10.0))
    assert_same_study(run(S, sigma, spec, eq=eq, **slots), one, rtol)


@pytest.mark.parametrize("name,S,sigma,spec,slots,eq", KEYED[:4], ids=[m[0] for m in KEYED[:4]])
def test_bit_identical_blocks_threads(name, S, sigma, spec, slots, eq):
    ref = run(S, sigma, spec, eq=eq, batch=2, threads=1, **slots)
    for batch, threads in ((7, 1), (0, 2), (64, 3), (1000, 2), (33, 4)):
        got = run(S, sigma, spec, eq=eq, batch=batch, threads=threads, **slots)
        for a, b in zip(ref, got):
            np.testing.assert_array_equal(a, b)


@pytest.mark.parametrize("cut", [80, 37, 1])
def test_sub_range_is_the_same_flights(cut):
    S, sigma, slots = KEYED[2][1], KEYED[2][2], KEYED[2][4]
    whole = run(S, sigma, first=5, nflights=150, **slots)[4]
    a = run(S, sigma, first=5, nflights=cut, **slots)[4]
    b = run(S, sigma, first=5 + cut, nflights=150 - cut, threads=2, **slots)[4]
    np.testing.assert_array_equal(whole, np.vstack([a, b]))


def test_size_of_the_test_on_the_keyed_streams():
    """Under H0 (sigma_w = 1, X drawn from its spec) the seed's chi-square
    test on the keyed streams rejects at about alpha; MODELS' 120x21 S,
    2000 flights, the chi-square component's rate within 4 binomial sd of
    the rate the default streams give on the same flights count."""
    S, sigma = MODELS[0][1], MODELS[0][2]
    xo = run(S, sigma, nflights=2000, sigma_w=1.0, generator=XO)[0]
    mt = run(S, sigma, nflights=2000, sigma_w=1.0)[0]
    n = 2000
    for k in (_capi.SIM_MC_CHI2_REJECT, _capi.SIM_MC_FAILED):
        p = (xo[k] + mt[k]) / (2 * n)
        assert abs(xo[k] - mt[k]) <= Z4 * np.sqrt(2 * n * p * (1 - p)) + 1


def test_the_names():
    import igea
    lib.igea_choice_name.restype = ctypes.c_char_p
    assert lib.igea_choice_name(_capi.CHOICE_SIM_GENERATOR, XO) == b"xoshiro"
    r = igea.montecarlo(MODELS[0][1], 0.01, 40, generator="xoshiro", sigma_w=1.3)
    assert r.flights == 40 and 0 < r.failed < 40
