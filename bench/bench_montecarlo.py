"""Monte Carlo of the equivalent-error test: benchmark and validation studies.

  python bench/bench_montecarlo.py                 benchmark: 10,000 flights of
                                                   120 epochs x 21 terms generated
                                                   and judged, 1 and 2 threads,
                                                   against a numpy loop
  python bench/bench_montecarlo.py --validation    the three studies of
                                                   docs/validation.md (tables on
                                                   stdout; PNG plots into docs/
                                                   when matplotlib is installed)

Run with the repository's venv, PYTHONPATH=python and IGEA_LIBRARY set
(`make bench` does).
"""
import argparse
import os
import subprocess
import sys
import time

import numpy as np
from scipy import stats

import igea

ALPHA = 0.01


# ---- numpy reference of the same loop -----------------------------------------
def numpy_loop(S, sigma, spec, nflights, seed, sigma_w=1.0, correct=True, alpha=ALPHA,
               lambda_test=10.0, lambda_small=0.1, n_min=5, tol=0.05, max_iter=10):
    """Generate and judge flights in numpy (METHODS 1.2 steps 1-5, sigma_w
    iteration included). Returns the number of 'out of spec' verdicts."""
    rng = np.random.default_rng(seed)
    St = S * spec / sigma[:, None]
    Sd = S * spec
    A = St.T @ St
    zc = stats.norm.ppf(1 - alpha / 2)
    crit_cache = {}
    failed = 0
    m, N = S.shape
    for _ in range(nflights):
        x = rng.standard_normal(N)
        dw = Sd @ x + sigma_w * sigma * rng.standard_normal(m)
        b = St.T @ (dw / sigma)
        lam0, P = np.linalg.eigh(A)          # as the library: one dsyevd per flight
        lam0, P = lam0[::-1], P[:, ::-1]
        keep = lam0 > N * 10 * np.finfo(float).eps * lam0[0]
        lam0, P = lam0[keep], P[:, keep]
        g0 = (P.T @ b) / np.sqrt(lam0)
        c, prev = 1.0, None
        if correct:
            for it in range(max_iter):
                lam, g = lam0 / c, g0 / np.sqrt(c)
                small = lam <= lambda_small
                if small.sum() < n_min:
                    break
                sw2 = np.mean(g[small] ** 2)
                if abs(sw2 - 1) <= tol and (it == 0 or np.array_equal(small, prev)):
                    break
                prev = small
                c *= sw2
        lam = lam0 / c
        xhat = (P.T @ b) / lam0
        t = lam >= lambda_test
        z = xhat[t] / np.sqrt(1 + 1 / lam[t])
        k = int(t.sum())
        if k == 0:
            continue
        if k not in crit_cache:
            crit_cache[k] = stats.chi2.isf(alpha, k)
        if np.any(np.abs(z) > zc) or np.sum(z ** 2) >= crit_cache[k]:
            failed += 1
    return failed


def benchmark(nflights):
    fl = igea.simulate(seed=1)
    S, sig, spec = fl.S, fl.sigma, fl.spec
    print(f"model: {S.shape[0] // 3} epochs x 3 axes, {S.shape[1]} terms; "
          f"{nflights} flights generated and judged (sigma_w correction on)")
    times = {}
    for nt in (1, 2):
        t0 = time.perf_counter()
        r = igea.montecarlo(S, sig, nflights, spec=spec, seed=7, threads=nt)
        times[nt] = time.perf_counter() - t0
        print(f"  igea.montecarlo, {nt} thread(s): {times[nt]:7.2f} s "
              f"({1e6 * times[nt] / nflights:6.1f} us/flight), 'out of spec' rate "
              f"{r.failed / nflights:.4f}")
    t0 = time.perf_counter()
    f_np = numpy_loop(S, sig, spec, nflights, seed=7)
    t_np = time.perf_counter() - t0
    print(f"  numpy loop, 1 process:      {t_np:7.2f} s "
          f"({1e6 * t_np / nflights:6.1f} us/flight), 'out of spec' rate "
          f"{f_np / nflights:.4f}")
    print(f"  speed-up: igea 1 thread / numpy = {t_np / times[1]:.1f}x, "
          f"2 threads / numpy = {t_np / times[2]:.1f}x, 2 threads / 1 thread = "
          f"{times[1] / times[2]:.2f}x")


def bench_all(nflights):
    """The benchmark as the environment has it, then (in a child process,
    since OpenBLAS reads it at load time) with OPENBLAS_NUM_THREADS=1: the
    21 x 21 eigenproblems are far too small for BLAS threads, whose wake-ups
    otherwise dominate and fight the Monte Carlo's own threads."""
    env_val = os.environ.get("OPENBLAS_NUM_THREADS")
    print(f"== OPENBLAS_NUM_THREADS={env_val if env_val is not None else '(unset)'}")
    benchmark(nflights)
    if env_val != "1":
        env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
        print("== OPENBLAS_NUM_THREADS=1", flush=True)
        subprocess.run([sys.executable, __file__, "--flights", str(nflights), "--child"],
                       env=env, check=True)


# ---- validation studies ------------------------------------------------------
def cp(k, n, level=0.99):
    """Clopper-Pearson interval."""
    a = 1 - level
    lo = stats.beta.ppf(a / 2, k, n - k + 1) if k > 0 else 0.0
    hi = stats.beta.ppf(1 - a / 2, k + 1, n - k) if k < n else 1.0
    return lo, hi


def fmt(k, n):
    lo, hi = cp(k, n)
    return f"{k} / {n} = {k / n:.4f} [{lo:.4f}, {hi:.4f}]"


def pooled(r, F, alpha=ALPHA):
    """Pooled verdicts over consecutive groups of F flights: (chi-square
    only rejected, full verdict rejected) counts and the number of pools."""
    n = (r.flights // F) * F
    T = r.chi2[:n].reshape(-1, F).sum(axis=1)
    d = r.dof[:n].reshape(-1, F).sum(axis=1)
    anyrej = (r.n_reject[:n].reshape(-1, F) > 0).any(axis=1)
    chi = T >= stats.chi2.isf(alpha, d)
    return int(chi.sum()), int((chi | anyrej).sum()), len(T)


def validation(n_size, n_power, outdir):
    fl = igea.simulate(seed=1)
    S, sig, spec, terms = fl.S, fl.sigma, fl.spec, list(fl.terms)
    St = S * spec / sig[:, None]
    lam = np.sort(np.linalg.eigvalsh(St.T @ St))[::-1]
    print(f"model: reference boost 120 s at 50 Hz, epochs 1..120 s, 21-term strapdown "
          f"model, tracking sigma 1 cm/s; eigenvalues >= 10: "
          f"{', '.join('%.4g' % v for v in lam[lam >= 10])}; next {lam[lam < 10][0]:.3g}")
    print(f"alpha = {ALPHA}; intervals are 99% Clopper-Pearson\n")

    print("## Study 1: size (X ~ N(0, I), sigma_w = 1)\n")
    print("| sigma_w correction | verdict 'out of spec' | chi-square rejected | "
          "mean c | mean tested |")
    print("|---|---|---|---|---|")
    res1 = {}
    for corr in (True, False):
        r = igea.montecarlo(S, sig, n_size, spec=spec, seed=101, correction=corr)
        res1[corr] = r
        print(f"| {'on' if corr else 'off'} | {fmt(r.failed, n_size)} | "
              f"{fmt(r.chi2_reject, n_size)} | {r.mean_scale:.4f} | {r.mean_tested:.2f} |")
    print("\nper-component false-alarm rates (correction on):\n")
    print("| component | lambda | tested | rejected, rate [99% CI] |")
    print("|---|---|---|---|")
    r = res1[True]
    for i in np.nonzero(r.comp_tested > 0)[0]:
        if r.comp_tested[i] < 20:
            print(f"| {i + 1} | {lam[i]:.4g} | {r.comp_tested[i]} | "
                  f"{r.comp_reject[i]} (too few to rate) |")
        else:
            print(f"| {i + 1} | {lam[i]:.4g} | {r.comp_tested[i]} | "
                  f"{fmt(int(r.comp_reject[i]), int(r.comp_tested[i]))} |")
    k = int(np.sum(lam >= 10))
    print(f"\nfamily-wise size of {k} independent component tests: "
          f"1 - (1 - alpha)^{k} = {1 - (1 - ALPHA) ** k:.4f}\n")

    print("## Study 2: tracking accuracy misstated (stated sigma 1 cm/s)\n")
    print("| true sigma_w | correction | verdict 'out of spec' | chi-square rejected | "
          "mean c | mean tested |")
    print("|---|---|---|---|---|---|")
    for sw in (1.8, 3.0, 5.0):
        for corr in (False, True):
            r = igea.montecarlo(S, sig, n_size, spec=spec, seed=202, sigma_w=sw,
                                correction=corr)
            print(f"| {sw} | {'on' if corr else 'off'} | {fmt(r.failed, n_size)} | "
                  f"{fmt(r.chi2_reject, n_size)} | {r.mean_scale:.4f} | "
                  f"{r.mean_tested:.2f} |")

    print("\n## Study 3: power (one term at k x spec, the others N(0, 1))\n")
    power_terms = ["acc_bias_x", "acc_scale_y", "acc_mis_zx", "gyro_bias_y", "gyro_g_x",
                   "att0_z"]
    ks = range(7)
    table = {}
    for t in power_terms:
        table[t] = []
        for k in ks:
            r = igea.montecarlo(S, sig, n_power, spec=spec, terms=terms, x={t: float(k)},
                                seed=303)
            table[t].append(r.failed / n_power)
    print("| term | " + " | ".join(f"k={k}" for k in ks) + " |")
    print("|---|" + "---|" * len(ks))
    for t in power_terms:
        print(f"| {t} | " + " | ".join(f"{p:.3f}" for p in table[t]) + " |")
    print(f"\n({n_power} flights per cell; 99% half-width at most "
          f"{2.576 * 0.5 / np.sqrt(n_power):.3f})\n")

    print("pooled flights needed to detect 2 x spec with 90 % probability "
          "(independent units, each with the term at 2 x spec):\n")
    print("| term | flights F (pooled chi-square) | power at F | size of the pooled "
          "chi-square at F | size of the full pooled verdict at F |")
    print("|---|---|---|---|---|")
    fmax = 80
    n_pool = fmax * 200
    h0 = igea.montecarlo(S, sig, n_pool, spec=spec, seed=404)
    for t in power_terms:
        r = igea.montecarlo(S, sig, n_pool, spec=spec, terms=terms, x={t: 2.0}, seed=405)
        found = None
        for F in range(1, fmax + 1):
            chi, full, npools = pooled(r, F)
            if chi / npools >= 0.9:
                found = (F, chi / npools)
                break
        if found is None:
            print(f"| {t} | > {fmax} | | | |")
            continue
        F = found[0]
        c0, f0, n0 = pooled(h0, F)
        print(f"| {t} | {F} | {found[1]:.3f} | {c0 / n0:.3f} | {f0 / n0:.3f} |")

    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("\n(matplotlib not installed: no plots)")
        return
    fig, ax = plt.subplots(figsize=(6, 4))
    for t in power_terms:
        ax.plot(list(ks), table[t], marker="o", label=t)
    ax.axhline(res1[True].failed / n_size, color="grey", ls=":", label="size (X ~ N(0, I))")
    ax.set_xlabel("term error, multiples of spec")
    ax.set_ylabel("P(verdict 'out of spec')")
    ax.set_title("Operating characteristic, one flight")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(outdir, "validation_power.png"), dpi=110)
    print(f"\nwrote {os.path.join(outdir, 'validation_power.png')}")


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--flights", type=int, default=10000)
    ap.add_argument("--validation", action="store_true")
    ap.add_argument("--power-flights", type=int, default=2000)
    ap.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--outdir", default=os.path.join(os.path.dirname(__file__), "..", "docs"))
    a = ap.parse_args()
    if a.validation:
        validation(a.flights, a.power_flights, a.outdir)
    elif a.child:
        benchmark(a.flights)
    else:
        bench_all(a.flights)


if __name__ == "__main__":
    main()
