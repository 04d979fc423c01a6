"""The seed's LS / EBR comparison (seed 003, Tables 1-2) rebuilt by simulation.

    PYTHONPATH=python python examples/accel_montecarlo.py [--runs 2000] [--seed 1]

Each run simulates one calibration of an orthogonal accelerometer pair on the
exact models (1)-(2) of METHODS 4.2 (20 equispaced positions, one reading
per position, 1 arcsec head angle error per reading, 1 micro-g noise on each
output; truth = METHODS 4.3's coefficients, installation angle 0) and fits it
four ways: single-accelerometer LS (A only), dual LS (minimum norm), dual
EBR with the isotropic prior, dual EBR with a historical prior scale
(1e-4 for biases, scale corrections and eta, 1e-5 for K2 and the
cross-couplings). Printed: mean and standard deviation over the runs of each
coefficient and of each estimable combination, the mean reported sd, the
mean residual rms; then the exact-model refinement at mg-level biases.
The tables in docs/accel.md are this script's output.
"""
import argparse
import time

import numpy as np

import igea
from igea.accel import coefficient_names, combination_names

TRUTH = np.array([2e-4, -1.5e-4, 3e-4, -2e-4, 0.5e-4, 0.2e-4, -0.1e-4, 0.1e-4, -0.2e-4])
TAU = np.array([1e-4] * 5 + [1e-5] * 4)
SINGLE_TO_DUAL = {0: 0, 1: 2, 3: 5, 4: 7}  # K0->KA0, k1->kA1, K2->KA2, Kio->KAio


def fmt(x):
    return "%.3e" % x


def run(n_runs, seed0, truth, delta0=0.0, head=1.0, noise=1e-6):
    th = igea.accel_schedule(20)
    tr = np.append(truth, delta0)
    fits = {"single LS": [], "dual LS": [], "dual EBR": [], "dual EBR prior": []}
    for k in range(n_runs):
        ya, yb = igea.accel_simulate(th, tr, head_sd_arcsec=head, noise_sd=noise, seed=seed0 + k)
        fits["single LS"].append(igea.accel_fit(th, ya, model="single"))
        fits["dual LS"].append(igea.accel_fit(th, ya, yb))
        fits["dual EBR"].append(igea.accel_fit(th, ya, yb, method="ebr"))
        fits["dual EBR prior"].append(igea.accel_fit(th, ya, yb, method="ebr", prior_scale=TAU))
    return fits


def coefficient_table(fits, truth):
    names = coefficient_names("dual")
    single_names = coefficient_names("single")
    print("| estimator | " + " | ".join(names) + " | delta0 | residual rms |")
    print("|---|" + "---|" * (len(names) + 2))
    print("| truth | " + " | ".join(fmt(v) for v in truth) + " | 0 | |")
    for key, fl in fits.items():
        C = np.array([f.coef for f in fl])
        mean, sd = C.mean(0), C.std(0, ddof=1)
        rms = np.mean([f.rms for f in fl])
        if key == "single LS":
            cells = ["—"] * 9
            for j, jd in SINGLE_TO_DUAL.items():
                cells[jd] = "%s ± %s" % (fmt(mean[j]), fmt(sd[j]))
            d0 = "%s ± %s" % (fmt(mean[2]), fmt(sd[2]))
        else:
            cells = ["%s ± %s%s" % (fmt(mean[j]), fmt(sd[j]), "" if fl[0].flags[j] == "data"
                                    else " (P)") for j in range(9)]
            d0 = "—"
        print("| %s | %s | %s | %s |" % (key, " | ".join(cells), d0, fmt(rms)))
    print("\n(P): flagged prior-determined. Single LS columns: K0, k1, K2, Kio of A "
          "(%s)." % ", ".join(single_names))


def combination_table(fits, truth):
    Cm = igea.accel_combinations()
    want = Cm.T @ truth
    names = combination_names("dual")
    print("| estimator | " + " | ".join(names) + " |")
    print("|---|" + "---|" * len(names))
    print("| truth | " + " | ".join(fmt(v) for v in want) + " |")
    for key in ["dual LS", "dual EBR", "dual EBR prior"]:
        fl = fits[key]
        M = np.array([f.comb for f in fl])
        S = np.array([f.comb_sd for f in fl])
        print("| %s: mean | %s |" % (key, " | ".join(fmt(v) for v in M.mean(0))))
        print("| %s: bias (mean - truth) | %s |" % (key, " | ".join(
            "%.1e" % v for v in M.mean(0) - want)))
        print("| %s: sd over runs | %s |" % (key, " | ".join(fmt(v) for v in M.std(0, ddof=1))))
        print("| %s: mean reported sd | %s |" % (key, " | ".join(fmt(v) for v in S.mean(0))))
    fl = fits["single LS"]
    M = np.array([f.coef for f in fl])
    print("\nsingle LS, sd over runs: K0 %s, k1 %s, delta0 %s, K2 %s, Kio %s"
          % tuple(fmt(v) for v in M.std(0, ddof=1)))
    print("single LS, mean reported sd: " + ", ".join(
        fmt(v) for v in np.mean([f.sd for f in fl], 0)))


def refine_table(n_runs, seed0):
    th = igea.accel_schedule(20)
    truth = np.array([1.2e-3, -0.9e-3, 3e-4, -2e-4, 0.5e-4, 0.2e-4, -0.1e-4, 0.1e-4, -0.2e-4])
    tr = np.append(truth, 4e-4)
    Cm = igea.accel_combinations()
    want = Cm.T @ truth
    lin, ref = [], []
    for k in range(n_runs):
        ya, yb = igea.accel_simulate(th, tr, head_sd_arcsec=1.0, noise_sd=1e-6, seed=seed0 + k)
        f = igea.accel_fit(th, ya, yb)
        r = igea.accel_refine(th, ya, yb, f.coef)
        lin.append(f.comb - want)
        ref.append(r.comb - want)
    lin, ref = np.array(lin), np.array(ref)
    names = combination_names("dual")
    print("| error of | " + " | ".join(names) + " |")
    print("|---|" + "---|" * len(names))
    for key, E in [("linear g² LS", lin), ("refined (exact model)", ref)]:
        print("| %s: mean | %s |" % (key, " | ".join(fmt(v) for v in E.mean(0))))
        print("| %s: sd | %s |" % (key, " | ".join(fmt(v) for v in E.std(0, ddof=1))))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--runs", type=int, default=2000)
    ap.add_argument("--seed", type=int, default=1)
    a = ap.parse_args()
    t0 = time.time()
    fits = run(a.runs, a.seed, TRUTH)
    lam = np.array([f.lam for f in fits["dual EBR"]])
    lamp = np.array([f.lam for f in fits["dual EBR prior"]])
    print("## %d simulated calibrations (20 positions, 1\" head errors, 1 µg noise)\n" % a.runs)
    coefficient_table(fits, TRUTH)
    print("\nEBR lambda: isotropic median %.3g (5-95 %%: %.3g-%.3g); prior-scaled median %.3g\n"
          % (np.median(lam), np.percentile(lam, 5), np.percentile(lam, 95), np.median(lamp)))
    combination_table(fits, TRUTH)
    n_ref = max(a.runs // 2, 200)
    print("\n## exact-model refinement, mg-level biases (KA0 = 1.2e-3, KB0 = -0.9e-3, "
          "delta0 = 4e-4), %d runs\n" % n_ref)
    refine_table(n_ref, a.seed + 100000)
    print("\n(%.1f s)" % (time.time() - t0))


if __name__ == "__main__":
    main()
