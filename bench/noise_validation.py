#!/usr/bin/env python3
"""The noise-model studies of docs/validation.md ("Tracking noise beyond a
diagonal K, and outliers") in one command, through igea.montecarlo on the
reference flight (120 epochs, 21 terms, sigma 1 cm/s):

    OPENBLAS_NUM_THREADS=1 PYTHONPATH=python IGEA_LIBRARY=build/lib/libigea.so.1 \\
      .venv/bin/python bench/noise_validation.py --flights 10000

Prints, per cell, the chi-square size (or the power) with its 99 % Wilson
interval (the library's igea_sim_interval), and with matplotlib installed
writes noise_size_phi.png and noise_power.png into --outdir.
"""
import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "python"))
import igea  # noqa: E402


def cell(name, r, what="chi2_reject"):
    k = getattr(r, what)
    lo, hi = r.ci99[what]
    extra = ""
    if r.scale_covered:
        extra += "; scale covered %d / %d" % (r.scale_covered, r.flights)
    if r.mean_outliers:
        extra += "; %.2f rows rejected per flight" % r.mean_outliers
    print("| %s | %s | %d / %d = %.4f [%.4f, %.4f]%s |" % (name, what, k, r.flights,
                                                         k / r.flights, lo, hi, extra))
    return k / r.flights, lo, hi


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--flights", type=int, default=2000)
    ap.add_argument("--threads", type=int, default=0)
    ap.add_argument("--outdir", default="docs")
    a = ap.parse_args()
    fl = igea.simulate(seed=1)
    S, sig, spec, terms = fl.S, fl.sigma, fl.spec, list(fl.terms)
    n, th = a.flights, a.threads

    def mc(**kw):
        return igea.montecarlo(S, sig, n, spec=spec, terms=terms, threads=th, seed=11, **kw)

    print("| cell | rate | value [99 % Wilson] |\n|---|---|---|")
    phis = (0.0, 0.5, 0.9, 0.98)
    seed_j = [cell("AR(1) phi=%g, seed's judge" % p, mc(ar1=p)) for p in phis]
    ar_j = [cell("AR(1) phi=%g, phi estimated" % p, mc(ar1=p, ar=1)) for p in phis]
    cell("3x3 correlation up to 0.9, judge told", mc(corr=0.9, judge_noise=True))
    cell("two stations, sigma_w 1 and 3, judge told",
         mc(group_split=0.5, sigma_w2=3.0, judge_noise=True))
    out = dict(outlier_prob=0.01, outlier_scale=30.0)
    cell("1 % rows at 30 sigma, robust", mc(robust=True, **out))
    power = {}
    for rob in (False, True):
        for o in (False, True):
            kw = dict(out) if o else {}
            r = mc(x={"gyro_bias_y": 4.0}, robust=rob or None, **kw)
            power[rob, o] = cell("power gyro_bias_y 4x, %s, %s" % (
                "robust" if rob else "seed's judge", "1 % outliers" if o else "clean"), r,
                "failed")
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("\n(matplotlib not installed: no plots)")
        return
    fig, ax = plt.subplots(figsize=(5, 3.5))
    for rows, lab in ((seed_j, "seed's judge"), (ar_j, "AR(1), phi estimated")):
        v = np.array(rows)
        ax.errorbar(phis, v[:, 0], yerr=[v[:, 0] - v[:, 1], v[:, 2] - v[:, 0]], marker="o",
                    capsize=3, label=lab)
    ax.axhline(0.01, color="k", lw=0.8)
    ax.set_xlabel("AR(1) phi")
    ax.set_ylabel("chi-square size (alpha = 0.01)")
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(a.outdir, "noise_size_phi.png"), dpi=120)
    fig, ax = plt.subplots(figsize=(5, 3.5))
    labels = ["clean", "1 % outliers"]
    for rob in (False, True):
        v = np.array([power[rob, o] for o in (False, True)])
        ax.errorbar([0, 1], v[:, 0], yerr=[v[:, 0] - v[:, 1], v[:, 2] - v[:, 0]], marker="o",
                    capsize=3, label="robust" if rob else "seed's judge")
    ax.set_xticks([0, 1], labels)
    ax.set_ylabel("power, gyro_bias_y at 4 x spec")
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(a.outdir, "noise_power.png"), dpi=120)


if __name__ == "__main__":
    main()
