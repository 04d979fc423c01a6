"""Benchmark of the rls module: time per epoch update of polynomial RLS
(m = 74 coefficients, k = 3 rows, p = 5, honest covariance tracked) over
60,000 epochs, against a numpy implementation of the same update loop run
in the same process on the same data.

    PYTHONPATH=python IGEA_LIBRARY=build/lib/libigea.so.1 \
        .venv/bin/python bench/bench_rls.py [--epochs N] [--numpy-epochs N]

BLAS runs single-threaded (OPENBLAS_NUM_THREADS=1 unless already set):
at m = 74 threads only add synchronisation, and both sides get the same.
"""
import argparse
import os
import sys
import time

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402

import igea  # noqa: E402


def numpy_rls(C, Y, g0, p, chunk):
    """The library's update in numpy: eigen form of METHODS 2.8 for K and
    K_p, symmetric downdate of Gamma, Joseph form of P, Q_p. Returns the
    final state and the time of each chunk of epochs."""
    n, k, m = C.shape
    x = np.zeros(m)
    G = g0.copy()
    P = g0.copy()
    q = 0.0
    Ik = np.eye(k)
    times = []
    t0 = time.perf_counter()
    for e in range(n):
        if e and e % chunk == 0:
            t1 = time.perf_counter()
            times.append(t1 - t0)
            t0 = t1
        c, y = C[e], Y[e]
        gt = G @ c.T
        A = c @ gt
        w, W = np.linalg.eigh(0.5 * (A + A.T))
        w = np.maximum(w, 0.0)
        K = gt @ ((W / (1.0 + w)) @ W.T)
        with np.errstate(divide="ignore", invalid="ignore"):
            f = np.where(w > 0, -np.expm1(-p * np.log1p(w)) / w, float(p))
        Kp = gt @ ((W * f) @ W.T)
        x = x + Kp @ (y - c @ x)
        V = gt @ (W / np.sqrt(1.0 + w))
        ut = P @ c.T
        Bp = 0.5 * Kp @ (c @ ut + Ik) - ut
        P = P + Kp @ Bp.T + Bp @ Kp.T
        G = G - V @ V.T
        r = y - c @ x
        q += r @ r
    times.append(time.perf_counter() - t0)
    del K
    return x, G, P, q, times


def make_data(n, k, m, seed=1):
    """Environment functions growing along the flight plus noise; y = c X + v."""
    rng = np.random.default_rng(seed)
    X = rng.normal(size=m)
    t = np.linspace(0.0, 1.0, n)[:, None, None]
    C = (t * rng.normal(size=(1, k, m)) + np.sin(3 * t + rng.normal(size=(1, k, m)))
         + 0.3 * rng.normal(size=(n, k, m)))
    Y = np.einsum("ekm,m->ek", C, X) + 0.01 * rng.normal(size=(n, k))
    return np.ascontiguousarray(C), Y, X


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--epochs", type=int, default=60000)
    ap.add_argument("--numpy-epochs", type=int, default=60000,
                    help="epochs for the numpy loop (same data, a prefix)")
    ap.add_argument("-m", type=int, default=74)
    ap.add_argument("-k", type=int, default=3)
    ap.add_argument("-p", type=int, default=5)
    ap.add_argument("--chunk", type=int, default=2000, help="epochs per timed chunk")
    a = ap.parse_args()
    n, m, k, p = a.epochs, a.m, a.k, a.p
    nn = min(a.numpy_epochs, n)
    C, Y, _ = make_data(n, k, m)
    g0 = 1e2 * np.eye(m)
    print("rls benchmark: m = %d, k = %d, p = %d (polynomial, honest covariance), "
          "%d epochs; OPENBLAS_NUM_THREADS=%s" % (m, k, p, n, os.environ["OPENBLAS_NUM_THREADS"]))

    ch = a.chunk

    def lib_run(covariance):
        """Whole record in chunks of epochs (one igea_rls_run call each)."""
        est = igea.RLS(None, g0, k, variant="polynomial", p=p, covariance=covariance)
        times = []
        for i in range(0, n, ch):
            t0 = time.perf_counter()
            est.run(C[i:i + ch], Y[i:i + ch])
            times.append(time.perf_counter() - t0)
        state = (est.x, est.gamma, est.covariance if covariance else None, est.q)
        est.close()
        return np.array(times), state

    t_lib, (xc, Gc, Pc, qc) = lib_run(True)
    t_lib_nocov, _ = lib_run(False)

    nper = min(n, 20000)  # one Python call per epoch (ctypes overhead included)
    est = igea.RLS(None, g0, k, variant="polynomial", p=p)
    t0 = time.perf_counter()
    for e in range(nper):
        est.update(C[e], Y[e])
    t_call = (time.perf_counter() - t0) / nper * 1e6
    est.close()

    xn, Gn, Pn, qn, t_np = numpy_rls(C[:nn], Y[:nn], g0, p, ch)
    t_np = np.array(t_np)

    def per(times, count):
        """(overall, best chunk) microseconds per update."""
        return times.sum() / count * 1e6, np.min(times[:-1] if len(times) > 1 else times) / ch * 1e6

    c_all, c_med = per(t_lib, n)
    c2_all, c2_med = per(t_lib_nocov, n)
    n_all, n_med = per(t_np, nn)
    if nn == n:
        dx = np.max(np.abs(xn - xc)) / np.max(np.abs(xn))
        dP = np.max(np.abs(Pn - Pc)) / np.max(np.abs(Pn))
        agree = "results agree: max rel. diff x %.1e, P %.1e, Q_p %.1e" % (
            dx, dP, abs(qn - qc) / qn)
    else:
        agree = "(numpy ran on the first %d epochs; results not compared)" % nn
    print("  %-44s %10s %14s" % ("", "overall", "best chunk"))
    print("  %-44s %10.2f %14.2f  us/update" % ("libigea, igea_rls_run (P tracked)", c_all, c_med))
    print("  %-44s %10.2f %14.2f  us/update" % ("libigea without the honest covariance",
                                                 c2_all, c2_med))
    print("  %-44s %10.2f %14s  us/update" % ("libigea, one ctypes call per epoch", t_call, "-"))
    print("  %-44s %10.2f %14.2f  us/update" % ("numpy loop, same algorithm", n_all, n_med))
    print("  %-44s %10.1f %14.1f  (target >= 30 x)" % ("ratio numpy / libigea", n_all / c_all,
                                                      n_med / c_med))
    print("  %-44s %10.1f %14.1f" % ("ratio numpy / libigea without P", n_all / c2_all,
                                     n_med / c2_med))
    print("  target < 10 us/update (best chunk):         %s" % ("met" if c_med < 10 else "NOT met"))
    print("  (chunks of %d epochs; the best chunk discounts other processes on the machine)" % ch)
    print("  " + agree)
    return 0


if __name__ == "__main__":
    sys.exit(main())
