"""The Fortran module igea (python/gen_fortran.py) and examples/eqerr_example.f90.

The module is generated into a temporary directory and compiled with
gfortran; programs are linked against the library the other tests use
($IGEA_LIBRARY's directory, else build/lib). Skipped, saying so, where
gfortran is not installed (make deps installs it).
"""
import json
import os
import re
import shutil
import subprocess
import sys

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(REPO, "python"))
import gen_fortran  # noqa: E402

FC = shutil.which(os.environ.get("FC", "gfortran")) or shutil.which("gfortran")
pytestmark = pytest.mark.skipif(FC is None, reason="gfortran is not installed")
FLIGHT = os.path.join(REPO, "examples", "flight")


def _libdir():
    lib = os.environ.get("IGEA_LIBRARY") or os.path.join(REPO, "build", "lib")
    return lib if os.path.isdir(lib) else os.path.dirname(lib)


def _driver():
    return os.environ.get("IGEA_DRIVER") or os.path.join(REPO, "build", "bin", "igea")


@pytest.fixture(scope="module")
def fmod(tmp_path_factory):
    d = tmp_path_factory.mktemp("fortran")
    src = d / "igea.f90"
    src.write_text(gen_fortran.generate())
    subprocess.run([FC, "-std=f2018", "-Wall", "-Werror", "-J", str(d), "-c", str(src), "-o",
                    str(d / "igea.o")], check=True, capture_output=True, text=True)
    return d


def _build(fmod, source, name):
    exe = fmod / name
    r = subprocess.run([FC, "-std=f2018", "-Wall", "-I", str(fmod), str(source), "-o", str(exe),
                        "-L", _libdir(), "-ligea", "-Wl,-rpath," + _libdir()],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    return exe


def _exported():
    so = os.path.join(_libdir(), "libigea.so.1")
    out = subprocess.run(["nm", "-D", "--defined-only", so], check=True, capture_output=True,
                         text=True).stdout
    return {ln.split()[-1] for ln in out.splitlines() if ln.split()[-1].startswith("igea_")}


def test_module_binds_every_exported_function():
    text = gen_fortran.generate()
    bound = set(re.findall(r"bind\(c, name='(igea_\w+)'\)", text))
    exported = _exported()
    assert exported, "no igea_ symbol in the library"
    assert exported - bound == set(), "exported but not in the Fortran module"
    assert bound - exported == set(), "in the Fortran module but not exported"


def test_module_constants_and_indices(fmod):
    prog = fmod / "consts.f90"
    prog.write_text("""
program consts
  use, intrinsic :: iso_c_binding
  use igea
  implicit none
  real(c_double) :: opts(IGEA_EQERR_OPT_LEN), p
  character(kind=c_char), pointer :: v(:)
  integer(c_int) :: st, code
  st = igea_eqerr_defaults(opts)
  ! the header's documented defaults: alpha 0.01, lambda_test 10, max_iter 10
  print '(i0, 3(1x, es12.5))', st, opts(IGEAF_EQERR_OPT_ALPHA), &
       opts(IGEAF_EQERR_OPT_LAMBDA_TEST), opts(IGEAF_EQERR_OPT_MAX_ITER)
  st = igea_stats_normal_cdf(0d0, p)       ! a scalar output
  print '(i0, 1x, f8.5)', st, p
  st = igea_choice_code(IGEA_CHOICE_EQERR_ROUTE, 'svd' // c_null_char, code)
  print '(i0, 1x, l1)', st, code == IGEA_EQERR_ROUTE_SVD
  print '(l1)', igea_version_number() == IGEA_VERSION_NUMBER_CONST
  call c_f_pointer(igea_version(), v, [int(igea_c_strlen(igea_version()))])
  print '(i0, 1x, 100a)', size(v), v
  st = igea_eqerr_defaults()               ! an absent array is NULL: status -1
  print '(i0)', st
  print '(f8.5, 1x, i0)', IGEA_SIGMA_MIN * 2d0**511, IGEAF_STATS_INFO_CHI2 - IGEA_STATS_INFO_CHI2
  block  ! a handle: created (igea_rls ** out), queried (scalars out), freed
    type(c_ptr) :: h
    real(c_double) :: g0(2, 2) = reshape([4d0, 0d0, 0d0, 9d0], [2, 2]), x(2)
    integer(c_int) :: m, k
    st = igea_rls_create(2_c_int, 1_c_int, gamma0=g0, ldg=2_c_int, out=h)  ! x0 absent: zeros
    print '(i0, 1x, l1)', st, c_associated(h)
    st = igea_rls_get_size(h, m, k)
    print '(3(i0, 1x))', st, m, k
    st = igea_rls_get_x(h, x)
    print '(i0, 2(1x, f4.1))', st, x
    call igea_rls_free(h)
  end block
end program consts
""")
    exe = _build(fmod, prog, "consts")
    out = subprocess.run([str(exe)], check=True, capture_output=True, text=True).stdout.split("\n")
    st, alpha, lam, it = out[0].split()
    assert (st, float(alpha), float(lam), float(it)) == ("0", 0.01, 10.0, 10.0)
    assert out[1].split() == ["0", "0.50000"]
    assert out[2].split() == ["0", "T"]
    assert out[3].strip() == "T"
    ver = subprocess.run([_driver(), "--version"], capture_output=True, text=True).stdout
    n, text = out[4].split()
    assert text in ver and int(n) == len(text) and text.count(".") == 2
    assert out[5].strip() == "-1"
    assert out[6].split() == ["1.00000", "1"]  # 2^-511 * 2^511; 1-based = 0-based + 1
    assert out[7].split() == ["0", "T"]
    assert out[8].split() == ["0", "2", "1"]
    assert out[9].split() == ["0", "0.0", "0.0"]  # the header: x0 NULL means zeros


def test_fortran_example_matches_driver(fmod):
    exe = _build(fmod, os.path.join(REPO, "examples", "eqerr_example.f90"), "eqerr_example_f")
    r = subprocess.run([str(exe), FLIGHT], capture_output=True, text=True)
    assert r.returncode in (0, 1), r.stdout + r.stderr
    got = dict(re.findall(r"^(verdict|c|T)\s*[:=]\s*(\S+)", r.stdout, re.M))
    d = subprocess.run([_driver(), "eqerr", "--S", "S.txt", "--dw", "dw.txt", "--sigma",
                        "sigma.txt", "--spec", "spec.txt", "--json"], cwd=FLIGHT,
                       capture_output=True, text=True)
    assert d.returncode in (0, 1), d.stderr
    j = json.loads(d.stdout)
    assert got["verdict"] == ("ACCEPTED" if j["passed"] else "REJECTED")
    assert r.returncode == (0 if j["passed"] else 1)
    # The driver streams the rows (igea_normal_accumulate + igea_eqerr_solve),
    # the example calls igea_eqerr_run on the whole matrix: the summation
    # order differs, so do the last bits of c (its small eigenvalues reach
    # 1e-14 lambda_1).
    assert float(got["c"]) == pytest.approx(j["scale"], rel=1e-8)
    assert float(got["T"]) == pytest.approx(j["chi2"], rel=1e-8)


def test_fortran_example_error_text(fmod, tmp_path):
    """A failing call prints igea_strerror's text: a zero tracking sigma."""
    exe = _build(fmod, os.path.join(REPO, "examples", "eqerr_example.f90"), "eqerr_example_f")
    for f in ("S.txt", "dw.txt", "spec.txt"):
        shutil.copy(os.path.join(FLIGHT, f), tmp_path / f)
    lines = open(os.path.join(FLIGHT, "sigma.txt")).read().splitlines()
    lines[-1] = "0"
    (tmp_path / "sigma.txt").write_text("\n".join(lines) + "\n")
    r = subprocess.run([str(exe), str(tmp_path)], capture_output=True, text=True)
    assert r.returncode == 2
    assert "status -1012" in r.stdout and "zero or negative" in r.stdout


def test_scalar_table_names_pointer_arguments():
    """Every entry of gen_fortran.SCALARS is a pointer argument of an
    exported function (a renamed argument would silently become an array)."""
    import gen_capi
    params = {name: dict((pn, pt) for pt, pn in ps) for _, _, name, ps in gen_capi.parse()[1]}
    for fname, names in gen_fortran.SCALARS.items():
        assert fname in params, fname
        for n in names.split():
            assert n in params[fname] and params[fname][n].rstrip().endswith("*"), (fname, n)
