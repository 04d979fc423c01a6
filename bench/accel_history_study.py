"""Monte Carlo study of the calibration-history prior (docs/accel.md,
"Priors from the calibration history").

Each run: a population of instruments of one type, beta_i = beta0 + u_i,
u_i ~ N(0, diag(tau^2)); M past instruments calibrated on the dividing head
(20 positions, 1 arcsec head errors, 1 ug noise) and fitted by the joint
model (all 10 coefficients determined; delta0 dropped); the prior from them
by REML (igea.accel_history); a new instrument calibrated the same way and
fitted by the dual model with that prior (igea.accel_fit(method="ebr",
history=...)). Reported per coefficient: the coverage of the truth by
coef +- 1.96 sd with its 95 % binomial (Clopper-Pearson) interval, the sd
of the error over the runs, the mean reported sd, and the mean prior sd.

    PYTHONPATH=python IGEA_LIBRARY=build/lib/libigea.so.1 \\
        nice .venv/bin/python bench/accel_history_study.py [--runs 2000] [--history 20]
"""
import argparse
import time

import numpy as np
from scipy import stats

import igea

BETA0 = np.array([2e-4, -1.5e-4, 3e-4, -2e-4, 5e-5, 2e-5, -1e-5, 1e-5, -2e-5])
TAU = np.array([2e-5, 2e-5, 2e-5, 2e-5, 1e-5, 4e-6, 4e-6, 4e-6, 4e-6])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--runs", type=int, default=2000)
    ap.add_argument("--history", type=int, default=20)
    ap.add_argument("--seed", type=int, default=17)
    a = ap.parse_args()
    th = igea.accel_schedule(20)
    rng = np.random.default_rng(a.seed)
    hit, err, sd, psd, tau_hat = [], [], [], [], []
    t0 = time.time()
    for r in range(a.runs):
        hist = []
        for i in range(a.history):
            beta = BETA0 + TAU * rng.standard_normal(9)
            ya, yb = igea.accel_simulate(th, np.append(beta, 0.0), head_sd_arcsec=1,
                                         noise_sd=1e-6, seed=(a.history + 1) * r + i)
            hist.append(igea.accel_joint(th, ya, yb))
        h = igea.accel_history(hist)
        bn = BETA0 + TAU * rng.standard_normal(9)
        ya, yb = igea.accel_simulate(th, np.append(bn, 0.0), head_sd_arcsec=1, noise_sd=1e-6,
                                     seed=(a.history + 1) * r + a.history)
        f = igea.accel_fit(th, ya, yb, method="ebr", history=h)
        e = f.coef - bn
        hit.append(np.abs(e) <= 1.96 * f.sd)
        err.append(e)
        sd.append(f.sd)
        psd.append(f.prior_sd)
        tau_hat.append(h.tau)
    hit, err = np.array(hit), np.array(err)
    n = a.runs
    print("runs %d, history %d calibrations, %.1f s" % (n, a.history, time.time() - t0))
    print("| coef | truth tau | mean tau hat | mean prior sd | error sd | mean reported sd "
          "| coverage (95 % interval) |")
    print("|---|---|---|---|---|---|---|")
    for j, name in enumerate(f.names):
        k = int(hit[:, j].sum())
        lo = stats.beta.ppf(0.025, k, n - k + 1) if k > 0 else 0.0
        hi = stats.beta.ppf(0.975, k + 1, n - k) if k < n else 1.0
        print("| %s | %.2e | %.2e | %.2e | %.3e | %.3e | %.3f (%.3f-%.3f) |" % (
            name, TAU[j], np.mean(np.array(tau_hat)[:, j]), np.mean(np.array(psd)[:, j]),
            err[:, j].std(ddof=1), np.mean(np.array(sd)[:, j]), k / n, lo, hi))


if __name__ == "__main__":
    main()
