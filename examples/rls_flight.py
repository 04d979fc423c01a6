"""Recursive estimation on simulated flights: the seed 001 figures (output
residuals for p = 1..8 and Q_p against p) next to the coefficient error
against p, for three priors Gamma_0 (docs/rls.md, METHODS 2.6).

    PYTHONPATH=python .venv/bin/python examples/rls_flight.py [--flights 20]

Each flight is `igea.simulate` (the 120 s strapdown boost, 21 error terms,
tracking sigma 0.01 m/s, X ~ N(0, 1) in spec units). The estimator works in
spec units (c = S diag(spec)), whitened by the tracking sigma, so Gamma_0 = I
is the honest in-spec prior; 1e4 I is diffuse, 1e-2 I far too tight.
With --plot and matplotlib installed it also draws rls_flight.png.
"""
import argparse
import sys

import numpy as np

import igea

PRIORS = (("diffuse 1e4 I", 1e4), ("in-spec I", 1.0), ("tight 1e-2 I", 1e-2))


def run(flights, pmax):
    res = {name: {"q": np.zeros(pmax), "resid": np.zeros(pmax), "err": np.zeros(pmax),
                  "sd": np.zeros(pmax), "err_obs": np.zeros(pmax)} for name, _ in PRIORS}
    for fl in range(flights):
        f = igea.simulate(seed=2026, flight=fl)
        n, N = len(f.epochs), len(f.terms)
        C = (f.S * f.spec).reshape(n, 3, N)
        Y = f.dw.reshape(n, 3)
        sig = f.sigma.reshape(n, 3)
        # the observable directions: eigenvectors of the whitened normal matrix
        A = (C / sig[:, :, None]).reshape(-1, N)
        w, V = np.linalg.eigh(A.T @ A)
        obs = V[:, w > 1.0]  # components known better than the spec
        for name, g in PRIORS:
            for p in range(1, pmax + 1):
                r = igea.rls_run(C, Y, None, g * np.eye(N), variant="polynomial", p=p,
                                 track_sigma=sig)
                d = res[name]
                d["q"][p - 1] += r.q / flights
                d["resid"][p - 1] += np.sqrt(np.mean(r.residual ** 2)) / flights
                e = r.x[-1] - f.x_true
                d["err"][p - 1] += np.sqrt(np.mean(e ** 2)) / flights
                d["err_obs"][p - 1] += np.sqrt(np.mean((obs.T @ e) ** 2)) / flights
                d["sd"][p - 1] += np.sqrt(np.mean(np.diag(r.covariance))) / flights
    return res


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--flights", type=int, default=20)
    ap.add_argument("--pmax", type=int, default=8)
    ap.add_argument("--plot", action="store_true")
    a = ap.parse_args()
    res = run(a.flights, a.pmax)
    print("mean over %d simulated flights (120 epochs x 3 axes, 21 terms, spec units)"
          % a.flights)
    for name, _ in PRIORS:
        d = res[name]
        print("\nGamma_0 = %s" % name)
        print("%3s %12s %14s %12s %14s %12s" % ("p", "Q_p", "resid rms m/s", "coef err",
                                               "err observable", "honest sd"))
        for p in range(a.pmax):
            print("%3d %12.4g %14.4g %12.4g %14.4g %12.4g"
                  % (p + 1, d["q"][p], d["resid"][p], d["err"][p], d["err_obs"][p],
                     d["sd"][p]))
    if a.plot:
        try:
            import matplotlib
            matplotlib.use("Agg")
            import matplotlib.pyplot as plt
        except ImportError:
            print("matplotlib is not installed: no plot", file=sys.stderr)
            return 0
        ps = np.arange(1, a.pmax + 1)
        fig, ax = plt.subplots(1, 2, figsize=(10, 4))
        for name, _ in PRIORS:
            ax[0].semilogy(ps, res[name]["q"], "o-", label=name)
            ax[1].semilogy(ps, res[name]["err_obs"], "o-", label=name)
        ax[0].set(xlabel="p", ylabel="Q_p (whitened)", title="Q_p falls with p by construction")
        ax[1].set(xlabel="p", ylabel="rms coefficient error (observable part, spec units)",
                  title="coefficient error against p")
        ax[0].legend()
        fig.tight_layout()
        fig.savefig("rls_flight.png", dpi=110)
        print("wrote rls_flight.png")
    return 0


if __name__ == "__main__":
    sys.exit(main())
