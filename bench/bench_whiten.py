#!/usr/bin/env python3
"""Streamed cost of whitening (igea/noise.h) against today's accumulation.

On the same rows (epoch-major, streamed in blocks of a tenth of the rows),
for each size (default 60,000 rows x 21 terms and 180,000 x 74):
  floor    one bare OpenBLAS dsyrk of the raw block (S^T S), the least any
           accumulation must do
  today    igea_normal_accumulate with per-row sigmas (the seed's diagonal K)
  today1   igea_normal_accumulate with one sigma for all rows (its fastest
           path: no copy, dsyrk on the caller's rows)
  cov      igea_whiten_accumulate with a 3x3 covariance per epoch
  cov+ar1  the same with AR(1) per axis (Prais-Winsten)
  ar3+grp  row sigmas, AR(3) per axis, two groups
  xcov     igea_whiten_accumulate_xcov: the 3x3 blocks K_ee with the cross
           blocks X_e between epochs (the whole K of igea dw: a random walk
           R_e = e r I on top of the 3x3 blocks, K_ee = C + R_e, X_e = R_e)
Each is timed by the CPU time of this process (not wall time: on a loaded
machine the preemptions inflate the wall clock, not the CPU time), the
variants interleaved (one run of each per round, --rounds rounds) and the
best round kept, so that a change of load hits all of them alike. Prints
each time and its ratio to today's (per-row sigma and one sigma), to the
floor and to the block-whitened accumulation (cov 3x3). Run with OPENBLAS_NUM_THREADS=1 (one thread for every variant).

    OPENBLAS_NUM_THREADS=1 python bench/bench_whiten.py [--sizes 60000x21,180000x74]
"""
import argparse
import ctypes
import ctypes.util
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "python"))
from igea import _lib  # noqa: E402


def variants(m, N, blk):
    """The timed functions on one flight of m rows x N terms."""
    rng = np.random.default_rng(0)
    S = np.asfortranarray(rng.normal(size=(m, N)))
    dw = rng.normal(size=m)
    sig = rng.uniform(0.5, 1.5, m)
    spec = np.ones(N)
    M = m // 3
    cov = np.tile([1.0, 0.3, 1.0, 0.2, 0.4, 1.0], (M, 1)).ravel()
    walk = 1e-4 * np.arange(M)  # the random walk's variance R_e = e r I
    kx = np.tile([1.0, 0.3, 1.0, 0.2, 0.4, 1.0], (M, 1))
    kx[:, [0, 2, 5]] += walk[:, None]
    kx = kx.ravel()
    xcov = np.zeros((M, 9))
    xcov[:, [0, 4, 8]] = walk[:, None]
    xcov = xcov.ravel()
    group = (np.arange(M) >= M // 2).astype(np.int32)
    blocks = [(r0, min(r0 + blk, m)) for r0 in range(0, m, blk)]
    Sb = [np.asfortranarray(S[r0:r1]) for r0, r1 in blocks]
    lib = _lib.lib
    blas = ctypes.CDLL(ctypes.util.find_library("openblas") or "libopenblas.so.0")
    C = np.zeros((N, N), order="F")

    def floor():
        for (r0, r1), s in zip(blocks, Sb):
            blas.cblas_dsyrk(102, 122, 112, N, r1 - r0, ctypes.c_double(1.0), _lib.dptr(s),
                             r1 - r0, ctypes.c_double(1.0), _lib.dptr(C), N)

    def normal(one):
        A = np.zeros((N, N)); b = np.zeros(N); w = np.zeros(2); o = np.ones(1)

        def run():
            for (r0, r1), s in zip(blocks, Sb):
                _lib.call("b", "igea_normal_accumulate", 0, r1 - r0, N, _lib.dptr(s), r1 - r0,
                          _lib.dptr(dw[r0:r1]), _lib.dptr(o if one else sig[r0:r1]),
                          0 if one else 1, _lib.dptr(spec), _lib.dptr(A), N, _lib.dptr(b),
                          _lib.dptr(w))
        return run

    handles = []

    def whitened(p, G, use_cov):
        phi = np.tile([0.5, 0.2, 0.1][:p], 3) if p else None
        h = ctypes.c_void_p()
        _lib.call("b", "igea_whiten_create", N, p, _lib.dptr(phi), G, ctypes.byref(h))
        handles.append(h)
        A = np.zeros((G, N, N)); b = np.zeros((G, N)); w = np.zeros(2 * G)

        def run():
            lib.igea_whiten_reset(h)
            for (r0, r1), s in zip(blocks, Sb):
                cv = cov[2 * r0:2 * r1] if use_cov else None
                sg = None if use_cov else sig[r0:r1]
                gr = group[r0 // 3:r1 // 3] if G > 1 else None
                _lib.call("b", "igea_whiten_accumulate", h, 0, r1 - r0, _lib.dptr(s), r1 - r0,
                          _lib.dptr(dw[r0:r1]), _lib.dptr(sg), 1, _lib.dptr(cv), _lib.iptr(gr),
                          None, _lib.dptr(spec), _lib.dptr(A), N, _lib.dptr(b), _lib.dptr(w),
                          None, None)
        return run

    def whitened_xcov():
        h = ctypes.c_void_p()
        _lib.call("b", "igea_whiten_create", N, 0, None, 1, ctypes.byref(h))
        handles.append(h)
        A = np.zeros((N, N)); b = np.zeros(N); w = np.zeros(2)

        def run():
            lib.igea_whiten_reset(h)
            for (r0, r1), s in zip(blocks, Sb):
                _lib.call("b", "igea_whiten_accumulate_xcov", h, 0, r1 - r0, _lib.dptr(s),
                          r1 - r0, _lib.dptr(dw[r0:r1]), _lib.dptr(kx[2 * r0:2 * r1]),
                          _lib.dptr(xcov[3 * r0:3 * r1]), None, _lib.dptr(spec), _lib.dptr(A),
                          N, _lib.dptr(b), _lib.dptr(w), None, None)
        return run

    out = [("floor (dsyrk)", floor), ("today (per-row sigma)", normal(False)),
           ("today, one sigma", normal(True)), ("cov 3x3", whitened(0, 1, True)),
           ("cov 3x3 + AR(1)", whitened(1, 1, True)),
           ("sigma + AR(3), 2 groups", whitened(3, 2, False)),
           ("cov 3x3 + xcov (whole K)", whitened_xcov())]
    return out, lambda: [lib.igea_whiten_free(h) for h in handles]


def cpu(f):
    t0 = time.process_time()
    f()
    return time.process_time() - t0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--sizes", default="60000x21,180000x74", help="ROWSxTERMS,...")
    ap.add_argument("--rounds", type=int, default=0, help="0: 40 / 8 by size")
    a = ap.parse_args()
    for size in a.sizes.split(","):
        m, N = (int(v) for v in size.lower().split("x"))
        m -= m % 3
        blk = max(3, (m // 10) - (m // 10) % 3)
        vs, free = variants(m, N, blk)
        rounds = a.rounds or (40 if m * N < 4e6 else 8)
        best = [float("inf")] * len(vs)
        for _ in range(rounds):  # interleaved: one run of each variant per round
            for i, (_, f) in enumerate(vs):
                best[i] = min(best[i], cpu(f))
        free()
        t_floor, t_today, t_one, t_cov = best[0], best[1], best[2], best[3]
        print(f"whitened accumulation, {m} rows x {N} terms, blocks of {blk} rows, "
              f"best of {rounds} interleaved rounds (CPU time)")
        print(f"{'':28s} {'seconds':>9s} {'/today':>8s} {'/today1':>8s} {'/floor':>8s} "
              f"{'/cov':>8s}")
        for (name, _), t in zip(vs, best):
            print(f"{name:28s} {t:9.5f} {t / t_today:8.2f} {t / t_one:8.2f} {t / t_floor:8.2f} "
                  f"{t / t_cov:8.2f}")


if __name__ == "__main__":
    main()
