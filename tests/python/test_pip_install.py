"""'pip install ./python' into a fresh virtual environment gives a package
that imports and runs from any directory, with the libigea.so.1 the
package build compiled from the repository beside it.

Offline: the build backend (python/igea_build.py) needs nothing from an
index and the install uses --no-index; numpy comes from this interpreter's
environment through a .pth file in the new one. About 20 s (the library is
compiled once, in a scratch directory).
"""
import json
import os
import subprocess
import sys

import numpy
import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
FLIGHT = os.path.join(REPO, "examples", "flight")

RUN = """
import json, sys, numpy as np, igea, igea._lib as L
d = sys.argv[1]
r = igea.eqerr(np.loadtxt(d + '/S.txt'), np.loadtxt(d + '/dw.txt'), np.loadtxt(d + '/sigma.txt'),
               np.loadtxt(d + '/spec.txt'))
print(r.passed)
print(json.dumps({'passed': r.passed, 'chi2': r.chi2, 'scale': r.scale, 'lib': L.lib._name,
                  'module': igea.__file__, 'version': igea.__version__}))
"""


def _clean_env():
    env = dict(os.environ)
    for k in ("PYTHONPATH", "IGEA_LIBRARY", "PIP_INDEX_URL", "PIP_FIND_LINKS", "MAKEFLAGS",
              "MAKELEVEL", "MFLAGS"):
        env.pop(k, None)
    env["PIP_DISABLE_PIP_VERSION_CHECK"] = "1"
    return env


@pytest.fixture(scope="module")
def venv(tmp_path_factory):
    d = tmp_path_factory.mktemp("pipvenv")
    v = d / "venv"
    r = subprocess.run([sys.executable, "-m", "venv", str(v)], capture_output=True, text=True)
    if r.returncode != 0:
        pytest.skip("python -m venv unavailable: " + r.stderr[-300:])
    py = v / "bin" / "python"
    site = subprocess.run([str(py), "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
                          check=True, capture_output=True, text=True).stdout.strip()
    with open(os.path.join(site, "numpy_from_test.pth"), "w") as f:
        f.write(os.path.dirname(os.path.dirname(numpy.__file__)) + "\n")
    return py, site


def test_pip_install_python_dir(venv, tmp_path):
    py, site = venv
    env = _clean_env()
    r = subprocess.run([str(py), "-m", "pip", "install", "--no-index", os.path.join(REPO, "python")],
                       capture_output=True, text=True, env=env, cwd=str(tmp_path))
    assert r.returncode == 0, r.stdout[-2000:] + r.stderr[-2000:]
    out = subprocess.run([str(py), "-c", RUN, FLIGHT], capture_output=True, text=True, env=env,
                         cwd="/tmp")
    assert out.returncode == 0, out.stderr
    first, doc = out.stdout.splitlines()[:2]
    got = json.loads(doc)
    assert first in ("True", "False")
    assert got["module"].startswith(site) and got["lib"] == os.path.join(site, "igea",
                                                                          "libigea.so.1")
    drv = subprocess.run([os.environ.get("IGEA_DRIVER", os.path.join(REPO, "build", "bin", "igea")),
                          "eqerr", "--S", "S.txt", "--dw", "dw.txt", "--sigma", "sigma.txt",
                          "--spec", "spec.txt", "--json"], cwd=FLIGHT, capture_output=True,
                         text=True)
    j = json.loads(drv.stdout)
    assert got["passed"] == j["passed"] and first == str(j["passed"])
    # driver: streamed normal equations; package: igea_eqerr_run (see test_fortran)
    assert got["chi2"] == pytest.approx(j["chi2"], rel=1e-8)
    assert got["scale"] == pytest.approx(j["scale"], rel=1e-8)
    ver = subprocess.run([str(py), "-m", "pip", "show", "igea"], capture_output=True, text=True,
                         env=env).stdout
    assert "Version: %s" % got["version"] in ver
    # the wheel is the platform's (it carries a compiled library)
    rec = [f for f in os.listdir(site) if f.startswith("igea-") and f.endswith(".dist-info")]
    wheel = open(os.path.join(site, rec[0], "WHEEL")).read()
    assert "Root-Is-Purelib: false" in wheel and "Tag: py3-none-linux" in wheel


def test_backend_reads_pyproject_without_tomllib():
    """The backend's own reader (for Python < 3.11 without tomli) gives what
    tomllib gives on both pyproject.toml files."""
    tomllib = pytest.importorskip("tomllib")
    sys.path.insert(0, os.path.join(REPO, "python"))
    try:
        import igea_build
    finally:
        sys.path.pop(0)
    for path in (os.path.join(REPO, "python", "pyproject.toml"),
                 os.path.join(REPO, "pyproject.toml")):
        text = open(path).read()
        assert igea_build._mini_toml(text) == tomllib.loads(text), path
    with pytest.raises(RuntimeError, match="unsupported value"):
        igea_build._mini_toml("[a]\nb = 3\n")
