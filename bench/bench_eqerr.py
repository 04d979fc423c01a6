#!/usr/bin/env python3
"""Speed and memory of the equivalent-error assessment (issue: 180,000 rows
x 74 terms; a 1,800,000-row flight through the driver in < 64 MB).

One run measures, on the same matrix, with OPENBLAS_NUM_THREADS=1, every
item once per round over several rounds (interleaved, so that a change of
the machine's load reaches all of them alike), keeping each one's fastest:
  floor   one bare OpenBLAS cblas_dsyrk (S^T S, column-major) on one thread:
          the least any method must do
  passes  igea_eqerr_run's two passes over S alone: the normal equations
          (igea_normal_accumulate_threads) and the residuals
          (igea_eqerr_residual_threads), 1 and 2 threads, beside one read of
          S (a numpy sum): two threads can do no better than half the floor
          and then one read of S, since the residuals need the solution
  run     igea_eqerr_run alone (normal equations, dsyevd, sigma_w loop,
          tests, residuals; no overall size) on S in Fortran order and, by
          igea_eqerr_run_layout, in C order, 1 and 2 threads
          (IGEA_EQERR_OPT_THREADS): wall time, the CPU time of the calling
          thread (getrusage RUSAGE_THREAD) and of the other, whose larger
          one is the critical path two free cores would see
  igea    igea.eqerr through Python (the whole job: + the verdict rule's
          overall size, whiteness, named components), S in Fortran and in
          C order (the latter read row by row, not copied), 2 threads
  driver  'igea eqerr' on .npy files (107 MB; both passes on a memory map),
          1 and 2 threads, wall and CPU, beside a bare process start ('igea
          version') and the overall size at 74 tested components in a fresh
          process
  numpy   the same steps written with numpy/scipy
and prints every ratio to the floor twice: in CPU time (meaningful on a
loaded machine) and in wall time (meaningful on a quiet one). Then it
writes a 1.8M-row .npy flight (1.07 GB) and reports the driver's peak
resident memory.

    make bench            (or: python bench/bench_eqerr.py [--rows N] [--skip-big]
                           [--rounds R])
"""
import os

# One BLAS thread (before numpy loads): the floor is one thread's dsyrk and
# igea's threads=2 runs its own threads, each with a one-thread dsyrk.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import ctypes  # noqa: E402
import resource  # noqa: E402
import ctypes.util  # noqa: E402
import shutil  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402
from scipy import stats  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "python"))
import igea  # noqa: E402

DRIVER = os.environ.get("IGEA_DRIVER", os.path.join(os.path.dirname(__file__), "..", "build", "bin", "igea"))


def other_library(path):
    """Another build of libigea (ctypes, its own symbols), with the
    prototypes of the two functions eqerr_run calls."""
    from igea import _capi
    lib = ctypes.CDLL(path)
    for f in ("igea_eqerr_defaults", "igea_eqerr_run", "igea_eqerr_run_layout"):
        res, args = _capi.PROTOTYPES[f]
        getattr(lib, f).restype = res
        getattr(lib, f).argtypes = [t for _, t in args]
    return lib


def eqerr_run(S, dw, sigma, spec, threads, lib=None):
    """igea_eqerr_run itself (S in Fortran order; in C order
    igea_eqerr_run_layout row by row), without the overall size of the
    verdict rule that igea.eqerr also asks for (IGEA_EQERR_OPT_OVERALL_SIZE:
    1.8 ms for 74 tested components, the rule's size, not the normal
    equations)."""
    from igea import _capi, _lib
    lib = lib or _lib.lib
    m, N = S.shape
    opts = np.zeros(_capi.EQERR_OPT_LEN)
    lib.igea_eqerr_defaults(_lib.dptr(opts))
    opts[_capi.EQERR_OPT_THREADS] = threads
    out = [np.empty(N), np.empty((N, N), order="F"), np.empty(N), np.empty(N),
           np.empty(N, dtype=np.intc), np.empty(_capi.STATS_INFO_LEN), np.empty(m), np.empty(3)]
    ptr = [_lib.iptr(a) if a.dtype == np.intc else _lib.dptr(a) for a in out]
    if S.flags.f_contiguous:
        st = lib.igea_eqerr_run(m, N, _lib.dptr(S), m, _lib.dptr(dw), _lib.dptr(sigma), 1,
                                _lib.dptr(spec), _lib.dptr(opts), ptr[0], ptr[1], N, *ptr[2:])
    else:
        st = lib.igea_eqerr_run_layout(_capi.ROWMAJOR, m, N, _lib.dptr(S), N, _lib.dptr(dw),
                                       _lib.dptr(sigma), 1, _lib.dptr(spec), _lib.dptr(opts),
                                       ptr[0], ptr[1], N, *ptr[2:])
    if st != 0:
        raise RuntimeError("igea_eqerr_run: status %d" % st)


def normal_eq(S, sigma, spec, threads):
    """igea_normal_accumulate_threads on S in Fortran order: the normal
    equations (S scaled by spec / sigma) that igea_eqerr_run forms first."""
    from igea import _lib
    m, N = S.shape
    A, b, w = np.zeros((N, N), order="F"), np.zeros(N), np.zeros(2)
    st = _lib.lib.igea_normal_accumulate_threads(
        0, m, N, _lib.dptr(S), m, _lib.dptr(np.zeros(m)), _lib.dptr(sigma), 1, _lib.dptr(spec),
        _lib.dptr(A), N, _lib.dptr(b), _lib.dptr(w), threads)
    if st != 0:
        raise RuntimeError("igea_normal_accumulate_threads: status %d" % st)


def residual_pass(S, dw, threads, coef=None):
    """igea_eqerr_residual_threads on S in Fortran order: the second pass of
    igea_eqerr_run (residuals and their per-axis sums of squares)."""
    from igea import _lib
    m, N = S.shape
    coef = np.full(N, 1e-3) if coef is None else coef
    e, ss = np.empty(m), np.zeros(6)
    st = _lib.lib.igea_eqerr_residual_threads(0, m, N, _lib.dptr(S), m, _lib.dptr(dw),
                                              _lib.dptr(coef), 0, _lib.dptr(e), _lib.dptr(ss),
                                              threads)
    if st != 0:
        raise RuntimeError("igea_eqerr_residual_threads: status %d" % st)


def thread_cpu():
    r = resource.getrusage(resource.RUSAGE_THREAD)
    return r.ru_utime + r.ru_stime


def children_cpu():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def in_process(f):
    """(wall, calling thread's CPU, all threads' CPU) of one call."""
    c0, t0, w0 = time.process_time(), thread_cpu(), time.perf_counter()
    f()
    return time.perf_counter() - w0, thread_cpu() - t0, time.process_time() - c0


def child(cmd, cwd):
    """(wall, CPU, CPU) of one run of a subprocess."""
    c0, w0 = children_cpu(), time.perf_counter()
    subprocess.run(cmd, cwd=cwd, check=False, stdout=subprocess.DEVNULL)
    w, c = time.perf_counter() - w0, children_cpu() - c0
    return w, c, c


def interleaved(items, rounds):
    """{name: (min wall, min calling-thread CPU, min CPU, min critical
    path)} over rounds, each round running every item once in turn; the
    critical path of a run is the larger of the calling thread's CPU and
    the other threads' (CPU - calling thread)."""
    got = {k: [] for k in items}
    for _ in range(rounds):
        for k, f in items.items():
            got[k].append(f())
    out = {}
    for k, v in got.items():
        out[k] = (min(x[0] for x in v), min(x[1] for x in v), min(x[2] for x in v),
                  min(max(x[1], x[2] - x[1]) for x in v))
    return out


def numpy_eqerr(S, dw, sigma, spec, alpha=0.01, lambda_test=10.0, lambda_small=0.1, n_min=5,
                tol=0.05, max_iter=10):
    St = S * (spec / sigma[:, None]) if sigma.ndim else S * (spec / sigma)
    A = St.T @ St
    b = St.T @ (dw / sigma)
    lam0, V = np.linalg.eigh(A)
    lam0, V = lam0[::-1], V[:, ::-1]
    N = len(lam0)
    r = int(np.sum(lam0 > N * 10 * np.finfo(float).eps * lam0[0]))
    pb = V.T @ b
    xhat = pb[:r] / lam0[:r]
    g0 = pb[:r] / np.sqrt(lam0[:r])
    c, prev = 1.0, None
    for it in range(max_iter):
        small = np.nonzero(lam0[:r] / c <= lambda_small)[0]
        if len(small) < n_min:
            break
        sw2 = np.mean(g0[small] ** 2) / c
        if abs(sw2 - 1) <= tol and (it == 0 or np.array_equal(small, prev)):
            break
        prev, c = small, c * sw2
    lam = lam0[:r] / c
    t = lam >= lambda_test
    z = xhat[t] / np.sqrt(1 + 1 / lam[t])
    T = np.sum(z * z)
    passed = not np.any(np.abs(z) > stats.norm.isf(alpha / 2)) and T < stats.chi2.isf(alpha, t.sum())
    coef = spec * (V[:, :r][:, t] @ xhat[t])
    res = dw - S @ coef
    return passed, res


def make_flight(m, N, seed=1):
    rng = np.random.default_rng(seed)
    tt = np.linspace(0, 1, m // 3).repeat(3)
    # smooth, strongly collinear columns like environment functions
    S = np.empty((m, N), order="F")
    for j in range(N):
        S[:, j] = np.cos((j % 12 + 1) * tt + j) * tt ** (1 + j % 5) + 1e-3 * rng.standard_normal(m)
    spec = 10.0 ** rng.uniform(-1, 1, N)
    sigma = np.full(m, 0.01)
    dw = S @ (rng.standard_normal(N) * spec) + 0.01 * rng.standard_normal(m)
    return S, dw, sigma, spec


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rows", type=int, default=180000)
    ap.add_argument("--terms", type=int, default=74)
    ap.add_argument("--big-rows", type=int, default=1800000)
    ap.add_argument("--skip-big", action="store_true")
    ap.add_argument("--rounds", type=int, default=7)
    ap.add_argument("--compare-library", metavar="LIBIGEA",
                    help="another build of libigea.so.1: its igea_eqerr_run in the same rounds")
    ap.add_argument("--compare-driver", metavar="IGEA",
                    help="another build of the driver, run in the same rounds on the same "
                         "files (a before/after comparison)")
    a = ap.parse_args()
    m, N = a.rows, a.terms
    S, dw, sigma, spec = make_flight(m, N)

    blas = ctypes.CDLL(ctypes.util.find_library("openblas") or "libopenblas.so.0")
    C = np.zeros((N, N), order="F")
    dp = ctypes.POINTER(ctypes.c_double)

    def floor():
        blas.cblas_dsyrk(102, 122, 112, N, m, ctypes.c_double(1.0), S.ctypes.data_as(dp), m,
                         ctypes.c_double(0.0), C.ctypes.data_as(dp), N)

    Sc = np.ascontiguousarray(S)
    union = ("import ctypes, sys, time; from scipy import stats; "
             "lib = ctypes.CDLL(sys.argv[1]); v = ctypes.c_double(); "
             "f = lib.igea_stats_union_size; f.argtypes = [ctypes.c_int, ctypes.c_double, "
             "ctypes.c_double, ctypes.POINTER(ctypes.c_double)]; "
             "a, b = stats.norm.isf(0.005), stats.chi2.isf(0.01, 74); "
             "c = time.process_time(); f(74, a, b, ctypes.byref(v)); "
             "print(time.process_time() - c)")
    from igea import _lib
    t_union = min(float(subprocess.run([sys.executable, "-c", union, _lib.lib._name],
                                       capture_output=True, text=True).stdout)
                  for _ in range(3))
    with tempfile.TemporaryDirectory() as d:
        for name, arr in [("S", Sc), ("dw", dw), ("sigma", sigma), ("spec", spec)]:
            np.save(os.path.join(d, name + ".npy"), arr)
        cmd = [DRIVER, "eqerr", "--S", "S.npy", "--dw", "dw.npy", "--sigma", "sigma.npy",
               "--spec", "spec.npy", "--out", "report.txt"]
        items = {
            "floor": lambda: in_process(floor),
            "read": lambda: in_process(lambda: S.sum()),
            "norm1": lambda: in_process(lambda: normal_eq(S, sigma, spec, 1)),
            "norm2": lambda: in_process(lambda: normal_eq(S, sigma, spec, 2)),
            "res1": lambda: in_process(lambda: residual_pass(S, dw, 1)),
            "res2": lambda: in_process(lambda: residual_pass(S, dw, 2)),
            "run1": lambda: in_process(lambda: eqerr_run(S, dw, sigma, spec, 1)),
            "run2": lambda: in_process(lambda: eqerr_run(S, dw, sigma, spec, 2)),
            "runc1": lambda: in_process(lambda: eqerr_run(Sc, dw, sigma, spec, 1)),
            "runc2": lambda: in_process(lambda: eqerr_run(Sc, dw, sigma, spec, 2)),
            "py": lambda: in_process(lambda: igea.eqerr(S, dw, sigma, spec)),
            "pyc": lambda: in_process(lambda: igea.eqerr(Sc, dw, sigma, spec)),
            "py2": lambda: in_process(lambda: igea.eqerr(S, dw, sigma, spec, threads=2)),
            "drv1": lambda: child(cmd, d),
            "drv2": lambda: child(cmd + ["--threads", "2"], d),
            "start": lambda: child([DRIVER, "version"], d),
        }
        if a.compare_library:
            olib = other_library(a.compare_library)
            for t in (1, 2):
                items["olib%d" % t] = (lambda t: lambda: in_process(
                    lambda: eqerr_run(S, dw, sigma, spec, t, olib)))(t)
                items["olibc%d" % t] = (lambda t: lambda: in_process(
                    lambda: eqerr_run(Sc, dw, sigma, spec, t, olib)))(t)
        if a.compare_driver:
            other = [a.compare_driver] + cmd[1:]
            items["cmp1"] = lambda: child(other, d)
            items["cmp2"] = lambda: child(other + ["--threads", "2"], d)
        r = interleaved(items, a.rounds)
    t_numpy = min(in_process(lambda: numpy_eqerr(S, dw, sigma, spec))[2] for _ in range(3))
    del Sc
    fw, fc = r["floor"][0], r["floor"][2]
    print(f"eqerr, {m} rows x {N} terms (fastest of {a.rounds} interleaved rounds; "
          f"OPENBLAS_NUM_THREADS={os.environ.get('OPENBLAS_NUM_THREADS', 'unset')}; load "
          f"average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores). Ratios to the floor "
          f"in CPU time (loaded machine) and in wall time (quiet machine):")
    print(f"  floor: one cblas_dsyrk, 1 thread      {fc * 1e3:7.1f} ms CPU, {fw * 1e3:7.1f} ms wall")

    def verdict(x, target):
        return f"target <= {target}: {'met' if x <= target else 'NOT met'}"

    def one(label, k, target=None):
        w, _, c, _ = r[k]
        t = f"  ({verdict(c / fc, target)} in CPU, {'met' if w / fw <= target else 'NOT met'} " \
            f"in wall)" if target else ""
        print(f"  {label:38s}{c * 1e3:7.1f} ms CPU = {c / fc:5.2f} x, {w * 1e3:7.1f} ms wall = "
              f"{w / fw:5.2f} x{t}")

    def two(label, k, target=None):
        w, m1, c, crit = r[k]
        t = f"; {verdict(crit / fc, target)} (critical path)" if target else ""
        print(f"  {label:38s}calling thread {m1 * 1e3:6.1f} ms CPU = {m1 / fc:4.2f} x, critical "
              f"path (the busier thread) {crit * 1e3:6.1f} ms = {crit / fc:4.2f} x, all threads "
              f"{c * 1e3:6.1f} ms = {c / fc:4.2f} x; wall {w * 1e3:6.1f} ms = {w / fw:4.2f} x{t}")

    print("  igea_eqerr_run's two passes over S in Fortran order, each alone:")
    one("  normal equations, 1 thread", "norm1")
    two("  normal equations, threads=2", "norm2", 0.6)
    one("  residuals, 1 thread", "res1")
    two("  residuals, threads=2", "res2")
    rw, _, rc, _ = r["read"]
    print(f"    one read of S (numpy sum, 1 thread)   {rc * 1e3:7.1f} ms CPU = {rc / fc:5.2f} x, "
          f"{rw * 1e3:7.1f} ms wall = {rw / fw:5.2f} x")
    print(f"    the least two threads can do for both passes (half the floor, then one read of S "
          f"for the residuals, which need the solution): {fw / 2 * 1e3 + rw * 1e3:.1f} ms wall = "
          f"{0.5 + rw / fw:.2f} x")
    print("  igea_eqerr_run (normal equations, eig, sigma_w loop, tests, residuals; no overall size):")
    one("  S in Fortran order, 1 thread", "run1")
    two("  S in Fortran order, threads=2", "run2", 0.6)
    one("  S in C order, 1 thread", "runc1")
    two("  S in C order, threads=2", "runc2", 0.6)
    if a.compare_library:
        print(f"  the other library's igea_eqerr_run ({a.compare_library}):")
        one("  S in Fortran order, 1 thread", "olib1")
        two("  S in Fortran order, threads=2", "olib2")
        one("  S in C order, 1 thread", "olibc1")
        two("  S in C order, threads=2", "olibc2")
    print("  igea.eqerr (Python, the whole job):")
    one("  S in Fortran order", "py", 1.3)
    one("  S in C order", "pyc", 1.3)
    two("  threads=2", "py2")
    print("  igea eqerr driver on .npy files (the whole job, a process):")
    one("  1 thread", "drv1", 1.3)
    one("  --threads 2", "drv2", 1.3)
    sw, _, sc, _ = r["start"]
    print(f"    of which a process start ('igea version') {sc * 1e3:.1f} ms CPU = {sc / fc:.2f} x, "
          f"{sw * 1e3:.1f} ms wall; the overall size at 74 tested components "
          f"{t_union * 1e3:.1f} ms CPU")
    if a.compare_driver:
        print(f"  the other driver ({a.compare_driver}), the same files and rounds:")
        one("  1 thread", "cmp1")
        one("  --threads 2", "cmp2")
    tp = r["py"][2]
    print(f"  numpy/scipy (same steps)              {t_numpy * 1e3:7.1f} ms CPU = "
          f"{t_numpy / tp:5.2f} x igea.eqerr's CPU (target >= 1.5: "
          f"{'met' if t_numpy >= 1.5 * tp else 'NOT met'})")
    if a.skip_big:
        return
    mb = a.big_rows
    with tempfile.TemporaryDirectory(dir=os.environ.get("IGEA_BENCH_TMP")) as d:
        path = os.path.join(d, "S.npy")
        mm = np.lib.format.open_memmap(path, mode="w+", dtype="<f8", shape=(mb, N))
        dwb = np.empty(mb)
        step = 60000
        for r0 in range(0, mb, step):
            r1 = min(mb, r0 + step)
            blk, d_, _, _ = make_flight(r1 - r0, N, seed=r0)
            mm[r0:r1] = blk
            dwb[r0:r1] = d_
        mm.flush()
        del mm
        np.save(os.path.join(d, "dw.npy"), dwb)
        np.save(os.path.join(d, "spec.npy"), spec)
        del dwb
        cmd = [DRIVER, "eqerr", "--S", "S.npy", "--dw", "dw.npy", "--sigma", "0.01", "--spec",
               "spec.npy", "--out", "report.txt"]
        # Peak memory of the driver alone: GNU time reports the child's own
        # maximum resident set (a child forked from this large Python
        # process would inherit its high-water mark in getrusage).
        gnu_time = shutil.which("time") and os.path.exists("/usr/bin/time")
        t0 = time.perf_counter()
        if gnu_time:
            r = subprocess.run(["/usr/bin/time", "-f", "%M"] + cmd, cwd=d, capture_output=True, text=True)
            peak_mb = int(r.stderr.strip().splitlines()[-1]) / 1024
        else:
            r = subprocess.run(cmd, cwd=d)
            peak_mb = None
        dt = time.perf_counter() - t0
        verdict = {0: "accepted", 1: "rejected"}.get(r.returncode, "exit %d" % r.returncode)
        if peak_mb is None:
            print(f"driver on a {mb}-row x {N} flight: {verdict}, {dt:.1f} s; peak memory not "
                  f"measured (install the Debian package 'time')")
        else:
            print(f"driver on a {mb}-row x {N} flight ({mb * N * 8 / 1e9:.2f} GB .npy): {verdict}, "
                  f"{dt:.1f} s, peak RSS {peak_mb:.1f} MB (target < 64 MB: "
                  f"{'met' if peak_mb < 64 else 'NOT met'})")


if __name__ == "__main__":
    main()
