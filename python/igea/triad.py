"""Turntable-free calibration of an accelerometer triad from a raw record
of static attitudes (include/igea/triad.h, docs/calibration.md).

a = T K (m - b), |a| = g in every static interval: biases b, scale factors
K = diag(k), unit lower-triangular non-orthogonality T (t_yx, t_zx, t_zy).
The gyroscope: w = M K (r - b), M unit-diagonal (6 misalignments), fitted
to the rotations between the static intervals."""
import ctypes
import math
from dataclasses import dataclass

import numpy as np

from . import _capi, _lib
from ._result import result

NAMES = ("b_x", "b_y", "b_z", "k_x", "k_y", "k_z", "t_yx", "t_zx", "t_zy")
EARTH_RATE = 7.292115e-5  # rad/s (WGS 84), the default earth_rate with lat=
GYRO_NAMES = ("b_x", "b_y", "b_z", "k_x", "k_y", "k_z",
              "m_xy", "m_xz", "m_yx", "m_yz", "m_zx", "m_zy")


def _warn(misfit):
    """The driver's warning for a misfit above 3."""
    return " (WARNING: residuals well above the noise)" if misfit > 3 else ""


@result
@dataclass(frozen=True)
class GyroResult:
    """The gyro part of igea.triad_calibrate / igea.triad_gyro_fit: theta
    (12,) in the order of GYRO_NAMES, its covariance (12, 12) and sd (12,);
    the rotations fitted (pairs), the rms of |v_{k+1} - R_k^T v_k| (rad)
    before (K = I, M = I) and after the fit, sigma = sqrt(sum r^2 / (2
    pairs - 9)), iterations, the static samples the biases average, the
    pooled within-interval sd per axis (noise, raw units), and misfit:
    sigma over the sd the gyro noise of the first interval predicts (about
    1; well above: motion in the intervals or a model that does not
    hold). With the Earth's rate (lat=): earth_h, the horizontal Earth rate
    the static intervals show (about W cos(lat)), and heading, the heading
    of the calibrated x axis in the first static interval (deg from north
    towards east), each with its sd, and the lat and earth_rate used (None
    without lat)."""
    theta: np.ndarray
    covariance: np.ndarray
    sd: np.ndarray
    pairs: int
    rms_before: float
    rms_after: float
    sigma: float
    iterations: int
    static_samples: int
    noise: np.ndarray
    misfit: float
    lat: float = None
    earth_rate: float = None
    earth_h: float = None
    earth_h_sd: float = None
    heading: float = None
    heading_sd: float = None

    def summary(self):
        lines = ["gyro: %d rotations, rms gravity-direction mismatch %.3e -> %.3e rad, "
                 "misfit %.3g%s" % (self.pairs, self.rms_before, self.rms_after, self.misfit,
                                    _warn(self.misfit))]
        if self.earth_h is not None:
            lines.append("Earth rate: horizontal %.4e +- %.2e, heading of x %.2f +- %.2f deg"
                         % (self.earth_h, self.earth_h_sd, self.heading, self.heading_sd))
        for name, v, s in zip(GYRO_NAMES, self.theta, self.sd):
            lines.append("%-6s %16.9g %12.3e" % (name, v, s))
        return "\n".join(lines)

    def apply(self, raw):
        """The calibrated rates of raw samples (n, 3)."""
        return triad_gyro_apply(raw, self.theta)


@result
@dataclass(frozen=True)
class TriadResult:
    """igea.triad_calibrate / triad_fit: theta (9,) in the order of NAMES,
    its covariance (9, 9) and sd (9,); the threshold multiple k used and the
    threshold; the number of static intervals; the rms of |a| - g before
    (start values) and after the fit; sigma = sqrt(sum r^2 / (n - 9));
    iterations; misfit, sigma over the sd the noise of the first static
    period predicts (about 1; well above: intervals holding motion, a
    threshold too high; NaN from triad_fit); the static intervals [(start,
    end)] and the gyro's GyroResult (triad_calibrate with gyro=)."""
    theta: np.ndarray
    covariance: np.ndarray
    sd: np.ndarray
    k: float
    threshold: float
    intervals: int
    rms_before: float
    rms_after: float
    sigma: float
    iterations: int
    misfit: float = float("nan")
    static_intervals: list = None
    gyro: GyroResult = None

    def summary(self):
        lines = ["triad: %d static intervals (threshold %g x zeta_init), rms |a| - g %.3e -> %.3e"
                 ", misfit %.3g%s" % (self.intervals, self.k, self.rms_before, self.rms_after,
                                      self.misfit, _warn(self.misfit))]
        for name, v, s in zip(NAMES, self.theta, self.sd):
            lines.append("%-6s %16.9g %12.3e" % (name, v, s))
        if self.gyro is not None:
            lines.append(self.gyro.summary())
        return "\n".join(lines)

    def apply(self, raw):
        """The calibrated outputs of raw samples (n, 3)."""
        return triad_apply(raw, self.theta)


def _record(acc, name="acc"):
    a = np.ascontiguousarray(_lib.as_f64(acc, name, ndim=2, shape=(None, 3)))
    if a.shape[0] < 1:
        raise ValueError(f"{name}: expected at least one sample")
    return a


def _result(theta, cov, info, **more):
    f = _lib.fields(info, "TRIAD_INFO_", k=float, threshold=float, intervals=int,
                    rms_before=float, rms_after=float, sigma=float, iterations=int,
                    misfit=float)
    return TriadResult(theta, cov, np.sqrt(np.diag(cov)), **f, **more)


def _gyro_result(theta, cov, info, lat=None, earth_rate=None):
    cov = np.ascontiguousarray(cov)
    f = _lib.fields(info, "TRIAD_GYRO_INFO_", pairs=int, rms_before=float, rms_after=float,
                    sigma=float, iterations=int, static_samples=int, misfit=float)
    if lat is not None and earth_rate > 0:
        f.update(_lib.fields(info, "TRIAD_GYRO_INFO_", earth_h=float, earth_h_sd=float,
                             heading=float, heading_sd=float), lat=lat, earth_rate=earth_rate)
    noise = info[[_capi.TRIAD_GYRO_INFO_NOISE_X, _capi.TRIAD_GYRO_INFO_NOISE_Y,
                  _capi.TRIAD_GYRO_INFO_NOISE_Z]].copy()
    return GyroResult(theta, cov, np.sqrt(np.diag(cov)), noise=noise, **f)


def _earth(lat, earth_rate):
    """(earth_rate, lat) for the library: None, None without lat."""
    if lat is None:
        if earth_rate is not None:
            raise ValueError("earth_rate: needs lat (the latitude, deg)")
        return None, None
    return (EARTH_RATE if earth_rate is None else float(earth_rate)), float(lat)


def triad_static(acc, fs, *, window=2.0, threshold, min_static=1.0):
    """Static intervals of a record (n, 3): [(start, end)] sample ranges and
    their mean outputs (nint, 3)."""
    a = _record(acc)
    n = a.shape[0]
    cap = n  # an upper bound
    nint = ctypes.c_int()
    start, end = np.zeros(cap, dtype=np.intc), np.zeros(cap, dtype=np.intc)
    means = np.zeros((cap, 3))
    _lib.call("igea.triad_static", "igea_triad_static", _capi.ROWMAJOR, n, _lib.dptr(a), 3,
              float(fs), float(window), float(threshold), float(min_static), cap,
              ctypes.byref(nint), _lib.iptr(start), _lib.iptr(end), _lib.dptr(means))
    k = nint.value
    return list(zip(start[:k].tolist(), end[:k].tolist())), means[:k].copy()


def triad_fit(means, *, g=9.80665, theta0=None, max_iter=200):
    """Fit the 9 parameters to static mean outputs (nint >= 12, 3)."""
    m = np.ascontiguousarray(_lib.as_f64(means, "means", ndim=2, shape=(None, 3)))
    t0 = None if theta0 is None else _lib.as_f64(theta0, "theta0", ndim=1, shape=(9,))
    theta, cov, info = np.zeros(9), np.zeros((9, 9), order="F"), np.zeros(_capi.TRIAD_INFO_LEN)
    _lib.call("igea.triad_fit", "igea_triad_fit", m.shape[0], _lib.dptr(m), float(g),
              _lib.dptr(t0), int(max_iter), _lib.dptr(theta), _lib.dptr(cov), 9, _lib.dptr(info))
    return _result(theta, np.ascontiguousarray(cov), info)


def triad_calibrate(acc, fs, *, gyro=None, acc_scale=1.0, gyro_scale=1.0, g=None, window=None,
                    init=None, min_static=None, threshold=None, max_iter=None, lat=None,
                    earth_rate=None):
    """The whole calibration from a raw record (n, 3) sampled at fs Hz:
    static intervals at threshold k zeta_init (k scanned 1..10 unless
    threshold= gives it), then the fit; with gyro (n, 3, the same instants)
    also the gyroscope (the result's gyro). acc_scale and gyro_scale (> 0)
    are nominal scale factors the raw outputs are multiplied by first.
    Options left None keep the library's defaults (g 9.80665, window 2 s,
    init 30 s, min_static 1 s). lat (deg) models the Earth's rate in the
    gyro fit (earth_rate, in the gyro's calibrated unit: EARTH_RATE rad/s
    unless given; docs/calibration.md)."""
    where = "igea.triad_calibrate"
    earth_rate, lat = _earth(lat, earth_rate)
    for name, v in (("acc_scale", acc_scale), ("gyro_scale", gyro_scale)):
        if not (isinstance(v, (int, float)) and v > 0 and math.isfinite(v)):
            raise ValueError(f"{name}: expected a positive number, got {v!r}")
    a = _record(acc) * float(acc_scale)
    o = _lib.options("triad", where, ("igea_triad_calibrate", "opts"), g=g, window=window,
                     init=init, min_static=min_static, threshold=threshold, max_iter=max_iter,
                     earth_rate=earth_rate, lat=lat)
    theta, cov, info = np.zeros(9), np.zeros((9, 9), order="F"), np.zeros(_capi.TRIAD_INFO_LEN)
    if gyro is None:
        _lib.call(where, "igea_triad_calibrate", _capi.ROWMAJOR, a.shape[0], _lib.dptr(a), 3,
                  float(fs), _lib.dptr(o), _lib.dptr(theta), _lib.dptr(cov), 9, _lib.dptr(info))
        gres = None
    else:
        w = _record(gyro, "gyro") * float(gyro_scale)
        if w.shape != a.shape:
            raise ValueError("gyro: %d samples, but acc has %d" % (w.shape[0], a.shape[0]))
        tg, cg = np.zeros(12), np.zeros((12, 12), order="F")
        ig = np.zeros(_capi.TRIAD_GYRO_INFO_LEN)
        _lib.call(where, "igea_triad_calibrate_imu", _capi.ROWMAJOR, a.shape[0], _lib.dptr(a), 3,
                  _lib.dptr(w), 3, float(fs), _lib.dptr(o), _lib.dptr(theta), _lib.dptr(cov), 9,
                  _lib.dptr(tg), _lib.dptr(cg), 12, _lib.dptr(info), _lib.dptr(ig))
        gres = _gyro_result(tg, cg, ig, lat, earth_rate)
    intervals, _ = triad_static(a, fs, window=o[_capi.TRIAD_OPT_WINDOW],
                                threshold=info[_capi.TRIAD_INFO_THRESHOLD],
                                min_static=o[_capi.TRIAD_OPT_MIN_STATIC])
    return _result(theta, np.ascontiguousarray(cov), info, static_intervals=intervals, gyro=gres)


def triad_gyro_fit(gyro, fs, intervals, means, theta_a, *, cov_a=None, max_iter=200, lat=None,
                   earth_rate=None):
    """The gyro parameters from a raw rate record (n, 3) at fs Hz, its static
    intervals [(start, end)] and the accelerometer's mean outputs there
    (nint, 3) with its calibration theta_a (9,) and covariance cov_a (9, 9;
    None: not carried into the gyro covariance); lat (deg) and earth_rate as
    triad_calibrate's. Returns a GyroResult."""
    earth_rate, lat = _earth(lat, earth_rate)
    w = _record(gyro, "gyro")
    iv = np.asarray(intervals, dtype=np.intc).reshape(-1, 2)
    start, end = np.ascontiguousarray(iv[:, 0]), np.ascontiguousarray(iv[:, 1])
    m = np.ascontiguousarray(_lib.as_f64(means, "means", ndim=2, shape=(len(iv), 3)))
    ta = _lib.as_f64(theta_a, "theta_a", ndim=1, shape=(9,))
    ca = None if cov_a is None else np.asfortranarray(
        _lib.as_f64(cov_a, "cov_a", ndim=2, shape=(9, 9)))
    theta, cov = np.zeros(12), np.zeros((12, 12), order="F")
    info = np.zeros(_capi.TRIAD_GYRO_INFO_LEN)
    common = (_capi.ROWMAJOR, w.shape[0], _lib.dptr(w), 3, float(fs), len(iv), _lib.iptr(start),
              _lib.iptr(end), _lib.dptr(m), _lib.dptr(ta), _lib.dptr(ca), 9, int(max_iter))
    if lat is None:
        _lib.call("igea.triad_gyro_fit", "igea_triad_gyro_fit", *common, _lib.dptr(theta),
                  _lib.dptr(cov), 12, _lib.dptr(info))
    else:
        _lib.call("igea.triad_gyro_fit", "igea_triad_gyro_fit_earth", *common, earth_rate, lat,
                  _lib.dptr(theta), _lib.dptr(cov), 12, _lib.dptr(info))
    return _gyro_result(theta, cov, info, lat, earth_rate)


def triad_gyro_apply(raw, theta):
    """w = M K (raw - b) for raw rate samples (n, 3) and theta (12,)."""
    a = _record(raw, "raw")
    t = _lib.as_f64(theta, "theta", ndim=1, shape=(12,))
    out = np.empty_like(a)
    _lib.call("igea.triad_gyro_apply", "igea_triad_gyro_apply", _capi.ROWMAJOR, a.shape[0],
              _lib.dptr(a), 3, _lib.dptr(t), _lib.dptr(out), 3)
    return out


def triad_apply(raw, theta):
    """cal = T K (raw - b) for raw samples (n, 3)."""
    a = _record(raw, "raw")
    t = _lib.as_f64(theta, "theta", ndim=1, shape=(9,))
    out = np.empty_like(a)
    _lib.call("igea.triad_apply", "igea_triad_apply", _capi.ROWMAJOR, a.shape[0], _lib.dptr(a), 3,
              _lib.dptr(t), _lib.dptr(out), 3)
    return out
