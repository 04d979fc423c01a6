#!/usr/bin/env python3
"""The two figures of docs/redundancy.md (seed 002), drawn with igea.

    PYTHONPATH=python IGEA_LIBRARY=build/lib/libigea.so.1 \
        python examples/redund_plots.py [--outdir docs]

(a) redund_adev.png: overlapping Allan deviation of a simulated gyro record
    (igea.allan: octave taus, 68.3 % EDF confidence intervals, noise type
    identified per tau) with the random walk and rate random walk that
    igea.noise_id reads from the curve. The record: 2 h at 100 Hz of a 1 deg/h
    rate with white rate noise (0.5 deg/h per sample) and a rate random walk
    (2e-4 deg/h per sample), numpy generator seed 1.
(b) redund_exclusions.png: the windowed consistency check of the seed's
    experiment (igea.simulate_redundant, igea.series_check): 4 X
    accelerometers at 1 g with offsets of a few micro-g, 30 micro-g noise at
    100 Hz, 10 mg added to Ax4 from 100 s to 120 s (GSL mt19937, seed 2024),
    1 s windows, sigma 20 micro-g, alpha 0.7. Top: the window means and the
    fused value; bottom: when each sensor is excluded from the fusion set.

Needs numpy and matplotlib. The numbers behind the figures are printed too.
"""
import argparse
import os

import numpy as np

import igea

HERE = os.path.dirname(os.path.abspath(__file__))


def adev_figure(plt, path):
    fs, hours = 100.0, 2.0
    n = int(hours * 3600 * fs)
    rng = np.random.default_rng(1)
    y = 1.0 + rng.normal(0.0, 0.5, n) + np.cumsum(rng.normal(0.0, 2e-4, n))  # deg/h
    r = igea.allan(y, fs)
    terms = igea.noise_id(r.taus, r.dev)
    print(r.summary())
    print(terms.summary())

    fig, ax = plt.subplots(figsize=(6, 4.2))
    ax.fill_between(r.taus, r.lo, r.hi, color="C0", alpha=0.25,
                    label="%.1f %% confidence interval (EDF)" % (100 * r.conf))
    ax.loglog(r.taus, r.dev, "o-", color="C0", ms=4, label="overlapping Allan deviation")
    t = np.geomspace(r.taus[0], r.taus[-1], 50)
    if np.isfinite(terms.random_walk):
        ax.loglog(t, terms.random_walk / np.sqrt(t), "--", color="C1",
                  label="random walk N = %.3g (°/h)·√s" % terms.random_walk)
    if np.isfinite(terms.rate_random_walk):
        ax.loglog(t, terms.rate_random_walk * np.sqrt(t / 3.0), "--", color="C2",
                  label="rate random walk K = %.3g (°/h)/√s" % terms.rate_random_walk)
    if np.isfinite(terms.bias_instability):
        ax.axhline(0.6643 * terms.bias_instability, ls=":", color="C4",
                   label="bias instability B = %.3g °/h (0.6643 B)" % terms.bias_instability)
    lo = np.nanmin(r.lo[r.lo > 0])
    ax.set_ylim(lo / 2, np.nanmax(r.hi) * 2)
    ax.set_xlabel("averaging time τ (s)")
    ax.set_ylabel("Allan deviation (°/h)")
    ax.set_title("Simulated gyro, 2 h at 100 Hz: Allan deviation")
    ax.grid(True, which="major", alpha=0.3)
    ax.legend(fontsize=8, loc="upper center")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
    print("wrote", os.path.normpath(path))


def exclusions_figure(plt, path):
    fs, sigma = 100.0, 20e-6
    rec = igea.simulate_redundant(20000, fs, [1.000004, 1.000001, 0.999998, 1.000003], 30e-6,
                                  fault_sensor=3, t0=100, t1=120, bias=0.010, seed=2024)
    c = igea.series_check(rec, fs, 1.0, sigma, 0.7)
    print(c.summary(), "(sensors counted from 0: sensor 3 is Ax4)")
    nsens = c.excluded.shape[1]
    names = ["Ax%d" % (s + 1) for s in range(nsens)]
    tmid = c.t + 0.5 * c.window

    fig, (ax0, ax1) = plt.subplots(2, 1, figsize=(7, 5), sharex=True,
                                   gridspec_kw={"height_ratios": [2, 1]})
    for s in range(nsens):
        ax0.plot(tmid, (c.means[:, s] - 1.0) * 1e3, lw=1, label=names[s])
    ax0.plot(tmid, (c.fused - 1.0) * 1e3, "k--", lw=1.2, label="fused")
    ax0.set_ylabel("window mean - 1 g (mg)")
    ax0.set_title("Seed 002's experiment: 10 mg on Ax4 from 100 s to 120 s\n"
                  "4 X accelerometers, 30 µg noise at 100 Hz; 1 s windows, σ = 20 µg, α = 0.7",
                  fontsize=10)
    ax0.legend(fontsize=8, ncol=5, loc="upper left")
    ax0.set_ylim(-1.0, 12.0)
    ax0.grid(True, alpha=0.3)

    for s in range(nsens):
        spans = [(a, b - a) for sens, a, b in c.intervals() if sens == s]
        ax1.broken_barh([(0.0, c.t[-1] + c.window)], (s + 0.6, 0.8), color="0.9")
        if spans:
            ax1.broken_barh(spans, (s + 0.6, 0.8), color="C3")
    ax1.set_yticks(np.arange(1, nsens + 1))
    ax1.set_yticklabels(names)
    ax1.set_ylim(nsens + 0.5, 0.5)
    ax1.set_xlim(0.0, c.t[-1] + c.window)
    ax1.set_xlabel("time (s)")
    ax1.set_ylabel("excluded (red)")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
    print("wrote", os.path.normpath(path))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--outdir", default=os.path.join(HERE, "..", "docs"))
    a = ap.parse_args()
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    adev_figure(plt, os.path.join(a.outdir, "redund_adev.png"))
    exclusions_figure(plt, os.path.join(a.outdir, "redund_exclusions.png"))


if __name__ == "__main__":
    main()
