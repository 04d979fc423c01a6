"""Navigation core (igea/nav.h): WGS-84 geodetic <-> ECEF, the launch-site
frames (LE Earth-fixed, LI launch-inertial, ECEF) with Earth rotation, J2
or point-mass gravitation with its gradient, and strapdown or platform
navigation from telemetry increments. Angles in radians except where a
name says _deg; times in seconds since lift-off.
"""
import ctypes
from dataclasses import dataclass

import numpy as np

from . import _capi, _lib
from ._result import result

ECEF, LE, LI = _capi.NAV_ECEF, _capi.NAV_LE, _capi.NAV_LI


def _vec(x, name, n=3):
    return np.ascontiguousarray(_lib.as_f64(x, name, ndim=1, shape=(n,)))


def nav_geodetic_to_ecef(lat, lon, height):
    """ECEF position (m) of a geodetic latitude, longitude (rad) and
    ellipsoidal height (m) on WGS-84."""
    r = np.zeros(3)
    _lib.call("igea.nav_geodetic_to_ecef", "igea_nav_geodetic_to_ecef", float(lat), float(lon),
              float(height), _lib.dptr(r))
    return r


def nav_ecef_to_geodetic(r):
    """(lat, lon, height) of an ECEF position (rad, rad, m)."""
    geo = np.zeros(3)
    _lib.call("igea.nav_ecef_to_geodetic", "igea_nav_ecef_to_geodetic", _lib.dptr(_vec(r, "r")),
              _lib.dptr(geo))
    return tuple(float(g) for g in geo)


def nav_site(lat, lon, height, azimuth):
    """The site array (IGEA_NAV_SITE_LEN values) of a launch point (rad, rad,
    m) and firing azimuth (rad from north toward east)."""
    site = np.zeros(_capi.NAV_SITE_LEN)
    _lib.call("igea.nav_site", "igea_nav_site", float(lat), float(lon), float(height),
              float(azimuth), _lib.dptr(site))
    return site


def _frame(f, argument):
    return _lib.choice(_capi.CHOICE_NAV_FRAME, f, "igea.nav_transform", argument)


def nav_transform(site, r, v, t, *, frm="le", to="li"):
    """Position and velocity (3-vectors) from frame `frm` to frame `to`
    ("ecef", "le", "li") at time t since lift-off: (r_out, v_out)."""
    s = _vec(site, "site", _capi.NAV_SITE_LEN)
    ro, vo = np.zeros(3), np.zeros(3)
    _lib.call("igea.nav_transform", "igea_nav_transform", _lib.dptr(s), _frame(frm, "frm"),
              _frame(to, "to"), float(t), _lib.dptr(_vec(r, "r")), _lib.dptr(_vec(v, "v")),
              _lib.dptr(ro), _lib.dptr(vo))
    return ro, vo


def nav_gravity(r, *, model="j2", site=None):
    """Gravitation g (m/s^2) and its gradient G (3 x 3, 1/s^2) at r:
    Earth-centred axes (ECEF or inertial, z polar) when site is None, else
    r in LI of that site."""
    code = _lib.choice(_capi.CHOICE_NAV_GRAVITY, model, "igea.nav_gravity", "model")
    g, G = np.zeros(3), np.zeros(9)
    rv = _vec(r, "r")
    if site is None:
        _lib.call("igea.nav_gravity", "igea_nav_gravity", code, _lib.dptr(rv), _lib.dptr(g),
                  _lib.dptr(G))
    else:
        s = _vec(site, "site", _capi.NAV_SITE_LEN)
        _lib.call("igea.nav_gravity", "igea_nav_gravity_li", _lib.dptr(s), code, _lib.dptr(rv),
                  _lib.dptr(g), _lib.dptr(G))
    return g, G.reshape(3, 3)


@result
@dataclass(frozen=True)
class NavResult:
    """States after each record (row k: after record k; row 0 the start)."""
    t: np.ndarray  # (n,)
    r: np.ndarray  # (n, 3) LI position, m
    v: np.ndarray  # (n, 3) LI velocity, m/s
    q: np.ndarray  # (n, 4) body -> LI (1 0 0 0 for a platform)
    w: np.ndarray  # (n, 3) apparent velocity int f dt in LI, m/s


def nav_navigate(site, telemetry, *, system="strapdown", gravity="j2", q0=None, r0=None,
                 v0=None, coning=True, sculling=True):
    """Navigate a telemetry record (rows t dvx dvy dvz [dthx dthy dthz];
    row 0 the start) in LI: igea_nav_init then igea_nav_step per row."""
    sc = _lib.choice(_capi.CHOICE_ENVFUN_SYSTEM, system, "igea.nav_navigate", "system")
    gc = _lib.choice(_capi.CHOICE_NAV_GRAVITY, gravity, "igea.nav_navigate", "gravity")
    tel = np.ascontiguousarray(_lib.as_f64(telemetry, "telemetry", ndim=2))
    need = 7 if sc == _capi.ENVFUN_STRAPDOWN else 4
    if tel.shape[1] < need or tel.shape[0] < 1:
        raise ValueError(f"telemetry: expected shape (*, {need}) or wider, got {tel.shape}")
    s = _vec(site, "site", _capi.NAV_SITE_LEN)
    flags = (0 if coning else _capi.NAV_NO_CONING) | (0 if sculling else _capi.NAV_NO_SCULLING)
    opt = [None if x is None else _vec(x, n, k) for x, n, k in
           ((q0, "q0", 4), (r0, "r0", 3), (v0, "v0", 3))]
    st = np.zeros(_capi.NAV_STATE_LEN)
    _lib.call("igea.nav_navigate", "igea_nav_init", sc, _lib.dptr(s), gc, flags,
              float(tel[0, 0]), *[_lib.dptr(x) for x in opt], _lib.dptr(st))
    n = tel.shape[0]
    out = np.zeros((n, _capi.NAV_STATE_LEN))
    out[0] = st
    for k in range(1, n):
        dv = np.ascontiguousarray(tel[k, 1:4])
        dth = np.ascontiguousarray(tel[k, 4:7]) if need == 7 else None
        _lib.call("igea.nav_navigate", "igea_nav_step", _lib.dptr(st), float(tel[k, 0]),
                  _lib.dptr(dv), _lib.dptr(dth))
        out[k] = st
    sl = lambda a, m: out[:, a:a + m].copy()  # noqa: E731
    return NavResult(t=out[:, _capi.NAV_STATE_T].copy(), r=sl(_capi.NAV_STATE_R, 3),
                     v=sl(_capi.NAV_STATE_V, 3), q=sl(_capi.NAV_STATE_Q, 4),
                     w=sl(_capi.NAV_STATE_W, 3))
