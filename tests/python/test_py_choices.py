"""The names of the library's enumerations (igea_choice_*) are the only
ones the driver and the Python package know: every choice option of every
command lists exactly the library's names in --help and accepts exactly
them, and every Python keyword of a choice accepts exactly the same set."""
import ctypes
import importlib
import os
import re
import subprocess

import numpy as np
import pytest

import igea
from igea import _capi, _lib

DRIVER = os.environ["IGEA_DRIVER"]


def library_names(kind):
    """The names of a kind, read from the C functions directly."""
    lib = _lib.lib
    n = lib.igea_choice_codes(kind, None, 0)
    assert n >= 2
    codes = (ctypes.c_int * n)()
    assert lib.igea_choice_codes(kind, codes, n) == n
    names = [lib.igea_choice_name(kind, c).decode() for c in codes]
    for name, c in zip(names, codes):
        out = ctypes.c_int(12345)
        assert lib.igea_choice_code(kind, name.encode(), ctypes.byref(out)) == 0
        assert out.value == c
    return names


DRIVER_OPTIONS = [
    ("eqerr", "--route", _capi.CHOICE_EQERR_ROUTE),
    ("accel", "--model", _capi.CHOICE_ACCEL_MODEL),
    ("accel", "--method", _capi.CHOICE_ACCEL_METHOD),
    ("accel", "--rule", _capi.CHOICE_REGRESS_EBR_RULE),
    ("accel", "--axis", _capi.CHOICE_ACCEL_AXIS),
    ("regress", "--method", _capi.CHOICE_REGRESS_METHOD),
    ("envfun", "--system", _capi.CHOICE_ENVFUN_SYSTEM),
    ("envfun", "--output", _capi.CHOICE_ENVFUN_OUTPUT),
    ("simulate", "--system", _capi.CHOICE_ENVFUN_SYSTEM),
    ("simulate", "--generator", _capi.CHOICE_SIM_GENERATOR),
    ("montecarlo", "--system", _capi.CHOICE_ENVFUN_SYSTEM),
    ("montecarlo", "--generator", _capi.CHOICE_SIM_GENERATOR),
    ("rls", "--variant", _capi.CHOICE_RLS_VARIANT),
    ("rls", "--anomaly", _capi.CHOICE_RLS_ANOMALY),
    ("stability", "--kind", _capi.CHOICE_STABILITY_KIND),
    ("stability", "--noise", _capi.CHOICE_STABILITY_NOISE),
]


def run(*args):
    return subprocess.run([DRIVER, *args], capture_output=True, text=True, timeout=60)


@pytest.mark.parametrize("cmd,opt,kind", DRIVER_OPTIONS)
def test_driver_lists_and_accepts_the_library_names(cmd, opt, kind):
    names = library_names(kind)
    r = run(cmd, "--help")
    assert r.returncode == 0
    m = re.search(r"^\s+%s (\S+)" % re.escape(opt), r.stdout, re.M)
    assert m, r.stdout
    assert m.group(1).split("|") == names
    for name in names:  # parsed, then --help stops the command
        assert run(cmd, opt, name, "--help").returncode == 0, name
    for bad in ("bogus", names[0].upper(), names[0] + "x", ""):
        r = run(cmd, opt, bad)
        assert r.returncode == 64, bad
        assert "is not one of " + "|".join(names) in r.stderr


def test_driver_regress_rules():
    """regress --rule is one option for two estimators: its help names
    the library's rules of each (ridge's fixed rule is --k)."""
    ridge = [n for n in library_names(_capi.CHOICE_REGRESS_RIDGE_RULE) if n != "fixed"]
    ebr = library_names(_capi.CHOICE_REGRESS_EBR_RULE)
    text = re.sub(r"\s+", " ", run("regress", "--help").stdout)
    assert "ridge: " + "|".join(ridge) + " " in text
    assert "ebr: " + "|".join(ebr) + " " in text
    r = run("regress", "--method", "ebr", "--rule", "bogus", "--S", "x", "--dw", "y")
    assert r.returncode == 64 and "|".join(ebr) in r.stderr


# ---- Python -----------------------------------------------------------------
_rng = np.random.default_rng(3)
_A = _rng.standard_normal((40, 3))
_y = _A @ np.array([1.0, -0.5, 0.25]) + 0.01 * _rng.standard_normal(40)
_TH = np.arange(0.0, 360.0, 15.0)
_TRAJ = igea.reference_trajectory(4.0, 20.0)


def _eqerr(route):
    S = _rng.standard_normal((60, 4))
    return igea.eqerr(S, S @ np.ones(4) * 1e-3, 0.01, route=route)


def _accel_fit(field):
    def call(name):
        ya, yb = igea.accel_simulate(_TH, np.full(9, 1e-4), seed=1)
        return igea.accel_fit(_TH, ya, yb, **{"method": "ls", "rule": "sc", field: name})
    return call


PYTHON_KEYWORDS = [
    ("route", _capi.CHOICE_EQERR_ROUTE, _eqerr),
    ("rule", _capi.CHOICE_REGRESS_RIDGE_RULE,
     lambda n: igea.ridge(_A, _y, rule=n)),
    ("rule", _capi.CHOICE_REGRESS_EBR_RULE, lambda n: igea.ebr(_A, _y, 0.01, rule=n)),
    ("model", _capi.CHOICE_ACCEL_MODEL, lambda n: igea.accel_design(_TH, model=n)),
    ("method", _capi.CHOICE_ACCEL_METHOD, _accel_fit("method")),
    ("rule", _capi.CHOICE_REGRESS_EBR_RULE, _accel_fit("rule")),
    ("system", _capi.CHOICE_ENVFUN_SYSTEM,
     lambda n: importlib.import_module("igea.envfun").default_terms(n)),
    ("output", _capi.CHOICE_ENVFUN_OUTPUT,
     lambda n: igea.envfun(_TRAJ, ["acc_bias_x"], [1.0, 2.0], output=n)),
    ("generator", _capi.CHOICE_SIM_GENERATOR,
     lambda n: igea.simulate(_TRAJ, ["acc_bias_x"], [1.0, 2.0], generator=n)),
    ("variant", _capi.CHOICE_RLS_VARIANT,
     lambda n: igea.RLS(np.zeros(2), 1e6 * np.eye(2), 1, variant=n, p=2)),
    ("anomaly", _capi.CHOICE_RLS_ANOMALY,
     lambda n: igea.RLS(np.zeros(2), 1e6 * np.eye(2), 1, anomaly=n)),
    ("kind", _capi.CHOICE_STABILITY_KIND, lambda n: igea.octave_taus(1000, 10.0, n)),
    ("noise", _capi.CHOICE_STABILITY_NOISE,
     lambda n: igea.allan(_rng.standard_normal(1000), 10.0, noise=n)),
    ("rule", _capi.CHOICE_STATS_VERDICT, lambda n: igea.verdict_thresholds(n, 3, 0.01)),
    ("blocks", _capi.CHOICE_REDUND_RBD,
     lambda n: igea.reliability_diagram([0.9, 0.8, 0.7], [(n, [0, 1, 2], 2)]
                                        if n == "kofn" else [(n, [0, 1, 2])])),
]


@pytest.mark.parametrize("arg,kind,call", PYTHON_KEYWORDS,
                         ids=[f"{a}-{k}" for a, k, _ in PYTHON_KEYWORDS])
def test_python_accepts_exactly_the_library_names(arg, kind, call):
    names = library_names(kind)
    for name in names:
        call(name)
    for bad in ("bogus", names[0].upper(), names[0] + "x", "", 1, "\0" + names[0]):
        with pytest.raises(ValueError, match=arg) as exc:
            call(bad)
        listed = re.search(r"expected one of (.*), got", str(exc.value)).group(1)
        assert [s.strip("'") for s in listed.split(", ")] == names


def test_python_reads_the_library_names():
    """Names the library returns are read through the same table."""
    assert list(igea.rls.FLAGS) == library_names(_capi.CHOICE_RLS_FLAG)
    assert list(igea.rls.ACTIONS.values()) == library_names(_capi.CHOICE_RLS_ACTION)
    r = _eqerr("eig")
    assert r.flag in library_names(_capi.CHOICE_STATS_SIGMAW_FLAG)
