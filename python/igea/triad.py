"""Turntable-free calibration of an accelerometer triad from a raw record
of static attitudes (include/igea/triad.h, docs/calibration.md).

a = T K (m - b), |a| = g in every static interval: biases b, scale factors
K = diag(k), unit lower-triangular non-orthogonality T (t_yx, t_zx, t_zy)."""
import ctypes
from dataclasses import dataclass

import numpy as np

from . import _capi, _lib
from ._result import result

NAMES = ("b_x", "b_y", "b_z", "k_x", "k_y", "k_z", "t_yx", "t_zx", "t_zy")


@result
@dataclass(frozen=True)
class TriadResult:
    """igea.triad_calibrate / triad_fit: theta (9,) in the order of NAMES,
    its covariance (9, 9) and sd (9,); the threshold multiple k used and the
    threshold; the number of static intervals; the rms of |a| - g before
    (start values) and after the fit; sigma = sqrt(sum r^2 / (n - 9));
    iterations."""
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

    def summary(self):
        lines = ["triad: %d static intervals (threshold %g x zeta_init), rms |a| - g %.3e -> %.3e"
                 % (self.intervals, self.k, self.rms_before, self.rms_after)]
        for name, v, s in zip(NAMES, self.theta, self.sd):
            lines.append("%-6s %16.9g %12.3e" % (name, v, s))
        return "\n".join(lines)

    def apply(self, raw):
        """The calibrated outputs of raw samples (n, 3)."""
        return triad_apply(raw, self.theta)


def _record(acc, name="acc"):
    a = np.ascontiguousarray(_lib.as_f64(acc, name, ndim=2, shape=(None, 3)))
    if a.shape[0] < 1:
        raise ValueError(f"{name}: expected at least one sample")
    return a


def _result(theta, cov, info):
    f = _lib.fields(info, "TRIAD_INFO_", k=float, threshold=float, intervals=int,
                    rms_before=float, rms_after=float, sigma=float, iterations=int)
    return TriadResult(theta, cov, np.sqrt(np.diag(cov)), **f)


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


def triad_calibrate(acc, fs, *, g=None, window=None, init=None, min_static=None, threshold=None,
                    max_iter=None):
    """The whole calibration from a raw record (n, 3) sampled at fs Hz:
    static intervals at threshold k zeta_init (k scanned 1..10 unless
    threshold= gives it), then the fit. Options left None keep the
    library's defaults (g 9.80665, window 2 s, init 30 s, min_static 1 s)."""
    where = "igea.triad_calibrate"
    a = _record(acc)
    o = _lib.options("triad", where, ("igea_triad_calibrate", "opts"), g=g, window=window,
                     init=init, min_static=min_static, threshold=threshold, max_iter=max_iter)
    theta, cov, info = np.zeros(9), np.zeros((9, 9), order="F"), np.zeros(_capi.TRIAD_INFO_LEN)
    _lib.call(where, "igea_triad_calibrate", _capi.ROWMAJOR, a.shape[0], _lib.dptr(a), 3,
              float(fs), _lib.dptr(o), _lib.dptr(theta), _lib.dptr(cov), 9, _lib.dptr(info))
    return _result(theta, np.ascontiguousarray(cov), info)


def triad_apply(raw, theta):
    """cal = T K (raw - b) for raw samples (n, 3)."""
    a = _record(raw, "raw")
    t = _lib.as_f64(theta, "theta", ndim=1, shape=(9,))
    out = np.empty_like(a)
    _lib.call("igea.triad_apply", "igea_triad_apply", _capi.ROWMAJOR, a.shape[0], _lib.dptr(a), 3,
              _lib.dptr(t), _lib.dptr(out), 3)
    return out
