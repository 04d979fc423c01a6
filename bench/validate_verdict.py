"""Overall size of the verdict rules by simulation (docs/validation.md,
"Study 4"): for n_test = 1..20 tested components, flights with X ~ N(0, I)
and white tracking noise of the stated sigma, judged by igea.montecarlo
with verdict="exact" (and "seed" beside it); pooled verdicts of groups
of flights by igea.pool(verdict="exact"); and the Monte Carlo's own pooled
study (igea.montecarlo(pool=F, verdict=...), `igea montecarlo --pool F
--verdict exact`) on the 21-term reference model for F = 2, 5, 10, 20,
beside a numpy Monte Carlo of F x 7 standard normal z under the same
thresholds. Every rate with its 99 % Clopper-Pearson interval
(scipy.stats.beta).

  OPENBLAS_NUM_THREADS=1 PYTHONPATH=python IGEA_LIBRARY=build/lib/libigea.so.1 \\
    .venv/bin/python bench/validate_verdict.py [--flights 10000] [--pools 4000]
    [--mc-pools 10000] [--only-mc-pool]

(the defaults take about 70 s of CPU; --pools 10000 for 10,000 pooled
groups per cell, about 2 minutes; the Monte Carlo's pooled study about
10 s more)

Geometry of cell n: N = n + 8 terms, 60 epochs x 3 axes, S = U diag(s) V^T
with the weighted normal matrix's eigenvalues log-spaced over [1e2, 1e4]
(the n tested ones) and over [1e-3, 10^-1.5] (8 small ones for sigma_w),
sigma = 1 cm/s, specs 1: n_test = n in every flight.
"""
import argparse
import time

import numpy as np
from scipy import stats

import igea

SIGMA = 0.01
ALPHA = 0.01


def geometry(n, seed, epochs=60):
    rng = np.random.default_rng(seed)
    m, N = 3 * epochs, n + 8
    U, _ = np.linalg.qr(rng.standard_normal((m, N)))
    V, _ = np.linalg.qr(rng.standard_normal((N, N)))
    lam = np.concatenate([np.logspace(4, 2, n), np.logspace(-1.5, -3, 8)])
    S = (U * (SIGMA * np.sqrt(lam))) @ V.T
    return S, np.full(m, SIGMA)


def cp(k, n, level=0.99):
    a = 1 - level
    lo = stats.beta.ppf(a / 2, k, n - k + 1) if k > 0 else 0.0
    hi = stats.beta.ppf(1 - a / 2, k + 1, n - k) if k < n else 1.0
    return lo, hi


def cell(k, n):
    lo, hi = cp(k, n)
    return "%d / %d = %.4f [%.4f, %.4f]%s" % (k, n, k / n, lo, hi,
                                               "" if lo <= ALPHA <= hi else " **")


def single(flights):
    print("| n_test | exact, correction off: 'out of spec' [99 % CP] | exact, correction on | "
          "seed, correction on | seed's size(n, z_0.995, chi2_0.01(n)) |")
    print("|---|---|---|---|---|")
    tot = [0, 0]
    for n in range(1, 21):
        S, sigma = geometry(n, seed=100 + n)
        run = dict(seed=4000 + n, threads=1)
        ex = igea.montecarlo(S, sigma, flights, verdict="exact", correction=False, **run)
        ec = igea.montecarlo(S, sigma, flights, verdict="exact", correction=True, **run)
        sd = igea.montecarlo(S, sigma, flights, verdict="seed", correction=True, **run)
        assert ex.not_testable == 0 and ex.mean_tested == n and ec.mean_tested == n
        print("| %d | %s | %s | %.4f | %.4f |" % (n, cell(ex.failed, flights),
                                                  cell(ec.failed, flights),
                                                  sd.failed / flights, sd.mean_size))
        tot[0] += ex.failed
        tot[1] += ec.failed
    print("| all 20 | %s | %s | | |" % (cell(tot[0], 20 * flights), cell(tot[1], 20 * flights)))


def pooled(pools, per_pool, n, correction):
    """pools groups of per_pool flights of n tested components, each judged
    by igea.eqerr, pooled by igea.pool(verdict="exact")."""
    S, sigma = geometry(n, seed=900 + n)
    rng = np.random.default_rng(77 + per_pool * n)
    fails = fails_seed = 0
    for _ in range(pools):
        res = []
        for _ in range(per_pool):
            dw = S @ rng.standard_normal(S.shape[1]) + SIGMA * rng.standard_normal(S.shape[0])
            res.append(igea.eqerr(S, dw, sigma, correction=correction))
        fails += not igea.pool(res, verdict="exact").passed
        fails_seed += not igea.pool(res).passed
    ntot = per_pool * n
    print("| %d x %d = %d | %s | %.4f | %.4f |"
          % (per_pool, n, ntot, cell(fails, pools), fails_seed / pools,
             igea.verdict_thresholds("seed", ntot, ALPHA)[2]))


def mc_pooled(pools, sizes=(2, 5, 10, 20)):
    """The Monte Carlo's pooled study: pools x F flights of the 21-term
    reference model in spec (X ~ N(0, I), sigma_w 1), each group of F judged
    by the exact rule for its pooled components (igea_sim_pool_ex), with the
    correction off (the z exactly N(0, 1)) and on (the default job); the
    seed's rule beside it with its overall size; and 10 x pools draws of
    numpy's F x 7 standard normal z under the exact thresholds for F x 7
    components (the rule's size by brute force, independent of igea's
    flights)."""
    fl = igea.simulate(seed=11)
    print("| F x n_test = dof_tot | exact, correction off: pooled 'out of spec' [99 % CP] | "
          "exact, correction on | numpy z ~ N(0, I), exact thresholds (10 x the pools) | "
          "seed, correction on "
          "| seed's mean size | CPU s (3 runs) |")
    print("|---|---|---|---|---|---|---|")
    for F in sizes:
        run = dict(spec=fl.spec, seed=5000 + F, pool=F, threads=1)
        c0 = time.process_time()
        ex = igea.montecarlo(fl.S, fl.sigma, pools * F, verdict="exact", correction=False, **run)
        ec = igea.montecarlo(fl.S, fl.sigma, pools * F, verdict="exact", **run)
        sd = igea.montecarlo(fl.S, fl.sigma, pools * F, verdict="seed", **run)
        cpu = time.process_time() - c0
        n = 7 * F
        assert (ex.dof == 7).all() and abs(ex.pool.mean_size - ALPHA) < 1e-12
        a, b = igea.verdict_thresholds("exact", n, ALPHA)[:2]
        rng = np.random.default_rng(600 + F)
        k = 0
        for p0 in range(0, 10 * pools, 10000):
            z = rng.standard_normal((min(10000, 10 * pools - p0), n))
            k += int(np.count_nonzero((np.abs(z).max(1) > a) | ((z * z).sum(1) >= b)))
        print("| %d x 7 = %d | %s | %s | %s | %.4f | %.4f | %.1f |"
              % (F, n, cell(ex.pool.failed, pools), cell(ec.pool.failed, pools), cell(k, 10 * pools),
                 sd.pool.rate, sd.pool.mean_size, cpu))


def naming(flights, term="gyro_bias_y", k=4.0):
    """Flights of the 21-term reference model with term at k x spec (the
    others N(0, 1)): how often the component that carries the term most
    (largest share) is rejected, and how often the term is then among
    that component's candidates (share >= 10 %)."""
    rej = named = any_named = any_rej = 0
    for f in range(flights):
        fl = igea.simulate(x={term: k}, seed=5, flight=f)
        r = igea.eqerr(fl.S, fl.dw, fl.sigma, fl.spec, names=list(fl.terms))
        main = max(r.components, key=lambda c: dict(c["terms"])[term])
        if main["reject"]:
            rej += 1
            named += term in main["candidates"]
        rc = [c for c in r.components if c["reject"]]
        if rc:
            any_rej += 1
            any_named += any(term in c["candidates"] for c in rc)
    share = dict(main["terms"])[term]
    print("| %s = %g x spec | %d / %d flights | its main component (share %.3f) rejected in %s; "
          "named among its candidates in %s | named by some rejected component in %s |"
          % (term, k, flights, flights, share, cell(rej, flights).split(" [")[0],
             cell(named, rej).split(" **")[0] if rej else "-",
             cell(any_named, any_rej).split(" **")[0] if any_rej else "-"))


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--flights", type=int, default=10000, help="flights per n_test cell")
    ap.add_argument("--pools", type=int, default=4000, help="pooled groups per cell")
    ap.add_argument("--naming", type=int, default=2000, help="flights of the naming study")
    ap.add_argument("--mc-pools", type=int, default=10000,
                    help="pooled groups per F of the Monte Carlo's pooled study")
    ap.add_argument("--only-mc-pool", action="store_true",
                    help="run the Monte Carlo's pooled study alone")
    a = ap.parse_args()
    t0 = time.time()
    if a.only_mc_pool:
        mc_pooled(a.mc_pools)
        print("\n(%.0f s; ** marks an interval that misses alpha = %g)" % (time.time() - t0, ALPHA))
        return
    single(a.flights)
    print()
    print("| pooled flights x n_test = dof_tot | exact: pooled 'out of spec' [99 % CP] | "
          "seed: pooled | seed's size |  (sigma_w correction off)")
    print("|---|---|---|---|")
    pooled(a.pools, 3, 4, correction=False)
    pooled(a.pools, 2, 3, correction=False)
    print()
    mc_pooled(a.mc_pools)
    print()
    naming(a.naming)
    print("\n(%.0f s; ** marks an interval that misses alpha = %g)" % (time.time() - t0, ALPHA))


if __name__ == "__main__":
    main()
