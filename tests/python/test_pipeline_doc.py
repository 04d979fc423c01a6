"""docs/pipeline.md's tutorial (section 6) runs as written.

Every fenced block of the page says what it is: sh (commands, run in
order, each block in a fresh bash, all in one scratch working directory;
each command must exit 0, or 1 when it is an igea verdict), console ("$
command" lines run the same way; the lines under a command must appear in
its output, "..." standing for lines left out), python (run in the same
directory with the package and library under test), text (not run). The
block reading and running follow tests/python/test_readme.py's."""
import os
import re
import subprocess
import sys

import pytest
from docblocks import commands, console, run_script

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
PAGE = os.path.join(REPO, "docs", "pipeline.md")
KINDS = {"sh", "console", "python", "text"}
_BLOCK = re.compile(r"^[ \t]*```([^\n`]*)\n(.*?)^[ \t]*```[ \t]*$", re.M | re.S)


def blocks():
    text = open(PAGE).read()
    return [(m.group(1).strip(), m.group(2), text.count("\n", 0, m.start()) + 1)
            for m in _BLOCK.finditer(text)]


def test_every_block_says_what_it_is():
    bad = [(line, kind) for kind, _, line in blocks() if kind not in KINDS]
    assert not bad, "docs/pipeline.md blocks (line, info string) not in %s" % sorted(KINDS)


def test_tutorial_runs(tmp_path):
    driver = os.environ["IGEA_DRIVER"]
    env = dict(os.environ, PATH="%s:%s" % (os.path.dirname(driver), os.environ.get("PATH", "")),
               PYTHONPATH=os.path.join(REPO, "python"))
    cwd, ran = str(tmp_path), 0
    for kind, body, line in blocks():
        where = "docs/pipeline.md:%d (%s)" % (line, kind)
        if kind == "sh":
            run_script(commands(body), cwd, env, where, subshell=True)
        elif kind == "console":
            steps = console(body)
            results = run_script([c for c, _ in steps], cwd, env, where, subshell=True)
            for (cmd, expected), (_, output) in zip(steps, results):
                have = {ln.rstrip() for ln in output.splitlines()}
                missing = [e for e in expected if e not in have]
                assert not missing, "%s: '%s' did not print %s; it printed:\n%s" % (
                    where, cmd, missing, output)
        elif kind == "python":
            r = subprocess.run([sys.executable, "-c", body], cwd=cwd, env=env,
                               capture_output=True, text=True, timeout=300)
            assert r.returncode == 0, "%s:\n%s%s" % (where, r.stdout, r.stderr)
        else:
            continue
        ran += 1
    assert ran >= 8
