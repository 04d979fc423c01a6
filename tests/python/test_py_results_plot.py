"""r.plot(ax=None): matplotlib is an optional extra. Without it plot()
raises an ImportError that says what to install; with it (here a stand-in
module recording the calls, matplotlib not being installed) the curves
drawn are the result's own arrays."""
import sys
import types

import numpy as np
import pytest

import igea


class Ax:
    """Records what is drawn on it."""

    def __init__(self):
        self.calls = []

    def __getattr__(self, name):
        def record(*args, **kw):
            self.calls.append((name, args, kw))
        return record


@pytest.fixture
def fake_matplotlib(monkeypatch):
    ax = Ax()
    plt = types.ModuleType("matplotlib.pyplot")
    plt.subplots = lambda *a, **k: (object(), ax)
    mpl = types.ModuleType("matplotlib")
    mpl.pyplot = plt
    monkeypatch.setitem(sys.modules, "matplotlib", mpl)
    monkeypatch.setitem(sys.modules, "matplotlib.pyplot", plt)
    return ax


@pytest.fixture(scope="module")
def r():
    fl = igea.simulate(seed=3)
    return igea.eqerr(fl.S, fl.dw, fl.sigma, fl.spec)


def test_without_matplotlib_the_error_says_what_to_install(r, monkeypatch):
    monkeypatch.setitem(sys.modules, "matplotlib", None)      # import fails
    monkeypatch.setitem(sys.modules, "matplotlib.pyplot", None)
    with pytest.raises(ImportError, match=r"needs matplotlib.*pip install matplotlib.*igea\[plots\]"):
        r.plot()


def test_eqerr_plot_draws_the_residuals_per_axis(r, fake_matplotlib):
    assert r.plot() is fake_matplotlib
    lines = [c for c in fake_matplotlib.calls if c[0] == "plot"]
    assert [c[2]["label"] for c in lines] == ["x", "y", "z"]
    for a, (_, (t, y), _) in enumerate(lines):
        np.testing.assert_array_equal(y, r.residual[a::3])
        np.testing.assert_array_equal(t, np.arange(len(r.residual) // 3))
    names = {c[0] for c in fake_matplotlib.calls}
    assert {"set_xlabel", "set_ylabel", "legend", "set_title"} <= names


def test_given_axes_need_no_pyplot(monkeypatch):
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    y = 0.5 + np.random.default_rng(1).normal(0, 0.01, 4000)
    a = igea.allan(y, 10.0)
    ax = Ax()
    assert a.plot(ax) is ax
    (name, (taus, dev), kw), = [c for c in ax.calls if c[0] == "errorbar"]
    np.testing.assert_array_equal(taus, a.taus)
    np.testing.assert_array_equal(dev, a.dev)
    np.testing.assert_allclose(kw["yerr"][0], a.dev - a.lo)
    np.testing.assert_allclose(kw["yerr"][1], a.hi - a.dev)
    assert ("set_xscale", ("log",), {}) in ax.calls and ("set_yscale", ("log",), {}) in ax.calls


def test_only_results_with_a_picture_have_plot():
    assert hasattr(igea.EqerrResult, "plot") and hasattr(igea.AllanResult, "plot")
    assert not hasattr(igea.TestResult, "plot")
