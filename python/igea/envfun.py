"""Environment-function matrices S from a trajectory (METHODS 5).

The C library takes integer term codes (IGEA_ENVFUN_TERM_*, igea/envfun.h)
and holds the term catalogue: the stable names of docs/terms.md, their
units, default 1-sigma specs and the default term sets. This module reads
them from the library.
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
    for code in range(_capi.ENVFUN_TERM_COUNT):
        if _lib.lib.igea_envfun_term_valid(sc, code):
            spec = ctypes.c_double()
            _lib.call("igea.envfun", "igea_envfun_default_spec", sc, code, ctypes.byref(spec))
            out[_lib.lib.igea_envfun_term_name(code).decode()] = (code, spec.value)
    return out


def _default_terms(sc):
    codes = np.zeros(_capi.ENVFUN_TERM_COUNT, dtype=np.intc)
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


def envfun(traj, terms, epochs, *, system="strapdown", spec=None, axes=None,
           output="velocity"):
    """Environment-function matrix S (3 len(epochs) x len(terms)).

    traj: (samples x 11) array t, f_x f_y f_z, w_x w_y w_z, q0 q1 q2 q3
    (specific force and rate in body axes for strapdown, force in
    launch-inertial axes for a platform); terms: list of names
    (docs/terms.md); epochs: times of the rows (non-decreasing, inside the
    trajectory); spec: None, "default", or one 1-sigma per term multiplying
    the columns; axes: platform gyro (input, spin) axes as 6 ints or None;
    output: "velocity", "position", "velocity_g", "position_g".
    Rows are epoch-major (x, y, z of epoch 0, then epoch 1, ...).
    """
    sys_code = _system_code(system)
    tr = _lib.as_f64(traj, "traj", ndim=2)
    if tr.shape[1] != _capi.ENVFUN_TRAJ_COLS:
        raise ValueError(f"traj: expected shape (*, {_capi.ENVFUN_TRAJ_COLS}), got {tr.shape}")
    if tr.shape[0] < 2:
        raise ValueError("traj: at least 2 samples are needed")
    codes = term_codes(terms, system)
    ep = _lib.as_f64(epochs, "epochs", ndim=1)
    if ep.size < 1:
        raise ValueError("epochs: empty")
    sp = None
    if isinstance(spec, str):
        if spec != "default":
            raise ValueError("spec: None, 'default' or an array")
        sp = default_spec(terms, system)
    elif spec is not None:
        sp = _lib.as_f64(spec, "spec", ndim=1, shape=(len(codes),))
    ax = None
    if axes is not None:
        ax = np.ascontiguousarray(axes, dtype=np.intc)
        if ax.shape != (6,):
            raise ValueError(f"axes: expected 6 ints, got shape {ax.shape}")
    output_code = _lib.choice(_capi.CHOICE_ENVFUN_OUTPUT, output, "igea.envfun", "output")
    n, m = tr.shape[0], 3 * ep.size
    S = np.zeros((m, len(codes)), order="F")
    _lib.call("igea.envfun", "igea_envfun_compute", sys_code, n, _lib.dptr(tr), n, len(codes),
              _lib.iptr(codes), _lib.iptr(ax), ep.size, _lib.dptr(ep), _lib.dptr(sp),
              output_code, _lib.dptr(S), m)
    return S
