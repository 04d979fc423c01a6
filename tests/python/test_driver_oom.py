"""Out of memory in the driver: the n-th allocation after main() fails
(LD_PRELOAD shim failmalloc.c), for every n until a run completes. Each run
either gives the same result as without the fault, or exit 70 with one line
"... out of memory ..." on stderr; never a signal, never another exit code
(an allocation failure is not a missing file, a write error or bad data,
and a text file cut short by it is not a shorter file), never a partial or
replaced output file, never a temporary file left behind."""
import os
import shutil
import subprocess

import numpy as np
import pytest

DRIVER = os.environ["IGEA_DRIVER"]
HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
FLIGHT = os.path.join(REPO, "examples", "flight")
MAX_CALLS = 4000


@pytest.fixture(scope="module")
def shim(tmp_path_factory):
    cc = shutil.which("cc") or shutil.which("gcc")
    if not cc:
        pytest.skip("no C compiler")
    d = tmp_path_factory.mktemp("failmalloc")
    so = d / "failmalloc.so"
    subprocess.run([cc, "-shared", "-fPIC", "-o", str(so), os.path.join(HERE, "failmalloc.c"),
                    "-ldl"], check=True)
    return so


@pytest.fixture(scope="module")
def work(tmp_path_factory):
    d = tmp_path_factory.mktemp("oomwork")
    for f in os.listdir(FLIGHT):
        shutil.copy(os.path.join(FLIGHT, f), d / f)
    (d / "sim").mkdir()
    r = subprocess.run([DRIVER, "simulate", "--seed", "3", "--duration", "20", "--save-traj",
                        "--dir", "sim"], cwd=d, capture_output=True)
    assert r.returncode == 0, r.stderr
    shutil.copy(d / "sim" / "traj.txt", d / "traj.txt")
    for f in ("accel_dual.txt", "seed000_table1.txt"):
        shutil.copy(os.path.join(REPO, "examples", f), d / f)
    r = subprocess.run([DRIVER, "eqerr", "--S", "S.txt", "--dw", "dw.txt", "--sigma",
                        "sigma.txt", "--spec", "spec.txt", "--json", "--out", "f1.json"],
                       cwd=d, capture_output=True)
    assert r.returncode == 0, r.stderr
    np.savetxt(d / "y.txt", np.random.default_rng(1).standard_normal(3000))
    return d


def listing(d):
    return sorted(os.listdir(d))


CASES = {
    "eqerr": (["eqerr", "--S", "S.txt", "--dw", "dw.txt", "--sigma", "sigma.txt", "--spec",
               "spec.txt", "--out", "OUT"], None),
    "eqerr_json_svd": (["eqerr", "--S", "S.txt", "--dw", "dw.txt", "--sigma", "sigma.txt",
                        "--spec", "spec.txt", "--route", "svd", "--json", "--out", "OUT"], None),
    "eqerr_stdin": (["eqerr", "--S", "-", "--dw", "dw.txt", "--sigma", "0.01", "--spec",
                     "spec.txt", "--out", "OUT"], "S.txt"),
    "eqerr_pipe_svd": (["eqerr", "--S", "-", "--dw", "dw.txt", "--sigma", "sigma.txt",
                        "--route", "svd", "--out", "OUT"], "pipe:S.txt"),
    "envfun": (["envfun", "--traj", "traj.txt", "--terms", "default", "--out", "OUT"], None),
    "stability": (["stability", "--data", "y.txt", "--fs", "10", "--block", "10", "--out", "OUT"], None),
    "regress": (["regress", "--method", "ls", "--S", "S.txt", "--dw", "dw.txt", "--sigma",
                 "sigma.txt", "--out", "OUT"], None),
    "simulate": (["simulate", "--seed", "4", "--duration", "20", "--dir", "simout"], None),
    "regress_ridge": (["regress", "--method", "ridge", "--S", "S.txt", "--dw", "dw.txt",
                       "--sigma", "sigma.txt", "--out", "OUT"], None),
    "rls": (["rls", "--S", "S.txt", "--dw", "dw.txt", "--sigma", "sigma.txt", "--out", "OUT"],
            None),
    "accel": (["accel", "--data", "accel_dual.txt", "--out", "OUT"], None),
    "montecarlo": (["montecarlo", "--flights", "4", "--duration", "20", "--threads", "1",
                    "--out", "OUT"], None),
    "test_table": (["test", "--table", "seed000_table1.txt", "--out", "OUT"], None),
    "test_pool": (["test", "--results", "f1.json,f1.json", "--out", "OUT"], None),
}


def run(cwd, args, stdin_file, env):
    if stdin_file and stdin_file.startswith("pipe:"):
        return subprocess.run([DRIVER, *args], cwd=cwd, input=(cwd / stdin_file[5:]).read_bytes(),
                              capture_output=True, env=env, timeout=120)
    stdin = open(cwd / stdin_file, "rb") if stdin_file else subprocess.DEVNULL
    try:
        return subprocess.run([DRIVER, *args], cwd=cwd, stdin=stdin, capture_output=True,
                              env=env, timeout=120)
    finally:
        if stdin_file:
            stdin.close()


@pytest.mark.parametrize("case", sorted(CASES))
def test_every_allocation_failure(shim, work, tmp_path, case):
    args, stdin_file = CASES[case]
    d = tmp_path
    for f in os.listdir(work):
        if os.path.isfile(work / f):
            shutil.copy(work / f, d / f)
    (d / "simout").mkdir()
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1")
    args = [a.replace("OUT", "out.txt") for a in args]

    def outputs():
        if case == "simulate":
            return {f: (d / "simout" / f).read_bytes() for f in listing(d / "simout")}
        return {"out.txt": (d / "out.txt").read_bytes()}

    ref = run(d, args, stdin_file, env)
    assert ref.returncode in (0, 1), ref.stderr
    want = outputs()
    # the old outputs that a failed run must leave alone
    for f in want:
        (d / ("simout" if case == "simulate" else ".") / f).write_bytes(b"old\n")
    old = outputs()
    log = d / "fired.log"
    for n in range(1, MAX_CALLS):
        if log.exists():
            log.unlink()
        e = dict(env, LD_PRELOAD=str(shim), IGEA_FAILMALLOC=str(n),
                 IGEA_FAILMALLOC_LOG=str(log))
        r = run(d, args, stdin_file, e)
        fired = log.exists()
        assert r.returncode >= 0, (n, "signal", r.returncode, r.stderr)
        if r.returncode == 70:
            assert fired, (n, r.stderr)
            lines = r.stderr.decode().splitlines()
            assert len(lines) == 1 and "out of memory" in lines[0], (n, r.stderr)
            assert outputs() == old, n
        else:
            assert r.returncode == ref.returncode, (n, r.returncode, r.stderr)
            assert outputs() == want, n
            for f in want:
                (d / ("simout" if case == "simulate" else ".") / f).write_bytes(b"old\n")
        assert not [f for f in listing(d) + listing(d / "simout") if ".tmp." in f], n
        if not fired:
            break
    else:
        pytest.fail("more than %d allocations" % MAX_CALLS)
    assert n > 3
