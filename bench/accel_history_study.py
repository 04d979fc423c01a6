"""Monte Carlo study of the calibration-history prior (docs/accel.md,
"Priors from the calibration history" and "The uncertainty of the
estimated prior").

Each run: a population of instruments of one type, beta_i = beta0 + u_i,
u_i ~ N(0, diag(tau^2)); M past instruments calibrated on the dividing head
(20 positions, 1 arcsec head errors, 1 ug noise) and fitted by the joint
model (all 10 coefficients determined; delta0 dropped); the prior from them
by REML (igea.accel_history, diagonal or --full Sigma); a new instrument
calibrated the same way and fitted by the dual model with that prior
(igea.accel_fit(method="ebr", history=...), igea_accel_fit_history).

Reported per coefficient: the error sd over the runs, the mean plug-in sd
(sd_plugin: the estimated prior taken as known), the mean reported sd, the
median Satterthwaite dof, and the coverage of the truth by
  plug-in   coef +- 1.96 sd_plugin,
  sd        coef +- 1.96 sd,
  interval  [conf_int_lower, conf_int_upper] = coef +- t(sd_dof, 0.975) sd,
each with its 99 % Clopper-Pearson interval; then the K2 error against
prior sd / sqrt(1 + M r), r = prior variance / one calibration's variance.

    PYTHONPATH=python IGEA_LIBRARY=build/lib/libigea.so.1 \\
        nice .venv/bin/python bench/accel_history_study.py --runs 2000 --history 20 [--full]

Long cells in pieces (runs are seeded by (seed, run index), so pieces give
the same runs as one call):

    ... accel_history_study.py --history 200 --first 0 --runs 500 --save h200a.npz
    ... accel_history_study.py --history 200 --first 500 --runs 500 --save h200b.npz
    ... accel_history_study.py --merge h200a.npz h200b.npz

The CPU time of one fit with the history (igea_accel_fit_history: the
posterior, the information, the second-order terms and the dof), the
history given:

    ... accel_history_study.py --history 20 [--full] --cpu 20
"""
import argparse
import time

import numpy as np
from scipy import stats

import igea

BETA0 = np.array([2e-4, -1.5e-4, 3e-4, -2e-4, 5e-5, 2e-5, -1e-5, 1e-5, -2e-5])
TAU = np.array([2e-5, 2e-5, 2e-5, 2e-5, 1e-5, 4e-6, 4e-6, 4e-6, 4e-6])
NAMES = ["KA0", "KB0", "kA1", "kB1", "eta", "KA2", "KB2", "KAio", "KBio"]
PRIOR_DETERMINED = [0, 1, 5, 6, 7, 8]
FIELDS = ("truth", "coef", "sd", "sd_plugin", "sd_dof", "lo", "hi", "tau_hat", "prior_sd",
          "beta0", "v_cal", "capped")


def one_run(th, m, full, seed, r, max_iter):
    rng = np.random.default_rng([seed, r])
    hist = []
    for i in range(m):
        beta = BETA0 + TAU * rng.standard_normal(9)
        ya, yb = igea.accel_simulate(th, np.append(beta, 0.0), head_sd_arcsec=1,
                                     noise_sd=1e-6, seed=(m + 1) * r + i)
        hist.append(igea.accel_joint(th, ya, yb))
    h = igea.accel_history(hist, full=full, max_iter=max_iter)
    bn = BETA0 + TAU * rng.standard_normal(9)
    ya, yb = igea.accel_simulate(th, np.append(bn, 0.0), head_sd_arcsec=1, noise_sd=1e-6,
                                 seed=(m + 1) * r + m)
    f = igea.accel_fit(th, ya, yb, method="ebr", history=h)
    v_cal = np.mean([np.diag(c) for c in h.covariances], axis=0)
    return dict(truth=bn, coef=f.coef, sd=f.sd, sd_plugin=f.sd_plugin, sd_dof=f.sd_dof,
                lo=f.conf_int_lower, hi=f.conf_int_upper, tau_hat=h.tau, prior_sd=f.prior_sd,
                beta0=h.beta0, v_cal=v_cal, capped=np.array([f.capped]))


def cpu_per_fit(th, m, full, seed, reps, max_iter):
    """CPU seconds of one igea.accel_fit(method="ebr", history=h), h from m
    joint fits (run 0's history), the mean over reps calls."""
    rng = np.random.default_rng([seed, 0])
    hist = []
    for i in range(m):
        beta = BETA0 + TAU * rng.standard_normal(9)
        ya, yb = igea.accel_simulate(th, np.append(beta, 0.0), head_sd_arcsec=1,
                                     noise_sd=1e-6, seed=i)
        hist.append(igea.accel_joint(th, ya, yb))
    h = igea.accel_history(hist, full=full, max_iter=max_iter)
    ya, yb = igea.accel_simulate(th, np.append(BETA0 + TAU * rng.standard_normal(9), 0.0),
                                 head_sd_arcsec=1, noise_sd=1e-6, seed=m)
    t0 = time.process_time()
    for _ in range(reps):
        igea.accel_fit(th, ya, yb, method="ebr", history=h)
    return (time.process_time() - t0) / reps


def cp(k, n, level=0.99):
    a = 1 - level
    lo = stats.beta.ppf(a / 2, k, n - k + 1) if k > 0 else 0.0
    hi = stats.beta.ppf(1 - a / 2, k + 1, n - k) if k < n else 1.0
    return lo, hi


def report(d, m, full):
    n = d["coef"].shape[0]
    e = d["coef"] - d["truth"]
    cover = {"plug-in": np.abs(e) <= 1.96 * d["sd_plugin"],
             "sd": np.abs(e) <= 1.96 * d["sd"],
             "interval": (d["lo"] <= d["truth"]) & (d["truth"] <= d["hi"])}
    print("runs %d, history %d calibrations, %s Sigma; capped corrections in %d runs"
          % (n, m, "full" if full else "diagonal", int(np.sum(d["capped"] > 0))))
    print("| coef | tau | mean tau hat | error sd | mean sd_plugin | mean sd | median dof "
          "| plug-in +-1.96 | sd +-1.96 | interval |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for j, name in enumerate(NAMES):
        cells = []
        for key in ("plug-in", "sd", "interval"):
            k = int(cover[key][:, j].sum())
            lo, hi = cp(k, n)
            cells.append("%.3f (%.3f-%.3f)" % (k / n, lo, hi))
        print("| %s%s | %.1e | %.2e | %.3e | %.3e | %.3e | %.1f | %s |" % (
            name, "*" if j in PRIOR_DETERMINED else "", TAU[j], d["tau_hat"][:, j].mean(),
            e[:, j].std(ddof=1), d["sd_plugin"][:, j].mean(), d["sd"][:, j].mean(),
            np.median(d["sd_dof"][:, j]), " | ".join(cells)))
    print("(* prior-determined; coverage with its 99 % Clopper-Pearson interval)")
    for j in (5, 6):
        r = d["prior_sd"][:, j] ** 2 / d["v_cal"][:, j]
        pred = d["prior_sd"][:, j] / np.sqrt(1 + m * r)
        e0 = d["beta0"][:, j] - BETA0[j]
        print("%s: rms error %.3e (new instrument), rms error of beta0 %.3e (type mean); "
              "prior sd %.3e, r %.2f, prior sd / sqrt(1 + %d r) %.3e"
              % (NAMES[j], np.sqrt(np.mean(e[:, j] ** 2)), np.sqrt(np.mean(e0 ** 2)),
                 d["prior_sd"][:, j].mean(), r.mean(), m, pred.mean()))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--runs", type=int, default=2000)
    ap.add_argument("--first", type=int, default=0)
    ap.add_argument("--history", type=int, default=20)
    ap.add_argument("--full", action="store_true")
    ap.add_argument("--seed", type=int, default=17)
    ap.add_argument("--max-iter", type=int, default=200000)
    ap.add_argument("--save", help="write the runs to this .npz")
    ap.add_argument("--merge", nargs="+", help="report the runs of these .npz files")
    ap.add_argument("--cpu", type=int, metavar="REPS",
                    help="only time REPS fits with one history of --history calibrations")
    a = ap.parse_args()
    if a.cpu:
        t = cpu_per_fit(igea.accel_schedule(20), a.history, a.full, a.seed, a.cpu, a.max_iter)
        print("history %d calibrations, %s Sigma: %.1f ms CPU per accel_fit(history=) "
              "(mean of %d)" % (a.history, "full" if a.full else "diagonal", 1e3 * t, a.cpu))
        return
    if a.merge:
        parts = [np.load(f) for f in a.merge]
        m, full = int(parts[0]["history"]), bool(parts[0]["full"])
        d = {k: np.concatenate([p[k] for p in parts]) for k in FIELDS}
        print("failed runs: %d" % sum(int(p["failed"]) for p in parts))
        report(d, m, full)
        return
    th = igea.accel_schedule(20)
    t0 = time.process_time()
    runs, failed = [], []
    for r in range(a.first, a.first + a.runs):
        try:
            runs.append(one_run(th, a.history, a.full, a.seed, r, a.max_iter))
        except igea.IgeaError as e:  # reported, never dropped silently
            failed.append((r, str(e)))
    d = {k: np.array([x[k] for x in runs]) for k in FIELDS}
    print("runs %d-%d: %.0f s CPU; %d failed%s" % (
        a.first, a.first + a.runs - 1, time.process_time() - t0, len(failed),
        "".join("\n  run %d: %s" % f for f in failed)))
    if a.save:
        np.savez(a.save, history=a.history, full=a.full, failed=len(failed), **d)
    report(d, a.history, a.full)


if __name__ == "__main__":
    main()
