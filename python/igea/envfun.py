"""Environment-function matrices S from a trajectory (METHODS 5).

The C library takes integer term codes (IGEA_ENVFUN_TERM_*, igea/envfun.h)
and holds the term catalogue: the stable names of docs/terms.md, their
units, default 1-sigma specs and the default term sets. This module reads
them from the library. User-defined terms (`user_terms=`) are sampled
unit errors in instrument axes, propagated like the catalogue's terms.
"""
import ctypes

import numpy as np

from . import _capi, _lib

STRAPDOWN, PLATFORM = _capi.ENVFUN_STRAPDOWN, _capi.ENVFUN_PLATFORM


def _system_code(system):
    return _lib.choice(_capi.CHOICE_ENVFUN_SYSTEM, system, "igea.envfun", "system")


def _catalogue(sc):
    """{name: (code, default spec)} of system code sc, in code order."""
    out = {}
    for code in range(_lib.lib.igea_envfun_term_count()):
        if _lib.lib.igea_envfun_term_valid(sc, code):
            spec = ctypes.c_double()
            _lib.call("igea.envfun", "igea_envfun_default_spec", sc, code, ctypes.byref(spec))
            out[_lib.lib.igea_envfun_term_name(code).decode()] = (code, spec.value)
    return out


def _default_terms(sc):
    codes = np.zeros(_lib.lib.igea_envfun_term_count(), dtype=np.intc)
    n = ctypes.c_int()
    _lib.call("igea.envfun", "igea_envfun_default_terms", sc, _lib.iptr(codes), codes.size,
              ctypes.byref(n))
    return [_lib.lib.igea_envfun_term_name(int(c)).decode() for c in codes[:n.value]]


TERMS_STRAPDOWN = _catalogue(STRAPDOWN)
TERMS_PLATFORM = _catalogue(PLATFORM)
# the 21-term models of METHODS 1.6(b) / 5.5
STRAPDOWN_21 = _default_terms(STRAPDOWN)
PLATFORM_21 = _default_terms(PLATFORM)


def term_table(system="strapdown"):
    """{name: (code, default spec)} of a system's catalogue."""
    return dict(TERMS_STRAPDOWN if _system_code(system) == STRAPDOWN else TERMS_PLATFORM)


def default_terms(system="strapdown"):
    """The names of the system's default (21-term) model, in model order."""
    return list(STRAPDOWN_21 if _system_code(system) == STRAPDOWN else PLATFORM_21)


def term_codes(terms, system="strapdown"):
    """Integer codes of a list of term names (ValueError names an unknown one)."""
    sc = _system_code(system)
    if isinstance(terms, str):
        raise ValueError("terms: expected a list of term names, got a string")
    out = []
    for t in terms:
        code = _lib.lib.igea_envfun_term_code(sc, str(t).encode())
        if code < 0:
            raise ValueError(f"terms: unknown {system} term {t!r}")
        out.append(code)
    if not out:
        raise ValueError("terms: empty list")
    return np.asarray(out, dtype=np.intc)


def default_spec(terms, system="strapdown"):
    """The library's default 1-sigma specs (SI) of these terms (docs/terms.md)."""
    sc = _system_code(system)
    out = np.zeros(len(terms))
    for i, code in enumerate(term_codes(terms, system)):
        _lib.call("igea.default_spec", "igea_envfun_default_spec", sc, int(code),
                  _lib.dptr(out[i:]))
    return out


def _user_terms(user_terms, nsamp, system):
    """(names, kinds, nsamp x 3 n array) of user_terms {name: (nsamp, 3)}."""
    if not isinstance(user_terms, dict):
        raise ValueError("user_terms: a dict {name: (samples x 3) array}")
    names, kinds, cols = [], [], []
    for name, u in user_terms.items():
        name = str(name)
        kind = (_capi.ENVFUN_USER_ACC if name.startswith("acc_") else
                _capi.ENVFUN_USER_GYRO if name.startswith("gyro_") else None)
        if kind is None or not name.replace("_", "a").isalnum() or name != name.lower():
            raise ValueError(f"user_terms: {name!r}: a name acc_* (specific-force error) or "
                             "gyro_* (rate or drift error), lower case, digits, '_'")
        if any(_lib.lib.igea_envfun_term_code(s, name.encode()) >= 0 for s in (STRAPDOWN, PLATFORM)):
            raise ValueError(f"user_terms: {name!r} is a catalogue term")
        a = _lib.as_f64(u, f"user_terms[{name!r}]", ndim=2, shape=(nsamp, 3))
        names.append(name)
        kinds.append(kind)
        cols.append(a)
    return names, np.asarray(kinds, dtype=np.intc), np.asfortranarray(np.hstack(cols))


def envfun(traj, terms, epochs, *, system="strapdown", spec=None, axes=None,
           output="velocity", user_terms=None, lat=None, lon=None, height=0.0, azimuth=None):
    """Environment-function matrix S (3 len(epochs) x (len(terms) + len(user_terms))).

    traj: (samples x 11) array t, f_x f_y f_z, w_x w_y w_z, q0 q1 q2 q3
    (specific force and rate in body axes for strapdown, force in
    launch-inertial axes for a platform); terms: list of names
    (docs/terms.md; may be empty with user_terms); epochs: times of the rows
    (non-decreasing, inside the trajectory); spec: None, "default" (user
    terms: 1), or one 1-sigma per column multiplying the columns; axes:
    platform gyro (input, spin) axes as 6 ints or None; output: "velocity",
    "position", "velocity_g", "position_g"; user_terms: None or {name:
    (samples x 3) unit error at the trajectory's samples in instrument axes},
    name acc_* a specific-force error (m/s^2), gyro_* a rate or drift error
    (rad/s); their columns follow the terms'.
    lat, lon, height, azimuth: the stated launch point (degrees, m, as
    igea.dw's), all of lat, lon, azimuth or none: the launch-point terms
    pos0_* then hold the stated pad velocity's error too and the _g kinds
    use the site's J2 gravity along the path that leaves the pad at its
    inertial velocity, the flown one (igea_envfun_compute_site,
    docs/envfun.md).
    Rows are epoch-major (x, y, z of epoch 0, then epoch 1, ...).
    """
    sys_code = _system_code(system)
    tr = _lib.as_f64(traj, "traj", ndim=2)
    if tr.shape[1] != _capi.ENVFUN_TRAJ_COLS:
        raise ValueError(f"traj: expected shape (*, {_capi.ENVFUN_TRAJ_COLS}), got {tr.shape}")
    if tr.shape[0] < 2:
        raise ValueError("traj: at least 2 samples are needed")
    user = _user_terms(user_terms, tr.shape[0], system) if user_terms else None
    if user and isinstance(terms, (list, tuple)) and not terms:
        codes = np.zeros(0, dtype=np.intc)
    else:
        codes = term_codes(terms, system)
    nu = len(user[0]) if user else 0
    ep = _lib.as_f64(epochs, "epochs", ndim=1)
    if ep.size < 1:
        raise ValueError("epochs: empty")
    sp = None
    if isinstance(spec, str):
        if spec != "default":
            raise ValueError("spec: None, 'default' or an array")
        sp = np.concatenate([default_spec(terms, system) if len(codes) else np.zeros(0),
                             np.ones(nu)])
    elif spec is not None:
        sp = _lib.as_f64(spec, "spec", ndim=1, shape=(len(codes) + nu,))
    ax = None
    if axes is not None:
        ax = np.ascontiguousarray(axes, dtype=np.intc)
        if ax.shape != (6,):
            raise ValueError(f"axes: expected 6 ints, got shape {ax.shape}")
    output_code = _lib.choice(_capi.CHOICE_ENVFUN_OUTPUT, output, "igea.envfun", "output")
    site = None
    given = [v is not None for v in (lat, lon, azimuth)]
    if any(given):
        if not all(given):
            raise ValueError("lat, lon, azimuth: give all three (the stated launch point) or none")
        from .nav import nav_site
        site = nav_site(np.radians(lat), np.radians(lon), height, np.radians(azimuth))
    n, m = tr.shape[0], 3 * ep.size
    S = np.zeros((m, len(codes) + nu), order="F")
    _lib.call("igea.envfun", "igea_envfun_compute_site", sys_code, n, _lib.dptr(tr), n,
              len(codes), _lib.iptr(codes) if len(codes) else None, _lib.iptr(ax), nu,
              _lib.iptr(user[1]) if user else None, _lib.dptr(user[2]) if user else None, n,
              ep.size, _lib.dptr(ep), _lib.dptr(sp), output_code, _lib.dptr(site), _lib.dptr(S), m)
    return S
