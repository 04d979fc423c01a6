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


def _noise(v, name):
    """N, B, K of a triad as (9,): a NoiseFit (its N, B, K for every axis),
    a (3,) sequence N, B, K for every axis, or (3, 3) rows N, B, K by axis."""
    if v is None:
        return np.zeros(_capi.INSERR_NOISE_LEN)
    if hasattr(v, "terms") and hasattr(v, "value"):
        val = np.asarray(v.value, dtype=float)
        nbk = val[[_capi.STABILITY_FIT_N, _capi.STABILITY_FIT_B, _capi.STABILITY_FIT_K]]
        a = np.repeat(nbk[:, None], 3, axis=1)
    else:
        a = np.asarray(v, dtype=float)
        if a.shape == (3,):
            a = np.repeat(a[:, None], 3, axis=1)
        elif a.shape != (3, 3):
            raise ValueError(f"{name}: expected N, B, K (3,) or rows N, B, K by axis (3, 3), "
                             f"got shape {a.shape}")
    return np.ascontiguousarray(a.reshape(-1))


def nav_errors(*, lat=0.0, duration=21600.0, epochs=361, step=None, acc_bias=None,
               gyro_drift=None, radius=None, g=None, omega=None, vn=None, ve=None,
               vertical=None, q=None, p0=None, acc_noise=None, gyro_noise=None, acc_tc=None,
               gyro_tc=None):
    """The INS errors over duration (s) at epochs equally spaced epochs from
    constant accelerometer biases acc_bias (3,) and gyro drifts gyro_drift
    (3,) at latitude lat (degrees). With q (12,): the covariance for white
    noise of those spectral densities (accelerometer and gyro white noise,
    accelerometer-bias and gyro-drift random walks, N E D each; see
    igea_inserr_covariance) from p0 (15, 15; None: 0). Options left None keep
    the library's defaults (R 6371008.8 m, g 9.80665 m/s^2, Earth rate
    7.292115e-5 rad/s, step 1 s, vertical channel aided).
    With acc_noise or gyro_noise instead of q: the covariance for noise given
    by its IEEE Std 952 coefficients (igea_inserr_noise_covariance): each a
    NoiseFit of igea.noise_fit (data in SI units, m/s^2 or rad/s: N in m/s
    /sqrt(s) or rad/sqrt(s), B in m/s^2 or rad/s, K in m/s^2/sqrt(s) or
    rad/s/sqrt(s); scale a fit of deg/h data by pi / 648000), N, B, K for
    every axis, or a (3, 3) array of rows N, B, K by axis N E D; bias
    instability B is a Gauss-Markov bias of correlation time acc_tc or
    gyro_tc (s), which a B > 0 needs."""
    where = "igea.nav_errors"
    lat = float(lat)
    if not abs(lat) <= 85.9:
        raise _lib.error(-1, "lat must lie in [-85.9, 85.9] degrees", where,
                         "igea_inserr_response", "opts")
    o = _lib.options("inserr", where, ("igea_inserr_response", "opts"), radius=radius, g=g,
                     omega=omega, lat=math.radians(lat), vn=vn, ve=ve, step=step,
                     vertical=vertical, acc_tc=acc_tc, gyro_tc=gyro_tc)
    n = int(epochs)
    acc, gyro = _triple(acc_bias, "acc_bias"), _triple(gyro_drift, "gyro_drift")
    x0 = np.zeros(_capi.INSERR_N)
    x0[_capi.INSERR_ACC:_capi.INSERR_ACC + 3] = acc
    x0[_capi.INSERR_GYRO:_capi.INSERR_GYRO + 3] = gyro
    x = np.zeros((max(n, 1), _capi.INSERR_N))
    _lib.call(where, "igea_inserr_response", _lib.dptr(o), _lib.dptr(x0), float(duration), n,
              _lib.dptr(x))
    cov = None
    by_fit = acc_noise is not None or gyro_noise is not None
    if q is not None and by_fit:
        raise ValueError(f"{where}: give q or acc_noise/gyro_noise, not both")
    P0 = None
    if p0 is not None:
        P0 = np.ascontiguousarray(_lib.as_f64(p0, "p0", ndim=2,
                                              shape=(_capi.INSERR_N, _capi.INSERR_N)))
    if q is not None:
        qv = np.ascontiguousarray(_lib.as_f64(q, "q", ndim=1, shape=(_capi.INSERR_NQ,)))
        cov = np.zeros((n, _capi.INSERR_N, _capi.INSERR_N))
        _lib.call(where, "igea_inserr_covariance", _lib.dptr(o), _lib.dptr(P0), _lib.dptr(qv),
                  float(duration), n, _lib.dptr(cov))
    elif by_fit:
        an, gn = _noise(acc_noise, "acc_noise"), _noise(gyro_noise, "gyro_noise")
        cov = np.zeros((n, _capi.INSERR_N, _capi.INSERR_N))
        _lib.call(where, "igea_inserr_noise_covariance", _lib.dptr(o), _lib.dptr(P0),
                  _lib.dptr(an), _lib.dptr(gn), float(duration), n, _lib.dptr(cov))
    t = np.arange(n) * (float(duration) / (n - 1))
    return NavErrors(lat, float(duration), acc, gyro, t, x[:, 0:3].copy(), x[:, 3:6].copy(),
                     x[:, 6:9].copy(), cov)


@result
@dataclass(frozen=True)
class NavErrorsLI:
    """igea.nav_errors_li: the errors in the launch-inertial frame at the
    epochs time (n,): position (n, 3) m, velocity (n, 3) m/s, attitude
    (n, 3) rad (the computed body-to-LI matrix is (I - [phi x]) C), the
    accelerometer biases acc_bias (n, 3) m/s^2 and gyro drifts gyro_drift
    (n, 3) rad/s in instrument axes; covariance (n, 15, 15) of the whole
    state when noise (q, acc_noise or gyro_noise) was given, else None."""
    system: str
    time: np.ndarray
    position: np.ndarray
    velocity: np.ndarray
    attitude: np.ndarray
    acc_bias: np.ndarray
    gyro_drift: np.ndarray
    covariance: Optional[np.ndarray] = None


def nav_errors_li(site, telemetry, *, epochs=None, system="strapdown", gravity="j2", q0=None,
                  r0=None, v0=None, x0=None, acc_bias=None, gyro_drift=None, q=None, p0=None,
                  acc_noise=None, gyro_noise=None, acc_tc=None, gyro_tc=None):
    """The INS errors along the reference trajectory that the nav core
    computes from an error-free telemetry record (rows t dvx dvy dvz
    [dthx dthy dthz], row 0 the start; as igea.nav_navigate) from site
    (igea.nav_site), in the launch-inertial frame: the deterministic
    response to the initial state x0 (15,: position, velocity, attitude
    errors, accelerometer biases, gyro drifts; None: 0) with acc_bias (3,)
    m/s^2 and gyro_drift (3,) rad/s in instrument axes (body for a
    strapdown system, platform for a platform) added into it; with q (12,):
    the covariance for white noise of those spectral densities per
    instrument axis (accelerometer white (m/s)^2/s, gyro white rad^2/s,
    accelerometer-bias random walk (m/s^2)^2/s, gyro-drift random walk
    (rad/s)^2/s; see igea_inserr_li_covariance) from p0 (15, 15; None: 0).
    epochs: sample times of the record (None: every sample).
    acc_tc, gyro_tc (s; None or 0: none): correlation times that make the
    bias states first-order Gauss-Markov (d(b)/dt = -b / T + w: an initial
    bias decays, q's bias slots drive them; igea_inserr_li_response_opts,
    _covariance_opts). acc_noise, gyro_noise instead of q: the noise as
    IEEE Std 952 coefficients per instrument axis, as igea.nav_errors takes
    them (a NoiseFit, N, B, K for every axis, or rows N, B, K by axis x y z;
    bias instability B a stationary Gauss-Markov bias of correlation time
    acc_tc or gyro_tc; igea_inserr_li_noise_covariance)."""
    where = "igea.nav_errors_li"
    sc = _lib.choice(_capi.CHOICE_ENVFUN_SYSTEM, system, where, "system")
    gc = _lib.choice(_capi.CHOICE_NAV_GRAVITY, gravity, where, "gravity")
    tel = _lib.as_f64(telemetry, "telemetry", ndim=2)
    need = 7 if sc == _capi.ENVFUN_STRAPDOWN else 4
    if tel.shape[1] < need or tel.shape[0] < 2:
        raise ValueError(f"telemetry: expected shape (n >= 2, {need}) or wider, got {tel.shape}")
    tel = np.asfortranarray(tel[:, :need])
    n = tel.shape[0]
    s = np.ascontiguousarray(_lib.as_f64(site, "site", ndim=1, shape=(_capi.NAV_SITE_LEN,)))
    opt = [None if v is None else np.ascontiguousarray(_lib.as_f64(v, name, ndim=1, shape=(k,)))
           for v, name, k in ((q0, "q0", 4), (r0, "r0", 3), (v0, "v0", 3))]
    ep = np.ascontiguousarray(tel[:, 0] if epochs is None else
                              _lib.as_f64(epochs, "epochs", ndim=1))
    ne = ep.shape[0]
    x = np.zeros(_capi.INSERR_N) if x0 is None else np.array(
        _lib.as_f64(x0, "x0", ndim=1, shape=(_capi.INSERR_N,)), dtype=float)
    x[_capi.INSERR_ACC:_capi.INSERR_ACC + 3] += _triple(acc_bias, "acc_bias")
    x[_capi.INSERR_GYRO:_capi.INSERR_GYRO + 3] += _triple(gyro_drift, "gyro_drift")
    by_fit = acc_noise is not None or gyro_noise is not None
    if q is not None and by_fit:
        raise ValueError(f"{where}: give q or acc_noise/gyro_noise, not both")
    o = _lib.options("inserr", where, ("igea_inserr_li_response_opts", "opts"), acc_tc=acc_tc,
                     gyro_tc=gyro_tc)
    head = (sc, _lib.dptr(s), gc, _lib.dptr(o), n, _lib.dptr(tel), n,
            *[_lib.dptr(v) for v in opt])
    out = np.zeros((max(ne, 1), _capi.INSERR_N))
    _lib.call(where, "igea_inserr_li_response_opts", *head, _lib.dptr(x), ne, _lib.dptr(ep),
              _lib.dptr(out))
    cov = None
    P0 = None if p0 is None else np.ascontiguousarray(
        _lib.as_f64(p0, "p0", ndim=2, shape=(_capi.INSERR_N, _capi.INSERR_N)))
    if q is not None:
        qv = np.ascontiguousarray(_lib.as_f64(q, "q", ndim=1, shape=(_capi.INSERR_NQ,)))
        cov = np.zeros((ne, _capi.INSERR_N, _capi.INSERR_N))
        _lib.call(where, "igea_inserr_li_covariance_opts", *head, _lib.dptr(P0), _lib.dptr(qv),
                  ne, _lib.dptr(ep), _lib.dptr(cov))
    elif by_fit:
        an, gn = _noise(acc_noise, "acc_noise"), _noise(gyro_noise, "gyro_noise")
        cov = np.zeros((ne, _capi.INSERR_N, _capi.INSERR_N))
        _lib.call(where, "igea_inserr_li_noise_covariance", *head, _lib.dptr(P0), _lib.dptr(an),
                  _lib.dptr(gn), ne, _lib.dptr(ep), _lib.dptr(cov))
    sl = lambda a: out[:, a:a + 3].copy()  # noqa: E731
    name = "strapdown" if sc == _capi.ENVFUN_STRAPDOWN else "platform"
    return NavErrorsLI(name, ep.copy(), sl(0), sl(3), sl(6), sl(_capi.INSERR_ACC),
                       sl(_capi.INSERR_GYRO), cov)
