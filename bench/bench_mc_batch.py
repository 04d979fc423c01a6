"""Batched Monte Carlo (IGEA_SIM_OPT_BATCH) against the flight-by-flight
path, a numpy peer vectorised over flights and the dgemm floor, with the
default streams (mt19937) and igea's keyed streams (generator xoshiro).

  python bench/bench_mc_batch.py            120x21, 120x74, 3000x74
  python bench/bench_mc_batch.py --scale 4  4x the flights (steadier)

Per-flight times (min of 3 repeats) of the whole study: truths and noises
drawn, right-hand sides formed, sigma_w loop and tests. The floor is the
product the study cannot avoid, Q^T W (N x m x F), timed as a numpy matmul
on the same shape; 'floor2' adds S X (m x N x F), the other product of the
default batched path and of the numpy peer (the keyed path forms
diag(lam0) V^T X instead, N x N x F). OPENBLAS_NUM_THREADS=1 is set here
before numpy loads (the library's own threads are igea's nthreads; the
numpy peer and the floor run on one thread). CPU columns are process
times (steady on a loaded machine). Two threads (xoshiro streams), runs of
1 and 2 threads interleaved, min of 3: "2t wall" is the 1 -> 2 thread
wall-clock ratio, meaningful only with the load average (printed) below
the cores; "2t crit" estimates it from CPU times, the 1-thread CPU over
the larger of the 2-thread run's two threads (the calling thread's CPU by
RUSAGE_THREAD, the other's the rest of the process's): what an idle
machine gives when the threads run side by side at the 1-thread speed;
"2t cpu" is the 2-thread run's CPU over the 1-thread run's (above 1: work
added, or each thread slowed by the other). The failed rates are printed
with their binomial standard errors and beside the rate the study must
give: with no eigenvalue below lambda_small (all three shapes) c = 1, so
z_i ~ N(0, (1 + sigma_w^2 / l_i) / (1 + 1 / l_i)) independent and the
rate is P(max |z_i| > z_0.995 or sum z_i^2 >= chi2_0.01(N)), drawn here
directly (1,000,000 z vectors, s.e. < 0.0005).
Run with the repository's venv, PYTHONPATH=python and IGEA_LIBRARY set
(`make bench` does).
"""
import os

os.environ["OPENBLAS_NUM_THREADS"] = "1"
os.environ["OMP_NUM_THREADS"] = "1"

import argparse  # noqa: E402
import ctypes  # noqa: E402
import resource  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402
from scipy import stats  # noqa: E402

from igea import _capi, _lib  # noqa: E402

lib = _lib.lib
ALPHA, LAM_TEST, LAM_SMALL, N_MIN, TOL, MAX_ITER = 0.01, 10.0, 0.1, 5, 0.05, 10


def model(M, N, seed=1):
    """A 3M x N design whose column norms span two decades, sigma 0.01."""
    rng = np.random.default_rng(seed)
    S = rng.standard_normal((3 * M, N)) * np.logspace(-1, 1, N) * 0.05
    return np.asfortranarray(S), 0.01


def igea_study(S, sigma, nflights, threads, batch, sigma_w=1.2, generator=0):
    m, N = S.shape
    h = ctypes.c_void_p()
    _lib.call("b", "igea_sim_model_create", m, N, _lib.dptr(S), m, ctypes.byref(h))
    _lib.call("b", "igea_sim_model_set_sigma", h, _lib.dptr(np.array([sigma])), 0, 0.0)
    opts = np.zeros(_capi.SIM_OPT_LEN)
    lib.igea_sim_defaults(_lib.dptr(opts))
    opts[_capi.SIM_OPT_SIGMA_W] = sigma_w
    opts[_capi.SIM_OPT_BATCH] = batch
    opts[_capi.SIM_OPT_GENERATOR] = generator
    _lib.call("b", "igea_sim_model_set_noise", h, _lib.dptr(opts))
    counts = np.zeros(_capi.SIM_MC_LEN)
    m0 = _thread_cpu()
    t0, c0 = time.perf_counter(), time.process_time()
    _lib.call("b", "igea_sim_montecarlo", h, None, 1, 0, nflights, threads,
              _lib.dptr(counts), None, None, None, None, 0)
    t, c = time.perf_counter() - t0, time.process_time() - c0
    m = _thread_cpu() - m0
    lib.igea_sim_model_free(h)
    return (t, c, m), counts[_capi.SIM_MC_FAILED] / nflights


def _thread_cpu():
    """CPU time of the calling thread (user + system)."""
    r = resource.getrusage(resource.RUSAGE_THREAD)
    return r.ru_utime + r.ru_stime


def expected_rate(S, sigma, sigma_w=1.2, draws=1000000, seed=9):
    """The study's failed rate when c stays 1 (no eigenvalue below
    lambda_small, every one tested): z_i ~ N(0, (1 + sigma_w^2 / l_i) /
    (1 + 1 / l_i)) drawn directly; None when the correction can act."""
    lam = np.linalg.eigvalsh((S / sigma).T @ (S / sigma))
    if (lam <= LAM_SMALL).any() or (lam < LAM_TEST).any():
        return None
    n = lam.size
    sd = np.sqrt((1 + sigma_w ** 2 / lam) / (1 + 1 / lam))
    zc, crit = stats.norm.isf(ALPHA / 2), stats.chi2.isf(ALPHA, n)
    rng, k = np.random.default_rng(seed), 0
    for d0 in range(0, draws, 50000):
        z = rng.standard_normal((min(50000, draws - d0), n)) * sd
        k += int(np.count_nonzero((np.abs(z).max(1) > zc) | ((z * z).sum(1) >= crit)))
    return k / draws


def threads_pair(S, sigma, nflights, reps=3):
    """Interleaved 1- and 2-thread runs on the xoshiro streams: (wall 1t,
    wall 2t, CPU 1t, CPU 2t, CPU of the busier thread of the 2-thread run),
    each the min over reps, and the run's failed rate."""
    one, two = [], []
    for _ in range(reps):
        one.append(igea_study(S, sigma, nflights, 1, 0, generator=2))
        two.append(igea_study(S, sigma, nflights, 2, 0, generator=2))
    busier = min(max(m, c - m) for (_, c, m), _ in two)
    return (min(t[0] for t, _ in one), min(t[0] for t, _ in two), min(t[1] for t, _ in one),
            min(t[1] for t, _ in two), busier, one[0][1])


def numpy_study(S, sigma, nflights, sigma_w=1.2, seed=1, block=256):
    """The same study in numpy, vectorised over blocks of flights: one eigh,
    the blocks' truths and noises, the two products, the sigma_w iteration
    and the seed's tests on every flight of the block at once."""
    t0, c0 = time.perf_counter(), time.process_time()
    rng = np.random.default_rng(seed)
    m, N = S.shape
    Sw = S / sigma
    lam0, V = np.linalg.eigh(Sw.T @ Sw)
    lam0, V = lam0[::-1], V[:, ::-1]
    r = int(np.sum(lam0 > N * 10 * np.finfo(float).eps * lam0[0]))
    lam0, Q = lam0[:r], (Sw @ V)[:, :r]
    zc = stats.norm.ppf(1 - ALPHA / 2)
    crit = stats.chi2.isf(ALPHA, np.arange(1, r + 1))
    failed = 0
    for f0 in range(0, nflights, block):
        b = min(block, nflights - f0)
        X = rng.standard_normal((N, b))
        W = (S @ X + sigma_w * sigma * rng.standard_normal((m, b))) / sigma
        PB = Q.T @ W
        g0 = PB / np.sqrt(lam0)[:, None]
        c = np.ones(b)
        active = np.ones(b, bool)
        prev = np.full(b, -1)
        for it in range(MAX_ITER):
            small = lam0[:, None] / c[None, :] <= LAM_SMALL
            ns = small.sum(0)
            active &= ns >= N_MIN
            sw2 = np.where(active, (small * g0 ** 2 / c).sum(0) / np.maximum(ns, 1), 1.0)
            lo = r - ns
            done = (np.abs(sw2 - 1) <= TOL) & ((it == 0) | (lo == prev))
            active &= ~done
            c = np.where(active, c * sw2, c)
            prev = lo
            if not active.any():
                break
        lam = lam0[:, None] / c[None, :]
        tested = lam >= LAM_TEST
        z = (PB / lam0[:, None]) / np.sqrt(1 + 1 / lam)
        k = tested.sum(0)
        T = (np.where(tested, z, 0.0) ** 2).sum(0)
        anyz = (np.abs(np.where(tested, z, 0.0)) > zc).any(0)
        fail = (k > 0) & (anyz | (T >= crit[np.maximum(k, 1) - 1]))
        failed += int(fail.sum())
    return (time.perf_counter() - t0, time.process_time() - c0), failed / nflights


def floor(S, nflights, reps=3):
    """Q^T W alone and with S X over all flights (numpy BLAS, CPU time)."""
    m, N = S.shape
    F = min(nflights, 4096)
    X, W = np.ones((N, F)), np.ones((m, F))
    Q = np.asfortranarray(S)
    one = two = np.inf
    for _ in range(reps):
        c0 = time.process_time()
        Q.T @ W
        c1 = time.process_time()
        S @ X
        c2 = time.process_time()
        one, two = min(one, c1 - c0), min(two, c2 - c0)
    return one / F, two / F


def best(fn, reps=3):
    """(min wall, min CPU) over reps, and the run's failed rate."""
    out = [fn() for _ in range(reps)]
    return min(t[0] for t, _ in out), min(t[1] for t, _ in out), out[0][1]


def se(p, n):
    return (p * (1 - p) / n) ** 0.5


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--scale", type=float, default=1.0)
    a = ap.parse_args()
    print("OPENBLAS_NUM_THREADS=1 (numpy peer and floor on 1 thread); igea at 1 and 2 "
          "threads; per-flight times in microseconds, min of 3; batch 0 = automatic "
          "(64 flights); load average %.1f on %d cores" % (os.getloadavg()[0], os.cpu_count()))
    print("CPU columns: floor, floor2, numpy, per-fl (mt19937 flight by flight), mt "
          "(batched, default streams), xo (batched, xoshiro), xo 2t (CPU per flight on 2 "
          "threads); wall 1t / wall 2t: xoshiro elapsed; 2t wall = wall 1t / wall 2t (the "
          "1 -> 2 thread speed-up on an idle machine); 2t crit = CPU 1t / the busier "
          "thread's CPU on 2 (its estimate from CPU times); 2t cpu = CPU 2t / CPU 1t")
    print(f"{'M x N':>9} {'flights':>7} {'floor':>7} {'floor2':>7} {'numpy':>7} "
          f"{'per-fl':>8} {'mt':>7} {'xo':>7} {'xo 2t':>7} {'wall 1t':>8} {'wall 2t':>8} "
          f"{'numpy/xo':>8} {'xo/floor':>8} {'numpy/mt':>8} {'2t wall':>7} {'2t crit':>7} "
          f"{'2t cpu':>6}")
    rates = []
    for M, N, F, Fone in ((120, 21, 20000, 2000), (120, 74, 10000, 600), (3000, 74, 600, 60)):
        F, Fone = int(F * a.scale), int(Fone * a.scale)
        S, sigma = model(M, N)
        tf, tf2 = floor(S, F)
        _, cn, rn = best(lambda: numpy_study(S, sigma, F))
        _, co, _ = best(lambda: igea_study(S, sigma, Fone, 1, 1))
        _, cm, rm = best(lambda: igea_study(S, sigma, F, 1, 0))
        w1, w2, c1, c2, cb, r1 = threads_pair(S, sigma, F)
        us = lambda t, n: 1e6 * t / n  # noqa: E731
        cn, co, cm, c1u, c2u, w1u, w2u = (us(cn, F), us(co, Fone), us(cm, F), us(c1, F),
                                          us(c2, F), us(w1, F), us(w2, F))
        tf, tf2 = 1e6 * tf, 1e6 * tf2
        print(f"{M:>4} x {N:<3} {F:>7} {tf:>7.2f} {tf2:>7.2f} {cn:>7.2f} {co:>8.1f} "
              f"{cm:>7.2f} {c1u:>7.2f} {c2u:>7.2f} {w1u:>8.2f} {w2u:>8.2f} {cn / c1u:>8.2f} "
              f"{c1u / tf:>8.2f} {cn / cm:>8.2f} {w1 / w2:>7.2f} {c1 / cb:>7.2f} "
              f"{c2 / c1:>6.2f}")
        rates.append((M, N, F, rn, rm, r1, expected_rate(S, sigma)))
    print("failed rates (+- binomial s.e.) and the rate the study must give:")
    for M, N, F, rn, rm, r1, ex in rates:
        print(f"  {M} x {N}, {F} flights: numpy {rn:.4f} +- {se(rn, F):.4f}, mt19937 {rm:.4f} "
              f"+- {se(rm, F):.4f}, xoshiro {r1:.4f} +- {se(r1, F):.4f}; expected "
              + ("(the correction acts)" if ex is None else f"{ex:.4f}"))
    print("load average after the run %.1f" % os.getloadavg()[0])


if __name__ == "__main__":
    main()
