"""r.plot(ax=None) with real matplotlib (the Agg backend): every result
class that has plot() is drawn here, and what is on the axes is the
result's own numbers (lines, error bars, log scales, labels, legend); the
figure renders to PNG. The ImportError without matplotlib is tested in
test_py_results_plot.py (the module hidden)."""
import io
import sys

import numpy as np
import pytest

import igea
from igea import _capi, _lib, _result

mpl = pytest.importorskip("matplotlib")
mpl.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


@pytest.fixture(scope="module")
def fl():
    return igea.simulate(seed=3)


def wilson99(k, n):
    """The 99 % Wilson score interval (z = Phi^-1(0.995) = 2.5758293035489004)."""
    z, p = 2.5758293035489004, k / n
    c = (p + z * z / (2 * n)) / (1 + z * z / n)
    h = z / (1 + z * z / n) * np.sqrt(p * (1 - p) / n + z * z / (4 * n * n))
    return max(c - h, 0.0), min(c + h, 1.0)


def make(name, fl):
    rng = np.random.default_rng(1)
    if name == "EqerrResult":
        return igea.eqerr(fl.S, fl.dw, fl.sigma, fl.spec)
    if name == "NoiseEqerrResult":   # a subclass: EqerrResult's picture
        return igea.eqerr(fl.S, fl.dw, fl.sigma, fl.spec, robust=True)
    if name == "AllanResult":
        return igea.allan(0.5 + rng.normal(0, 0.01, 4000), 10.0)
    if name == "StabilityResult":
        return igea.stability(rng.normal(0, 1.0, 4000), 1.0, kind="mdev")
    if name == "MonteCarloResult":
        return igea.montecarlo(fl.S, fl.sigma, 50, spec=fl.spec, seed=2)
    raise AssertionError("no example of %s here: add one" % name)


def png(ax):
    buf = io.BytesIO()
    ax.figure.savefig(buf, format="png")
    data = buf.getvalue()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 5000
    return data


def test_every_plot_class_is_drawn_here(fl):
    with_plot = [c for c in vars(igea).values()
                 if isinstance(c, type) and hasattr(c, "plot") and c.__module__.startswith("igea")]
    assert set(_result.PLOTS) <= {c.__name__ for c in with_plot}
    assert all(any(c.__name__ in _result.PLOTS for c in k.__mro__) for k in with_plot)
    for c in with_plot:
        r = make(c.__name__, fl)
        ax = r.plot()
        assert isinstance(ax, mpl.axes.Axes)
        png(ax)
        assert ax.get_xlabel() and ax.get_ylabel() and ax.get_legend() is not None
        plt.close(ax.figure)


def test_eqerr_residuals(fl):
    r = make("EqerrResult", fl)
    fig, given = plt.subplots()
    assert r.plot(ax=given) is given and len(fig.axes) == 1
    lines = given.get_lines()
    assert [ln.get_label() for ln in lines] == ["x", "y", "z"]
    for a, ln in enumerate(lines):
        np.testing.assert_array_equal(ln.get_ydata(), r.residual[a::3])
        np.testing.assert_array_equal(ln.get_xdata(), np.arange(r.residual.size // 3))
    assert [t.get_text() for t in given.get_legend().get_texts()] == ["x", "y", "z"]
    assert "units of dw" in given.get_ylabel()
    assert ("passed" if r.passed else "out of spec") in given.get_title()
    png(given)
    plt.close(fig)


@pytest.mark.parametrize("name", ["AllanResult", "StabilityResult"])
def test_deviation_log_log_with_intervals(fl, name):
    r = make(name, fl)
    ax = r.plot()
    assert ax.get_xscale() == "log" and ax.get_yscale() == "log"
    (line,) = [ln for ln in ax.get_lines() if ln.get_marker() == "o"]
    np.testing.assert_array_equal(line.get_xdata(), r.taus)
    np.testing.assert_array_equal(line.get_ydata(), r.dev)
    # the error bars span [lo, hi] at every tau
    segs = [c for c in ax.collections if hasattr(c, "get_segments")]
    (bars,) = [c for c in segs if len(c.get_segments()) == len(r.taus)]
    for (p, q), t, lo, hi in zip(bars.get_segments(), r.taus, r.lo, r.hi):
        assert p[0] == q[0] == t
        np.testing.assert_allclose(sorted([p[1], q[1]]), [lo, hi], rtol=1e-12)
    assert "tau (s)" in ax.get_xlabel()
    png(ax)
    plt.close(ax.figure)


def test_montecarlo_rates_with_wilson_intervals(fl):
    r = make("MonteCarloResult", fl)
    ax = r.plot()
    tested = np.flatnonzero(r.comp_tested > 0)
    assert tested.size > 0
    (pts,) = [ln for ln in ax.get_lines() if ln.get_marker() == "o"]
    np.testing.assert_array_equal(pts.get_xdata(), tested)
    np.testing.assert_allclose(pts.get_ydata(), r.comp_reject[tested] / r.comp_tested[tested])
    segs = [c for c in ax.collections if hasattr(c, "get_segments")]
    (bars,) = [c for c in segs if len(c.get_segments()) == tested.size]
    for (p, q), j in zip(bars.get_segments(), tested):
        np.testing.assert_allclose(sorted([p[1], q[1]]),
                                   wilson99(r.comp_reject[j], r.comp_tested[j]), rtol=1e-9)
    eq = np.zeros(_capi.EQERR_OPT_LEN)
    _lib.lib.igea_eqerr_defaults(_lib.dptr(eq))
    (hl,) = [ln for ln in ax.get_lines() if ln.get_linestyle() == "--"]
    assert list(hl.get_ydata()) == [eq[_capi.EQERR_OPT_ALPHA]] * 2
    texts = [t.get_text() for t in ax.get_legend().get_texts()]
    assert sorted(texts) == ["alpha = %g" % eq[_capi.EQERR_OPT_ALPHA],
                             "rate, 99 % Wilson interval"]
    assert ax.get_xlim() == (-0.5, r.comp_tested.size - 0.5)
    png(ax)
    plt.close(ax.figure)


def test_without_matplotlib_still_the_clear_error(fl, monkeypatch):
    r = make("MonteCarloResult", fl)
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    monkeypatch.setitem(sys.modules, "matplotlib.pyplot", None)
    with pytest.raises(ImportError, match=r"needs matplotlib.*igea\[plots\]"):
        r.plot()
