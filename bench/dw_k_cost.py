#!/usr/bin/env python3
"""The cost of eqerr --cov's block-diagonal K (docs/pipeline.md 4.2).

dW's covariance K with 28-column tracking is not block-diagonal: the
tracking position errors move the gravity integral of every later epoch
(igea_dw_compute_k). igea eqerr --cov takes one 3 x 3 block per epoch. On
the 120-s platform flight of the tutorial (21 default terms at their
specs, 120 epochs, tracking errors of igea.track_errors: position sigma
SIGMA_R, velocity SIGMA_V, axis correlation CORR, position-velocity CROSS)
this prints, for the errors distributed with the full K:
  - the range of the eigenvalues of K_bd^-1 K (K_bd the diagonal blocks);
  - the chi-square T judged with K_bd, with K without the gravity part
    (igea_dw_compute's blocks) and with the full K: its mean tr(R K) and
    variance 2 tr((R K)^2), R the GLS residual maker of the judging K, and
    its size at 5 % and 1 % by Satterthwaite's c chi2(nu);
  - the estimates' stated standard errors over their true ones;
  - a Monte Carlo of FLIGHTS flights (default 10,000; the terms drawn at
    their specs, the tracking errors from the full K by numpy's Cholesky
    factor) judged by igea.eqerr with the diagonal blocks (cov=, `eqerr
    --cov`) and with the whole K (cov= and xcov=, `eqerr --cov --xcov`):
    the rejection rate at 5 % of the residual chi-square (the whitened
    residuals' sum of squares against chi2(m - rank)) and of eqerr's own
    chi-square test (T of the tested components, the seed's correction
    on), each with its 99 % Clopper-Pearson interval, and the mean
    Helmert scale c of the tracking accuracy (1 when K is right).

    PYTHONPATH=python IGEA_LIBRARY=build/lib/libigea.so.1 \\
        .venv/bin/python bench/dw_k_cost.py SIGMA_R SIGMA_V [CORR CROSS [FLIGHTS]]
"""
import ctypes
import sys

import numpy as np
from scipy import stats

import igea
from igea import _lib
from igea.envfun import default_terms
from igea.nav import nav_site


def blocks(cov):
    return np.array([[[r[0], r[1], r[2]], [r[1], r[3], r[4]], [r[2], r[4], r[5]]] for r in cov])


def block_diag(B):
    n = len(B)
    K = np.zeros((3 * n, 3 * n))
    for e, b in enumerate(B):
        K[3 * e:3 * e + 3, 3 * e:3 * e + 3] = b
    return K


def judged(S, K, Kj):
    W = np.linalg.inv(Kj)
    N = S.T @ W @ S
    R = W - W @ S @ np.linalg.solve(N, S.T @ W)
    A = R @ K
    m, v = np.trace(A), 2 * np.trace(A @ A)
    c, nu = v / (2 * m), 2 * m * m / v
    dof = S.shape[0] - S.shape[1]
    size = [stats.chi2.sf(stats.chi2.ppf(1 - a, dof) / c, nu) for a in (0.05, 0.01)]
    M = np.linalg.solve(N, S.T @ W)
    ratio = np.sqrt(np.diag(np.linalg.inv(N)) / np.diag(M @ K @ M.T))
    return m, v, size, ratio


def clopper_pearson(k, n, conf=0.99):
    a = 1 - conf
    lo = stats.beta.ppf(a / 2, k, n - k + 1) if k > 0 else 0.0
    hi = stats.beta.ppf(1 - a / 2, k + 1, n - k) if k < n else 1.0
    return lo, hi


def monte_carlo(S, d, K, flights, seed=20250612):
    """Rejection counts of the residual chi-square and of eqerr's verdict
    chi-square at 5 %, and the summed scale c, per route."""
    Kb = blocks(d.cov)
    L = np.linalg.cholesky(K)
    m, N = S.shape
    rng = np.random.default_rng(seed)
    out = {w: [0, 0, 0.0] for w in ("diagonal blocks", "whole K")}
    for _ in range(flights):
        dw = S @ rng.standard_normal(N) + L @ rng.standard_normal(m)
        for w in out:
            r = igea.eqerr(S, dw, None, cov=Kb, xcov=d.xcov if w == "whole K" else None,
                           alpha=0.05, verdict="chi2")
            T = float(r.residual @ r.residual)
            out[w][0] += T >= stats.chi2.ppf(0.95, m - r.rank)
            out[w][1] += not r.passed
            out[w][2] += r.groups[0]["scale"]
    return out


def main():
    sr, sv = float(sys.argv[1]), float(sys.argv[2])
    corr = float(sys.argv[3]) if len(sys.argv) > 3 else 0.5
    cross = float(sys.argv[4]) if len(sys.argv) > 4 else 0.2
    flights = int(sys.argv[5]) if len(sys.argv) > 5 else 10000
    traj = igea.reference_trajectory(120.0, 50.0, system="platform")
    ep = np.arange(1.0, 121.0)
    n = ep.size
    acc, _ = igea.track_errors(np.full(n, sv), sr, corr=corr, cross=cross)
    raw = igea.simulate_raw(traj, ["acc_bias_x"], ep, system="platform", x=[0.0], noise=False,
                            acc=acc)
    d = igea.dw(raw.telemetry, raw.tracking, **raw.dw_kwargs())
    K = block_diag(blocks(d.cov))
    for e in range(n):
        K[3 * e:3 * e + 3, 3 * e + 3:] = np.tile(d.xcov[e], (1, n - e - 1))
        K[3 * e + 3:, 3 * e:3 * e + 3] = np.tile(d.xcov[e].T, (n - e - 1, 1))
    Kbd = block_diag(blocks(d.cov))
    # igea_dw_compute's blocks: K without the gravity integral's part
    tel, trk = np.asfortranarray(raw.telemetry), np.asfortranarray(raw.tracking)
    site = nav_site(np.radians(raw.lat), np.radians(raw.lon), raw.height,
                    np.radians(raw.azimuth))
    out, cov, bad, q = np.zeros(3 * n), np.zeros(6 * n), ctypes.c_int(), np.array([1.0, 0, 0, 0])
    st = _lib.lib.igea_dw_compute(_lib.dptr(site), 1, 0, _lib.dptr(q), 0.0, tel.shape[0],
                                  _lib.dptr(tel), tel.shape[0], tel.shape[1], 0, n,
                                  _lib.dptr(trk), n, trk.shape[1], _lib.dptr(out),
                                  _lib.dptr(cov), None, ctypes.byref(bad))
    assert st == 0
    Kold = block_diag(blocks(cov.reshape(n, 6)))
    S = igea.envfun(traj, default_terms("platform"), ep, system="platform", spec="default",
                    lat=raw.lat, lon=raw.lon, height=raw.height, azimuth=raw.azimuth)
    L = np.linalg.cholesky(Kbd)
    Li = np.linalg.inv(L)
    ev = np.linalg.eigvalsh(Li @ K @ Li.T)
    print("sigma_r %g m, sigma_v %g m/s, corr %g, cross %g: eigenvalues of K_bd^-1 K in "
          "[%.4f, %.4f]" % (sr, sv, corr, cross, ev.min(), ev.max()))
    for name, Kj in (("diagonal blocks", Kbd), ("without the gravity part", Kold),
                     ("full K", K)):
        m, v, size, ratio = judged(S, K, Kj)
        print("  %-25s E T %.2f (dof %d), var %.2f; size at 5 %% %.4f, at 1 %% %.4f; stated/true "
              "sd %.4f..%.4f" % (name, m, S.shape[0] - S.shape[1], v, size[0], size[1],
                                 ratio.min(), ratio.max()))
    if flights <= 0:
        return
    mc = monte_carlo(S, d, K, flights)
    print("  Monte Carlo, %d flights (terms at their specs, tracking errors from the full K), "
          "igea.eqerr; rejection rate at 5 %% [99 %% Clopper-Pearson]:" % flights)
    for w, (kr, kv, cs) in mc.items():
        lo, hi = clopper_pearson(kr, flights)
        lov, hiv = clopper_pearson(kv, flights)
        print("    %-16s residual chi-square %.4f [%.4f, %.4f]; eqerr's chi-square test %.4f "
              "[%.4f, %.4f]; mean scale c %.4f" % (w, kr / flights, lo, hi, kv / flights, lov,
                                                   hiv, cs / flights))


if __name__ == "__main__":
    main()
