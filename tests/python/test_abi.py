"""The Python mirror of the C API against the headers and the library.

The headers are parsed here on their own (not with python/gen_capi.py), so
that an error of the generator shows as a difference."""
import ctypes
import importlib.util
import os
import re
import subprocess

import pytest

import igea
from igea import _capi, _lib

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
INCLUDE = os.path.join(REPO, "include", "igea")

_CTYPE = {"void": None, "int": ctypes.c_int, "double": ctypes.c_double,
          "int*": ctypes.POINTER(ctypes.c_int), "double*": ctypes.POINTER(ctypes.c_double),
          "char*": ctypes.c_char_p, "igea_rls*": ctypes.c_void_p,
          "igea_rls**": ctypes.POINTER(ctypes.c_void_p)}


def _headers():
    for fn in sorted(os.listdir(INCLUDE)):
        if fn.endswith(".h"):
            with open(os.path.join(INCLUDE, fn)) as fh:
                yield fn, re.sub(r"/\*.*?\*/", " ", fh.read(), flags=re.S)


def _prototypes():
    """{name: (C return type, [(C type, name)])} of every IGEA_API function."""
    out = {}
    for _, text in _headers():
        for m in re.finditer(r"IGEA_API\s+([\w\s*]+?)\s*\b(igea_\w+)\s*\(([^)]*)\)\s*;", text):
            params = []
            for p in m.group(3).split(","):
                p = " ".join(p.split())
                if p in ("void", ""):
                    continue
                t, name = re.match(r"(.*?)\s*(\w+)$", p).groups()
                params.append((t, name))
            out[m.group(2)] = (m.group(1), params)
    return out


def _ctype(c):
    t = c.replace("const", "").replace(" ", "")
    if re.fullmatch(r"igea_\w+\*", t):  # every handle type is an opaque pointer
        t = "igea_rls*"
    if re.fullmatch(r"igea_\w+\*\*", t):
        t = "igea_rls**"
    assert t in _CTYPE, "C type %r has no ctypes counterpart in this test" % c
    return _CTYPE[t]


def test_prototype_table_matches_exports():
    """Every exported igea_* symbol has a prototype and vice versa."""
    path = _lib.lib._name
    out = subprocess.run(["nm", "-D", "--defined-only", path], capture_output=True, text=True).stdout
    exported = {line.split()[-1] for line in out.splitlines() if line.split()[-1].startswith("igea_")}
    assert exported == set(_capi.PROTOTYPES), exported ^ set(_capi.PROTOTYPES)


def test_prototypes_used_match_the_headers():
    """The ctypes argtypes and restype set on each library function have
    the count, order and types of the header's parameters, and the mirror
    holds the header's parameter names."""
    headers = _prototypes()
    assert set(headers) == set(_capi.PROTOTYPES)
    for name, (ret, params) in headers.items():
        fn = getattr(_lib.lib, name)
        want = [_ctype(t) for t, _ in params]
        assert len(fn.argtypes) == len(params), name
        assert list(fn.argtypes) == want, (name, fn.argtypes, want)
        assert fn.restype == _ctype(ret), (name, fn.restype, ret)
        assert _lib.argnames(name) == [n for _, n in params], name


def test_constants_match_the_headers():
    """Every #define IGEA_X with a plain number is _capi.X (no macro lost)."""
    n = 0
    for fn, text in _headers():
        for m in re.finditer(r"(?m)^#define (IGEA_\w+) +\(?(-?[0-9][0-9.e+-]*)\)?\s*$", text):
            name, lit = m.groups()
            value = float(lit) if re.search(r"[.e]", lit) else int(lit)
            assert getattr(_capi, name[len("IGEA_"):]) == value, (fn, name)
            n += 1
    assert n > 100


def test_generated_module_is_up_to_date():
    """python/igea/_capi.py equals a fresh generation from the headers."""
    spec = importlib.util.spec_from_file_location("gen_capi",
                                                  os.path.join(REPO, "python", "gen_capi.py"))
    gen = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(gen)
    with open(os.path.join(REPO, "python", "igea", "_capi.py")) as fh:
        have = fh.read()
    assert have == gen.generate(), "python/igea/_capi.py is stale: run python3 python/gen_capi.py"


def test_version_defined_once():
    """The library, the package and the build read the header's version."""
    major, minor, patch = _capi.VERSION_MAJOR, _capi.VERSION_MINOR, _capi.VERSION_PATCH
    text = "%d.%d.%d" % (major, minor, patch)
    assert (major, minor) == (1, 1)
    assert _capi.VERSION_STRING == text == igea.__version__
    assert _lib.lib.igea_version().decode() == text
    assert _lib.lib.igea_version_number() == major * 10000 + minor * 100 + patch
    with open(os.path.join(REPO, "python", "pyproject.toml")) as fh:
        toml = fh.read()
    assert re.search(r'(?m)^dynamic = \["version"\]', toml)
    assert re.search(r'(?m)^version = \{attr = "igea\._capi\.VERSION_STRING"\}', toml)
    assert not re.search(r'(?m)^version = "', toml)
    try:
        out = subprocess.run(["make", "-s", "--no-print-directory", "-f", "Makefile", "-f", "-",
                              "igea-print-version"], cwd=REPO, capture_output=True, text=True,
                             input="igea-print-version:\n\t@echo $(VERSION) $(SOMAJOR)\n")
    except OSError:
        pytest.skip("make not available")
    assert out.stdout.split() == [text, str(major)], out.stderr


def test_error_names_the_argument():
    """Status -i names the i-th parameter of the prototype; library-wide
    codes carry igea_strerror's text."""
    with pytest.raises(igea.IgeaError) as e:
        igea.reliability_kofn([0.9, 0.9], 3)
    assert e.value.code == -2
    assert e.value.function == "igea_redund_reliability_kofn" and e.value.argument == "k"
    assert "invalid argument 2 (k)" in str(e.value)
    S = [[1.0, 0.5], [0.2, 1.0], [0.3, 0.1], [1.0, 1.0], [0.0, 2.0], [1.0, 0.0]]
    with pytest.raises(igea.IgeaError) as e:
        igea.eqerr(S, [0.1, float("nan"), 0.0, 0.2, 0.1, 0.0], 0.1)
    assert e.value.code == _capi.ENONFINITE and e.value.argument is None
    assert e.value.message == "an input holds NaN or Inf"
    with pytest.raises(igea.IgeaError) as e:  # a bad slot of an options array
        igea.eqerr(S, [0.0] * 6, 0.1, alpha=1.5)
    assert e.value.argument == "opts" and e.value.code == -9
    assert "alpha" in str(e.value)
