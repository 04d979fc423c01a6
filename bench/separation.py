#!/usr/bin/env python3
"""The estimator comparison of docs/separation.md (seeds 000 and 003).

Part A - seed 000's question, on the bundled flight's environment functions
(examples/flight/S.txt, 360 rows x 18 terms, specs and tracking sigma from
the same directory): many simulated flights of an IN-SPEC system, truth
X ~ N(0, I) in spec units, white tracking noise of the stated sigma. For
each estimator: the MSE of every coefficient (spec units) and how often the
flight is wrongly called out of spec, next to the equivalent-error test's
false-alarm rate (igea.eqerr, alpha = 0.01, tracking correction off: the
noise sigma is known exactly here).

Part B - seed 003's question, on the 20-position dual-accelerometer design
(METHODS 4.2, exactly rank 7): MSE of LS (minimum norm), isotropic EBR,
prior-scaled EBR and a Bayesian estimate per coefficient, split into the
estimable coefficients and the null-space ones.

    PYTHONPATH=python IGEA_LIBRARY=build/lib/libigea.so.1 \
        .venv/bin/python bench/separation.py [--flights 500] [--seed 1]

Prints markdown tables (pasted into docs/separation.md); if matplotlib is
installed, also writes docs/separation_mse.png.
"""
import argparse
import os
import time

import numpy as np

import igea

HERE = os.path.dirname(os.path.abspath(__file__))
FLIGHT = os.path.join(HERE, "..", "examples", "flight")
Z995 = 2.5758293035489004  # z_{1 - 0.01/2}


def load_flight():
    S = np.loadtxt(os.path.join(FLIGHT, "S.txt"))
    spec = np.loadtxt(os.path.join(FLIGHT, "spec.txt")).ravel()
    sigma = np.loadtxt(os.path.join(FLIGHT, "sigma.txt")).ravel()
    with open(os.path.join(FLIGHT, "spec.txt")) as f:
        names = f.readlines()[1].split(":", 1)[1].split()
    return S, spec, sigma, names


def part_a(nflights, seed, shift=None):
    S, spec, sigma, names = load_flight()
    m, N = S.shape
    A = S * spec / sigma[:, None]  # whitened, spec-scaled: X in spec units, unit noise
    rng = np.random.default_rng(seed)
    methods = ["LS", "ridge GCV", "ridge HKB", "PCE (d>=1)", "Bayes N(0,I)", "EBR SC",
               "EBR MM", "EBR ML2"]
    err = {k: np.zeros((nflights, N)) for k in methods}
    out_naive = {k: 0 for k in methods}   # any |x_j| > 3 spec
    out_z = {k: 0 for k in methods}       # any |x_j| > z sqrt(1 + sd_j^2)
    eq_reject = 0
    n_test = []
    t0 = time.time()
    for f in range(nflights):
        X = rng.standard_normal(N)
        if shift:
            for nm, v in shift.items():
                X[names.index(nm)] = v
        y = A @ X + rng.standard_normal(m)
        est = {}
        r = igea.ls(A, y)
        est["LS"] = (r.x, r.sd)
        r = igea.ridge(A, y, rule="gcv")
        est["ridge GCV"] = (r.x, r.sd)
        r = igea.ridge(A, y, rule="hkb")
        est["ridge HKB"] = (r.x, r.sd)
        r = igea.pce(A, y, eig_min=1.0)
        est["PCE (d>=1)"] = (r.x, r.sd)
        r = igea.bayes(A, y, np.eye(N))
        est["Bayes N(0,I)"] = (r.x, r.sd)
        r = igea.ebr(A, y, rule="sc")
        est["EBR SC"] = (r.x, r.sd)
        r = igea.ebr(A, y, rule="mm")
        est["EBR MM"] = (r.x, r.sd)
        r = igea.ebr(A, y, rule="ml2")
        est["EBR ML2"] = (r.x, r.sd)
        for k, (x, sd) in est.items():
            err[k][f] = x - X
            out_naive[k] += bool(np.any(np.abs(x) > 3.0))
            out_z[k] += bool(np.any(np.abs(x) > Z995 * np.sqrt(1.0 + sd ** 2)))
        q = igea.eqerr(S, y * sigma, sigma, spec, correction=False)
        eq_reject += not q.passed
        n_test.append(q.n_test)
    elapsed = time.time() - t0
    mse = {k: np.mean(v ** 2, axis=0) for k, v in err.items()}
    lam = np.linalg.svd(A, compute_uv=False) ** 2
    return dict(names=names, methods=methods, mse=mse, out_naive=out_naive, out_z=out_z,
                eq_reject=eq_reject, n_test=np.mean(n_test), n=nflights, shift=shift, elapsed=elapsed, lam=lam, m=m, N=N,
                cond=igea.collinearity(A).cond)


def part_b(ncal, seed):
    th = np.deg2rad(18.0 * np.arange(20))
    s, c = np.sin(th), np.cos(th)
    A = np.column_stack([s, c, s * s, c * c, -s * c, s ** 3, c ** 3, s * s * c, -s * c * c])
    names = ["K_A0", "K_B0", "k_A1", "k_B1", "eta", "K_A2", "K_B2", "K_Aix", "K_Bix"]
    beta = np.array([2, -1.5, 3, -2, 0.5, 0.2, -0.1, 0.1, -0.2]) * 1e-4   # METHODS 4.3
    tau = np.array([1e-4, 1e-4, 3e-4, 3e-4, 1e-4, 2e-5, 2e-5, 2e-5, 2e-5])  # historical spread
    noise = 1e-6
    rng = np.random.default_rng(seed)
    methods = ["LS min-norm", "EBR isotropic", "EBR prior-scaled", "Bayes N(0, tau^2)"]
    err = {k: np.zeros((ncal, 9)) for k in methods}
    for i in range(ncal):
        y = A @ beta + noise * rng.standard_normal(20)
        err["LS min-norm"][i] = igea.ls(A, y).x - beta
        err["EBR isotropic"][i] = igea.ebr(A, y).x - beta
        err["EBR prior-scaled"][i] = igea.ebr(A, y, spec=tau).x - beta
        err["Bayes N(0, tau^2)"][i] = igea.bayes(A, y, np.diag(tau ** 2), sigma=noise).x - beta
    coll = igea.collinearity(A, names=names)
    return dict(names=names, methods=methods, beta=beta,
                rmse={k: np.sqrt(np.mean(v ** 2, axis=0)) for k, v in err.items()},
                bias={k: np.mean(v, axis=0) for k, v in err.items()},
                prior=coll.prior_determined, n=ncal)


def report_a(a):
    what = ("in-spec flights" if not a["shift"] else "out-of-spec flights ("
            + ", ".join("%s = %g spec" % kv for kv in a["shift"].items()) + ")")
    print("## Part A: %s, %d rows x %d terms, %d flights (%.1f s)"
          % (what, a["m"], a["N"], a["n"], a["elapsed"]))
    print("condition number of the whitened spec-scaled design: %.3e; eigenvalues of the normal "
          "matrix %.3e ... %.3e, %d of them below 1"
          % (a["cond"], a["lam"][0], a["lam"][-1], int(np.sum(a["lam"] < 1))))
    print()
    print("| estimator | mean MSE (spec^2) | max MSE | flights called out of spec: any abs(x_j) > 3 |"
          " any abs(x_j) > 2.576 sqrt(1+sd_j^2) |")
    print("|---|---|---|---|---|")
    for k in a["methods"]:
        print("| %s | %.3g | %.3g | %.1f %% | %.1f %% |"
              % (k, np.mean(a["mse"][k]), np.max(a["mse"][k]), 100.0 * a["out_naive"][k] / a["n"],
                 100.0 * a["out_z"][k] / a["n"]))
    print("| equivalent-error test (alpha 0.01, %.1f components tested on average) | - | - | "
          "%.1f %% (rejected) | |" % (a["n_test"], 100.0 * a["eq_reject"] / a["n"]))
    print()
    if a["shift"]:
        return
    print("MSE per coefficient (spec units squared; the prior variance of a coefficient is 1):")
    print()
    print("| term | " + " | ".join(a["methods"]) + " |")
    print("|---|" + "---|" * len(a["methods"]))
    for j, nm in enumerate(a["names"]):
        print("| %s | " % nm + " | ".join("%.3g" % a["mse"][k][j] for k in a["methods"]) + " |")
    print()


def report_b(b):
    print("## Part B: dual-accelerometer 20-position design (rank 7), %d calibrations, "
          "noise 1 ug" % b["n"])
    print()
    print("RMS error / mean error per coefficient (units of 1e-6 g or 1e-6 rad):")
    print()
    print("| term | truth | determined by | " + " | ".join(b["methods"]) + " |")
    print("|---|---|---|" + "---|" * len(b["methods"]))
    for j, nm in enumerate(b["names"]):
        print("| %s | %.0f | %s | " % (nm, b["beta"][j] * 1e6, "PRIOR" if b["prior"][j] else "data")
              + " | ".join("%.3g / %+.3g" % (b["rmse"][k][j] * 1e6, b["bias"][k][j] * 1e6)
                           for k in b["methods"]) + " |")
    print()


def plot(a):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return
    fig, ax = plt.subplots(figsize=(10, 4))
    w = 0.8 / len(a["methods"])
    for i, k in enumerate(a["methods"]):
        ax.bar(np.arange(a["N"]) + i * w, a["mse"][k], w, label=k)
    ax.set_yscale("log")
    ax.set_xticks(np.arange(a["N"]) + 0.4)
    ax.set_xticklabels(a["names"], rotation=60, fontsize=7)
    ax.set_ylabel("MSE (spec units^2)")
    ax.set_title("MSE of each estimator per coefficient over simulated in-spec flights")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(HERE, "..", "docs", "separation_mse.png"), dpi=110)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--flights", type=int, default=500)
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args()
    a = part_a(args.flights, args.seed)
    report_a(a)
    report_a(part_a(args.flights, args.seed + 10, {"acc_bias_y": 4.0}))
    report_a(part_a(args.flights, args.seed + 20, {"gyro_gi_z": 4.0}))
    report_b(part_b(2000, args.seed + 1))
    plot(a)


if __name__ == "__main__":
    main()
