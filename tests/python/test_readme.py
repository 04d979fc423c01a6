"""README.md runs as written.

Every fenced block of the README says what it is:
  sh       commands, run in order (from the repository root, each block in a
           fresh bash); a command must exit 0, or 1 when it is an igea
           verdict ("rejected");
  console  "$ command" lines run the same way, in one bash per block; the
           lines below a command are its output: each must appear in what
           it printed ("..." stands for lines left out);
  python   run with this interpreter, from the root, PYTHONPATH=python
           (the README says that finds the library in build/lib);
  c, fortran, text
           fragments and commands the README does not mean to be run here
           (make check would run this test again; asan and bench are long).

The blocks run in a scratch copy of the repository: the working tree's
files and its build/ (modification times kept, so that 'make' finds it up
to date), with build/bin on PATH and HOME a scratch directory (so that
'make install PREFIX=$HOME/.local' stays inside). About 20 s.
"""
import os
import re
import shutil
import subprocess
import sys

import pytest
from docblocks import commands, console, run_script

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
KINDS = {"sh", "console", "python", "c", "fortran", "text"}
_BLOCK = re.compile(r"^```([^\n`]*)\n(.*?)^```[ \t]*$", re.M | re.S)


def blocks():
    with open(os.path.join(REPO, "README.md")) as f:
        text = f.read()
    return [(m.group(1).strip(), m.group(2), text.count("\n", 0, m.start()) + 1)
            for m in _BLOCK.finditer(text)]


def test_every_block_says_what_it_is():
    found = blocks()
    assert found, "no fenced block in README.md"
    bad = [(line, kind) for kind, _, line in found if kind not in KINDS]
    assert not bad, "README.md blocks (line, info string) not in %s" % sorted(KINDS)


@pytest.fixture(scope="module")
def scratch(tmp_path_factory):
    root = tmp_path_factory.mktemp("readme")
    repo = root / "repo"
    skip = shutil.ignore_patterns(".git", "build", ".venv", "__pycache__", "*.egg-info",
                                  ".pytest_cache")
    shutil.copytree(REPO, repo, ignore=skip, symlinks=True)
    build = os.path.join(REPO, "build")
    if not os.path.isfile(os.path.join(build, "bin", "igea")):
        pytest.skip("build/bin/igea missing: run make first")
    for sub in ("obj", "lib", "bin", "fortran", "share"):
        if os.path.isdir(os.path.join(build, sub)):
            shutil.copytree(os.path.join(build, sub), repo / "build" / sub, symlinks=True)
    home = root / "home"
    home.mkdir()
    env = {k: v for k, v in os.environ.items()
           if k not in ("MAKEFLAGS", "MAKELEVEL", "MFLAGS", "IGEA_LIBRARY", "IGEA_DRIVER",
                        "PYTHONPATH", "PKG_CONFIG_PATH", "LD_LIBRARY_PATH")}
    env.update(HOME=str(home), PATH="%s:%s" % (repo / "build" / "bin", env.get("PATH", "")))
    return repo, env


def test_readme_blocks_run(scratch):
    repo, env = scratch
    ran = 0
    for kind, body, line in blocks():
        where = "README.md:%d (%s)" % (line, kind)
        if kind == "sh":
            run_script(commands(body), repo, env, where)
        elif kind == "console":
            steps = console(body)
            results = run_script([c for c, _ in steps], repo, env, where)
            for (cmd, expected), (_, output) in zip(steps, results):
                have = {ln.rstrip() for ln in output.splitlines()}
                missing = [e for e in expected if e not in have]
                assert not missing, "%s: '%s' did not print %s; it printed:\n%s" % (
                    where, cmd, missing, output)
        elif kind == "python":
            penv = dict(env, PYTHONPATH="python")
            r = subprocess.run([sys.executable, "-c", body], cwd=str(repo), env=penv,
                               capture_output=True, text=True, timeout=300)
            assert r.returncode == 0, "%s:\n%s%s" % (where, r.stdout, r.stderr)
        else:
            continue
        ran += 1
    assert ran >= 5
