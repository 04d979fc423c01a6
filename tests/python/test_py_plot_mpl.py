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
    if name == "NavErrors":
        return nav()
    if name == "NavErrorsLI":
        return nav_li()
    if name == "ImpactBudget":
        return budget()
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
        panels = list(ax) if isinstance(ax, np.ndarray) else [ax]   # several panels: an array
        assert all(isinstance(a, mpl.axes.Axes) for a in panels)
        png(panels[0])
        for a in panels:
            assert a.get_xlabel() and a.get_legend() is not None
        assert panels[0].get_ylabel()
        plt.close(panels[0].figure)


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



# ---- NavErrors, NavErrorsLI, ImpactBudget ----------------------------------

ARCSEC = np.degrees(1.0) * 3600      # arcsec per rad
UNITS = {"m": 1.0, "km": 1e-3, "m/s": 1.0, "mm/s": 1e3, "arcsec": ARCSEC,
         "deg": np.degrees(1.0), "h": 1 / 3600.0, "min": 1 / 60.0, "s": 1.0}


def unit_of(label):
    """The factor from SI of the unit an axis label names last, "(m)"."""
    return UNITS[label[label.rindex("(") + 1:label.rindex(")")].split(",")[0]]


def nav():
    return igea.nav_errors(lat=45, acc_bias=[1e-4, 0, 0], gyro_drift=[0, 4.85e-8, 0],
                           acc_noise=[5e-5, 0, 0], gyro_noise=[2.9e-7, 0, 0])


def nav_li():
    """A strapdown 2-g climb with roll (tests/python/test_inserr_li.py's),
    with a bias and white gyro noise."""
    n, rate = 201, 20.0
    tel = np.zeros((n, 7))
    tel[:, 0] = np.arange(n) / rate
    tel[1:, 1] = 2 * 9.80665 / rate
    tel[1:, 4] = 0.05 / rate
    tel[1:, 6] = 0.002 / rate
    u = (np.pi / 2 - np.radians(20)) / 2
    site = igea.nav_site(np.radians(30), np.radians(110), 0.0, np.radians(80))
    return igea.nav_errors_li(site, tel, q0=[np.cos(u), 0, 0, np.sin(u)], epochs=tel[::4, 0],
                              acc_bias=[1e-3, -2e-3, 0], q=[0, 0, 0, 1e-10, 1e-10, 4e-10] +
                              [0] * 6)


def budget(n=3):
    """The budget of n terms at the tests' reference burnout (150 km up at
    30 N 10 E, 6 km/s): the first three the docs' example, then smaller ones."""
    rng = np.random.default_rng(4)
    E = np.array([[10, 0, 5], [0, 20, 3], [2, 4, 30], [0.01, 0, 0.002], [0, 0.02, 0.001],
                  [0.005, 0.001, 0.01]])
    if n > 3:
        E = np.column_stack([E, rng.normal(0, 1, (6, n - 3)) * [[3], [3], [3], [3e-3], [3e-3],
                                                                  [3e-3]]])
    im = igea.impact([5561563.2, 980653.6, 3260504.4, -495.5, 3461.9, 4875.4])
    names = ["acc", "gyro", "align"] + ["t%d" % j for j in range(3, n)]
    return igea.impact_budget(im.miss_jacobian, E[:, :n], names)


@pytest.mark.parametrize("li", [False, True])
def test_nav_errors_lines_and_bands(li):
    r = nav_li() if li else nav()
    axes = r.plot()
    assert isinstance(axes, np.ndarray) and axes.shape == (3,)
    sd = np.sqrt(np.array([np.diag(P)[:9] for P in r.covariance]))
    names = ["x", "y", "z"] if li else ["north", "east", "down"]
    for q, (a, key) in enumerate(zip(axes, ("position", "velocity", "attitude"))):
        tf, f = unit_of(a.get_xlabel()), unit_of(a.get_ylabel())
        assert key + " error" in a.get_ylabel()
        e = getattr(r, key)
        lines = a.get_lines()
        assert [ln.get_label() for ln in lines] == names
        for k, ln in enumerate(lines):
            np.testing.assert_allclose(ln.get_xdata(), r.time * tf, rtol=1e-15)
            np.testing.assert_allclose(ln.get_ydata(), f * e[:, k], rtol=1e-15)
        # the bands: x -+ sd of the covariance's diagonal, one per axis
        bands = [c for c in a.collections if len(c.get_paths()) and
                 len(c.get_paths()[0].vertices) > 2]
        assert len(bands) == 3
        for k, band in enumerate(bands):
            v = band.get_paths()[0].vertices
            for tt, lo, hi in zip(r.time[::7], e[::7, k] - sd[::7, 3 * q + k],
                                  e[::7, k] + sd[::7, 3 * q + k]):
                y = v[np.isclose(v[:, 0], tt * tf, rtol=0, atol=1e-12), 1]
                np.testing.assert_allclose([y.min(), y.max()], f * np.array([lo, hi]),
                                           rtol=1e-12, atol=1e-12 * f * abs(hi))
        texts = [t.get_text() for t in a.get_legend().get_texts()]
        assert texts == names + ["shaded: \u00b11\u03c3 of the sensor noise"]
    assert axes[0].get_xlabel() == ("time (s)" if li else "time (h)")
    assert "launch-inertial" in axes[2].get_title() if li else "45 deg" in axes[0].get_title()
    png(axes[0])
    plt.close(axes[0].figure)


def test_nav_errors_schuler_in_the_velocity_panel():
    """At rest without Earth rate a north accelerometer bias b gives dvN =
    (b/ws) sin ws t (docs/inserr.md): the drawn north velocity."""
    b, g, R = 1e-4, 9.80665, 6371008.8
    r = igea.nav_errors(lat=45, omega=0, acc_bias=[b, 0, 0])
    assert r.covariance is None
    axes = r.plot()
    ws = np.sqrt(g / R)
    ln = axes[1].get_lines()[0]
    f = unit_of(axes[1].get_ylabel())
    np.testing.assert_allclose(ln.get_ydata(), f * (b / ws) * np.sin(ws * r.time),
                               atol=1e-12 * f * b / ws)
    assert all(len(a.collections) == 0 for a in axes)            # no noise, no band
    plt.close(axes[0].figure)


def test_nav_units_follow_the_size():
    r = igea.nav_errors(lat=45, omega=0, gyro_drift=[0, 3e-6, 3e-6])
    axes = r.plot()
    assert [a.get_ylabel() for a in axes] == ["position error (km)", "velocity error (m/s)",
                                             "attitude error phi (deg)"]
    np.testing.assert_allclose(axes[2].get_lines()[2].get_ydata(), np.degrees(r.attitude[:, 2]))
    plt.close(axes[0].figure)


def test_nav_given_axes():
    r = nav()
    fig, given = plt.subplots(3, 1)
    assert r.plot(ax=given) is given and len(fig.axes) == 3
    fig2, one = plt.subplots()
    assert r.plot(ax=one) is one and len(fig2.axes) == 1        # the position panel alone
    assert "position error" in one.get_ylabel()
    with pytest.raises(ValueError, match="ax"):
        r.plot(ax=given[:2])
    plt.close(fig)
    plt.close(fig2)


@pytest.mark.parametrize("n", [3, 21])
def test_budget_ellipses_circle_and_bars(n):
    r = budget(n)
    plane, bars = r.plot()
    f = unit_of(plane.get_xlabel())
    # x crossrange, y downrange: the covariance in that order, its
    # eigen-decomposition by numpy
    C = f * f * np.asarray(r.covariance)[::-1, ::-1]
    lam, vec = np.linalg.eigh(C)
    ells = [p for p in plane.patches if isinstance(p, mpl.patches.Ellipse)
            and not isinstance(p, mpl.patches.Circle)]
    # labelled with their probability: chi-square with 2 dof at k^2 (scipy)
    from scipy.stats import chi2
    assert [e.get_label() for e in ells] == [
        "%d\u03c3 ellipse (%.1f %%)" % (k, 100 * chi2.cdf(k * k, 2)) for k in (1, 3)]
    for k, e in zip((1, 3), ells):
        assert e.center == (0, 0)
        np.testing.assert_allclose([e.width, e.height], 2 * k * np.sqrt(lam[::-1]), rtol=1e-12)
        major = np.array([np.cos(np.radians(e.angle)), np.sin(np.radians(e.angle))])
        assert abs(abs(major @ vec[:, 1]) - 1) < 1e-12
    (circle,) = [p for p in plane.patches if isinstance(p, mpl.patches.Circle)]
    np.testing.assert_allclose(circle.radius, f * igea.cep(r.covariance), rtol=1e-15)
    assert circle.get_label() == "CEP %.4g m (50 %%)" % igea.cep(r.covariance)
    assert plane.get_aspect() == 1.0
    # the bars: shares of the misses (numpy), largest first, 15 and the rest
    m2 = np.sum(r.miss ** 2, axis=1)
    share, down = 100 * m2 / m2.sum(), 100 * r.miss[:, 0] ** 2 / m2.sum()
    order = np.argsort(-share, kind="stable")
    want_share, want_down = list(share[order[:15]]), list(down[order[:15]])
    labels = [r.names[j] for j in order[:15]]
    if n > 15:
        want_share.append(share[order[15:]].sum())
        want_down.append(down[order[15:]].sum())
        labels.append("the other %d terms" % (n - 15))
    rects = bars.patches
    nb = len(labels)
    assert len(rects) == 2 * nb
    dn, cr = rects[:nb], rects[nb:]
    np.testing.assert_allclose([p.get_width() for p in dn], want_down, rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose([p.get_x() + p.get_width() for p in cr], want_share, rtol=1e-12)
    ys = [p.get_y() + p.get_height() / 2 for p in dn]
    assert np.all(np.diff(ys) < 0)                                   # the largest at the top
    assert [t.get_text() for t in bars.get_yticklabels()] == labels
    assert [t.get_text() for t in bars.get_legend().get_texts()] == ["downrange part",
                                                                    "crossrange part"]
    png(plane)
    plt.close(plane.figure)


def test_budget_long_names_are_cut():
    r = budget()
    long = "\u0394v_misalignment_\u00e0_la_pitch_axis"
    r = type(r)([long, "b" * 24, "c"], r.miss, r.covariance, r.share, r.cep)
    plane, bars = r.plot()
    labels = {t.get_text() for t in bars.get_yticklabels()}
    assert labels == {long[:21] + "...", "b" * 24, "c"}
    plt.close(plane.figure)


def test_budget_given_axes_and_without_matplotlib(monkeypatch):
    r = budget()
    fig, one = plt.subplots()
    assert r.plot(ax=one) is one and len(one.patches) == 3         # the plane alone
    plt.close(fig)
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    monkeypatch.setitem(sys.modules, "matplotlib.pyplot", None)
    monkeypatch.setitem(sys.modules, "matplotlib.patches", None)
    for res in (r, nav()):
        with pytest.raises(ImportError, match=r"needs matplotlib.*igea\[plots\]"):
            res.plot()
