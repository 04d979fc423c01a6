"""docs/calibration.md's dividing-head walk-through runs as written: its
sh and python blocks, in order, in a scratch copy of the repository's
examples/ with the driver on the PATH (the way test_readme.py runs the
README)."""
import os
import re
import shutil
import subprocess
import sys

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
_BLOCK = re.compile(r"^```([^\n`]*)\n(.*?)^```[ \t]*$", re.M | re.S)
DRIVER = os.environ.get("IGEA_DRIVER")


def walkthrough_blocks():
    with open(os.path.join(REPO, "docs", "calibration.md")) as f:
        text = f.read()
    start = text.index("# From a raw tumble file to compensated outputs: a dividing head")
    return [(m.group(1).strip(), m.group(2)) for m in _BLOCK.finditer(text, start)]


@pytest.mark.skipif(not DRIVER or not os.path.exists(DRIVER), reason="IGEA_DRIVER not set")
def test_dividing_head_walkthrough_runs(tmp_path):
    blocks = walkthrough_blocks()
    kinds = [k for k, _ in blocks]
    assert kinds.count("sh") >= 3 and kinds.count("python") >= 2, kinds
    shutil.copytree(os.path.join(REPO, "examples"), tmp_path / "examples")
    env = dict(os.environ)
    env["PATH"] = os.path.dirname(os.path.abspath(DRIVER)) + os.pathsep + env.get("PATH", "")
    env["PYTHONPATH"] = os.path.join(REPO, "python")
    for kind, body in blocks:
        if kind == "sh":
            p = subprocess.run(["bash", "-e", "-c", body], cwd=tmp_path, env=env,
                               capture_output=True, text=True, timeout=120)
        elif kind == "python":
            p = subprocess.run([sys.executable, "-c", body], cwd=tmp_path, env=env,
                               capture_output=True, text=True, timeout=300)
        else:
            continue
        assert p.returncode == 0, (kind, body, p.stdout[-2000:], p.stderr[-2000:])
    assert (tmp_path / "cal.json").exists()
