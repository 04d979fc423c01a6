"""Navigation error propagation: the linearised INS error model in
local-level north-east-down axes on a spherical Earth (include/igea/inserr.h,
docs/inserr.md). The same names as `igea nav`: lat in degrees, the sensor
errors in m/s^2 and rad/s (measured minus true, resolved in NED)."""
import math
from dataclasses import dataclass
from typing import Optional

import numpy as np

from . import _capi, _lib
from ._result import result


@result
@dataclass(frozen=True)
class NavErrors:
    """igea.nav_errors: the errors at the epochs time (n,): position (n, 3)
    m, velocity (n, 3) m/s and attitude (n, 3) rad, north east down;
    covariance (n, 15, 15) of the whole state (position, velocity, attitude,
    accelerometer bias, gyro drift) when noise q was given, else None."""
    lat: float
    duration: float
    acc_bias: np.ndarray
    gyro_drift: np.ndarray
    time: np.ndarray
    position: np.ndarray
    velocity: np.ndarray
    attitude: np.ndarray
    covariance: Optional[np.ndarray] = None


def _triple(v, name):
    if v is None:
        return np.zeros(3)
    return np.ascontiguousarray(_lib.as_f64(v, name, ndim=1, shape=(3,)))


def nav_errors(*, lat=0.0, duration=21600.0, epochs=361, step=None, acc_bias=None,
               gyro_drift=None, radius=None, g=None, omega=None, vn=None, ve=None,
               vertical=None, q=None, p0=None):
    """The INS errors over duration (s) at epochs equally spaced epochs from
    constant accelerometer biases acc_bias (3,) and gyro drifts gyro_drift
    (3,) at latitude lat (degrees). With q (12,): the covariance for white
    noise of those spectral densities (accelerometer and gyro white noise,
    accelerometer-bias and gyro-drift random walks, N E D each; see
    igea_inserr_covariance) from p0 (15, 15; None: 0). Options left None keep
    the library's defaults (R 6371008.8 m, g 9.80665 m/s^2, Earth rate
    7.292115e-5 rad/s, step 1 s, vertical channel aided)."""
    where = "igea.nav_errors"
    lat = float(lat)
    if not abs(lat) <= 85.9:
        raise _lib.error(-1, "lat must lie in [-85.9, 85.9] degrees", where,
                         "igea_inserr_response", "opts")
    o = _lib.options("inserr", where, ("igea_inserr_response", "opts"), radius=radius, g=g,
                     omega=omega, lat=math.radians(lat), vn=vn, ve=ve, step=step,
                     vertical=vertical)
    n = int(epochs)
    acc, gyro = _triple(acc_bias, "acc_bias"), _triple(gyro_drift, "gyro_drift")
    x0 = np.zeros(_capi.INSERR_N)
    x0[_capi.INSERR_ACC:_capi.INSERR_ACC + 3] = acc
    x0[_capi.INSERR_GYRO:_capi.INSERR_GYRO + 3] = gyro
    x = np.zeros((max(n, 1), _capi.INSERR_N))
    _lib.call(where, "igea_inserr_response", _lib.dptr(o), _lib.dptr(x0), float(duration), n,
              _lib.dptr(x))
    cov = None
    if q is not None:
        qv = np.ascontiguousarray(_lib.as_f64(q, "q", ndim=1, shape=(_capi.INSERR_NQ,)))
        P0 = None
        if p0 is not None:
            P0 = np.ascontiguousarray(_lib.as_f64(p0, "p0", ndim=2,
                                                  shape=(_capi.INSERR_N, _capi.INSERR_N)))
        cov = np.zeros((n, _capi.INSERR_N, _capi.INSERR_N))
        _lib.call(where, "igea_inserr_covariance", _lib.dptr(o), _lib.dptr(P0), _lib.dptr(qv),
                  float(duration), n, _lib.dptr(cov))
    t = np.arange(n) * (float(duration) / (n - 1))
    return NavErrors(lat, float(duration), acc, gyro, t, x[:, 0:3].copy(), x[:, 3:6].copy(),
                     x[:, 6:9].copy(), cov)
