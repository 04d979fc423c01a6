"""The PEP 517 build backend of the igea package (standard library only).

    pip install ./python        (or: pip install . from the repository root)

The wheel holds the Python modules of python/igea/, _capi.py written from
the headers (gen_capi.py), and libigea.so.MAJOR compiled from the
repository's sources by 'make' in a scratch build directory; igea._lib
loads that library first (after $IGEA_LIBRARY). The backend needs no
package from an index (build isolation works offline); building needs the
C toolchain, make and the Debian packages of 'make deps'. The wheel is
tagged py3-none-<platform>: the library is loaded by ctypes, so any
Python 3 of the platform can use it, but it links the system's LAPACKE,
OpenBLAS and GSL (not a manylinux wheel).

Metadata comes from pyproject.toml's [project] table (name, description,
requires-python, dependencies, optional-dependencies); the version from
[tool.igea_build.dynamic], the headers' IGEA_VERSION_STRING.
"""
import base64
import hashlib
import os
import re
import shutil
import subprocess
import sys
import sysconfig
import tempfile
import zipfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)


def _gen_capi():
    sys.path.insert(0, HERE)
    try:
        import gen_capi
        return gen_capi
    finally:
        sys.path.pop(0)


def _mini_toml(text):
    """The subset of TOML that pyproject.toml uses, for a Python without
    tomllib (< 3.11) and without tomli: [tables], and one-line values that
    are strings, lists of strings or inline tables of strings."""
    def value(v, where):
        v = v.strip()
        if v.startswith("{") and v.endswith("}"):
            return dict((k.strip(), value(x, where)) for k, x in
                        (item.split("=", 1) for item in v[1:-1].split(",") if item.strip()))
        if v.startswith("[") and v.endswith("]"):
            return [value(x, where) for x in re.findall(r'"(?:[^"\\]|\\.)*"', v)]
        if len(v) >= 2 and v[0] == v[-1] == '"':
            return v[1:-1].replace('\\"', '"').replace("\\\\", "\\")
        raise RuntimeError("igea_build: pyproject.toml: %s: unsupported value %r" % (where, v))

    doc, table = {}, None
    for n, line in enumerate(text.splitlines(), 1):
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        if line.startswith("["):
            table = doc
            for k in line.strip("[]").split("."):
                table = table.setdefault(k.strip(), {})
            continue
        k, _, v = line.partition("=")
        if table is None or not _:
            raise RuntimeError("igea_build: pyproject.toml:%d: cannot read %r" % (n, line))
        table[k.strip()] = value(v, "line %d" % n)
    return doc


def _pyproject():
    path = os.path.join(HERE, "pyproject.toml")
    try:
        import tomllib
    except ImportError:  # Python < 3.11
        try:
            import tomli as tomllib
        except ImportError:
            with open(path) as f:
                return _mini_toml(f.read())
    with open(path, "rb") as f:
        return tomllib.load(f)


def _project():
    return _pyproject()["project"]


def _version():
    """(version, major): [tool.igea_build.dynamic] version's attr, a name of
    the generated igea._capi, and the library's major version."""
    attr = _pyproject()["tool"]["igea_build"]["dynamic"]["version"]["attr"]
    mod, _, name = attr.rpartition(".")
    if mod != "igea._capi":
        raise RuntimeError("igea_build: the version attr must be igea._capi.NAME, not %r" % attr)
    capi = {}
    exec(compile(_gen_capi().generate(), "igea/_capi.py", "exec"), capi)
    return capi[name], capi["VERSION_MAJOR"]


def _metadata(version):
    p = _project()
    lines = ["Metadata-Version: 2.1", "Name: %s" % p["name"], "Version: %s" % version,
             "Summary: %s" % p.get("description", "")]
    if "requires-python" in p:
        lines.append("Requires-Python: %s" % p["requires-python"])
    for d in p.get("dependencies", []):
        lines.append("Requires-Dist: %s" % d)
    for extra, deps in p.get("optional-dependencies", {}).items():
        lines.append("Provides-Extra: %s" % extra)
        for d in deps:
            lines.append('Requires-Dist: %s ; extra == "%s"' % (d, extra))
    return "\n".join(lines) + "\n"


def _tag():
    plat = re.sub(r"[-.]", "_", sysconfig.get_platform())
    return "py3-none-%s" % plat


def _build_library(scratch, version):
    build = os.path.join(scratch, "c")
    target = os.path.join(build, "lib", "libigea.so.%s" % version)
    jobs = [] if "MAKEFLAGS" in os.environ else ["-j%d" % min(4, os.cpu_count() or 1)]
    cmd = [os.environ.get("MAKE", "make")] + jobs + ["-C", ROOT, "BUILD=" + build, target]
    sys.stderr.write("igea: building the library: %s\n" % " ".join(cmd))
    subprocess.check_call(cmd, stdout=sys.stderr)
    return target


def _record_hash(data):
    digest = base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=")
    return "sha256=" + digest.decode()


def build_wheel(wheel_directory, config_settings=None, metadata_directory=None):
    if not os.path.isfile(os.path.join(ROOT, "include", "igea", "common.h")):
        raise RuntimeError("igea: the package is built inside the igea repository "
                           "(include/ and src/ beside python/); %s has none" % ROOT)
    version, major = _version()
    name = _project()["name"]
    tag = _tag()
    dist_info = "%s-%s.dist-info" % (name, version)
    files = {}
    pkg = os.path.join(HERE, "igea")
    for fn in sorted(os.listdir(pkg)):
        if fn.endswith(".py") and fn != "_capi.py":
            with open(os.path.join(pkg, fn), "rb") as f:
                files["igea/" + fn] = f.read()
    files["igea/_capi.py"] = _gen_capi().generate().encode()
    scratch = tempfile.mkdtemp(prefix="igea-wheel-")
    try:
        with open(_build_library(scratch, version), "rb") as f:
            files["igea/libigea.so.%d" % major] = f.read()
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
    files[dist_info + "/METADATA"] = _metadata(version).encode()
    files[dist_info + "/WHEEL"] = ("Wheel-Version: 1.0\nGenerator: igea_build\n"
                                   "Root-Is-Purelib: false\nTag: %s\n" % tag).encode()
    record = "".join("%s,%s,%d\n" % (p, _record_hash(d), len(d)) for p, d in files.items())
    record += dist_info + "/RECORD,,\n"
    files[dist_info + "/RECORD"] = record.encode()
    wheel = "%s-%s-%s.whl" % (name, version, tag)
    with zipfile.ZipFile(os.path.join(wheel_directory, wheel), "w", zipfile.ZIP_DEFLATED) as z:
        for p, d in files.items():
            info = zipfile.ZipInfo(p, date_time=(2020, 1, 1, 0, 0, 0))
            info.external_attr = (0o755 if p.endswith(".so.%d" % major) else 0o644) << 16
            info.compress_type = zipfile.ZIP_DEFLATED
            z.writestr(info, d)
    return wheel


def get_requires_for_build_wheel(config_settings=None):
    return []


def get_requires_for_build_sdist(config_settings=None):
    return []


def build_sdist(sdist_directory, config_settings=None):
    raise RuntimeError("igea: no source distribution of the package alone: it is built "
                       "from the repository (pip install ./python, or make wheel)")
