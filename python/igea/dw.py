"""Telemetry minus tracking (igea/dw.h): the apparent-velocity differences
dW at the tracking epochs in the launch-inertial frame, the rows that
igea.eqerr reads, with the tracking covariance propagated into LI (K, with
the gravity integral's part and its correlation between epochs) and the
clock-offset column. Same names as `igea dw`.
"""
import ctypes
from dataclasses import dataclass

import numpy as np

from . import _capi, _lib
from .nav import nav_site
from ._result import result


@result
@dataclass(frozen=True)
class DwResult:
    """Velocity differences of a flight against its tracking (igea.dw), the dw
    input of igea.eqerr."""
    dw: np.ndarray           # (3 n_epochs,) epoch-major x, y, z, m/s
    cov: np.ndarray          # (n_epochs, 6) c_xx c_xy c_xz c_yy c_yz c_zz in LI, or None
    xcov: np.ndarray         # (n_epochs, 3, 3) Cov(dW_e, dW_f) for every f > e, or None
    sigma: np.ndarray        # (3 n_epochs,) sqrt of the diagonal, or None
    dw_dtau: np.ndarray      # (3 n_epochs,) dW / dtau, m/s^2 (the time_offset term's column)
    n_epochs: int
    rows: int
    samples: int
    max_abs: float
    rms: np.ndarray          # (3,) per axis


def dw(telemetry, tracking, *, lat, lon, height=0.0, azimuth, frame="le", system="strapdown",
       kind="apparent", q0=(1.0, 0.0, 0.0, 0.0), time_offset=0.0):
    """dW from a telemetry record (rows t dvx dvy dvz [dthx dthy dthz]) and a
    tracking record (rows t x y z vx vy vz [sigma | sx sy sz | c_xx c_xy
    c_xz c_yy c_yz c_zz | the 21 upper-triangle values of the 6 x 6
    position-velocity covariance]) in frame "le" or "ecef"; lat, lon, azimuth in
    degrees (as the driver's --lat, --lon, --azimuth), height in m; kind
    "apparent" (W_tel - W_trk) or "navigated" (v_nav - v_trk).
    cov is each epoch's 3 x 3 covariance of dW (with the 6 x 6 tracking
    covariance and the apparent kind the position errors' part through the
    gravity integral included); xcov[e] the block Cov(dW_e, dW_f), the same
    for every later epoch f (zero where dW of different epochs are
    uncorrelated; the last epoch's is zero): the whole covariance of the
    stacked dW has the cov blocks on its diagonal and xcov[min(e, f)] off
    it, transposed below (igea_dw_compute_k, docs/pipeline.md 4.2)."""
    sc = _lib.choice(_capi.CHOICE_ENVFUN_SYSTEM, system, "igea.dw", "system")
    fc = _lib.choice(_capi.CHOICE_DW_FRAME, frame, "igea.dw", "frame")
    kc_ = _lib.choice(_capi.CHOICE_DW_KIND, kind, "igea.dw", "kind")
    tel = _lib.as_f64(telemetry, "telemetry", ndim=2)
    trk = _lib.as_f64(tracking, "tracking", ndim=2)
    site = nav_site(np.radians(lat), np.radians(lon), height, np.radians(azimuth))
    q = np.ascontiguousarray(_lib.as_f64(q0, "q0", ndim=1, shape=(4,)))
    ne, kc = trk.shape
    if ne < 1:
        raise ValueError("tracking: no epochs")
    out = np.zeros(3 * ne)
    cov = np.zeros(6 * ne) if kc > 7 else None
    xcov = np.zeros(9 * ne) if kc > 7 else None
    col = np.zeros(3 * ne)
    bad = ctypes.c_int(-1)
    st = _lib.lib.igea_dw_compute_k(_lib.dptr(site), sc, kc_, _lib.dptr(q), float(time_offset),
                                    tel.shape[0], _lib.dptr(tel), tel.shape[0], tel.shape[1], fc,
                                    ne, _lib.dptr(trk), ne, kc, _lib.dptr(out), _lib.dptr(cov),
                                    _lib.dptr(xcov), _lib.dptr(col), ctypes.byref(bad))
    where = {_capi.DW_ESPAN: "tracking: epoch %d (t = %r s) is outside the telemetry span",
             _capi.DW_ETRACK: "tracking: epoch %d (t = %r s) does not follow the one before",
             _capi.DW_ETELEMETRY: "telemetry: row %d (t = %r s) does not follow the one before"}
    if st in where:
        arr = tel if st == _capi.DW_ETELEMETRY else trk
        raise _lib.IgeaError(st, where[st] % (bad.value, float(arr[bad.value, 0])), "igea.dw",
                             "igea_dw_compute_k")
    _lib.check(st, "igea.dw", "igea_dw_compute_k")
    c = None if cov is None else cov.reshape(ne, 6)
    sig = None if cov is None else np.empty(3 * ne)
    mx, rms = ctypes.c_double(), np.empty(3)
    _lib.call("igea.dw", "igea_dw_summary", ne, _lib.dptr(out), _lib.dptr(cov), _lib.dptr(sig),
              ctypes.byref(mx), _lib.dptr(rms))
    return DwResult(dw=out, cov=c, xcov=None if xcov is None else xcov.reshape(ne, 3, 3),
                    sigma=sig, dw_dtau=col, n_epochs=ne, rows=3 * ne, samples=tel.shape[0],
                    max_abs=mx.value, rms=rms)

