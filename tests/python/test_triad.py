"""Turntable-free calibration of an accelerometer triad, on records
simulated here with known parameters: the fit against scipy's
least_squares on the same model written in the test, the parameters
within 3 sd of the truth over many records (binomial bound), no bias
beyond 0.3 sd, the static intervals the simulation laid out, and a badly
chosen threshold refused rather than fitted."""
import math

import numpy as np
import pytest
from scipy import optimize

import igea

G = 9.80665
FS = 100.0
TRUTH = np.array([0.08, -0.05, 0.03,           # biases (raw units, ~m/s^2)
                  1.002, 0.997, 1.004,         # scale factors
                  1.5e-3, -2.0e-3, 0.8e-3])    # t_yx, t_zx, t_zy


def model(theta, m):
    """a = T K (m - b) for rows m (n, 3): the model written here."""
    b, k, (tyx, tzx, tzy) = theta[:3], theta[3:6], theta[6:]
    T = np.array([[1, 0, 0], [tyx, 1, 0], [tzx, tzy, 1]])
    return (T @ (k * (m - b)).T).T


def raw_of(a, theta):
    """The raw output whose calibration is a (the model inverted)."""
    b, k, (tyx, tzx, tzy) = theta[:3], theta[3:6], theta[6:]
    T = np.array([[1, 0, 0], [tyx, 1, 0], [tzx, tzy, 1]])
    return np.linalg.solve(T, a.T).T / k + b


def record(rng, attitudes=24, static=4.0, move=2.0, init=30.0, noise=0.005, theta=TRUTH):
    """Raw samples (n, 3): an initial static period, then `attitudes`
    random gravity directions held `static` s each, joined by `move`-s
    rotations with vibration. Returns (raw, [(start, end)] of the static
    segments)."""
    dirs = rng.normal(size=(attitudes + 1, 3))
    dirs /= np.linalg.norm(dirs, axis=1, keepdims=True)
    dirs[0] = [0, 0, 1]
    segs, parts, t = [], [], 0
    for i, d in enumerate(dirs):
        n = int((init if i == 0 else static) * FS)
        parts.append(np.tile(G * d, (n, 1)))
        segs.append((t, t + n))
        t += n
        if i + 1 < len(dirs):
            nm = int(move * FS)
            s = np.linspace(0, 1, nm)[:, None]
            path = (1 - s) * d + s * dirs[i + 1]
            path /= np.linalg.norm(path, axis=1, keepdims=True)
            parts.append(G * path + 0.5 * rng.normal(size=(nm, 3)))
            t += nm
    a = np.vstack(parts)
    return raw_of(a, theta) + noise * rng.normal(size=a.shape), segs


def test_the_fit_is_the_least_squares_solution():
    rng = np.random.default_rng(1)
    raw, segs = record(rng)
    intervals, means = igea.triad_static(raw, FS, threshold=1e-3)
    r = igea.triad_fit(means)
    ref = optimize.least_squares(lambda th: np.linalg.norm(model(th, means), axis=1) - G,
                                 np.r_[0, 0, 0, 1, 1, 1, 0, 0, 0], xtol=1e-15, ftol=1e-15,
                                 gtol=1e-15)
    np.testing.assert_allclose(r.theta, ref.x, rtol=1e-7, atol=1e-9)
    cal = model(r.theta, means)
    assert r.rms_after == pytest.approx(np.sqrt(np.mean((np.linalg.norm(cal, axis=1) - G) ** 2)),
                                        rel=1e-9)
    J = ref.jac
    s2 = np.sum(ref.fun ** 2) / (len(means) - 9)
    np.testing.assert_allclose(r.covariance, s2 * np.linalg.inv(J.T @ J), rtol=1e-5)


def test_static_intervals_are_the_designed_ones():
    rng = np.random.default_rng(2)
    raw, segs = record(rng)
    res = igea.triad_calibrate(raw, FS)
    intervals, _ = igea.triad_static(raw, FS, threshold=res.threshold)
    assert len(intervals) == len(segs) == res.intervals
    for (a, b), (s, e) in zip(intervals, segs):
        assert s <= a < b <= e  # inside the designed segment
        assert b - a >= (e - s) - 2.1 * FS  # lost at most the half windows and a little
    assert 1 <= res.k <= 10
    assert res.rms_after < 0.1 * res.rms_before


def test_parameters_within_3_sd_over_many_records():
    """100 records of 31 static intervals: the sd comes from sigma estimated
    with 31 - 9 = 22 degrees of freedom, so a standardised error is t(22)
    and lies within 3 sd with probability 0.9934 (scipy below); over the
    900 parameter estimates the fraction is above that less 3.1 binomial
    sds (99.9 %): 0.985. The mean standardised error of each parameter is
    below 0.3 (its sd is 1.05 / sqrt(100) = 0.1)."""
    from scipy import stats
    rng = np.random.default_rng(3)
    z = []
    for _ in range(100):
        raw, _ = record(rng, attitudes=30)
        r = igea.triad_calibrate(raw, FS)
        assert r.intervals == 31
        z.append((r.theta - TRUTH) / r.sd)
    z = np.array(z)
    p = 1 - 2 * stats.t.sf(3, 22)
    assert p == pytest.approx(0.9934, abs=1e-4)
    assert np.mean(np.abs(z) < 3) >= p - 3.1 * math.sqrt(p * (1 - p) / z.size)
    assert np.all(np.abs(z.mean(axis=0)) < 0.3), z.mean(axis=0)


def test_apply_calibrates_every_static_mean_to_g():
    rng = np.random.default_rng(4)
    raw, segs = record(rng)
    r = igea.triad_calibrate(raw, FS)
    cal = r.apply(raw)
    np.testing.assert_allclose(cal, model(r.theta, raw), rtol=1e-14, atol=1e-13)
    before = [np.linalg.norm(raw[s + 150:e - 150].mean(axis=0)) - G for s, e in segs]
    after = [np.linalg.norm(cal[s + 150:e - 150].mean(axis=0)) - G for s, e in segs]
    # the raw magnitudes are off by the scale and bias errors, by centimetres
    # per second squared; the calibrated ones by the noise of the means
    assert np.sqrt(np.mean(np.square(before))) > 0.02
    assert np.sqrt(np.mean(np.square(after))) < 1e-3


def test_bad_threshold_and_bad_records_are_refused():
    rng = np.random.default_rng(5)
    raw, _ = record(rng)
    for k in (1e-6, 1e9):  # nothing static / everything one interval
        with pytest.raises(igea.IgeaError) as e:
            igea.triad_calibrate(raw, FS, threshold=k)
        assert e.value.code == -1020
    # six attitudes: too few intervals, or (a low threshold cutting them into
    # twelve fragments) too few directions for 9 parameters
    few, _ = record(rng, attitudes=5)
    with pytest.raises(igea.IgeaError) as e:
        igea.triad_calibrate(few, FS)
    assert e.value.code in (-1020, -1014)
    with pytest.raises(igea.IgeaError) as e:
        igea.triad_calibrate(few, FS, threshold=3.0)
    assert e.value.code == -1020
    # twelve intervals in only three attitudes do not determine 9 parameters
    d = np.array([[0, 0, G], [G, 0, 0], [0, G, 0]] * 4, dtype=float)
    with pytest.raises(igea.IgeaError) as e:
        igea.triad_fit(raw_of(d, TRUTH) + 1e-4 * rng.normal(size=d.shape))
    assert e.value.code == -1014
    bad = raw.copy()
    bad[100, 1] = np.nan
    with pytest.raises(igea.IgeaError) as e:
        igea.triad_calibrate(bad, FS)
    assert e.value.code == -1011
    with pytest.raises(igea.IgeaError, match="window"):
        igea.triad_calibrate(raw, FS, window=-1.0)
    with pytest.raises(ValueError, match="acc"):
        igea.triad_calibrate(raw[:, :2], FS)
