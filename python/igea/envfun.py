"""Environment-function matrices S from a trajectory (METHODS 5).

The C library takes integer term codes (IGEA_ENVFUN_TERM_*, igea/envfun.h); this
module holds the stable term names of docs/envfun.md and maps them.
"""
import math

import numpy as np

from . import _lib

STRAPDOWN, PLATFORM = 0, 1
_SYSTEMS = {"strapdown": STRAPDOWN, "platform": PLATFORM}
_OUTPUTS = {"velocity": 0, "position": 1, "velocity_g": 2, "position_g": 3}

_AX = "xyz"
G0 = 9.80665
_DEG_H = math.pi / 180.0 / 3600.0

# name -> (code, default 1-sigma spec in SI units), per system
_COMMON = {}
for _a in range(3):
    _COMMON["acc_bias_" + _AX[_a]] = (0 + _a, 1e-3 * G0)          # 1 mg
    _COMMON["acc_scale_" + _AX[_a]] = (3 + _a, 1e-4)
    _COMMON["acc_sq_" + _AX[_a]] = (6 + _a, 1e-5 / G0)            # 10 ug/g^2
    _COMMON["gyro_bias_" + _AX[_a]] = (15 + _a, 0.5 * _DEG_H)     # 0.5 deg/h
for _i, (_j, _k) in enumerate([(0, 1), (0, 2), (1, 0), (1, 2), (2, 0), (2, 1)]):
    _COMMON["acc_mis_" + _AX[_j] + _AX[_k]] = (9 + _i, 1e-4)

TERMS_STRAPDOWN = dict(_COMMON)
TERMS_PLATFORM = dict(_COMMON)
for _a in range(3):
    TERMS_STRAPDOWN["gyro_g_" + _AX[_a]] = (18 + _a, 0.5 * _DEG_H / G0)   # 0.5 deg/h/g
    TERMS_STRAPDOWN["gyro_scale_" + _AX[_a]] = (21 + _a, 1e-4)
    TERMS_STRAPDOWN["att0_" + _AX[_a]] = (24 + _a, 1e-4)                  # rad
    TERMS_PLATFORM["gyro_gi_" + _AX[_a]] = (27 + _a, 0.5 * _DEG_H / G0)
    TERMS_PLATFORM["gyro_gs_" + _AX[_a]] = (30 + _a, 0.5 * _DEG_H / G0)
    TERMS_PLATFORM["align0_" + _AX[_a]] = (33 + _a, 1e-4)

# the 21-term strapdown model of METHODS 1.6(b) / 5.5
STRAPDOWN_21 = ([f"acc_bias_{a}" for a in _AX] + [f"acc_scale_{a}" for a in _AX]
                + ["acc_mis_xy", "acc_mis_xz", "acc_mis_yx", "acc_mis_yz", "acc_mis_zx",
                   "acc_mis_zy"]
                + [f"gyro_bias_{a}" for a in _AX] + [f"gyro_g_{a}" for a in _AX]
                + [f"att0_{a}" for a in _AX])
PLATFORM_21 = ([f"acc_bias_{a}" for a in _AX] + [f"acc_scale_{a}" for a in _AX]
               + [f"gyro_bias_{a}" for a in _AX] + [f"gyro_gi_{a}" for a in _AX]
               + [f"gyro_gs_{a}" for a in _AX] + [f"align0_{a}" for a in _AX]
               + [f"acc_sq_{a}" for a in _AX])

_ENVFUN_ARGS = ["system", "nsamp", "traj", "ldt", "nterms", "terms", "axes", "nepochs",
                "epochs", "spec", "output", "S", "lds"]


def _system_code(system):
    if system not in _SYSTEMS:
        raise ValueError(f"system: expected 'strapdown' or 'platform', got {system!r}")
    return _SYSTEMS[system]


def term_table(system="strapdown"):
    """{name: (code, default spec)} of a system's catalogue."""
    return dict(TERMS_STRAPDOWN if _system_code(system) == STRAPDOWN else TERMS_PLATFORM)


def term_codes(terms, system="strapdown"):
    """Integer codes of a list of term names (ValueError names an unknown one)."""
    table = term_table(system)
    if isinstance(terms, str):
        raise ValueError("terms: expected a list of term names, got a string")
    out = []
    for t in terms:
        if t not in table:
            raise ValueError(f"terms: unknown {system} term {t!r}")
        out.append(table[t][0])
    if not out:
        raise ValueError("terms: empty list")
    return np.asarray(out, dtype=np.intc)


def default_spec(terms, system="strapdown"):
    """The default 1-sigma specs (SI) of docs/envfun.md for these terms."""
    table = term_table(system)
    term_codes(terms, system)
    return np.array([table[t][1] for t in terms])


def envfun(traj, terms, epochs, *, system="strapdown", spec=None, axes=None,
           output="velocity"):
    """Environment-function matrix S (3 len(epochs) x len(terms)).

    traj: (samples x 11) array t, f_x f_y f_z, w_x w_y w_z, q0 q1 q2 q3
    (specific force and rate in body axes for strapdown, force in
    launch-inertial axes for a platform); terms: list of names
    (docs/envfun.md); epochs: times of the rows (non-decreasing, inside the
    trajectory); spec: None, "default", or one 1-sigma per term multiplying
    the columns; axes: platform gyro (input, spin) axes as 6 ints or None;
    output: "velocity", "position", "velocity_g", "position_g".
    Rows are epoch-major (x, y, z of epoch 0, then epoch 1, ...).
    """
    sys_code = _system_code(system)
    tr = _lib.as_f64(traj, "traj", ndim=2)
    if tr.shape[1] != 11:
        raise ValueError(f"traj: expected shape (*, 11), got {tr.shape}")
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
    if output not in _OUTPUTS:
        raise ValueError(f"output: one of {sorted(_OUTPUTS)}, got {output!r}")
    n, m = tr.shape[0], 3 * ep.size
    S = np.zeros((m, len(codes)), order="F")
    st = _lib.lib.igea_envfun_compute(sys_code, n, _lib.dptr(tr), n, len(codes),
                                      _lib.iptr(codes), _lib.iptr(ax), ep.size,
                                      _lib.dptr(ep), _lib.dptr(sp), _OUTPUTS[output],
                                      _lib.dptr(S), m)
    _lib.check(st, "igea.envfun", _ENVFUN_ARGS)
    return S
