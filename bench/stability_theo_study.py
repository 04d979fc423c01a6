"""Monte Carlo study behind docs/stability.md's Theo1, Htot, TheoBR and TheoH
figures (about 4 min of CPU at the defaults):

1. Theo1's EDF: 2 E[Theo1]^2 / var(Theo1) over R records of N phase points
   of white PM, white FM and random-walk FM, against SP 1065's formula
   (r / (r + c) multiplying) and the form that divides by it;
2. Htot's EDF: the same for HTOTDEV on white, flicker and random-walk FM,
   against SP 1065's (b0, b1) and another published set;
3. TheoBR: mean TheoBR^2 / AVAR (the exact Allan variance of the simulated
   noise) per tau, and the noise type its bias factor gives;
4. coverage of the 68.3 % intervals of Theo1 (truth E[Theo1]) and TheoH
   (truth the Allan variance) on white and random-walk FM, noise type given
   and identified, with 95 % Clopper-Pearson intervals.

    PYTHONPATH=python IGEA_LIBRARY=build/lib/libigea.so.1 .venv/bin/python \\
        bench/stability_theo_study.py [--seed 5] [--records 1000]
"""
import argparse

import numpy as np
from scipy.stats import beta

import igea


def kasdin(rng, ax, n):
    """Phase noise with S_x ~ f^ax (Kasdin and Walter's filter) and the filter."""
    h = np.ones(n)
    for k in range(1, n):
        h[k] = h[k - 1] * (k - 1 - ax / 2) / k
    L = 1 << int(np.ceil(np.log2(2 * n)))
    w = rng.standard_normal(n)
    return np.fft.irfft(np.fft.rfft(h, L) * np.fft.rfft(w, L), L)[:n], h


def theo1_edf(a, N, r, divide=False):
    if a == 2:
        core, f = 0.86 * (N + 1) * (N - 4 * r / 3) / (N - r), r / (r + 1.14)
    elif a == 1:
        core, f = (4.798 * N ** 2 - 6.374 * N * r + 12.387 * r) / (np.sqrt(r + 36.6) * (N - r)), r / (r + 0.3)
    elif a == 0:
        core, f = (4.1 * N + 0.8) / r - (3.1 * N + 6.5) / N, r ** 1.5 / (r ** 1.5 + 5.2)
    elif a == -1:
        core, f = (2 * N ** 2 - 1.3 * N * r - 3.5 * r) / (N * r), r ** 3 / (r ** 3 + 2.3)
    else:
        core, f = ((4.4 * N - 2) / (2.9 * r) * ((4.4 * N - 1) ** 2 - 8.6 * r * (4.4 * N - 1) + 11.4 * r ** 2)
                   / (4.4 * N - 3) ** 2), 1.0
    return core / f if divide else core * f


def cp(k, n, c=0.95):
    a = (1 - c) / 2
    return (beta.ppf(a, k, n - k + 1) if k > 0 else 0.0, beta.ppf(1 - a, k + 1, n - k) if k < n else 1.0)


def study_theo1(rng, R):
    N = 1000
    ms = np.array([2, 4, 10, 20, 50, 100, 300, 600])
    print("1. Theo1 EDF, N = %d phase points, %d records: Monte Carlo / multiply / divide" % (N, R))
    for a, name, ax in ((2, "wpm", 0), (0, "wfm", -2), (-2, "rwfm", -4)):
        v = np.array([igea.stability(kasdin(rng, ax, N)[0], 1.0, 0.75 * ms, kind="theo1",
                                     data_type="phase", noise=name).dev ** 2 for _ in range(R)])
        mc = 2 * v.mean(0) ** 2 / v.var(0, ddof=1)
        print("  %-5s " % name + "  ".join("m %d: %.0f/%.0f/%.0f" % (m, e, theo1_edf(a, N, 0.75 * m),
                                                                   theo1_edf(a, N, 0.75 * m, True))
                                         for m, e in zip(ms, mc)))


def study_htot(rng, R):
    N = 1024
    ms = np.array([4, 8, 16, 32, 64, 128, 256])
    sp = {0: (0.559, 1.004), -1: (0.868, 1.140), -2: (0.938, 1.696)}
    other = {0: (0.546, 1.41), -1: (0.667, 2.00), -2: (0.909, 1.00)}
    print("2. Htot EDF, N = %d, %d records: Monte Carlo / SP 1065 (b0, b1) / another set / "
          "OHDEV (Greenhall)" % (N, R))
    for a, name in ((0, "wfm"), (-1, "ffm"), (-2, "rwfm")):
        v = np.array([igea.stability(kasdin(rng, a - 2, N)[0], 1.0, ms.astype(float), kind="htotdev",
                                     data_type="phase", noise=name).dev ** 2 for _ in range(R)])
        mc = 2 * v.mean(0) ** 2 / v.var(0, ddof=1)
        oh = igea.stability(kasdin(rng, a - 2, N)[0], 1.0, ms.astype(float), kind="ohdev",
                            data_type="phase", noise=name).edf
        f = lambda b, m: (N / m) / (b[a][0] + b[a][1] * m / N)
        print("  %-5s " % name + "  ".join("m %d: %.0f/%.0f/%.0f/%.0f" % (m, e, f(sp, m), f(other, m), o)
                                         for m, e, o in zip(ms, mc, oh)))


def study_theobr(rng, R):
    N = 1024
    taus = np.array([3.0, 6.0, 12.0, 24.0, 48.0, 96.0, 192.0, 384.0])
    print("3. TheoBR^2 / AVAR, N = %d, %d records (tau: mean ratio), noise type of the factor" % (N, R))
    for a, name in ((0, "wfm"), (-1, "ffm"), (-2, "rwfm"), (2, "wpm")):
        br, t1, al, h = np.zeros(taus.size), np.zeros(taus.size), [], None
        for _ in range(R):
            x, h = kasdin(rng, a - 2, N)
            r = igea.stability(x, 1.0, taus, kind="theobr", data_type="phase")
            br += r.dev ** 2 / R
            t1 += igea.stability(x, 1.0, taus, kind="theo1", data_type="phase").dev ** 2 / R
            al.append(r.alpha[0])
        truth = []
        for t in taus:
            m = int(t)
            c = np.zeros(N)
            i = N - 2 * m - 1
            c[i + 2 * m] += 1
            c[i + m] -= 2
            c[i] += 1
            g = np.array([np.dot(c[k:], h[:N - k]) for k in range(N)])
            truth.append(np.dot(g, g) / (2 * m * m))
        counts = np.bincount(np.array(al) + 2, minlength=5)
        print("  %-5s TheoBR " % name + " ".join("%g:%.3f" % (t, q) for t, q in zip(taus, br / truth)))
        print("        Theo1  " + " ".join("%g:%.3f" % (t, q) for t, q in zip(taus, t1 / truth)))
        print("        type of the factor (alpha -2..2): %s" % list(counts))


def study_coverage(rng, R):
    N = 512
    print("4. coverage of the 68.3 %% intervals, N = %d, %d records (count, 95 %% CP interval)"
          % (N, R))
    for ax, name in ((-2, "wfm"), (-4, "rwfm")):
        h = np.ones(N)
        for k in range(1, N):
            h[k] = h[k - 1] * (k - 1 - ax / 2) / k
        H = np.zeros((N, N))
        for i in range(N):
            H[i, :i + 1] = h[i::-1]
        S = H @ H.T
        tt = igea.stability_taus(N, 1.0, "theo1", data_type="phase")
        t1 = []
        for t in tt:
            m = int(round(t / 0.75))
            hm, i, tot = m // 2, np.arange(N - m), 0.0
            for d in range(hm):
                idx, c = [i, i - d + hm, i + m, i + d + hm], [1, -1, 1, -1]
                tot += sum(c[p] * c[q] * S[idx[p], idx[q]] for p in range(4) for q in range(4)).sum() / (hm - d)
            t1.append(tot / (0.75 * (N - m) * m * m))
        t1 = np.array(t1)
        th = igea.stability_taus(N, 1.0, "theoh", data_type="phase")
        av = th ** -1.0 if name == "wfm" else (2 * th ** 2 + 1) / (6 * th)
        for noise in (name, "auto"):
            c1, ch = np.zeros(tt.size, int), np.zeros(th.size, int)
            for _ in range(R):
                x = H @ rng.standard_normal(N)
                a = igea.stability(x, 1.0, tt, kind="theo1", data_type="phase", noise=noise)
                c1 += (a.lo ** 2 <= t1) & (t1 <= a.hi ** 2)
                b = igea.stability(x, 1.0, th, kind="theoh", data_type="phase", noise=noise)
                ch += (b.lo ** 2 <= av) & (av <= b.hi ** 2)
            for lab, taus, cnt in (("theo1", tt, c1), ("theoh", th, ch)):
                print("  %-5s noise %-5s %-6s " % (name, noise, lab) + "  ".join(
                    "%g:%d [%.2f,%.2f]" % ((t, k) + cp(int(k), R)) for t, k in zip(taus, cnt)))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--seed", type=int, default=5)
    ap.add_argument("--records", type=int, default=1000)
    args = ap.parse_args()
    rng = np.random.default_rng(args.seed)
    study_theo1(rng, args.records)
    study_htot(rng, max(400, args.records // 2))
    study_theobr(rng, 200)
    study_coverage(rng, 400)


if __name__ == "__main__":
    main()
