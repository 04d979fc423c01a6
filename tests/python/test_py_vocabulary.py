"""The Python keywords and result fields follow docs/vocabulary.md: a
keyword is the driver's option with hyphens as underscores, a result field
is the JSON key of the same command."""
import dataclasses
import inspect
import os
import re

import pytest

import igea

HERE = os.path.dirname(os.path.abspath(__file__))
DOC = os.path.join(os.path.dirname(os.path.dirname(HERE)), "docs", "vocabulary.md")


def _section(cmd):
    with open(DOC) as fh:
        text = fh.read()
    m = re.search(r"(?ms)^### %s\n(.*?)(?=^### |\Z)" % re.escape(cmd), text)
    assert m, "docs/vocabulary.md has no section for %s" % cmd
    return m.group(1)


def options(cmd):
    """The option names of a command, as Python spells them."""
    names = set(re.findall(r"--([A-Za-z][A-Za-z0-9-]*)", _section(cmd)))
    out = {n.replace("-", "_") for n in names}
    return out | {n[3:] for n in out if n.startswith("no_")}  # --no-x sets x


def json_keys(cmd):
    """The words of the first `...` after 'JSON:' in the command's section."""
    m = re.search(r"JSON(?: \([a-z]+\))?:\s*`([^`]*)`", _section(cmd))
    return set(re.findall(r"[a-z_][a-z0-9_]*", m.group(1)))


def keywords(fn):
    return set(inspect.signature(fn).parameters)


def fields(cls):
    return {f.name for f in dataclasses.fields(cls)}


@pytest.mark.parametrize("fn, cmds, python_only", [
    (igea.eqerr, ["eqerr"], {"rank_tol"}),
    (igea.simulate, ["simulate"], set()),
    (igea.montecarlo, ["montecarlo", "simulate", "eqerr"], {"client", "chunk"}),
    (igea.accuracy_test, ["test"], {"equiv_err", "eigenvalues"}),
])
def test_keywords_are_option_names(fn, cmds, python_only):
    known = set().union(*(options(c) for c in cmds))
    assert keywords(fn) - python_only <= known, keywords(fn) - python_only - known


def test_renamed_keywords_are_gone():
    old = {"nflights", "nthreads", "correct_tracking", "outliers", "first", "prior_scale"}
    for fn in (igea.eqerr, igea.simulate, igea.montecarlo, igea.ebr):
        assert not keywords(fn) & old, (fn.__name__, keywords(fn) & old)


def test_result_fields_are_json_keys():
    assert fields(igea.EqerrResult) <= json_keys("eqerr")
    assert fields(igea.TestResult) <= json_keys("test")
    assert json_keys("redund").isdisjoint({"sensor_1", "isolated_1"})
    fdi_keys = {"statistic", "threshold", "dof", "p_value", "detected", "isolated", "isolable",
                "parity"}
    assert fdi_keys <= fields(igea.FdiResult)
    for key in ("lam", "sd_frequentist", "shrink", "sigma2", "x"):
        assert key in fields(igea.EbrResult) or hasattr(igea.EbrResult, key), key
    assert hasattr(igea.EbrResult, "sd") and "lam" in json_keys("regress")
    mc = fields(igea.sim.MonteCarloResult)
    assert {"flights", "mean_scale", "mean_tested", "comp_tested", "comp_reject"} <= mc
    assert {"flights", "mean_scale"} <= json_keys("montecarlo")
    assert "n_epochs" in json_keys("rls")
    assert fields(igea.AccelFit) <= json_keys("accel")


# Keywords that were spelled apart from the driver: the driver's spelling is
# the keyword, the old one only a deprecated alias (default: the sentinel).
RENAMED = [
    (igea.rls_run, "rls", {"sigma": "track_sigma", "jump": "jump_max"}),
    (igea.RLS, "rls", {"jump": "jump_max"}),
    (igea.accel_fit, "accel", {"prior": "prior_scale"}),
    (igea.series_check, "redund", {"one_shot": "iterative", "average": "weighted"}),
    (igea.fusion_set, "redund", {"one_shot": "iterative"}),
    (igea.fuse, "redund", {"average": "weighted"}),
]


@pytest.mark.parametrize("fn, cmd, pairs", RENAMED)
def test_driver_spelling_with_deprecated_aliases(fn, cmd, pairs):
    from igea._compat import _UNSET
    params = inspect.signature(fn).parameters
    for new, old in pairs.items():
        assert new in options(cmd), (cmd, new)
        assert new in params and params[old].default is _UNSET, (fn.__name__, new, old)
