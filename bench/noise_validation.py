#!/usr/bin/env python3
"""The noise-model studies of docs/validation.md ("Tracking noise beyond a
diagonal K, and outliers") in one command, through igea.montecarlo on the
reference flight (120 epochs, 21 terms, sigma 1 cm/s):

    OPENBLAS_NUM_THREADS=1 PYTHONPATH=python IGEA_LIBRARY=build/lib/libigea.so.1 \\
      .venv/bin/python bench/noise_validation.py --flights 10000 --threads 1

Prints, per cell, the chi-square size (or the power) with its exact 99 %
Clopper-Pearson interval (igea_sim_interval_cp; the Wilson one of
igea_sim_interval is in the JSON lines), the cell's CPU time, and appends
one JSON line per cell to --results. --cells NAME,... runs some cells only
(names below; a name that is not a cell's selects the family it begins:
"ar1_ls", "ar1_reml", "power", "curve"); "naming", "phi_bias" (phi-hat's
bias by least squares and by REML, flight by flight) and "ar_robust" (phi-hat
with outliers and the robust route against the same flight without them,
flight by flight) are asked by name;
--plot-only draws noise_size_phi.png (size against phi), noise_power.png
(power at 4 x spec with and without the robust route) and
noise_power_curve.png (power against the term's size) into --outdir from
the --results files.

The naming cell runs flight by flight through igea.simulate and
igea.eqerr: among the flights where a component is rejected, how often
gyro_bias_y (true value 4 x spec) is one of that component's candidate
terms (share >= 10 %).
"""
import argparse
import json
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "python"))
import igea  # noqa: E402
from igea.sim import interval_cp  # noqa: E402

OUT = dict(outlier_prob=0.01, outlier_scale=30.0)
PHIS = (0.0, 0.5, 0.9, 0.98)
CURVE = (1, 2, 3, 4, 5)


def cells():
    """name -> (label, montecarlo keywords, the count reported)."""
    c = {}
    for p in PHIS:
        c["ar1_seed_%g" % p] = ("AR(1) phi=%g, seed's judge" % p, dict(ar1=p), "chi2_reject")
        c["ar1_ls_%g" % p] = ("AR(1) phi=%g, phi by least squares" % p,
                              dict(ar1=p, ar=1, ar_method="ls"), "chi2_reject")
        c["ar1_reml_%g" % p] = ("AR(1) phi=%g, phi by REML" % p,
                                dict(ar1=p, ar=1, ar_method="reml"), "chi2_reject")
    c["ar2_ls"] = ("AR(2) phi=(0.6, 0.3), phi by least squares",
                   dict(ar1=0.6, ar2=0.3, ar=2, ar_method="ls"), "chi2_reject")
    c["ar3_ls"] = ("AR(3) phi=(0.5, 0.2, 0.2), phi by least squares",
                   dict(ar1=0.5, ar2=0.2, ar3=0.2, ar=3, ar_method="ls"), "chi2_reject")
    c["ar2_reml"] = ("AR(2) phi=(0.6, 0.3), phi by REML", dict(ar1=0.6, ar2=0.3, ar=2,
                                                              ar_method="reml"), "chi2_reject")
    c["ar3_reml"] = ("AR(3) phi=(0.5, 0.2, 0.2), phi by REML",
                     dict(ar1=0.5, ar2=0.2, ar3=0.2, ar=3, ar_method="reml"), "chi2_reject")
    for meth in ("ls", "reml"):  # phi estimated together with the other noise models
        c["mixed_robust_%s" % meth] = (
            "AR(1) phi=0.9 and 1 %% rows at 30 sigma, robust, phi by %s" % meth,
            dict(ar1=0.9, ar=1, ar_method=meth, robust=True, **OUT), "chi2_reject")
        c["mixed_stations_%s" % meth] = (
            "AR(1) phi=0.9, two stations sigma_w 1 and 3, phi by %s" % meth,
            dict(ar1=0.9, ar=1, ar_method=meth, group_split=0.5, sigma_w2=3.0,
                 judge_noise=True), "chi2_reject")
        c["mixed_corr_%s" % meth] = (
            "AR(2) phi=(0.6, 0.3) and 3x3 correlation up to 0.9, phi by %s" % meth,
            dict(ar1=0.6, ar2=0.3, ar=2, ar_method=meth, corr=0.9, judge_noise=True),
            "chi2_reject")
    c["corr_0.9"] = ("3x3 correlation up to 0.9, judge told", dict(corr=0.9, judge_noise=True),
                     "chi2_reject")
    c["stations"] = ("two stations, sigma_w 1 and 3, judge told",
                     dict(group_split=0.5, sigma_w2=3.0, judge_noise=True), "chi2_reject")
    c["outliers_robust"] = ("1 % rows at 30 sigma, robust", dict(robust=True, **OUT),
                            "chi2_reject")
    for rob in (False, True):
        for o in (False, True):
            kw = dict(x={"gyro_bias_y": 4.0}, **(OUT if o else {}))
            if rob:
                kw["robust"] = True
            c["power_%s_%s" % ("robust" if rob else "seed", "out" if o else "clean")] = (
                "power gyro_bias_y 4x, %s, %s" % ("robust" if rob else "seed's judge",
                                                  "1 % outliers" if o else "clean"), kw, "failed")
    for k in CURVE:  # power curves: gyro_bias_y at k x spec
        for rob, o in ((False, False), (False, True), (True, True)):
            kw = dict(x={"gyro_bias_y": float(k)}, **(OUT if o else {}))
            if rob:
                kw["robust"] = True
            c["curve_%s_%s_%g" % ("robust" if rob else "seed", "out" if o else "clean", k)] = (
                "power gyro_bias_y %gx, %s, %s" % (k, "robust" if rob else "seed's judge",
                                                  "1 % outliers" if o else "clean"), kw, "failed")
    return c


def naming(n, seed=11):
    """gyro_bias_y at 4 x spec, the other terms N(0, 1), flight by flight
    (igea.simulate, igea.eqerr with the terms' names). Returns
    (top_named, top_rejected, any_named, any_rejected): the flights where
    the component carrying gyro_bias_y most (largest share) is rejected, and
    those where gyro_bias_y is among its candidate terms; the flights with
    any rejected component, and those where some rejected component names
    gyro_bias_y."""
    tn = tr = an = ar = 0
    for f in range(n):
        fl = igea.simulate(seed=seed, flight=f, x={"gyro_bias_y": 4.0})
        r = igea.eqerr(fl.S, fl.dw, fl.sigma, fl.spec, names=list(fl.terms))
        if not r.components:
            continue
        share = [dict(c["terms"]).get("gyro_bias_y", 0.0) for c in r.components]
        top = r.components[int(np.argmax(share))]
        if top["reject"]:
            tr += 1
            tn += "gyro_bias_y" in top["candidates"]
        bad = [c for c in r.components if c["reject"]]
        if bad:
            ar += 1
            an += any("gyro_bias_y" in c["candidates"] for c in bad)
    return tn, tr, an, ar


PHI_MODELS = (("AR(1) phi=0.5", (0.5,)), ("AR(1) phi=0.9", (0.9,)), ("AR(1) phi=0.98", (0.98,)),
              ("AR(2) phi=(0.6, 0.3)", (0.6, 0.3)), ("AR(3) phi=(0.5, 0.2, 0.2)", (0.5, 0.2, 0.2)))


def phi_bias(n, seed=11):
    """phi-hat flight by flight (igea.simulate, igea.eqerr with ar=p) by
    least squares and by REML: the mean error of each lag and of their sum
    with its standard error, and for REML the standardised log scale
    z = ln(c-hat / c) / (se(c-hat) / c-hat) (mean, sd, the fractions below
    -3 and above 3): what the sigma_w cover counts. Yields one row per
    model and method."""
    for label, phi in PHI_MODELS:
        kw = dict(zip(("ar1", "ar2", "ar3"), phi))
        for meth in ("ls", "reml"):
            t0 = time.process_time()
            est, z = [], []
            for f in range(n):
                fl = igea.simulate(seed=seed, flight=f, **kw)
                r = igea.eqerr(fl.S, fl.dw, fl.sigma, fl.spec, ar=len(phi), ar_method=meth)
                est.append(r.ar_phi)
                g = r.groups[0]
                z.append(np.log(g["scale"]) / (g["scale_se_reml"] / g["scale"]))
            est = np.array(est).reshape(-1, len(phi))  # flights x axes, lags
            err, tot = est - np.array(phi), est.sum(axis=1) - sum(phi)
            z = np.array(z)
            yield dict(cell="phi_bias", label="%s, %s" % (label, meth), method=meth,
                       phi=list(phi), flights=n, bias=list(err.mean(axis=0)),
                       bias_se=list(err.std(axis=0) / np.sqrt(len(err))),
                       sum_bias=float(tot.mean()), sum_bias_se=float(tot.std() / np.sqrt(len(tot))),
                       z_mean=float(z.mean()), z_sd=float(z.std()),
                       z_below=float(np.mean(z < -3)), z_above=float(np.mean(z > 3)),
                       cpu_s=time.process_time() - t0)


AR_ROBUST_MODELS = (("AR(2) phi=(0.6, 0.3)", (0.6, 0.3)), ("AR(1) phi=0.9", (0.9,)))


def ar_robust(n, seed=11):
    """phi-hat with outliers and the robust route against phi-hat of the
    same flight without them, flight by flight: igea.simulate(seed, flight,
    ar, outlier_prob=0.01, outlier_scale=30) and the same draw with
    outlier_prob=0 (the same noise: the outliers' draws are made for every
    row), each judged by igea.eqerr(ar=p, robust=True), and the clean flight
    also without the robust route. A flight matches when every phi_(a,k)
    with outliers is within one standard error (the clean robust judge's)
    of the clean one. Also counted: the flights with the smallest phi_1 of
    the three axes below 0.3, the planted rows missed, and the rows rejected
    that were not planted. Yields one row per model."""
    for label, phi in AR_ROBUST_MODELS:
        kw = dict(zip(("ar1", "ar2", "ar3"), phi))
        p = len(phi)
        t0 = time.process_time()
        match = match_plain = low = low_clean = missed = false = planted = nconv = 0
        dmax = []
        for f in range(n):
            clean = igea.simulate(seed=seed, flight=f, outlier_prob=0.0, **kw)
            dirty = igea.simulate(seed=seed, flight=f, outlier_prob=0.01, outlier_scale=30.0, **kw)
            rc = igea.eqerr(clean.S, clean.dw, clean.sigma, clean.spec, ar=p, robust=True)
            rp = igea.eqerr(clean.S, clean.dw, clean.sigma, clean.spec, ar=p)
            ro = igea.eqerr(dirty.S, dirty.dw, dirty.sigma, dirty.spec, ar=p, robust=True)
            se = np.asarray(rc.ar_se)
            d = np.max(np.abs(np.asarray(ro.ar_phi) - rc.ar_phi) / se)
            dmax.append(d)
            match += d <= 1.0
            match_plain += np.max(np.abs(np.asarray(ro.ar_phi) - rp.ar_phi) / rp.ar_se) <= 1.0
            low += np.min(np.asarray(ro.ar_phi)[:, 0]) < 0.3
            low_clean += np.min(np.asarray(rp.ar_phi)[:, 0]) < 0.3
            truth = set(np.flatnonzero(dirty.dw != clean.dw).tolist())
            rej = {r["row"] for r in ro.rejected_rows}
            planted += len(truth)
            missed += len(truth - rej)
            false += len(rej - truth)
            nconv += bool(ro.noise_converged)
        dmax = np.array(dmax)
        yield dict(cell="ar_robust", label="%s, 1 %% rows at 30 sigma, robust" % label, phi=list(phi),
                   flights=n, match=int(match), match_cp99=list(interval_cp(int(match), n)),
                   match_plain=int(match_plain),
                   match_plain_cp99=list(interval_cp(int(match_plain), n)),
                   low=int(low), low_clean=int(low_clean), planted=planted, missed=missed,
                   false=false, converged=nconv, dmax_q=[float(np.quantile(dmax, q)) for q in
                                                         (0.5, 0.9, 0.99, 1.0)],
                   cpu_s=time.process_time() - t0)


def run_cell(name, spec, fl, a):
    label, kw, what = spec
    t0 = time.process_time()
    r = igea.montecarlo(fl.S, fl.sigma, a.flights, spec=fl.spec, terms=list(fl.terms),
                        threads=a.threads, seed=11, **kw)
    cpu = time.process_time() - t0
    k = getattr(r, what)
    row = dict(cell=name, label=label, what=what, count=int(k), flights=r.flights,
               rate=k / r.flights, cp99=list(r.ci99_cp[what]), wilson99=list(r.ci99[what]),
               cpu_s=cpu, overall=r.failed / r.flights, mean_scale=r.mean_scale)
    extra = ""
    if r.scale_covered or r.sigma_covered:
        row.update(scale_covered=r.scale_covered, sigma_covered=r.sigma_covered,
                   sigma_cp99=list(interval_cp(r.sigma_covered, r.flights)),
                   scale_cp99=list(interval_cp(r.scale_covered, r.flights)))
        extra += "; sigma_w-hat covered (log scale, REML se) %d / %d [%.4f, %.4f]" % (
            r.sigma_covered, r.flights, *row["sigma_cp99"])
        extra += "; c-hat covered (c scale, plug-in se) %d" % r.scale_covered
    if what != "failed":
        extra += "; overall 'out of spec' %.4f" % (r.failed / r.flights)
    if r.mean_outliers:
        row["mean_outliers"] = r.mean_outliers
        extra += "; %.2f rows rejected per flight" % r.mean_outliers
    row["mean_tested"] = r.mean_tested
    return row, extra


def report(row, extra):
    lo, hi = row["cp99"]
    print("| %s | %s | %d / %d = %.4f [%.4f, %.4f] | %.0f s%s |" % (
        row["label"], row["what"], row["count"], row["flights"], row["rate"], lo, hi,
        row["cpu_s"], extra), flush=True)


def plots(results, outdir):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    by = {}
    for path in results.split(","):  # several files: the run with most flights wins
        with open(path) as fh:
            for line in fh:
                d = json.loads(line)
                if d["flights"] >= by.get(d["cell"], {"flights": 0})["flights"]:
                    by[d["cell"]] = d
    def save(fig, drawn, name):  # a figure without data is not written
        if drawn:
            fig.savefig(os.path.join(outdir, name), dpi=120)
        plt.close(fig)

    fig, ax = plt.subplots(figsize=(5.5, 3.8))
    drawn = False
    for fam, lab, dx in (("ar1_seed_", "seed's judge (white K)", -0.006),
                         ("ar1_ls_", "AR(1) judge, phi by least squares", 0.0),
                         ("ar1_reml_", "AR(1) judge, phi by REML", 0.006)):
        pts = [(p, by[fam + "%g" % p]) for p in PHIS if fam + "%g" % p in by]
        if not pts:
            continue
        drawn = True
        x = np.array([p for p, _ in pts]) + dx
        v = np.array([d["rate"] for _, d in pts])
        lo = np.array([d["cp99"][0] for _, d in pts])
        hi = np.array([d["cp99"][1] for _, d in pts])
        nf = sorted({d["flights"] for _, d in pts})
        ax.errorbar(x, 100 * v, yerr=[100 * (v - lo), 100 * (hi - v)], marker="o", capsize=3,
                    label="%s (%s flights)" % (lab, "/".join(map(str, nf))))
    ax.axhline(1.0, color="k", lw=0.8, ls="--")
    ax.set_xlabel("AR(1) coefficient phi of the tracking noise")
    ax.set_ylabel("chi-square size, % (alpha = 1 %)")
    ax.set_title("chi-square size against phi, 99 % Clopper-Pearson intervals", fontsize=9)
    ax.legend(fontsize=8)
    fig.tight_layout()
    save(fig, drawn, "noise_size_phi.png")
    fig, ax = plt.subplots(figsize=(5.5, 3.8))
    drawn = False
    for rob, lab, dx in (("seed", "seed's judge", -0.03), ("robust", "robust route", 0.03)):
        pts = [(i, by["power_%s_%s" % (rob, o)]) for i, o in enumerate(("clean", "out"))
               if "power_%s_%s" % (rob, o) in by]
        if not pts:
            continue
        drawn = True
        x = np.array([i for i, _ in pts]) + dx
        v = np.array([d["rate"] for _, d in pts])
        lo = np.array([d["cp99"][0] for _, d in pts])
        hi = np.array([d["cp99"][1] for _, d in pts])
        nf = sorted({d["flights"] for _, d in pts})
        ax.errorbar(x, v, yerr=[v - lo, hi - v], marker="o", capsize=3,
                    label="%s (%s flights)" % (lab, "/".join(map(str, nf))))
    ax.axhline(0.90, color="k", lw=0.8, ls="--")
    ax.set_xticks([0, 1], ["no outliers", "1 % rows at 30 sigma"])
    ax.set_xlim(-0.5, 1.5)
    ax.set_ylabel("power, gyro_bias_y at 4 x spec")
    ax.set_title("Power with and without the robust route, 99 % Clopper-Pearson", fontsize=9)
    ax.legend(fontsize=8)
    fig.tight_layout()
    save(fig, drawn, "noise_power.png")
    fig, ax = plt.subplots(figsize=(5.5, 3.8))
    drawn = False
    for fam, lab in (("curve_seed_clean_", "seed's judge, no outliers"),
                     ("curve_seed_out_", "seed's judge, 1 % rows at 30 sigma"),
                     ("curve_robust_out_", "robust route, 1 % rows at 30 sigma")):
        pts = [(k, by[fam + "%g" % k]) for k in CURVE if fam + "%g" % k in by]
        if not pts:
            continue
        drawn = True
        x = np.array([k for k, _ in pts], dtype=float)
        v = np.array([d["rate"] for _, d in pts])
        lo = np.array([d["cp99"][0] for _, d in pts])
        hi = np.array([d["cp99"][1] for _, d in pts])
        nf = sorted({d["flights"] for _, d in pts})
        ax.errorbar(x, v, yerr=[v - lo, hi - v], marker="o", capsize=3,
                    label="%s (%s flights)" % (lab, "/".join(map(str, nf))))
    ax.set_xlabel("true gyro_bias_y, multiples of its spec (other terms N(0, 1))")
    ax.set_ylabel("P(verdict 'out of spec')")
    ax.set_ylim(0, 1.02)
    ax.set_title("Power curves, 99 % Clopper-Pearson intervals", fontsize=9)
    ax.legend(fontsize=8)
    fig.tight_layout()
    save(fig, drawn, "noise_power_curve.png")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--flights", type=int, default=2000)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--cells", default="", help="comma-separated names or prefixes; "
                    "empty: all, and naming")
    ap.add_argument("--results", default="noise_validation.jsonl",
                    help="JSON lines file (appended); --plot-only: comma-separated files")
    ap.add_argument("--outdir", default="docs")
    ap.add_argument("--plot-only", action="store_true")
    ap.add_argument("--naming-flights", type=int, default=0, help="0: --flights")
    ap.add_argument("--phi-flights", type=int, default=0,
                    help="phi_bias, ar_robust: 0: --flights")
    a = ap.parse_args()
    if a.plot_only:
        plots(a.results, a.outdir)
        return
    want = [w for w in a.cells.split(",") if w]
    fl = igea.simulate(seed=1)
    print("| cell | rate | value [99 % Clopper-Pearson] | CPU, other |\n|---|---|---|---|")
    allc = cells()
    order = ([n for w in want for n in ([w] if w in allc else
                                        [k for k in allc if k.startswith(w)])]
             if want else list(allc))
    for name in dict.fromkeys(order):  # in the order asked for, each once
        spec = allc[name]
        row, extra = run_cell(name, spec, fl, a)
        report(row, extra)
        with open(a.results, "a") as fh:
            fh.write(json.dumps(row) + "\n")
    if not want or "naming" in want:
        t0 = time.process_time()
        tn, tr, an, ar = naming(a.naming_flights or a.flights)
        cpu = time.process_time() - t0
        for name, label, k, n in (
                ("naming_top", "gyro_bias_y 4x named by its own component, when rejected", tn, tr),
                ("naming_any", "gyro_bias_y 4x named by some rejected component", an, ar)):
            row = dict(cell=name, label=label, what="named", count=k, flights=n,
                       rate=k / max(n, 1), cp99=list(interval_cp(k, max(n, 1))), wilson99=[],
                       cpu_s=cpu)
            report(row, "; %d flights drawn" % (a.naming_flights or a.flights))
            with open(a.results, "a") as fh:
                fh.write(json.dumps(row) + "\n")
    if "ar_robust" in want:
        print("\n| model | flights | phi-hat with outliers within 1 se of the clean flight's "
              "(robust / plain judge) [99 % CP] | min-axis phi_1 < 0.3 (outliers / clean) | "
              "planted rows missed, rows rejected not planted | max |d phi|/se: median, 90 %, "
              "99 %, max | CPU |\n|---|---|---|---|---|---|---|")
        for row in ar_robust(a.phi_flights or a.flights):
            print("| %s | %d | %d [%.4f, %.4f] / %d [%.4f, %.4f] | %d / %d | %d of %d, %d | "
                  "%.2f, %.2f, %.2f, %.2f | %.0f s |" % (
                      row["label"], row["flights"], row["match"], *row["match_cp99"],
                      row["match_plain"], *row["match_plain_cp99"], row["low"], row["low_clean"],
                      row["missed"], row["planted"], row["false"], *row["dmax_q"], row["cpu_s"]),
                  flush=True)
            with open(a.results, "a") as fh:
                fh.write(json.dumps(row) + "\n")
    if "phi_bias" in want:
        print("\n| model, estimator | mean phi-hat - phi per lag (se) | sum of the lags | "
              "z = ln(c-hat/c) / se: mean, sd, P(z < -3), P(z > 3) | CPU |\n|---|---|---|---|---|")
        for row in phi_bias(a.phi_flights or a.flights):
            print("| %s | %s | %+.4f (%.4f) | %.2f, %.2f, %.4f, %.4f | %.0f s |" % (
                row["label"], ", ".join("%+.4f (%.4f)" % b for b in zip(row["bias"], row["bias_se"])),
                row["sum_bias"], row["sum_bias_se"], row["z_mean"], row["z_sd"], row["z_below"],
                row["z_above"], row["cpu_s"]), flush=True)
            with open(a.results, "a") as fh:
                fh.write(json.dumps(row) + "\n")
    if not want:
        try:
            plots(a.results, a.outdir)
        except ImportError:
            print("\n(matplotlib not installed: no plots)")


if __name__ == "__main__":
    main()
