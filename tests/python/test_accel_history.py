"""igea.accel_history (REML of the random-effects model of earlier
calibrations) and igea.accel_fit(..., history=) against a REML written here
with scipy, the normal posterior in numpy, and Monte Carlo coverage checks
with their binomial intervals; the uncertainty of the estimated prior
(igea_accel_history_information, igea_accel_fit_history) against the
REML information by numerical differentiation of a restricted likelihood
written here, and the second-order terms by numerical derivatives of the
posterior written here."""
import json

import numpy as np
import pytest
from scipy import optimize, stats

import igea


def reml_reference(b, V):
    """-2 log restricted likelihood of b_i ~ N(beta0, diag(t^2) + V_i),
    minimised over log t with scipy (beta0 profiled by GLS)."""
    m, p = b.shape

    def nll(lt):
        S = np.diag(np.exp(2 * lt))
        W = [np.linalg.inv(S + Vi) for Vi in V]
        Ssum = sum(W)
        beta = np.linalg.solve(Ssum, sum(Wi @ bi for Wi, bi in zip(W, b)))
        val = sum(np.linalg.slogdet(S + Vi)[1] for Vi in V) + np.linalg.slogdet(Ssum)[1]
        val += sum((bi - beta) @ Wi @ (bi - beta) for Wi, bi in zip(W, b))
        return val, beta, Ssum

    x0 = np.log(np.std(b, axis=0, ddof=1))
    r = optimize.minimize(lambda lt: nll(lt)[0], x0, method="Nelder-Mead",
                          options=dict(xatol=1e-10, fatol=1e-13, maxiter=20000, maxfev=40000))
    _, beta, Ssum = nll(r.x)
    return beta, np.exp(r.x), np.linalg.inv(Ssum)


def random_psd(rng, p, scale):
    G = rng.standard_normal((p, p)) * scale
    return G @ G.T / p + np.diag(np.full(p, 0.1 * scale ** 2))


def test_reml_against_scipy():
    rng = np.random.default_rng(11)
    m, p = 15, 3
    tau = np.array([2.0, 0.5, 1.0])
    V = [random_psd(rng, p, s) for s in rng.uniform(0.3, 1.5, m)]
    b = np.array([np.array([1.0, -2.0, 0.5]) + tau * rng.standard_normal(p)
                  + rng.multivariate_normal(np.zeros(p), Vi) for Vi in V])
    # p = 3 is no accel model: the C function directly
    from igea import _capi, _lib
    B = np.asfortranarray(b.T)
    VV = np.concatenate([np.asfortranarray(Vi).ravel(order="F") for Vi in V])
    beta0, t, pc = np.zeros(p), np.zeros(p), np.zeros((p, p), order="F")
    info = np.zeros(_capi.ACCEL_HIST_LEN)
    _lib.call("t", "igea_accel_history", m, p, _lib.dptr(B), p, _lib.dptr(VV), p, 200000, 1e-12,
              _lib.dptr(beta0), _lib.dptr(t), _lib.dptr(pc), p, _lib.dptr(info))
    rb, rt, rcov = reml_reference(b, V)
    np.testing.assert_allclose(t, rt, rtol=2e-5)
    np.testing.assert_allclose(beta0, rb, rtol=1e-6, atol=1e-9)
    np.testing.assert_allclose(pc, np.diag(rt ** 2) + rcov, rtol=5e-5)


def test_full_sigma_against_scipy():
    """Full Sigma (p = 2, unequal V_i): the REML written here over the
    Cholesky factor of Sigma, against igea.accel_history(full=True) through
    the C function directly (p = 2 is no accel model)."""
    from igea import _capi, _lib
    rng = np.random.default_rng(21)
    m, p = 40, 2       # an interior optimum (with few, noisy calibrations it is often
    L = np.array([[1.0, 0.0], [0.7, 0.5]])   # singular, where EM creeps)
    V = [random_psd(rng, p, s) for s in rng.uniform(0.1, 0.3, m)]
    b = np.array([np.array([1.0, -1.0]) + L @ rng.standard_normal(p)
                  + rng.multivariate_normal(np.zeros(p), Vi) for Vi in V])

    def nll(x):
        Lc = np.array([[np.exp(x[0]), 0.0], [x[1], np.exp(x[2])]])
        S = Lc @ Lc.T
        W = [np.linalg.inv(S + Vi) for Vi in V]
        Ssum = sum(W)
        beta = np.linalg.solve(Ssum, sum(Wi @ bi for Wi, bi in zip(W, b)))
        return (sum(np.linalg.slogdet(S + Vi)[1] for Vi in V) + np.linalg.slogdet(Ssum)[1]
                + sum((bi - beta) @ Wi @ (bi - beta) for Wi, bi in zip(W, b)))

    # BFGS to the optimum, Nelder-Mead to polish it without gradients
    # (Nelder-Mead alone from zero spent 80,000 evaluations, 40 s, on it)
    r = optimize.minimize(nll, np.zeros(3), method="BFGS", options=dict(gtol=1e-9))
    r = optimize.minimize(nll, r.x, method="Nelder-Mead",
                          options=dict(xatol=1e-10, fatol=1e-14, maxfev=4000))
    Lc = np.array([[np.exp(r.x[0]), 0.0], [r.x[1], np.exp(r.x[2])]])
    B = np.asfortranarray(b.T)
    VV = np.concatenate([np.asfortranarray(Vi).ravel(order="F") for Vi in V])
    beta0, Sg, pc = np.zeros(p), np.zeros((p, p), order="F"), np.zeros((p, p), order="F")
    _lib.call("t", "igea_accel_history_full", m, p, _lib.dptr(B), p, _lib.dptr(VV), p, 500000,
              1e-10, _lib.dptr(beta0), _lib.dptr(Sg), p, _lib.dptr(pc), p, None)
    assert np.linalg.eigvalsh(Lc @ Lc.T).min() > 0.05      # interior
    np.testing.assert_allclose(Sg, Lc @ Lc.T, rtol=1e-5, atol=1e-7)


TH = igea.accel_schedule(20)
BETA0 = np.array([2e-4, -1.5e-4, 3e-4, -2e-4, 5e-5, 2e-5, -1e-5, 1e-5, -2e-5])
TAU = np.array([2e-5, 2e-5, 2e-5, 2e-5, 1e-5, 4e-6, 4e-6, 4e-6, 4e-6])


def test_fit_with_history_against_numpy(tmp_path):
    rng = np.random.default_rng(5)
    hist = []
    for i in range(12):
        beta = BETA0 + TAU * rng.standard_normal(9)
        ya, yb = igea.accel_simulate(TH, np.append(beta, 0.0), head_sd_arcsec=1,
                                     noise_sd=1e-6, seed=i)
        hist.append(igea.accel_joint(TH, ya, yb))
    # one entry as the JSON file of a fit (coef, cov, flags)
    f = tmp_path / "cal0.json"
    f.write_text(json.dumps(dict(coef=list(hist[0].coef), cov=hist[0].cov.tolist(),
                                 flags=["data"] * 10)))
    hist[0] = str(f)
    h = igea.accel_history(hist)
    ya, yb = igea.accel_simulate(TH, np.append(BETA0, 0.0), head_sd_arcsec=1, noise_sd=1e-6,
                                 seed=99)
    fit = igea.accel_fit(TH, ya, yb, method="ebr", history=h)
    A = igea.accel_design(TH, model="dual")
    y = 0.5 * (ya ** 2 + yb ** 2 - 1)
    x, *_ = np.linalg.lstsq(A, y, rcond=None)
    s2 = np.sum((y - A @ x) ** 2) / (20 - 7)
    Pinv = np.linalg.inv(h.prior_cov)
    C = np.linalg.inv(A.T @ A / s2 + Pinv)
    xpost = C @ (A.T @ y / s2 + Pinv @ h.beta0)
    np.testing.assert_allclose(fit.coef, xpost, rtol=1e-6, atol=1e-12)
    np.testing.assert_allclose(fit.sd_plugin, np.sqrt(np.diag(C)), rtol=1e-6)
    with pytest.raises(ValueError):
        igea.accel_fit(TH, ya, yb, method="ls", history=h)
    with pytest.raises(ValueError):  # minimum-norm values are not estimates
        igea.accel_history([igea.accel_fit(TH, ya, yb)] * 3)


# ---- the uncertainty of the estimated prior ------------------------------------

from igea import _capi, _lib  # noqa: E402


def directions(p, full):
    """dSigma/dtheta_a: the diagonal (q = p) or the lower triangle by
    columns (q = p (p + 1) / 2)."""
    D = []
    for l in range(p):
        for k in range(l, p if full else l + 1):
            E = np.zeros((p, p))
            E[k, l] = E[l, k] = 1.0
            D.append(E)
    return D


def sigma_of(theta, p, full):
    return sum(t * E for t, E in zip(theta, directions(p, full)))


def theta_of(Sig, full):
    p = Sig.shape[0]
    return np.array([Sig[k, l] for l in range(p) for k in range(l, p if full else l + 1)])


def expected_reml(theta1, theta, V, full):
    """E over y ~ N(X beta, Omega(theta)) of the restricted log-likelihood
    at theta1, with the dense P_R of the stacked model (X the stacked
    identities): -1/2 [log|Omega1| + log|X' Omega1^-1 X| + tr(P1 Omega)]
    (E y' P1 y = tr(P1 Omega) since P1 X = 0)."""
    p = V[0].shape[0]
    m = len(V)
    X = np.vstack([np.eye(p)] * m)

    def omega(th):
        S = sigma_of(th, p, full)
        O = np.zeros((m * p, m * p))
        for i, Vi in enumerate(V):
            O[i * p:(i + 1) * p, i * p:(i + 1) * p] = S + Vi
        return O

    O1, O = omega(theta1), omega(theta)
    Oi = np.linalg.inv(O1)
    XtOiX = X.T @ Oi @ X
    P1 = Oi - Oi @ X @ np.linalg.solve(XtOiX, X.T @ Oi)
    return -0.5 * (np.linalg.slogdet(O1)[1] + np.linalg.slogdet(XtOiX)[1] + np.trace(P1 @ O))


def library_information(b, V, Sig, full):
    m, p = b.shape
    q = p * (p + 1) // 2 if full else p
    B = np.asfortranarray(b.T)
    VV = np.concatenate([np.asfortranarray(Vi).ravel(order="F") for Vi in V])
    I = np.zeros((q, q), order="F")
    _lib.call("t", "igea_accel_history_information", m, p, _lib.dptr(B), p, _lib.dptr(VV), p,
              _lib.dptr(np.asfortranarray(Sig)), p, int(full), _lib.dptr(I), q)
    return I


@pytest.mark.parametrize("full", [False, True])
def test_reml_information_is_minus_the_expected_hessian(full):
    """I = -E[d2 l_R / dtheta2] by central second differences of the
    expected restricted log-likelihood written above (p = 3, 10 calibrations
    with unequal full V_i)."""
    rng = np.random.default_rng(31)
    m, p = 10, 3
    V = [random_psd(rng, p, s) for s in rng.uniform(0.3, 1.0, m)]
    G = rng.standard_normal((p, p))
    Sig = G @ G.T + 0.5 * np.eye(p) if full else np.diag([1.5, 0.4, 0.9])
    b = rng.standard_normal((m, p))  # I does not depend on the data
    th = theta_of(Sig, full)
    q = len(th)
    h = 2e-4
    H = np.zeros((q, q))
    for a in range(q):
        for c in range(q):
            def f(sa, sc):
                t1 = th.copy()
                t1[a] += sa * h
                t1[c] += sc * h
                return expected_reml(t1, th, V, full)
            H[a, c] = (f(1, 1) - f(1, -1) - f(-1, 1) + f(-1, -1)) / (4 * h * h)
    np.testing.assert_allclose(library_information(b, V, Sig, full), -H, rtol=2e-5, atol=1e-7)


class Posterior:
    """The calibration with the history prior written here: prior
    N(beta0(theta), Sigma(theta) + Q(theta)) with beta0 the GLS mean of the
    history and Q its covariance, the dual design A and y of the new
    calibration, s2 its residual variance: t and C of the normal posterior."""

    def __init__(self, b, V, A, y, full):
        self.b, self.V, self.A, self.y, self.full = b, np.array(V), A, y, full
        self.p = b.shape[1]

    def __call__(self, theta, s2):
        S = sigma_of(theta, self.p, self.full)
        W = np.linalg.inv(S[None] + self.V)
        Q = np.linalg.inv(W.sum(axis=0))
        beta0 = Q @ np.einsum("ijk,ik->j", W, self.b)
        Pi = np.linalg.inv(S + Q)
        C = np.linalg.inv(self.A.T @ self.A / s2 + Pi)
        return C @ (self.A.T @ self.y / s2 + Pi @ beta0), C


def corrected_mse(post, theta, s2, nus, Iinv):
    """(C + Lambda) / f by numerical derivatives of post: Lambda =
    sum Cov_ab dt/dpsi_a dt/dpsi_b (psi = theta and s2, Cov = I^-1 and
    2 s2^2 / nus), B = (1/2) sum Cov_ab d2C_jj / dpsi_a dpsi_b, f = max(1 +
    B / C, 0.2). Returns mse_jj, C_jj, Lambda_jj, B_jj."""
    q = len(theta)
    Cov = np.zeros((q + 1, q + 1))
    Cov[:q, :q] = Iinv
    Cov[q, q] = 2 * s2 ** 2 / nus
    sd = np.sqrt(np.diag(Cov))
    x0 = np.r_[theta, s2]

    def ev(x):
        return post(x[:q], x[q])

    t0, C0 = ev(x0)
    h = 1e-3 * sd
    dt, d2 = np.zeros((q + 1, len(t0))), np.zeros((q + 1, q + 1, len(t0)))
    for a in range(q + 1):
        ea = np.zeros(q + 1)
        ea[a] = h[a]
        dt[a] = (ev(x0 + ea)[0] - ev(x0 - ea)[0]) / (2 * h[a])
        for c in range(a + 1):
            ec = np.zeros(q + 1)
            ec[c] = h[c]
            v = (np.diag(ev(x0 + ea + ec)[1]) - np.diag(ev(x0 + ea - ec)[1])
                 - np.diag(ev(x0 - ea + ec)[1]) + np.diag(ev(x0 - ea - ec)[1])) / (4 * h[a] * h[c])
            d2[a, c] = d2[c, a] = v
    Lam = np.einsum("aj,ab,bj->j", dt, Cov, dt)
    B = 0.5 * np.einsum("ab,abj->j", Cov, d2)
    C = np.diag(C0)
    f = np.maximum(1 + B / C, 0.2)
    return (C + Lam) / f, C, Lam, B


def history_case(rng, m, full):
    ya, yb = igea.accel_simulate(TH, np.append(BETA0, 0.0), head_sd_arcsec=1, noise_sd=1e-6,
                                 seed=3)
    V0 = igea.accel_joint(TH, ya, yb).cov[:9, :9]
    L = np.linalg.cholesky(V0)
    V = [V0 * s for s in rng.uniform(0.7, 1.4, m)]
    b = np.array([BETA0 + TAU * rng.standard_normal(9) + np.sqrt(s) * L @ rng.standard_normal(9)
                  for s in [np.trace(Vi) / np.trace(V0) for Vi in V]])
    h = igea.accel_history([dict(coef=bi, cov=Vi) for bi, Vi in zip(b, V)], full=full,
                           max_iter=200000)
    bn = BETA0 + TAU * rng.standard_normal(9)
    ya, yb = igea.accel_simulate(TH, np.append(bn, 0.0), head_sd_arcsec=1, noise_sd=1e-6,
                                 seed=4)
    return b, V, h, ya, yb


def dense_information(V, Sig, full):
    """I_ab = (1/2) tr(P_R Omega_a P_R Omega_b) with the dense P_R."""
    p, m = Sig.shape[0], len(V)
    X = np.vstack([np.eye(p)] * m)
    O = np.zeros((m * p, m * p))
    for i, Vi in enumerate(V):
        O[i * p:(i + 1) * p, i * p:(i + 1) * p] = Sig + Vi
    Oi = np.linalg.inv(O)
    P = Oi - Oi @ X @ np.linalg.solve(X.T @ Oi @ X, X.T @ Oi)
    PD = [P @ np.kron(np.eye(m), D) for D in directions(p, full)]
    return 0.5 * np.array([[np.trace(x @ y) for y in PD] for x in PD])


@pytest.mark.parametrize("full", [False, True])
def test_corrected_sd_against_numerical_derivatives(full):
    """sd^2 = (C + Lambda) / f and sd_plugin^2 = C of a dual calibration
    with the prior of 12 (diagonal Sigma) or 20 (full) earlier ones
    (unequal V_i), against the terms
    computed here by numerical derivatives of the posterior; for the
    diagonal Sigma also the Satterthwaite dof 2 mse^2 / Var(mse) with
    Var(mse) by numerical derivatives of that mse."""
    rng = np.random.default_rng(41)
    b, V, h, ya, yb = history_case(rng, 20 if full else 12, full)
    A = igea.accel_design(TH, model="dual")
    y = 0.5 * (ya ** 2 + yb ** 2 - 1)
    x, *_ = np.linalg.lstsq(A, y, rcond=None)
    nus = 20 - 7
    s2 = np.sum((y - A @ x) ** 2) / nus
    post = Posterior(b, V, A, y, full)
    th = theta_of(h.sigma_u, full)
    if full:  # the 45 x 45 information: checked against the likelihood above
        Iinv = np.linalg.inv(h.information)
    else:
        np.testing.assert_allclose(h.information, dense_information(V, h.sigma_u, full),
                                   rtol=1e-9)
        Iinv = np.linalg.inv(h.information)
    mse, C, Lam, B = corrected_mse(post, th, s2, nus, Iinv)
    fit = igea.accel_fit(TH, ya, yb, method="ebr", history=h)
    assert fit.capped == 0  # smooth in theta: no bias factor at its floor
    np.testing.assert_allclose(fit.sd_plugin ** 2, C, rtol=1e-9)
    np.testing.assert_allclose(fit.sd ** 2, mse, rtol=2e-5)
    assert np.all(Lam > 0) and np.all(fit.sd > fit.sd_plugin)
    if full:
        return
    q = len(th)
    Cov = np.zeros((q + 1, q + 1))
    Cov[:q, :q] = Iinv
    Cov[q, q] = 2 * s2 ** 2 / nus
    g = np.zeros((q + 1, 9))
    x0 = np.r_[th, s2]
    for a in range(q + 1):
        e = np.zeros(q + 1)
        e[a] = 1e-2 * np.sqrt(Cov[a, a])

        def m_at(xx):
            ii = np.linalg.inv(dense_information(V, sigma_of(xx[:q], 9, False), False))
            return corrected_mse(post, xx[:q], xx[q], nus, ii)[0]

        g[a] = (m_at(x0 + e) - m_at(x0 - e)) / (2 * e[a])
    dof = 2 * mse ** 2 / np.einsum("aj,ab,bj->j", g, Cov, g)
    np.testing.assert_allclose(fit.sd_dof, dof, rtol=2e-3)
    t = stats.t.ppf(0.975, fit.sd_dof)
    np.testing.assert_allclose(fit.conf_int_upper, fit.coef + t * fit.sd, rtol=1e-9)
    np.testing.assert_allclose(fit.conf_int_lower, fit.coef - t * fit.sd, rtol=1e-9)


def test_interval_coverage_with_a_short_history():
    """10 earlier calibrations (drawn from one joint fit's covariance),
    300 runs: the truth inside [conf_int_lower, conf_int_upper] (95 %) for
    each of the six prior-determined coefficients in 271..296 runs, the
    Binomial(300, 0.95) 99.9 % interval; the plug-in sd (+-1.96 sd_plugin)
    falls short on these runs (below 271 on average)."""
    rng = np.random.default_rng(2025)
    ya, yb = igea.accel_simulate(TH, np.append(BETA0, 0.0), head_sd_arcsec=1, noise_sd=1e-6,
                                 seed=1)
    V = igea.accel_joint(TH, ya, yb).cov[:9, :9]
    L = np.linalg.cholesky(V)
    lo, hi = stats.binom.ppf(0.0005, 300, 0.95), stats.binom.isf(0.0005, 300, 0.95)
    assert (lo, hi) == (271, 296)
    inside, plug = np.zeros(9), np.zeros(9)
    for r in range(300):
        betas = BETA0 + TAU * rng.standard_normal((10, 9))
        h = igea.accel_history([dict(coef=bi + L @ rng.standard_normal(9), cov=V)
                                for bi in betas])
        bn = BETA0 + TAU * rng.standard_normal(9)
        ya, yb = igea.accel_simulate(TH, np.append(bn, 0.0), head_sd_arcsec=1, noise_sd=1e-6,
                                     seed=1000 + r)
        fit = igea.accel_fit(TH, ya, yb, method="ebr", history=h)
        inside += (fit.conf_int_lower <= bn) & (bn <= fit.conf_int_upper)
        plug += np.abs(fit.coef - bn) <= 1.96 * fit.sd_plugin
    prior_dir = [0, 1, 5, 6, 7, 8]
    assert np.all((inside[prior_dir] >= lo) & (inside[prior_dir] <= hi)), inside
    assert plug[prior_dir].mean() < lo, plug


def test_coverage_with_a_long_history():
    """With 200 past calibrations the plug-in prior is accurate and the
    posterior sd covers: 300 runs, |error| <= 1.96 sd counted for each of
    the six coefficients the dual data leave to the prior (KA0, KB0, KA2,
    KB2, KAio, KBio); each count within the Binomial(300, 0.95) 99.9 %
    interval [271, 296]. (kA1, kB1, eta are the data's: their coverage is
    the dual g^2 fit's own, lowered by its second-order bias, docs/accel.md.)"""
    rng = np.random.default_rng(2024)
    ya, yb = igea.accel_simulate(TH, np.append(BETA0, 0.0), head_sd_arcsec=1, noise_sd=1e-6,
                                 seed=1)
    V = igea.accel_joint(TH, ya, yb).cov[:9, :9]
    L = np.linalg.cholesky(V)
    lo, hi = stats.binom.ppf(0.0005, 300, 0.95), stats.binom.isf(0.0005, 300, 0.95)
    hits = np.zeros(9)
    for r in range(300):
        betas = BETA0 + TAU * rng.standard_normal((200, 9))
        hist = [dict(coef=bi + L @ rng.standard_normal(9), cov=V) for bi in betas]
        h = igea.accel_history(hist)
        bn = BETA0 + TAU * rng.standard_normal(9)
        ya, yb = igea.accel_simulate(TH, np.append(bn, 0.0), head_sd_arcsec=1, noise_sd=1e-6,
                                     seed=1000 + r)
        fit = igea.accel_fit(TH, ya, yb, method="ebr", history=h)
        hits += np.abs(fit.coef - bn) <= 1.96 * fit.sd
    assert (lo, hi) == (271, 296)
    prior_dir = [0, 1, 5, 6, 7, 8]
    assert np.all((hits[prior_dir] >= lo) & (hits[prior_dir] <= hi)), hits


DRIVER = __import__("os").environ.get("IGEA_DRIVER")


@pytest.mark.skipif(not DRIVER, reason="IGEA_DRIVER not set")
def test_driver_joint_json_is_a_history_entry(tmp_path):
    """'igea accel --method joint --json' writes coef, cov and flags: the
    files are history entries, equal to the Python fits they come from."""
    import subprocess
    rng = np.random.default_rng(8)
    files, fits = [], []
    for i in range(4):
        beta = BETA0 + TAU * rng.standard_normal(9)
        ya, yb = igea.accel_simulate(TH, np.append(beta, 0.0), head_sd_arcsec=1,
                                     noise_sd=1e-6, seed=50 + i)
        data = tmp_path / ("run%d.txt" % i)
        np.savetxt(data, np.c_[TH, ya, yb], fmt="%.17g")
        out = tmp_path / ("cal%d.json" % i)
        p = subprocess.run([DRIVER, "accel", "--method", "joint", "--json", "--data", str(data),
                            "--out", str(out)], capture_output=True, text=True)
        assert p.returncode == 0, p.stderr
        files.append(str(out))
        fits.append(igea.accel_joint(TH, ya, yb))
    np.testing.assert_allclose(json.load(open(files[0]))["cov"], fits[0].cov, rtol=1e-9)
    a, b = igea.accel_history(files), igea.accel_history(fits)
    np.testing.assert_allclose(a.tau, b.tau, rtol=1e-6)

    np.testing.assert_allclose(a.beta0, b.beta0, rtol=1e-9, atol=1e-15)


@pytest.mark.skipif(not DRIVER, reason="IGEA_DRIVER not set")
def test_driver_method_ebr_history(tmp_path):
    """'igea accel --method ebr --history LIST' equals
    igea.accel_fit(method="ebr", history=files) (sd, sd_plugin, sd_dof and
    the interval), with --full and --alpha too; a dual LS result is refused
    with its file named; --history needs --method ebr, --full --history."""
    import subprocess
    rng = np.random.default_rng(3)
    files = []
    for i in range(14):
        beta = BETA0 + TAU * rng.standard_normal(9)
        ya, yb = igea.accel_simulate(TH, np.append(beta, 0.0), noise_sd=1e-6, seed=i)
        data = tmp_path / ("h%d.txt" % i)
        np.savetxt(data, np.c_[TH, ya, yb], fmt="%.17g")
        out = tmp_path / ("h%d.json" % i)
        subprocess.run([DRIVER, "accel", "--method", "joint", "--json", "--data", str(data),
                        "--out", str(out)], check=True)
        files.append(str(out))
    ya, yb = igea.accel_simulate(TH, np.append(BETA0, 0.0), noise_sd=1e-6, seed=77)
    new = tmp_path / "new.txt"
    np.savetxt(new, np.c_[TH, ya, yb], fmt="%.17g")
    p = subprocess.run([DRIVER, "accel", "--method", "ebr", "--history", ",".join(files[:6]),
                        "--json", "--data", str(new)], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    out = json.loads(p.stdout)
    fit = igea.accel_fit(TH, ya, yb, method="ebr", history=files[:6])
    np.testing.assert_allclose(out["coef"], fit.coef, rtol=1e-12, atol=1e-18)
    for key in ("sd", "sd_plugin", "sd_dof", "conf_int_lower", "conf_int_upper"):
        np.testing.assert_allclose(out[key], getattr(fit, key), rtol=1e-12, err_msg=key)
    np.testing.assert_allclose(out["prior_mean"], fit.prior_mean, rtol=1e-12)
    assert out["history"] == 6 and out["flags"][2] == "data" and out["flags"][5] == "prior"
    assert out["alpha"] == 0.05 and out["full"] is False and out["capped"] == fit.capped
    # --full --alpha: the full Sigma's REML (14 calibrations) and intervals at 99 %
    p = subprocess.run([DRIVER, "accel", "--method", "ebr", "--history", ",".join(files),
                        "--full", "--alpha", "0.01", "--json", "--data", str(new)],
                       capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    out = json.loads(p.stdout)
    fit = igea.accel_fit(TH, ya, yb, method="ebr", alpha=0.01,
                         history=igea.accel_history(files, full=True, max_iter=200000))
    assert out["full"] is True and out["alpha"] == 0.01
    for key in ("coef", "sd", "sd_plugin", "sd_dof", "conf_int_lower", "conf_int_upper"):
        np.testing.assert_allclose(out[key], getattr(fit, key), rtol=1e-9, atol=1e-18,
                                   err_msg=key)
    text = subprocess.run([DRIVER, "accel", "--method", "ebr", "--history", ",".join(files),
                           "--data", str(new)], capture_output=True, text=True)
    assert text.returncode == 0 and "sd_plugin" in text.stdout and "interval" in text.stdout
    p = subprocess.run([DRIVER, "accel", "--full", "--data", str(new)], capture_output=True,
                       text=True)
    assert p.returncode == 64 and "--full needs --history" in p.stderr
    ls = tmp_path / "ls.json"
    subprocess.run([DRIVER, "accel", "--json", "--data", str(new), "--out", str(ls)], check=True)
    p = subprocess.run([DRIVER, "accel", "--method", "ebr", "--history", "%s,%s" % (ls, files[0]),
                        "--data", str(new)], capture_output=True, text=True)
    assert p.returncode == 65 and "ls.json" in p.stderr and "flagged prior" in p.stderr
    p = subprocess.run([DRIVER, "accel", "--history", ",".join(files), "--data", str(new)],
                       capture_output=True, text=True)
    assert p.returncode == 64 and "--method ebr" in p.stderr
