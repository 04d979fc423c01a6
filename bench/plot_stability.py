"""One picture per family of stability statistics on a simulated record with
known noise: white rate N, flicker rate (bias instability) B and rate random
walk K (2^16 samples at 1 Hz), with the IEEE 952 model of the known terms
where the statistic estimates the Allan variance. Writes docs/stability_*.png.

    PYTHONPATH=python IGEA_LIBRARY=build/lib/libigea.so.1 .venv/bin/python bench/plot_stability.py

(TTOTDEV over every octave of the whole record is O(N m) per tau: about a
minute of CPU; the total family and the Theo statistics use the first 2^13
samples.)
"""
import math
import os

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import igea  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
DOCS = os.path.join(HERE, "..", "docs")
N, B, K, FS, NS = 1e-2, 1e-3, 1e-5, 1.0, 2 ** 16
C_B = 2 * math.log(2) / math.pi


def flicker(rng, n):
    """Kasdin and Walter's flicker FM (spectrum 1 / (pi f))."""
    k = np.arange(1, n)
    h = np.concatenate([[1.0], np.cumprod((k - 0.5) / k)])
    P = 1 << int(np.ceil(np.log2(2 * n)))
    return np.fft.irfft(np.fft.rfft(h, P) * np.fft.rfft(rng.standard_normal(n), P), P)[:n]


def model(t):
    return np.sqrt(N * N / t + C_B * B * B + K * K * t / 3)


def panel(ax, y, kinds, title, allan_model):
    for kind in kinds:
        r = igea.stability(y, FS, kind=kind)
        if r.lo is not None:
            ax.errorbar(r.taus, r.dev, yerr=[r.dev - r.lo, r.hi - r.dev], fmt="o-", ms=3,
                        capsize=2, label=kind)
        else:
            ax.plot(r.taus, r.dev, "o-", ms=3, label=kind)
    if allan_model:
        t = np.logspace(0, math.log10(NS / 2), 200)
        ax.plot(t, model(t), "k--", lw=1, label="model of the known N, B, K")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("tau (s)")
    ax.set_title(title)
    ax.grid(True, which="both", lw=0.3)
    ax.legend(fontsize=8)


def main():
    rng = np.random.default_rng(2024)
    y = (N * math.sqrt(FS) * rng.standard_normal(NS) + B * flicker(rng, NS) +
         np.cumsum(K / math.sqrt(FS) * rng.standard_normal(NS)))
    families = [
        ("allan", ["adev", "oadev", "mdev"], "Allan family: ADEV, OADEV, MDEV", True, "deviation"),
        ("hadamard", ["hdev", "ohdev"], "Hadamard family: HDEV, OHDEV", True, "deviation"),
        ("total", ["totdev", "mtotdev", "htotdev"], "Total family: TOTDEV, MTOTDEV, HTOTDEV",
         True, "deviation"),
        ("theo", ["theo1", "theobr", "theoh", "oadev"],
         "Theo1, TheoBR, TheoH against OADEV", True, "deviation"),
        ("time", ["tdev", "ttotdev", "tierms", "mtie"], "Time deviations: TDEV, TTOTDEV, "
         "TIE rms, MTIE", False, "seconds of time error"),
    ]
    for name, kinds, title, mod, ylabel in families:
        fig, ax = plt.subplots(figsize=(6.4, 4.4))
        if name in ("total", "theo"):   # O(N m), O(N^3): a shorter record
            panel(ax, y[:2 ** 13], kinds, title + " (first 2^13 samples)", mod)
        else:
            panel(ax, y, kinds, title, mod)
        ax.set_ylabel(ylabel)
        fig.text(0.01, 0.01, "white rate N = %g, flicker B = %g, random walk K = %g; %d samples "
                 "at %g Hz; 68.3 %% intervals" % (N, B, K, NS, FS), fontsize=7)
        fig.tight_layout(rect=(0, 0.03, 1, 1))
        out = os.path.join(DOCS, "stability_%s.png" % name)
        fig.savefig(out, dpi=90)
        plt.close(fig)
        print("wrote", os.path.normpath(out))


if __name__ == "__main__":
    main()
