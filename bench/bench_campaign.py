#!/usr/bin/env python3
"""Monte Carlo campaigns on Dask: flights per second of one process (the
floor a worker cannot beat) against a LocalCluster of 1 and 2 worker
processes on this machine (one thread each, BLAS on one thread), the
scaling from 1 to 2 workers, and the throughput a cluster of W such
workers is expected to reach from the per-flight cost and the measured
efficiency. Prints the thread settings and the machine's load.

    python bench/bench_campaign.py [flights] [chunk]
"""
import os
import sys
import time

import numpy as np

import igea

try:
    import distributed
except ImportError:
    print("bench_campaign: dask.distributed is not installed (pip install ./python[dask])")
    sys.exit(0)

FLIGHTS = int(sys.argv[1]) if len(sys.argv) > 1 else 200000
CHUNK = int(sys.argv[2]) if len(sys.argv) > 2 else 5000
rng = np.random.default_rng(1)
S = rng.standard_normal((360, 74))  # 120 epochs x 3 axes, 74 terms
KW = dict(S=S, sigma=0.01, flights=FLIGHTS, seed=3)


def warm(S):
    """What every process pays once: the verdict rule's overall size for the
    tested counts that occur (kept by the library for the process)."""
    with igea.blas_threads(1):
        igea.montecarlo(S, 0.01, 2000, seed=3, threads=1)


def one_process():
    with igea.blas_threads(1):
        warm(S)
        t0, c0 = time.perf_counter(), time.process_time()
        r = igea.montecarlo(**KW, threads=1)
        return time.perf_counter() - t0, time.process_time() - c0, r


def cluster(workers):
    with distributed.LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as c, distributed.Client(c) as cl:
        cl.run(warm, S)  # every worker, as this process was
        c0 = cl.run(time.process_time)
        t0 = time.perf_counter()
        r = igea.campaign_montecarlo(cl, CHUNK, **KW)
        t = time.perf_counter() - t0
        c1 = cl.run(time.process_time)
        return t, sum(c1[k] - c0[k] for k in c1), r


def main():
    print(f"campaign: {FLIGHTS} flights of a 360 x 74 model, chunks of {CHUNK}; "
          f"{os.cpu_count()} cores, load {os.getloadavg()[0]:.2f}; one thread per worker, "
          "BLAS on one thread")
    t1, cpu1, ref = one_process()
    rate1 = FLIGHTS / t1
    print(f"  one process (the floor of a worker):  {t1:7.2f} s wall  {cpu1:7.2f} s CPU  "
          f"{rate1:9.0f} flights/s")
    rates = {}
    for w in (1, 2):
        t, cpu, r = cluster(w)
        assert np.array_equal(r.chi2, ref.chi2) and r.failed == ref.failed, "not the same result"
        rates[w] = FLIGHTS / t
        print(f"  LocalCluster, {w} worker process(es): {t:7.2f} s wall  {cpu:7.2f} s CPU of "
              f"the workers  {rates[w]:9.0f} flights/s  ratio to one process "
              f"{rates[w] / rate1:5.2f}  workers' CPU / one process's {cpu / cpu1:5.2f}")
    eff = rates[2] / (2 * rates[1])
    print(f"  scaling 1 -> 2 workers: {rates[2] / rates[1]:.2f}x "
          f"(efficiency {eff:.2f} per worker; this machine has {os.cpu_count()} cores)")
    per = rates[1] / rate1
    for w in (16, 64, 256):
        print(f"  expected with {w:3d} such workers: {w * rate1 * per * eff:11.0f} flights/s "
              f"({1e8 / (w * rate1 * per * eff) / 60:6.1f} min per 1e8 flights)")


if __name__ == "__main__":
    main()
