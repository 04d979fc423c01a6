"""The driver's command line: 'igea help CMD', --opt=value, options given
twice, the generated man page and bash completion; igea.blas_threads."""
import ctypes
import json
import os
import shutil
import subprocess
import sys

import pytest

import igea
from igea import _lib

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
DRIVER = os.environ.get("IGEA_DRIVER", os.path.join(REPO, "build", "bin", "igea"))
FLIGHT = os.path.join(REPO, "examples", "flight")
EQ = ["eqerr", "--S", "S.txt", "--dw", "dw.txt", "--sigma", "sigma.txt", "--spec", "spec.txt"]


def run(*args, cwd=FLIGHT):
    return subprocess.run([DRIVER] + list(args), capture_output=True, text=True, cwd=cwd)


def _commands():
    out = run("--help").stdout.split("Commands:\n")[1].split("\n\n")[0]
    return [ln.split()[0] for ln in out.splitlines()]


def test_help_command_is_command_help():
    names = _commands()
    assert "eqerr" in names and "redund" in names
    for name in names:
        a, b = run("help", name), run(name, "--help")
        assert a.returncode == b.returncode == 0
        assert a.stdout == b.stdout and a.stdout.startswith("usage: igea ")
    r = run("help", "nosuch")
    assert r.returncode == 64 and "nosuch" in r.stderr


def test_equals_form_is_the_same_option():
    a = run(*EQ, "--alpha", "0.05", "--route", "svd", "--json")
    eq = ["--S=S.txt", "--dw=dw.txt", "--sigma=sigma.txt", "--spec=spec.txt"]
    b = run("eqerr", *eq, "--alpha=0.05", "--route=svd", "--json")
    assert a.returncode == b.returncode and a.returncode in (0, 1)
    ja, jb = json.loads(a.stdout), json.loads(b.stdout)
    assert ja == jb and ja["alpha"] == 0.05
    r = run("eqerr", *eq, "--json=yes")
    assert r.returncode == 64 and "--json takes no value" in r.stderr
    r = run("eqerr", *eq, "--alpha=")  # an empty value is not a number
    assert r.returncode == 64 and "--alpha" in r.stderr


def test_option_given_twice_is_refused():
    r = run(*EQ, "--alpha", "0.05", "--alpha=0.01")
    assert r.returncode == 64 and "option --alpha given twice" in r.stderr
    r = run(*EQ, "--json", "--json")
    assert r.returncode == 64 and "--json given twice" in r.stderr


def _docs(tmp_path):
    gen = os.path.join(REPO, "src", "cli", "gen_docs.py")
    subprocess.run([sys.executable, gen, DRIVER, str(tmp_path)], check=True)
    return (tmp_path / "igea.1").read_text(), tmp_path / "igea.bash"


def test_man_page_lists_every_option(tmp_path):
    man, _ = _docs(tmp_path)
    for name in _commands():
        assert ".SS %s\n" % name in man
        help_text = run(name, "--help").stdout
        for line in help_text.splitlines():
            if line.startswith("  --"):
                opt = line.split()[0]
                assert opt.replace("-", "\\-") in man, (name, opt)
    if shutil.which("man"):
        r = subprocess.run(["man", "-l", str(tmp_path / "igea.1")], capture_output=True, text=True,
                           env=dict(os.environ, MANPAGER="cat", PAGER="cat", MANWIDTH="80"))
        assert r.returncode == 0 and "igea - inertial guidance error analysis" in r.stdout


def _complete(script, *words):
    """COMPREPLY of the completion function for the words typed so far."""
    quoted = " ".join("'%s'" % w for w in words)
    code = ("source '%s'; COMP_WORDS=(igea %s); COMP_CWORD=%d; _igea; "
            "printf '%%s\\n' \"${COMPREPLY[@]}\"" % (script, quoted, len(words)))
    r = subprocess.run(["bash", "-c", code], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    return set(r.stdout.split())


@pytest.mark.skipif(shutil.which("bash") is None, reason="bash is not installed")
def test_bash_completion(tmp_path):
    _, script = _docs(tmp_path)
    assert _complete(script, "eq") == {"eqerr"}
    assert _complete(script, "help", "montec") == {"montecarlo"}
    assert _complete(script, "eqerr", "--rou") == {"--route"}
    assert _complete(script, "eqerr", "--rob") == {"--robust", "--robust-alpha"}
    assert _complete(script, "eqerr", "--route", "") == {"eig", "svd"}
    assert _complete(script, "redund", "f") == {"fuse", "fdi"}
    assert "--pfa" in _complete(script, "redund", "fdi", "--")


def _openblas_threads():
    f = _lib.lib.openblas_get_num_threads
    f.restype, f.argtypes = ctypes.c_int, []
    return f()


def test_blas_threads_without_threadpoolctl(monkeypatch):
    monkeypatch.setitem(sys.modules, "threadpoolctl", None)  # import fails: the ctypes path
    before = _openblas_threads()
    with igea.blas_threads(1):
        assert _openblas_threads() == 1
    assert _openblas_threads() == before
    with pytest.raises(RuntimeError):
        with igea.blas_threads(1):
            raise RuntimeError("inside")
    assert _openblas_threads() == before
    for bad in (0, -1, 1.5, True, "2"):
        with pytest.raises(ValueError, match="n: expected an int >= 1"):
            with igea.blas_threads(bad):
                pass
