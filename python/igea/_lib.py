"""Loading libigea and the one table of its C prototypes.

The shared library is found through $IGEA_LIBRARY, then beside this
package, then the repository's build/lib, then the system's loader path.
Every exported symbol is declared in PROTOTYPES below (a test compares the
table with the library's exports).
"""
import ctypes
import os
from ctypes import POINTER, c_char_p, c_double, c_int, c_void_p

import numpy as np

MAJOR = 1

_D = POINTER(c_double)
_I = POINTER(c_int)
_P = c_void_p

# name: (restype, [argtypes])
PROTOTYPES = {
    # common
    "igea_strerror": (c_char_p, [c_int]),
    "igea_version": (c_char_p, []),
    "igea_version_number": (c_int, []),
    "igea_init": (c_int, []),
    "igea_opt_name": (c_char_p, [c_int, c_int]),
    # stats
    "igea_stats_normal_cdf": (c_int, [c_double, _D]),
    "igea_stats_normal_quantile": (c_int, [c_double, _D]),
    "igea_stats_chi2_cdf": (c_int, [c_double, c_double, _D]),
    "igea_stats_chi2_sf": (c_int, [c_double, c_double, _D]),
    "igea_stats_chi2_quantile": (c_int, [c_double, c_double, _D]),
    "igea_stats_chi2_upper": (c_int, [c_double, c_double, _D]),
    "igea_stats_accuracy_test": (c_int, [c_int, _D, _D, c_double, c_double, c_double, _D, _I, _D]),
    "igea_stats_pool": (c_int, [c_int, _D, _I, _I, _I, c_double, _D]),
    # normal
    "igea_normal_accumulate": (c_int, [c_int, c_int, c_int, _D, c_int, _D, _D, c_int, _D, _D, c_int, _D, _D]),
    "igea_normal_qr_accumulate": (c_int, [c_int, c_int, c_int, _D, c_int, _D, _D, c_int, _D, _D, c_int, _D]),
    # eqerr
    "igea_eqerr_defaults": (c_int, [_D]),
    "igea_eqerr_check_opts": (c_int, [_D]),
    "igea_eqerr_solve": (c_int, [c_int, _D, c_int, _D, _D, _D, _D, c_int, _D, _D, _I, _D]),
    "igea_eqerr_solve_qr": (c_int, [c_int, _D, c_int, c_double, _D, _D, _D, c_int, _D, _D, _I, _D]),
    "igea_eqerr_run": (c_int, [c_int, c_int, _D, c_int, _D, _D, c_int, _D, _D,
                               _D, _D, c_int, _D, _D, _I, _D, _D, _D]),
    "igea_eqerr_coef": (c_int, [c_int, _D, c_int, _D, c_int, _D, _D]),
    "igea_eqerr_residual": (c_int, [c_int, c_int, c_int, _D, c_int, _D, _D, c_int, _D, _D]),
    # -- further modules add their block below, one block per module --
    # redund
    "igea_redund_exponential": (c_int, [c_double, c_double, _D, _D]),
    "igea_redund_reliability_series": (c_int, [c_int, _D, _D]),
    "igea_redund_reliability_parallel": (c_int, [c_int, _D, _D]),
    "igea_redund_reliability_kofn": (c_int, [c_int, c_int, _D, _D]),
    "igea_redund_diagram": (c_int, [c_int, _D, c_int, _I, _I, _I, _I, _D]),
    "igea_redund_seed002": (c_int, [c_double, c_double, _D]),
    "igea_redund_geometry": (c_int, [c_int, _D, c_int, _D, c_int, _D]),
    "igea_stats_erfinv": (c_int, [c_double, _D]),
    "igea_redund_confidence_distance": (c_int, [c_int, _D, _D, _D, c_int]),
    "igea_redund_thresholds": (c_int, [c_int, _D, _D, c_int, _D, c_int]),
    "igea_redund_relation": (c_int, [c_int, _D, c_int, _D, c_int, _I, c_int]),
    "igea_redund_relation_delta": (c_int, [c_int, _D, _D, c_int, _I, c_int]),
    "igea_redund_fusion_set": (c_int, [c_int, _D, c_int, _D, c_int, c_int, _I, _I]),
    "igea_redund_fuse": (c_int, [c_int, _D, _D, _I, c_int, _D, _D]),
    "igea_redund_false_alarm": (c_int, [c_double, c_double, c_double, c_double, _D]),
    "igea_redund_transform": (c_int, [c_int, _D, _D, _D]),
    "igea_redund_parity": (c_int, [c_int, c_int, _D, c_int, _D, c_int]),
    "igea_redund_fdi": (c_int, [c_int, c_int, _D, c_int, _D, _D, c_double, _D, _D, _I]),
    "igea_redund_skew_check": (c_int, [c_int, _D, _D, c_int, _D, _D, c_double, c_double, c_double,
                                       c_double, c_double, _D, _I, _I, _I]),
    "igea_redund_window_count": (c_int, [c_int, c_double, c_double, _I]),
    "igea_redund_monitor": (c_int, [c_int, c_int, _D, c_int, c_double, c_double, _D, _D,
                                         c_int, c_int, c_int, c_int, _D, _I, _D, _D]),
    "igea_redund_simulate": (c_int, [c_int, c_int, c_double, _D, _D, c_int, c_double, c_double,
                                     c_double, c_int, _D, c_int]),
    # stability
    "igea_stability_block": (c_int, [c_int, _D, c_double, c_double, _D]),
    "igea_stability_allan": (c_int, [c_int, _D, c_double, c_int, _D, c_int, c_int, c_double, _D,
                                     _D, _D, _D, _I]),
    "igea_stability_octave_taus": (c_int, [c_int, c_double, c_int, c_int, _D, _I]),
    "igea_stability_noise_id": (c_int, [c_int, _D, _D, _D]),
    # rls
    "igea_rls_create": (c_int, [c_int, c_int, _D, _D, c_int, POINTER(c_void_p)]),
    "igea_rls_free": (None, [c_void_p]),
    "igea_rls_set_variant": (c_int, [c_void_p, c_int, c_int]),
    "igea_rls_set_anomaly": (c_int, [c_void_p, c_int, c_double, _D]),
    "igea_rls_set_forget": (c_int, [c_void_p, c_double]),
    "igea_rls_set_covariance": (c_int, [c_void_p, c_int]),
    "igea_rls_update": (c_int, [c_void_p, _D, c_int, _D, _D, _I]),
    "igea_rls_run": (c_int, [c_void_p, c_int, c_int, _D, c_int, _D, _D, c_int, _D, c_int, _I,
                             _I, _I]),
    "igea_rls_get_x": (c_int, [c_void_p, _D]),
    "igea_rls_get_gamma": (c_int, [c_void_p, _D, c_int]),
    "igea_rls_get_covariance": (c_int, [c_void_p, _D, c_int]),
    "igea_rls_get_q": (c_int, [c_void_p, _D]),
    "igea_rls_get_counts": (c_int, [c_void_p, _I]),
    "igea_rls_get_size": (c_int, [c_void_p, _I, _I]),
    "igea_rls_compensate": (c_int, [c_void_p, _D, c_int, _D, _D]),
    # regress
    "igea_regress_ls": (c_int, [c_int, c_int, _D, c_int, _D, _D, c_double, _D, _D, c_int, _I,
                                _D, _D]),
    "igea_regress_ebr": (c_int, [c_int, c_int, _D, c_int, _D, _D, c_int, c_double, _D, _D, _I,
                                 _D, _D, _D]),
    "igea_regress_ridge": (c_int, [c_int, c_int, _D, c_int, _D, _D, c_int, c_double, _D, _D,
                                   c_int, _D, _D, _D]),
    "igea_regress_ridge_trace": (c_int, [c_int, c_int, _D, c_int, _D, _D, c_int, _D, _D, c_int,
                                         _D]),
    "igea_regress_pce": (c_int, [c_int, c_int, _D, c_int, _D, _D, c_int, c_double, _D, _D, c_int,
                                 _I, _D, _D]),
    "igea_regress_bayes": (c_int, [c_int, c_int, _D, c_int, _D, _D, _D, _D, c_int, _D, _D, c_int,
                                   _D]),
    "igea_regress_collinearity": (c_int, [c_int, c_int, _D, c_int, _D, _D, c_double, _D, _I, _D,
                                          _D, c_int, _D, _D, _I]),
    # envfun
    "igea_envfun_term_valid": (c_int, [c_int, c_int]),
    "igea_envfun_term_name": (c_char_p, [c_int]),
    "igea_envfun_term_unit": (c_char_p, [c_int]),
    "igea_envfun_term_code": (c_int, [c_int, c_char_p]),
    "igea_envfun_default_spec": (c_int, [c_int, c_int, _D]),
    "igea_envfun_default_terms": (c_int, [c_int, _I, c_int, _I]),
    "igea_envfun_compute": (c_int, [c_int, c_int, _D, c_int, c_int, _I, _I, c_int, _D, _D,
                                    c_int, _D, c_int]),
    # sim
    "igea_sim_defaults": (c_int, [_D]),
    "igea_sim_trajectory_length": (c_int, [c_double, c_double, _I]),
    "igea_sim_trajectory": (c_int, [c_int, c_double, c_double, c_int, _D, c_int]),
    "igea_sim_flight": (c_int, [c_int, c_int, _D, c_int, _D, c_int, _D, _D, _I, _D, c_int,
                                c_int, _D, _D]),
    "igea_sim_montecarlo": (c_int, [c_int, c_int, _D, c_int, _D, c_int, _D, _D, _I, _D, c_int,
                                    _D, c_int, c_int, c_int, _D, _I, _I, _D, _I, _I, _D]),
    "igea_sim_nonlinear": (c_int, [c_int, c_int, _D, c_int, _D, _I, c_int, _D, _D]),
    # accel
    "igea_accel_schedule": (c_int, [c_int, c_double, _D]),
    "igea_accel_merge": (c_int, [c_int, _D, _D, _D, c_double, _D, _D, _D, _I, _I]),
    "igea_accel_to_g": (c_int, [c_int, _D, c_double, _D]),
    "igea_accel_observe": (c_int, [c_int, c_int, _D, _D, _D, _D]),
    "igea_accel_design": (c_int, [c_int, c_int, _D, _D, c_int]),
    "igea_accel_combinations": (c_int, [c_int, _D, c_int]),
    "igea_accel_analyze": (c_int, [c_int, c_int, _D, _D, _D, c_int, _D, _D, _I]),
    "igea_accel_fit": (c_int, [c_int, c_int, c_int, _D, _D, _D, _D, c_int, c_double,
                               _D, _D, _I, _D, _D, _D]),
    "igea_accel_refine": (c_int, [c_int, _D, _D, _D, _D, c_int, c_double, _D, _D, _D, _D]),
    "igea_accel_simulate": (c_int, [c_int, _D, _D, c_double, c_double, c_int, _D, _D]),
}


class IgeaError(Exception):
    """A libigea call failed: .code is the status, .message its text."""

    def __init__(self, code, message, where=""):
        self.code = int(code)
        self.message = message
        super().__init__(f"{where + ': ' if where else ''}{message} (status {code})")


def _candidates():
    env = os.environ.get("IGEA_LIBRARY")
    if env:
        yield env
    here = os.path.dirname(os.path.abspath(__file__))
    yield os.path.join(here, "libigea.so.%d" % MAJOR)
    repo = os.path.dirname(os.path.dirname(here))
    yield os.path.join(repo, "build", "lib", "libigea.so.%d" % MAJOR)
    yield "libigea.so.%d" % MAJOR


def _load():
    errors = []
    for path in _candidates():
        if os.sep in path and not os.path.exists(path):
            continue
        try:
            return ctypes.CDLL(path)
        except OSError as exc:
            errors.append(f"{path}: {exc}")
    raise ImportError("libigea not found; build it with 'make' or set IGEA_LIBRARY\n"
                      + "\n".join(errors))


lib = _load()
for _name, (_res, _args) in PROTOTYPES.items():
    _f = getattr(lib, _name)
    _f.restype = _res
    _f.argtypes = _args

if lib.igea_version_number() // 10000 != MAJOR:
    raise ImportError("libigea major version %d, this package needs %d"
                      % (lib.igea_version_number() // 10000, MAJOR))
lib.igea_init()


def strerror(code):
    return lib.igea_strerror(int(code)).decode()


def check(status, where="", argnames=None):
    """Raise IgeaError for a negative status; return status otherwise.

    argnames: the C argument names in order, so that -i names argument i."""
    if status < 0:
        msg = strerror(status)
        if -1000 < status < 0 and argnames and -status <= len(argnames):
            msg = "invalid argument %d (%s)" % (-status, argnames[-status - 1])
        raise IgeaError(status, msg, where)
    return status


def dptr(a):
    """double* of a numpy float64 array (None -> NULL)."""
    if a is None:
        return None
    return a.ctypes.data_as(_D)


def iptr(a):
    if a is None:
        return None
    return a.ctypes.data_as(_I)


def as_f64(x, name, ndim=None, shape=None):
    """x as a finite-checked-later float64 array in Fortran order.

    Raises ValueError naming the argument for a wrong number of dimensions
    or a wrong shape (None entries in shape match anything)."""
    try:
        a = np.asarray(x, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{name}: not an array of numbers ({exc})") from None
    if ndim is not None and a.ndim != ndim:
        raise ValueError(f"{name}: expected a {ndim}-D array, got shape {a.shape}")
    if shape is not None:
        if len(shape) != a.ndim or any(s is not None and s != d for s, d in zip(shape, a.shape)):
            want = "(" + ", ".join("*" if s is None else str(s) for s in shape) + ")"
            raise ValueError(f"{name}: expected shape {want}, got {a.shape}")
    return np.asfortranarray(a)
