"""Real pandas inputs: S as a DataFrame (its columns the term names), dw
and sigma as Series on its index, spec as a Series on its columns, in
igea.eqerr (both routes), igea.montecarlo and the estimators of igea.regress. Labels in another order are
aligned as pandas aligns; other labels are refused naming the argument.
The stand-in frame of test_py_results_input.py keeps the duck-typed path
tested without pandas."""
import numpy as np
import pytest

import igea

pd = pytest.importorskip("pandas")


@pytest.fixture(scope="module")
def fl():
    return igea.simulate(seed=7)


@pytest.fixture(scope="module")
def frame(fl):
    t = np.repeat(fl.epochs, 3)
    axis = np.tile(["x", "y", "z"], fl.epochs.size)
    index = pd.MultiIndex.from_arrays([t, axis], names=["t", "axis"])
    return pd.DataFrame(fl.S, columns=list(fl.terms), index=index)


def test_dataframe_columns_are_the_term_names(fl, frame):
    dw = pd.Series(fl.dw, index=frame.index)
    a = igea.eqerr(frame, dw, fl.sigma, fl.spec)
    b = igea.eqerr(fl.S, fl.dw, fl.sigma, fl.spec, names=fl.terms)
    assert a.to_dict() == b.to_dict()
    assert getattr(a, "_names") == list(fl.terms)
    named = {t[0] for c in a.components for t in c["terms"]}
    assert named and named <= set(fl.terms)


def test_series_are_aligned_by_label(fl, frame):
    rng = np.random.default_rng(0)
    rows = rng.permutation(len(frame))
    cols = rng.permutation(frame.shape[1])
    dw = pd.Series(fl.dw, index=frame.index).iloc[rows]       # shuffled rows
    sigma = pd.Series(fl.sigma, index=frame.index).iloc[rows[::-1]]
    spec = pd.Series(fl.spec, index=list(fl.terms)).iloc[cols]  # shuffled terms
    a = igea.eqerr(frame, dw, sigma, spec)
    b = igea.eqerr(fl.S, fl.dw, fl.sigma, fl.spec, names=fl.terms)
    assert a.to_dict() == b.to_dict()
    # the noise-model route takes the same inputs
    c = igea.eqerr(frame, dw, sigma, spec, robust=True)
    d = igea.eqerr(fl.S, fl.dw, fl.sigma, fl.spec, names=fl.terms, robust=True)
    assert c.to_dict() == d.to_dict()


def test_other_labels_are_refused(fl, frame):
    dw = pd.Series(fl.dw)              # 0 .. m-1, but S is indexed by (t, axis)
    with pytest.raises(ValueError, match=r"^dw: its index .* is not S's index"):
        igea.eqerr(frame, dw, fl.sigma, fl.spec)
    spec = pd.Series(fl.spec, index=["a%d" % j for j in range(fl.spec.size)])
    with pytest.raises(ValueError, match=r"^spec: its index .* is not S's columns"):
        igea.eqerr(frame, fl.dw, fl.sigma, spec)
    # arrays pair by position, as without a frame
    r = igea.eqerr(frame, fl.dw, fl.sigma, fl.spec)
    assert r.passed == igea.eqerr(fl.S, fl.dw, fl.sigma, fl.spec).passed
    # a default-indexed frame with default-indexed Series: in order
    f0 = pd.DataFrame(fl.S, columns=list(fl.terms))
    r0 = igea.eqerr(f0, pd.Series(fl.dw), pd.Series(fl.sigma), fl.spec)
    assert r0.to_dict() == r.to_dict()


def test_a_missing_value_is_refused(fl, frame):
    bad = frame.copy()
    bad.iloc[4, 2] = np.nan
    with pytest.raises(ValueError):
        igea.eqerr(bad, fl.dw, fl.sigma, fl.spec)
    obj = frame.astype(object)
    obj.iloc[0, 0] = "n/a"
    with pytest.raises(ValueError, match="^S: not an array of numbers"):
        igea.eqerr(obj, fl.dw, fl.sigma, fl.spec)


def test_transposed_frame_is_named(fl, frame):
    m, N = fl.S.shape
    with pytest.raises(ValueError, match=r"S has %d rows and %d columns; dw has %d values: "
                                         r"pass S\.T\?" % (N, m, m)):
        igea.eqerr(frame.T, fl.dw, fl.sigma)


def test_montecarlo_frame_terms(fl, frame):
    spec = pd.Series(fl.spec, index=list(fl.terms)).iloc[::-1]
    sigma = pd.Series(fl.sigma, index=frame.index)
    name = fl.terms[3]
    a = igea.montecarlo(frame, sigma, 30, spec=spec, x={name: 3.0}, seed=4)
    b = igea.montecarlo(fl.S, fl.sigma, 30, spec=fl.spec, terms=fl.terms, x={name: 3.0}, seed=4)
    np.testing.assert_array_equal(a.chi2, b.chi2)
    assert a.failed == b.failed and a.mean_scale == b.mean_scale
    with pytest.raises(ValueError, match="not one of the terms"):
        igea.montecarlo(frame, sigma, 3, spec=spec, x={"nope": 1.0})


def test_regress_estimators_take_a_frame(fl, frame):
    """ls, ridge, pce, ebr, bayes and collinearity name their terms from a
    frame's columns and align Series as eqerr does; the estimate is the
    weighted least-squares solution numpy gives on the same rows."""
    rng = np.random.default_rng(3)
    rows = rng.permutation(len(frame))
    y = pd.Series(fl.dw, index=frame.index).iloc[rows]
    sigma = pd.Series(fl.sigma, index=frame.index).iloc[rows[::-1]]
    spec = pd.Series(fl.spec, index=list(fl.terms)).iloc[::-1]
    r = igea.regress.ls(frame, y, sigma, spec=spec)
    assert r.names == tuple(fl.terms)
    w = 1.0 / fl.sigma
    ref = np.linalg.lstsq(fl.S * w[:, None], fl.dw * w, rcond=None)[0]
    np.testing.assert_allclose(r.x, ref, rtol=1e-8, atol=1e-12 * np.abs(ref).max())
    assert r.summary().splitlines()[2].split()[0] == fl.terms[0]
    N = len(fl.terms)
    for f in (lambda a, y, s, p, **k: igea.regress.ridge(a, y, s, spec=p, rule="hkb", **k),
              lambda a, y, s, p, **k: igea.regress.pce(a, y, s, spec=p, ncomp=5, **k),
              lambda a, y, s, p, **k: igea.regress.ebr(a, y, s, spec=p, **k),
              lambda a, y, s, p, **k: igea.regress.bayes(a, y, np.eye(N), sigma=s, spec=p, **k),
              lambda a, y, s, p, **k: igea.regress.collinearity(a, y, s, spec=p, **k)):
        a = f(frame, y, sigma, spec)
        b = f(fl.S, fl.dw, fl.sigma, fl.spec, names=fl.terms)
        assert a.names == tuple(fl.terms)
        np.testing.assert_array_equal(getattr(a, "x", getattr(a, "vif", None)),
                                      getattr(b, "x", getattr(b, "vif", None)))
    with pytest.raises(ValueError, match=r"^y: its index .* is not S's index"):
        igea.regress.ls(frame, pd.Series(fl.dw), fl.sigma)
