"""The driver follows docs/vocabulary.md: every option its --help lists is in
the vocabulary, the old spellings are refused, inputs are options, JSON keys
are the table's, indices count from 0, and --help lists what the one option
table parses."""
import json
import os
import re
import shutil
import subprocess

import numpy as np
import pytest

DRIVER = os.environ["IGEA_DRIVER"]
REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
FLIGHT = os.path.join(REPO, "examples", "flight")
VOCAB = open(os.path.join(REPO, "docs", "vocabulary.md")).read()
COMMANDS = ["eqerr", "test", "regress", "rls", "redund", "stability", "accel", "envfun",
            "simulate", "montecarlo"]


def run(cwd, *args, input=None):
    return subprocess.run([DRIVER, *args], cwd=cwd, capture_output=True, text=True,
                          input=input, timeout=120)


def help_options(cmd):
    h = run(REPO, cmd, "--help")
    assert h.returncode == 0, h.stderr
    # the generated option list: lines "  --name [ARG]  help"
    return set(re.findall(r"^  (--[A-Za-z0-9-]+)", h.stdout, re.M))


@pytest.mark.parametrize("cmd", COMMANDS)
def test_help_options_are_in_the_vocabulary(cmd):
    opts = help_options(cmd)
    assert "--json" in opts or cmd == "simulate" or cmd == "montecarlo" or opts
    missing = sorted(o for o in opts if "`" + o not in VOCAB)
    assert not missing, (cmd, missing)


@pytest.mark.parametrize("cmd", COMMANDS)
def test_every_listed_option_is_parsed(cmd, tmp_path):
    # an option the help lists is never "unknown" (one table for both)
    for o in sorted(help_options(cmd)):
        args = [cmd] + (["fdi"] if cmd == "redund" else []) + [o, "1"]
        r = run(tmp_path, *args)
        assert "unknown option" not in r.stderr, (cmd, o, r.stderr)


@pytest.mark.parametrize("args", [
    ["montecarlo", "--no-correct"], ["montecarlo", "--first", "3"],
    ["montecarlo", "--sigma-file", "s.txt"], ["montecarlo", "--spec-file", "s.txt"],
    ["montecarlo", "--outliers", "0.1"], ["simulate", "--outliers", "0.1"],
    ["rls", "--data", "r.txt", "-p", "2"], ["redund", "fuse", "--record", "r.txt"],
    ["stability", "y.txt", "--fs", "1"], ["accel", "a.txt"], ["envfun", "t.txt", "--terms", "all"],
    ["test", "r1.json", "r2.json"]])
def test_old_spellings_and_positionals_refused(args, tmp_path):
    r = run(tmp_path, *args)
    assert r.returncode == 64, (args, r.returncode, r.stderr)
    assert "unknown option" in r.stderr or "inputs are options" in r.stderr, r.stderr


@pytest.fixture
def flight(tmp_path):
    for f in ("S.txt", "dw.txt", "sigma.txt", "spec.txt"):
        shutil.copy(os.path.join(FLIGHT, f), tmp_path)
    return tmp_path


def test_json_keys_and_bases(flight):
    S = np.loadtxt(flight / "S.txt")
    args = ["--S", "S.txt", "--dw", "dw.txt", "--sigma", "sigma.txt", "--spec", "spec.txt"]
    e = json.loads(run(flight, "eqerr", *args, "--json").stdout)
    assert e["n_terms"] == S.shape[1] and "terms" not in e and e["rows"] == S.shape[0]
    g = json.loads(run(flight, "regress", "--method", "ebr", *args, "--json").stdout)
    assert "lam" in g and "lambda" not in g and g["n_terms"] == S.shape[1]
    m = json.loads(run(flight, "montecarlo", "--flights", "3", "--first-flight", "2",
                       "--duration", "20", "--rate", "10", "--no-correction", "--json").stdout)
    assert m["first_flight"] == 2 and m["correction"] is False and "mean_scale" in m
    assert not {"first", "correct_tracking", "mean_c"} & set(m)
    # the text table numbers components from 0, as the JSON arrays index them
    t = run(flight, "eqerr", *args).stdout
    rows = [ln.split() for ln in t.splitlines() if re.match(r"^\s+\d+\s+\d\.\d+e[+-]\d+", ln)]
    assert rows and rows[0][0] == "0"


def test_rls_epochs_from_zero(tmp_path):
    rec = np.array([[1.0, 1.0], [2.0, 1.0], [3.0, 1.0]])
    np.savetxt(tmp_path / "r.txt", rec)
    d = json.loads(run(tmp_path, "rls", "--data", "r.txt", "--k", "1", "--json").stdout)
    assert [e["epoch"] for e in d["epochs"]] == [0, 1, 2]
    lines = [ln for ln in run(tmp_path, "rls", "--data", "r.txt", "--k", "1").stdout.splitlines()
             if not ln.startswith("#")]
    assert [ln.split()[0] for ln in lines] == ["0", "1", "2"]


def test_stability_column_from_zero(tmp_path):
    rng = np.random.default_rng(3)
    y = rng.standard_normal(400)
    np.savetxt(tmp_path / "two.txt", np.column_stack([y, 5 * y]))
    a = json.loads(run(tmp_path, "stability", "--data", "two.txt", "--fs", "1", "--column", "0",
                       "--json").stdout)
    d = np.diff(y)  # overlapping ADEV at one sample, computed here
    assert a["dev"][0] == pytest.approx(np.sqrt(0.5 * np.mean(d * d)), rel=1e-12)
    assert run(tmp_path, "stability", "--data", "two.txt", "--fs", "1", "--column",
               "2").returncode == 64


def test_json_strings_escaped(flight):
    sim = run(flight, "simulate", "--duration", "20", "--rate", "10", "--save-traj", "--dir", ".")
    assert sim.returncode == 0, sim.stderr
    out = 'S "q" \\ b.txt'
    r = run(flight, "envfun", "--traj", "traj.txt", "--terms", "acc_bias_x", "--out", out,
            "--json")
    assert r.returncode == 0, r.stderr
    d = json.loads(r.stdout)
    assert d["out"] == out and d["terms"] == ["acc_bias_x"]
    assert (flight / out).exists()


def test_help_shows_library_defaults():
    h = run(REPO, "eqerr", "--help").stdout
    # igea_eqerr_defaults: alpha 0.01, lambda_test 10, lambda_small 0.1, n_min 5
    for opt, val in [("--alpha", "0.01"), ("--lambda-test", "10"), ("--lambda-small", "0.1"),
                     ("--n-min", "5")]:
        line = next(ln for ln in h.splitlines() if ln.startswith("  " + opt + " "))
        assert "(default %s)" % val in line, line


def test_library_checks_and_names_options(flight):
    args = ["--S", "S.txt", "--dw", "dw.txt", "--sigma", "0.01", "--alpha", "1.5"]
    r = run(flight, "eqerr", *args)
    assert r.returncode == 64 and "--alpha" in r.stderr, r.stderr
    r = run(flight, "simulate", "--duration", "20", "--rate", "10", "--ar1", "1", "--dir", ".")
    assert r.returncode == 64 and "--ar1" in r.stderr, r.stderr
