#!/usr/bin/env python3
"""Least squares and the other SVD-based estimators on a tall design
(180,000 x 74) against a QR + SVD peer.

  peer   scipy.linalg.qr(A, mode='r') then numpy's SVD of the 74 x 74 R: the
         least a dense least-squares SVD must do (one Householder QR of A)
  igea   igea_regress_ls_ex (the default refinement in double-double, and
         without it), igea.ls (the fit and its diagnostics in one call,
         igea_regress_ls_full: one fit and the leverages), igea.ebr,
         igea.ridge (fixed k), igea.pce, igea.collinearity

CPU time (process_time, min of repeats) with OPENBLAS_NUM_THREADS=1, as a
ratio to the peer's; the target is igea_regress_ls within 1.2 x the peer.
Every estimator of a design with m >= 2 N rows works through the QR factor
of the weighted design first (docs/regress.md, "Tall designs").

    make bench            (or: python bench/bench_ls.py [--rows N] [--terms N])
"""
import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402
import scipy.linalg  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "python"))
sys.path.insert(0, HERE)
import igea  # noqa: E402
from igea import _capi, _lib  # noqa: E402
from bench_eqerr import make_flight  # noqa: E402


def best_cpu(f, repeat=3):
    ts = []
    for _ in range(repeat):
        c0 = time.process_time()
        f()
        ts.append(time.process_time() - c0)
    return min(ts)


def ls_ex(A, y, flags):
    m, N = A.shape
    x, sd, res = np.empty(N), np.empty(N), np.empty(m)
    cov = np.empty((N, N), order="F")
    s2, info = np.zeros(1), np.zeros(_capi.REGRESS_INFO_LEN)
    _lib.call("bench", "igea_regress_ls_ex", m, N, _lib.dptr(A), m, _lib.dptr(y), None, None,
              0.0, flags, _lib.dptr(x), _lib.dptr(cov), N, _lib.dptr(sd), _lib.dptr(s2),
              _lib.dptr(res), _lib.dptr(info))
    return x, info


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rows", type=int, default=180000)
    ap.add_argument("--terms", type=int, default=74)
    a = ap.parse_args()
    S, dw, _, _ = make_flight(a.rows, a.terms)
    A = np.asfortranarray(S)

    def peer():
        R = scipy.linalg.qr(A, mode="r", check_finite=False)[0]
        return np.linalg.svd(R[:a.terms], compute_uv=True)

    t_peer = best_cpu(peer)
    x, info = ls_ex(A, dw, 0)
    ref = np.linalg.lstsq(A, dw, rcond=None)[0]
    rows = [
        ("igea_regress_ls_ex (refined, the default)", lambda: ls_ex(A, dw, 0)),
        ("igea_regress_ls_ex (IGEA_REGRESS_NO_REFINE)",
         lambda: ls_ex(A, dw, _capi.REGRESS_NO_REFINE)),
        ("igea.ls (+ diagnostics: one fit, leverages)", lambda: igea.ls(A, dw)),
        ("igea.ebr (rule sc)", lambda: igea.ebr(A, dw)),
        ("igea.ridge (k = 1)", lambda: igea.ridge(A, dw, k=1.0)),
        ("igea.pce (60 components)", lambda: igea.pce(A, dw, ncomp=60)),
        ("igea.collinearity", lambda: igea.collinearity(A, dw)),
    ]
    print(f"least squares, {a.rows} rows x {a.terms} terms (CPU time, min of 3; "
          f"OPENBLAS_NUM_THREADS={os.environ.get('OPENBLAS_NUM_THREADS', 'unset')}; "
          f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores):")
    print(f"  peer: scipy qr(mode='r') + SVD of R   {t_peer * 1e3:8.1f} ms")
    for name, f in rows:
        t = best_cpu(f)
        target = ""
        if name.startswith("igea_regress_ls_ex (refined"):
            target = f"  (target <= 1.2 x peer: {'met' if t <= 1.2 * t_peer else 'NOT met'})"
        print(f"  {name:44s}{t * 1e3:8.1f} ms   {t / t_peer:5.2f} x peer{target}")
    print(f"  rank {int(info[_capi.REGRESS_INFO_RANK])}, cond {info[_capi.REGRESS_INFO_COND]:.4g}, "
          f"refinement steps {int(info[_capi.REGRESS_INFO_REFINE_STEPS])}; "
          f"max |x - numpy lstsq| / |x| = {np.max(np.abs(x - ref)) / np.max(np.abs(x)):.1e}")


if __name__ == "__main__":
    main()
