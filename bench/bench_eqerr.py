#!/usr/bin/env python3
"""Speed and memory of the equivalent-error assessment (issue: 180,000 rows
x 74 terms; a 1,800,000-row flight through the driver in < 64 MB).

One run measures, on the same matrix, interleaved, with OPENBLAS_NUM_THREADS=1:
  floor   one bare OpenBLAS cblas_dsyrk (S^T S) on one thread - the least any
          method must do
  run     igea_eqerr_run alone (normal equations, dsyevd, sigma_w loop,
          tests, residuals; no overall size), 1 and 2 threads
          (IGEA_EQERR_OPT_THREADS): wall time, and the CPU time of the
          calling thread (getrusage RUSAGE_THREAD) and of the others
  igea    igea.eqerr through Python (the whole job: + the verdict rule's
          overall size, whiteness, named components), S in Fortran and in
          C order (the latter read row by row, not copied)
  driver  'igea eqerr' on .npy files (107 MB; both passes on a memory map),
          wall and CPU, beside a bare process start ('igea version') and the
          overall size at 74 tested components in a fresh process
  numpy   the same steps written with numpy/scipy
and prints the ratios to the floor. Then it writes a 1.8M-row .npy flight
(1.07 GB) and reports the driver's peak resident memory. Wall-clock ratios
need a quiet machine; the CPU times are printed beside them.

    make bench            (or: python bench/bench_eqerr.py [--rows N] [--skip-big])
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


def best(f, repeat=5):
    ts = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        f()
        ts.append(time.perf_counter() - t0)
    return min(ts)


def eqerr_run(S, dw, sigma, spec, threads):
    """igea_eqerr_run itself, without the overall size of the verdict rule
    that igea.eqerr also asks for (IGEA_EQERR_OPT_OVERALL_SIZE: ~1.8 s for
    74 tested components, the rule's size, not the normal equations)."""
    from igea import _capi, _lib
    m, N = S.shape
    opts = np.zeros(_capi.EQERR_OPT_LEN)
    _lib.lib.igea_eqerr_defaults(_lib.dptr(opts))
    opts[_capi.EQERR_OPT_THREADS] = threads
    out = [np.empty(N), np.empty((N, N), order="F"), np.empty(N), np.empty(N),
           np.empty(N, dtype=np.intc), np.empty(_capi.STATS_INFO_LEN), np.empty(m), np.empty(3)]
    ptr = [_lib.iptr(a) if a.dtype == np.intc else _lib.dptr(a) for a in out]
    _lib.call("bench", "igea_eqerr_run", m, N, _lib.dptr(S), m, _lib.dptr(dw), _lib.dptr(sigma),
              1, _lib.dptr(spec), _lib.dptr(opts), ptr[0], ptr[1], N, *ptr[2:])


def thread_cpu():
    r = resource.getrusage(resource.RUSAGE_THREAD)
    return r.ru_utime + r.ru_stime


def best_threads(f, repeat=5):
    """(wall, calling thread's CPU, all threads' CPU) of the fastest of
    repeat runs."""
    out = []
    for _ in range(repeat):
        c0, t0, w0 = time.process_time(), thread_cpu(), time.perf_counter()
        f()
        out.append((time.perf_counter() - w0, thread_cpu() - t0, time.process_time() - c0))
    return min(out)


def children_cpu():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def best_process(cmd, cwd, repeat=3):
    """(wall, CPU) of the fastest of repeat runs of a subprocess."""
    out = []
    for _ in range(repeat):
        c0, w0 = children_cpu(), time.perf_counter()
        subprocess.run(cmd, cwd=cwd, check=False, stdout=subprocess.DEVNULL)
        out.append((time.perf_counter() - w0, children_cpu() - c0))
    return min(out)


def best_cpu(f, repeat=3):
    """Min CPU time (process_time, all threads) over repeats."""
    ts = []
    for _ in range(repeat):
        c0 = time.process_time()
        f()
        ts.append(time.process_time() - c0)
    return min(ts)


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
    a = ap.parse_args()
    m, N = a.rows, a.terms
    S, dw, sigma, spec = make_flight(m, N)

    blas = ctypes.CDLL(ctypes.util.find_library("openblas") or "libopenblas.so.0")
    C = np.zeros((N, N), order="F")
    dp = ctypes.POINTER(ctypes.c_double)

    def floor():
        blas.cblas_dsyrk(102, 122, 112, N, m, ctypes.c_double(1.0), S.ctypes.data_as(dp), m,
                         ctypes.c_double(0.0), C.ctypes.data_as(dp), N)

    t_floor = best(floor)
    c_floor = best_cpu(floor)
    Sc = np.ascontiguousarray(S)
    t_igea = best(lambda: igea.eqerr(S, dw, sigma, spec))
    t_igea_c = best(lambda: igea.eqerr(Sc, dw, sigma, spec))
    t_igea2 = best(lambda: igea.eqerr(S, dw, sigma, spec, threads=2))
    run = {t: best_threads(lambda: eqerr_run(S, dw, sigma, spec, t)) for t in (1, 2)}
    c_igea = best_cpu(lambda: igea.eqerr(S, dw, sigma, spec))
    t_numpy = best(lambda: numpy_eqerr(S, dw, sigma, spec), repeat=3)
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
        t_drv, c_drv = best_process(cmd, d)
        t_start, c_start = best_process([DRIVER, "version"], d, repeat=5)
    del Sc
    f = t_floor
    print(f"eqerr, {m} rows x {N} terms (best of several runs; OPENBLAS_NUM_THREADS="
          f"{os.environ.get('OPENBLAS_NUM_THREADS', 'unset')}; load average "
          f"{os.getloadavg()[0]:.1f} on {os.cpu_count()} cores):")
    print(f"  floor  (one cblas_dsyrk, 1 thread) {t_floor * 1e3:8.1f} ms wall, {c_floor * 1e3:.1f} ms CPU")
    print(f"  igea_eqerr_run (normal equations, eig, sigma_w loop, tests, residuals; "
          f"no overall size):")
    w1, m1, a1 = run[1]
    w2, m2, a2 = run[2]
    print(f"         1 thread                {w1 * 1e3:8.1f} ms   {w1 / f:5.2f} x floor "
          f"(CPU {a1 * 1e3:.1f} ms, {a1 / c_floor:.2f} x the floor's)")
    print(f"         threads=2               {w2 * 1e3:8.1f} ms   {w2 / f:5.2f} x the one-thread "
          f"floor (target <= 0.6: {'met' if w2 <= 0.6 * f else 'NOT met'}); CPU: calling thread "
          f"{m2 * 1e3:.1f} ms ({m2 / c_floor:.2f} x the floor's), other thread "
          f"{(a2 - m2) * 1e3:.1f} ms")
    print(f"  igea.eqerr (Python, whole job) {t_igea * 1e3:8.1f} ms   {t_igea / f:5.2f} x floor "
          f"(target <= 1.3: {'met' if t_igea <= 1.3 * f else 'NOT met'}; CPU "
          f"{c_igea * 1e3:.1f} ms, {c_igea / c_floor:.2f} x the floor's)")
    print(f"         S in C order            {t_igea_c * 1e3:8.1f} ms   {t_igea_c / f:5.2f} x floor")
    print(f"         threads=2               {t_igea2 * 1e3:8.1f} ms   {t_igea2 / f:5.2f} x floor")
    print(f"  driver (.npy files, whole job) {t_drv * 1e3:8.1f} ms   {t_drv / f:5.2f} x floor "
          f"(target <= 1.3: {'met' if t_drv <= 1.3 * f else 'NOT met'}; CPU {c_drv * 1e3:.1f} ms, "
          f"{c_drv / c_floor:.2f} x the floor's)")
    print(f"         of which a process start ('igea version') {t_start * 1e3:.1f} ms wall, "
          f"{c_start * 1e3:.1f} ms CPU; the overall size at 74 tested components "
          f"{t_union * 1e3:.1f} ms CPU")
    print(f"  numpy/scipy (same steps)       {t_numpy * 1e3:8.1f} ms   {t_numpy / t_igea:5.2f} x igea "
          f"(target >= 1.5: {'met' if t_numpy >= 1.5 * t_igea else 'NOT met'})")
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
