"""Results: a concise repr, and to_dict()/to_json() giving the driver's
--json document of the same command on the same inputs.

Where the driver's document holds keys the Python result does not (the
driver's inputs echoed, or several library calls in one document), the
gap is listed here per command, so that closing or widening it is seen."""
import dataclasses
import json
import math
import re
import os
import subprocess
import sys

import numpy as np
import pytest

import igea

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
DRIVER = os.environ.get("IGEA_DRIVER")
needs_driver = pytest.mark.skipif(not DRIVER or not os.path.exists(DRIVER),
                                  reason="IGEA_DRIVER not built")
TABLE = os.path.join(os.path.dirname(os.path.dirname(HERE)), "examples", "seed000_table1.txt")


def driver(*args, cwd=None):
    r = subprocess.run([DRIVER, *map(str, args)], capture_output=True, text=True, cwd=cwd)
    assert r.returncode in (0, 1), r.stderr
    return json.loads(r.stdout)


def same(a, b, rtol, path="$"):
    """a == b as JSON values, numbers within rtol (relative to the larger)."""
    if isinstance(a, dict):
        assert isinstance(b, dict) and set(a) == set(b), (path, sorted(set(a) ^ set(b)))
        for k in a:
            same(a[k], b[k], rtol, "%s.%s" % (path, k))
    elif isinstance(a, list):
        assert isinstance(b, list) and len(a) == len(b), (path, a, b)
        for i, (x, y) in enumerate(zip(a, b)):
            same(x, y, rtol, "%s[%d]" % (path, i))
    elif isinstance(a, bool) or isinstance(b, bool) or a is None or isinstance(a, str):
        assert a == b and type(a) is type(b), (path, a, b)
    else:
        assert isinstance(a, (int, float)) and isinstance(b, (int, float)), (path, a, b)
        assert math.isclose(a, b, rel_tol=rtol, abs_tol=1e-300), (path, a, b)


def check(py, js, rtol, driver_only=(), py_only=(), differ=()):
    """py (a to_dict()) against js (the driver's document): the keys apart
    from the listed gaps are the same and hold the same values; `differ`
    are keys of both whose values are not the same thing."""
    assert json.loads(json.dumps(py, allow_nan=False)) == py   # plain JSON types
    assert set(js) - set(py) == set(driver_only), sorted(set(js) - set(py))
    assert set(py) - set(js) == set(py_only), sorted(set(py) - set(js))
    for k in set(py) & set(js) - set(differ):
        same(py[k], js[k], rtol, k)


@pytest.fixture(scope="module")
def flight_files(tmp_path_factory):
    d = tmp_path_factory.mktemp("flight")
    fl = igea.simulate(seed=3)
    for name, a in [("S", fl.S), ("dw", fl.dw), ("sigma", fl.sigma), ("spec", fl.spec)]:
        np.savetxt(d / ("%s.txt" % name), a, fmt="%.17g")
    return fl, d


@needs_driver
@pytest.mark.parametrize("route", ["svd", "eig"])
def test_eqerr_to_dict_is_the_driver_document(flight_files, route):
    fl, d = flight_files
    r = igea.eqerr(fl.S, fl.dw, fl.sigma, fl.spec, route=route)
    js = driver("eqerr", "--S", "S.txt", "--dw", "dw.txt", "--sigma", "sigma.txt", "--spec",
                "spec.txt", "--route", route, "--json", cwd=d)
    if route == "svd":   # the same in-memory QR: every key, every value
        check(r.to_dict(), js, 1e-9)
    else:                # the driver streams rows: its normal matrix sums in another order,
        check(r.to_dict(), js, 1e-6, differ={"eigenvalues", "eigenvectors", "equiv_err"})
    assert json.loads(r.to_json()) == r.to_dict()
    assert r.to_dict()["route"] == route and r.to_dict()["rows"] == fl.S.shape[0]


@needs_driver
def test_test_to_dict_is_the_driver_document():
    t = np.loadtxt(TABLE)
    r = igea.accuracy_test(t[:, 1], t[:, 2])
    check(r.to_dict(), driver("test", "--table", TABLE, "--json"), 1e-12)


@needs_driver
def test_regress_shared_keys(flight_files):
    fl, d = flight_files
    r = igea.ls(fl.S, fl.dw, sigma=fl.sigma)
    js = driver("regress", "--method", "ls", "--S", "S.txt", "--dw", "dw.txt", "--sigma",
                "sigma.txt", "--json", cwd=d)
    # the driver adds its collinearity diagnostics (igea.collinearity) and
    # echoes method, rows, n_terms; Python keeps cov and residual, and names
    check(r.to_dict(), js, 1e-9,
          driver_only={"cond", "cond_estimable", "eigenvalues", "method", "n_terms",
                       "prior_determined", "rows", "sd_comb", "vif"},
          py_only={"cov", "names", "residual"})


@needs_driver
def test_stability_shared_keys(flight_files):
    fl, d = flight_files
    js = driver("stability", "--data", "dw.txt", "--fs", "1", "--json", cwd=d)
    # the driver's document is allan + block_3sigma (block) + noise_terms
    # (noise, fit) with its inputs echoed
    check(igea.allan(fl.dw, 1.0).to_dict(), js, 1e-12,
          driver_only={"alpha", "block", "data_type", "fit", "fs", "noise", "samples"})
    b = igea.block_3sigma(fl.dw, 1.0, js["block"]["seconds"]).to_dict()
    check(b, js["block"], 1e-12, driver_only=set(), py_only=set(b) - set(js["block"]))


@needs_driver
@pytest.mark.parametrize("pool", [None, 4])
def test_montecarlo_shared_keys(flight_files, pool):
    fl, d = flight_files
    r = igea.montecarlo(fl.S, fl.sigma, 20, spec=fl.spec, seed=8, pool=pool)
    js = driver("montecarlo", "--S", "S.txt", "--sigma", "sigma.txt", "--spec", "spec.txt",
                "--flights", "20", "--seed", "8", "--json", *(["--pool", pool] if pool else []),
                cwd=d)
    # Python keeps the per-flight chi2, dof, n_reject, scale and zmax (and
    # pool=None without pooling). The driver's
    # flights take the streamed normal-matrix route: c from the small
    # eigenvalues agrees to ~1e-6 (as in test_eqerr's driver test).
    check(r.to_dict(), js, 1e-6,
          py_only={"chi2", "dof", "n_reject", "scale", "zmax"} |
          ({"pool"} if pool is None else set()))
    assert js["failed"]["count"] == r.failed and js["failed"]["rate"] == r.failed / 20


@needs_driver
def test_impact_shared_keys():
    from test_impact import burnout
    s = burnout()
    js = driver("impact", "--burnout", ",".join(repr(float(v)) for v in s), "--model", "j2",
                "--json")
    check(igea.impact(s, model="j2").to_dict(), js, 1e-12)


@needs_driver
def test_accel_shared_keys(tmp_path):
    from test_accel import BETA, _write_experiment
    f = tmp_path / "cal.txt"
    ang, ya, yb = _write_experiment(f, np.append(BETA, 2e-4), volts=2.5)
    th, ma, mb, _ = igea.accel_merge(ang, ya, yb)
    js = driver("accel", "--json", "--scale-a", "2.5", "--scale-b", "2.5", "--data", f)
    # the driver echoes the merged data (readings, readings_per_position, theta_deg);
    # it fits the file as written to 15 digits: the small combinations move ~1e-7
    check(igea.accel_fit(th, ma, mb).to_dict(), js, 1e-6,
          driver_only={"readings", "readings_per_position", "theta_deg"})


@needs_driver
def test_rls_shared_keys(tmp_path):
    rng = np.random.default_rng(2)
    C, Y = rng.normal(size=(40, 3, 4)), rng.normal(size=(40, 3))
    np.save(tmp_path / "C.npy", C.reshape(120, 4))
    np.savetxt(tmp_path / "Y.txt", Y.reshape(-1), fmt="%.17g")
    r = igea.rls_run(C, Y, None, 10 * np.eye(4), sigma=1.0)
    js = driver("rls", "--S", "C.npy", "--dw", "Y.txt", "--sigma", "1", "--gamma0", "10",
                "--json", cwd=tmp_path)
    # the driver reports the last state and a thinned epoch list; Python the
    # whole history (x per epoch), its action codes, flags and residuals
    check(r.to_dict(), js, 1e-12,
          driver_only={"anomalous", "anomaly", "epochs", "forget", "k", "kappa", "m",
                       "n_epochs", "rows", "updates"},
          py_only={"actions", "counts", "flags", "residual"}, differ={"x"})
    same(r.to_dict()["x"][-1], js["x"], 1e-12)


def test_repr_is_concise():
    fl = igea.simulate(seed=3)
    r = igea.eqerr(fl.S, fl.dw, fl.sigma, fl.spec)
    text = repr(r)
    assert len(text) < 700 and "\n" not in text, len(text)
    assert text.startswith("EqerrResult(") and "rank=%d" % r.rank in text
    assert "eigenvectors=<float64 (%d, %d)>" % r.eigenvectors.shape in text
    assert "residual=<float64 (%d,)>" % len(r.residual) in text
    assert "passed=%r" % r.passed in text and "flag=%r" % r.flag in text
    assert "components=[%d dict]" % len(r.components) in text
    mc = igea.montecarlo(fl.S, fl.sigma, 4, spec=fl.spec, seed=1, pool=2)
    assert "pool=<MonteCarloPool>" in repr(mc) and len(repr(mc)) < 700


def test_to_dict_converts_numpy_and_nan():
    from igea._result import to_json_value
    v = to_json_value({"a": np.array([1.0, np.nan, np.inf]), "b": np.float32(0.5),
                       "c": np.int64(3), "d": np.bool_(True), "e": (1, 2), "f": float("nan")})
    assert v == {"a": [1.0, None, None], "b": 0.5, "c": 3, "d": True, "e": [1, 2], "f": None}
    assert type(v["c"]) is int and type(v["d"]) is bool


def test_every_result_class_has_the_methods():
    classes = [c for c in vars(igea).values()
               if isinstance(c, type) and dataclasses.is_dataclass(c)]
    classes += [igea.sim.MonteCarloResult, igea.sim.MonteCarloPool, igea.sim.Flight]
    assert len(classes) > 20
    for c in classes:
        if c.__name__ == "MatrixFile":
            continue
        assert "to_dict" in vars(c) and "to_json" in vars(c), c
        assert vars(c)["__repr__"].__module__ == "igea._result", c


def _result_classes():
    import importlib
    import pkgutil
    out = []
    for mod in pkgutil.iter_modules(igea.__path__):
        m = importlib.import_module("igea." + mod.name)
        out += [c for c in vars(m).values() if isinstance(c, type)
                and dataclasses.is_dataclass(c) and c.__module__ == m.__name__
                and c.__name__ != "MatrixFile"]
    return out


def test_every_result_class_and_field_is_documented():
    classes = _result_classes()
    assert len(classes) >= 33, [c.__name__ for c in classes]
    for c in classes:
        doc = c.__doc__ or ""
        head = doc.split("\n\nFields")[0]
        assert head.strip() and not head.startswith(c.__name__ + "("), c   # its own words
        described = dict(re.findall(r"(?m)^    (\w+): (\S.*)$", doc.split("\n\nFields")[-1]))
        for f in dataclasses.fields(c):
            assert len(described.get(f.name, "")) > 3, (c.__name__, f.name)
        if "summary" in vars(c):
            assert vars(c)["summary"].__doc__, (c.__name__, "summary")
    assert "eigenvalues: eigenvalues lambda" in igea.EqerrResult.__doc__
    assert "size: flights per group" in igea.sim.MonteCarloPool.__doc__
