"""Loading libigea with the prototypes of its headers.

The shared library is found through $IGEA_LIBRARY (the library file, or
the directory that holds libigea.so.MAJOR), then beside this package (where
'pip install ./python' puts the one it builds), then the repository's
build/lib, then the system's loader path.
Every function of the headers gets the ctypes prototype that
python/gen_capi.py wrote into _capi.PROTOTYPES; the constants of the
headers are the names of _capi (IGEA_X is _capi.X).
"""
import ctypes
import os
from ctypes import POINTER, c_double, c_int

import numpy as np

from . import _capi

MAJOR = _capi.VERSION_MAJOR
PROTOTYPES = _capi.PROTOTYPES

_D = POINTER(c_double)
_I = POINTER(c_int)


class IgeaError(Exception):
    """A libigea call failed: .code is the status, .message its text,
    .function the C function and .argument the name of the invalid
    argument (status -i: the i-th parameter of the prototype) or None.
    .detail, for a data error the library reports without naming an
    argument (NaN or Inf, a sigma <= 0 or too small), names the first
    offending element of the inputs passed ("dw[17] = nan"), or is None."""

    def __init__(self, code, message, where="", function=None, argument=None, detail=None):
        self.code = int(code)
        self.message = message
        self.function = function
        self.argument = argument
        self.detail = detail
        text = f"{detail}: {message}" if detail else message
        super().__init__(f"{where + ': ' if where else ''}{text} (status {code})")


class DataError(IgeaError, ValueError):
    """An IgeaError caused by the values passed (an invalid argument -i, or
    a data status: NaN, a non-positive sigma, rank, ...): also a ValueError,
    so that 'except ValueError' catches bad data. Which statuses are data
    is the library's igea_status_class (the driver's exit 65 is the same
    class); out of memory, a failed iteration, LAPACK, an unreadable file
    raise a plain IgeaError."""


def error(code, message, where="", function=None, argument=None, detail=None):
    """The exception for status `code`: DataError for an invalid argument or
    bad data (igea_status_class ARGUMENT or DATA), else IgeaError."""
    cls = (DataError if lib.igea_status_class(code) in (_capi.STATUS_ARGUMENT, _capi.STATUS_DATA)
           else IgeaError)
    return cls(code, message, where, function, argument, detail)


def _candidates():
    env = os.environ.get("IGEA_LIBRARY")
    if env:
        yield os.path.join(env, "libigea.so.%d" % MAJOR) if os.path.isdir(env) else env
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


def _absent(name):
    def call(*args):
        raise ImportError("%s lacks %s: the library is older than this package's headers"
                          % (lib._name, name))
    return call


lib = _load()
for _name, (_res, _args) in _capi.PROTOTYPES.items():
    try:
        _f = getattr(lib, _name)
    except AttributeError:  # an older minor version: fails when called
        setattr(lib, _name, _absent(_name))
        continue
    _f.restype = _res
    _f.argtypes = [t for _, t in _args]

if lib.igea_version_number() // 10000 != MAJOR:
    raise ImportError("libigea major version %d, this package needs %d"
                      % (lib.igea_version_number() // 10000, MAJOR))
lib.igea_init()


def strerror(code):
    return lib.igea_strerror(int(code)).decode()


def argnames(function):
    """The parameter names of a C function, in order (from its header)."""
    return [n for n, _ in _capi.PROTOTYPES[function][1]]


def check(status, where, function, detail=None):
    """Raise IgeaError (DataError for bad data, see error) for a negative
    status of `function`; return status otherwise. Status -i names the
    i-th parameter of the prototype; the library-wide codes carry
    igea_strerror's text (and detail, when given, first)."""
    if status < 0:
        names = argnames(function)
        if -status <= len(names):
            arg = names[-status - 1]
            raise error(status, "invalid argument %d (%s)" % (-status, arg), where, function,
                        arg)
        raise error(status, strerror(status), where, function, detail=detail)
    return status


def _index(a, flat):
    """The index of element `flat` of a (counted in a's memory order, F for a
    Fortran-ordered matrix, else C) as text: "3" or "12, 4"."""
    idx = np.unravel_index(flat, a.shape, order="F" if a.flags.f_contiguous and a.ndim > 1
                           else "C")
    return ", ".join(str(int(i)) for i in idx)


_SIGMA_LIKE = ("sigma", "spec", "sd", "scale", "noise", "var", "level")


def diagnose(status, function, args):
    """For a data status that does not name an argument, the first input
    element at fault, as "name[i] = value", or None: IGEA_ENONFINITE the
    first NaN or Inf of the read-only arrays passed (in argument order),
    IGEA_ENONPOSITIVE the first value <= 0 and IGEA_ERANGE the first below
    IGEA_SIGMA_MIN of those named like a standard deviation (sigma, spec,
    ...). Only arrays passed through dptr are seen."""
    if status not in (_capi.ENONFINITE, _capi.ENONPOSITIVE, _capi.ERANGE):
        return None
    names = argnames(function)
    inputs = set(_capi.INPUTS.get(function, ()))
    for name, arg in zip(names, args):
        a = getattr(arg, "_igea_array", None)
        if name not in inputs or a is None or a.dtype != np.float64 or a.size == 0:
            continue
        if status == _capi.ENONFINITE:
            bad = ~np.isfinite(a)
        elif not any(k in name.lower() for k in _SIGMA_LIKE):
            continue
        elif status == _capi.ENONPOSITIVE:
            bad = a <= 0
        else:
            bad = (a > 0) & (a < _capi.SIGMA_MIN)
        order = "F" if a.flags.f_contiguous and a.ndim > 1 else "C"
        flat = np.flatnonzero(bad.ravel(order=order))
        if flat.size:
            k = int(flat[0])
            return "%s[%s] = %r" % (name, _index(a, k), float(a.ravel(order=order)[k]))
    return None


def call(where, function, *args):
    """lib.function(*args), checked: returns the status (>= 0) or raises
    IgeaError naming the failing argument (see check), or for a data
    status the first offending input element (see diagnose)."""
    status = getattr(lib, function)(*args)
    if status < 0:
        check(status, where, function, diagnose(status, function, args))
    return status


def choice_codes(kind):
    """{name: code} of the library's enumeration kind (_capi.CHOICE_*), in
    the library's listing order (igea_choice_codes, igea_choice_name)."""
    n = check(lib.igea_choice_codes(kind, None, 0), "igea.choice_codes", "igea_choice_codes")
    codes = (c_int * max(n, 1))()
    check(lib.igea_choice_codes(kind, codes, n), "igea.choice_codes", "igea_choice_codes")
    return {lib.igea_choice_name(kind, c).decode(): c for c in codes[:n]}


def choice_name(kind, code):
    """The name of code `code` of enumeration kind ("" when it has none)."""
    return lib.igea_choice_name(kind, int(code)).decode()


def choice(kind, value, where, argument):
    """The code of the name `value` in enumeration kind (_capi.CHOICE_*):
    ValueError "where: argument: expected one of 'a', 'b', got 'x'" when
    it is not one of the library's names."""
    code = c_int(0)
    if isinstance(value, str) and "\0" not in value and lib.igea_choice_code(
            kind, value.encode(), ctypes.byref(code)) == 0:
        return code.value
    names = ", ".join(repr(n) for n in choice_codes(kind))
    raise ValueError(f"{where}: {argument}: expected one of {names}, got {value!r}")


def fields(array, prefix, **kinds):
    """{name: kind(array[_capi.<PREFIX><NAME>])}: an output array of the
    library (info, counts, out) read slot by slot by name."""
    return {n: k(array[getattr(_capi, prefix + n.upper())]) for n, k in kinds.items()}


def options(module, where, at, **slots):
    """The options array of a module (module "eqerr": opts[EQERR_OPT_LEN]):
    the library's defaults (igea_<module>_defaults), then each slot given
    (named as its IGEA_<MODULE>_OPT_* macro, in lower case) and not None
    set: a keyword left None keeps the library's default. Checked by
    igea_<module>_check_opts: a bad slot raises IgeaError with the status
    that at = (function, argument) gives for that options argument, naming
    the slot as igea_opt_name does."""
    m = module.upper()
    opts = np.zeros(getattr(_capi, m + "_OPT_LEN"))
    call(where, "igea_%s_defaults" % module, dptr(opts))
    for name, value in slots.items():
        if value is not None:
            opts[getattr(_capi, "%s_OPT_%s" % (m, name.upper()))] = float(value)
    checker = "igea_%s_check_opts" % module
    st = getattr(lib, checker)(dptr(opts)) if checker in _capi.PROTOTYPES else 0
    if st > 0:
        function, arg = at
        i = argnames(function).index(arg)
        slot = lib.igea_opt_name(getattr(_capi, "MODULE_" + m), st - 1).decode()
        raise error(-(i + 1), "invalid argument %d (%s): the options slot %s = %r is out "
                    "of its range" % (i + 1, arg, slot, opts[st - 1]), where, function, arg)
    check(st, where, checker)
    return opts


def dptr(a):
    """double* of a numpy float64 array (None -> NULL)."""
    if a is None:
        return None
    p = a.ctypes.data_as(_D)
    p._igea_array = a  # for diagnose
    return p


def iptr(a):
    if a is None:
        return None
    p = a.ctypes.data_as(_I)
    p._igea_array = a
    return p


def as_f64(x, name, ndim=None, shape=None, rows=False):
    """x as a finite-checked-later float64 array in Fortran order (rows:
    a C-contiguous 2-D array is returned as it is, not transposed into a
    copy, for a function that takes IGEA_ROWMAJOR).

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
    if rows and a.ndim == 2 and a.flags.c_contiguous and not a.flags.f_contiguous:
        return a
    return np.asfortranarray(a)
