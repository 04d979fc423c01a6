"""phi and the group scales by restricted maximum likelihood
(IGEA_NOISE_AR_REML, docs/eqerr.md) against the REML written here on the
dense covariance: V = sum_g c_g D K_g D, K_g the AR autocorrelation of each
axis's segments from the MA(infinity) weights (not Yule-Walker), maximised
by scipy; the standard errors against the inverse of the numerical Hessian
of the same dense likelihood."""
import numpy as np
import pytest
from scipy import linalg, optimize, signal

from igea import _capi
from test_noise import noise_eqerr

REML, LS = _capi.NOISE_AR_REML, _capi.NOISE_AR_LS


def flight(rng, M, N, phi, groups=None, scale=(1.0, 1.0), dup=False):
    """Epoch-major rows: smooth terms (polynomials of time on each axis) and
    a random one, row sigmas 0.5..2, AR(p) noise per axis restarted at each
    change of group."""
    m = 3 * M
    t = np.repeat(np.linspace(-1, 1, M), 3)
    ax = np.tile(np.arange(3), M)
    cols = [(ax == a) * t ** k for k in range(2) for a in range(3)][:N - 1]
    S = np.column_stack(cols + [rng.normal(size=m)])
    if dup:  # a repeated column: rank N - 1
        S = np.column_stack([S, S[:, 0]])
    sigma = rng.uniform(0.5, 2.0, m)
    gr = np.zeros(M, dtype=int) if groups is None else groups
    K = ar_cov(phi, gr)
    c = np.array(scale)[np.repeat(gr, 3)]
    L = np.linalg.cholesky(K * np.sqrt(np.outer(c, c)))
    dw = sigma * (L @ rng.normal(size=m)) + S @ rng.normal(size=S.shape[1]) * 0.1
    return S, dw, sigma, gr


def ar_autocorr(phi, n, L=6000):
    """rho_0 .. rho_(n-1) of a stationary AR(p) from its MA(infinity)
    weights psi (the impulse response of 1 / (1 - sum phi_k B^k)),
    truncated at L terms."""
    psi = signal.lfilter([1.0], np.r_[1.0, -np.asarray(phi)], np.r_[1.0, np.zeros(L - 1)])
    g = np.array([psi[:L - k] @ psi[k:] for k in range(n)])
    return g / g[0]


def ar_cov(phi, gr):
    """Epoch-major correlation: each axis an AR(p) (phi[a]) within each
    segment of constant group, segments independent."""
    M = len(gr)
    K = np.zeros((3 * M, 3 * M))
    seg = np.concatenate([[0], np.cumsum(gr[1:] != gr[:-1])])
    for a in range(3):
        rho = ar_autocorr(phi[a], M)
        for s in np.unique(seg):
            e = np.flatnonzero(seg == s)
            i = 3 * e + a
            K[np.ix_(i, i)] = rho[np.abs(e[:, None] - e[None, :])]
    return K


def dense_reml(theta, X, y, sigma, gr, p, G):
    """- the restricted log-likelihood at theta = (phi (3 p), log c (G))."""
    phi = theta[:3 * p].reshape(3, p)
    c = np.exp(theta[3 * p:])
    for a in range(3):  # stationary: the roots of 1 - sum phi z^k outside the unit circle
        if np.any(np.abs(np.roots(np.r_[-phi[a][::-1], 1.0])) <= 1.0001):
            return 1e10
    K = ar_cov(phi, gr)
    cr = c[np.repeat(gr, 3)]
    V = K * np.sqrt(np.outer(cr, cr)) * np.outer(sigma, sigma)
    cf = linalg.cho_factor(V)
    Vi_X = linalg.cho_solve(cf, X)
    Vi_y = linalg.cho_solve(cf, y)
    A = X.T @ Vi_X
    beta = np.linalg.solve(A, X.T @ Vi_y)
    r = y - X @ beta
    ld = 2 * np.sum(np.log(np.diag(cf[0])))
    return 0.5 * (ld + np.linalg.slogdet(A)[1] + r @ linalg.cho_solve(cf, r))


def hessian(f, x, h):
    n = len(x)
    H = np.empty((n, n))
    for i in range(n):
        for k in range(n):
            e_i, e_k = np.eye(n)[i] * h[i], np.eye(n)[k] * h[k]
            H[i, k] = (f(x + e_i + e_k) - f(x + e_i - e_k) - f(x - e_i + e_k)
                       + f(x - e_i - e_k)) / (4 * h[i] * h[k])
    return 0.5 * (H + H.T)


@pytest.mark.parametrize("p,G,dup", [(1, 1, False), (2, 2, False), (3, 1, True)])
def test_reml_equals_dense_restricted_likelihood(p, G, dup):
    rng = np.random.default_rng(10 + p)
    M, N = 60, 5
    phi = np.array([[0.7, 0.1, 0.05][:p], [0.5, 0.2, -0.1][:p], [0.8, -0.1, 0.1][:p]])
    gr = (np.arange(M) >= 35).astype(int) if G == 2 else None
    S, dw, sigma, g = flight(rng, M, N, phi, gr, scale=(1.0, 4.0)[:G] if G == 2 else (1.0,),
                            dup=dup)
    r = noise_eqerr(S, dw, sigma=sigma, group=gr, G=G, ar=p, ar_estimate=1, ar_method=REML,
                    noise_tol=1e-10, noise_max_iter=300)
    assert r["info"][_capi.STATS_INFO_NOISE_CONVERGED] == 1
    ph = r["ar"][:9].reshape(3, 3)[:, :p]
    se = r["ar"][9:].reshape(3, 3)[:, :p]
    c = r["groups"][:, _capi.NOISE_GROUP_SCALE]
    c_se = r["groups"][:, _capi.NOISE_GROUP_SE_REML]
    X = S[:, :N]  # a basis of the columns (the repeated one dropped)
    f = lambda th: dense_reml(th, X, dw, sigma, g, p, G)  # noqa: E731
    x0 = np.r_[phi.ravel(), np.zeros(G)]  # from the truth
    best = optimize.minimize(f, x0, method="BFGS", options=dict(gtol=1e-9))
    best = optimize.minimize(f, best.x, method="Nelder-Mead",
                             options=dict(xatol=1e-10, fatol=1e-13, maxfev=20000))
    np.testing.assert_allclose(ph.ravel(), best.x[:3 * p], atol=2e-5)
    np.testing.assert_allclose(np.log(c), best.x[3 * p:], atol=2e-5)
    # standard errors: the inverse Hessian of the dense likelihood in (phi, c)
    th = np.r_[best.x[:3 * p], np.exp(best.x[3 * p:])]
    fc = lambda t: f(np.r_[t[:3 * p], np.log(t[3 * p:])])  # noqa: E731
    cov = np.linalg.inv(hessian(fc, th, np.r_[np.full(3 * p, 2e-4), 2e-4 * th[3 * p:]]))
    sd = np.sqrt(np.diag(cov))
    np.testing.assert_allclose(se.ravel(), sd[:3 * p], rtol=2e-3)
    np.testing.assert_allclose(c_se, sd[3 * p:], rtol=2e-3)
    # the scale's se with phi estimated exceeds the one with phi known
    c_only = np.sqrt(np.diag(np.linalg.inv(hessian(
        lambda t: fc(np.r_[th[:3 * p], t]), th[3 * p:], 2e-4 * th[3 * p:]))))
    assert np.all(c_se > c_only)


def test_reml_removes_the_bias_of_the_fitted_terms():
    """Mean phi-hat over 300 series of 80 epochs with 9 smooth terms fitted
    (1, t, t^2 on each axis), AR(2) (0.6, 0.3): least squares
    (Cochrane-Orcutt) is biased low by many standard errors of the mean;
    REML's bias of phi_1 + phi_2 is less than a fifth of it."""
    rng = np.random.default_rng(4)
    M, p = 80, 2
    phi = np.array([0.6, 0.3])
    t = np.repeat(np.linspace(-1, 1, M), 3)
    ax = np.tile(np.arange(3), M)
    S = 30 * np.column_stack([(ax == a) * t ** k for k in range(3) for a in range(3)])
    K = ar_cov(np.tile(phi, (3, 1)), np.zeros(M, dtype=int))
    L = np.linalg.cholesky(K)
    out = {LS: [], REML: []}
    for _ in range(300):
        dw = L @ rng.normal(size=3 * M)
        for meth in out:
            r = noise_eqerr(S, dw, sigma=np.ones(3 * M), ar=p, ar_estimate=1, ar_method=meth)
            out[meth].append(r["ar"][:9].reshape(3, 3)[:, :p])
    bias, sem = {}, {}
    for meth, v in out.items():
        v = np.array(v).reshape(-1, p).sum(axis=1)
        bias[meth], sem[meth] = v.mean() - phi.sum(), v.std() / np.sqrt(len(v))
    assert bias[LS] < -10 * sem[LS], (bias, sem)
    assert abs(bias[REML]) < 0.2 * abs(bias[LS]), (bias, sem)


def test_reml_choice_names_and_refusals():
    import igea
    from igea import _lib
    opts = _lib.options("eqerr", "t", ("igea_noise_eqerr", "opts"))
    assert opts[_capi.EQERR_OPT_AR_METHOD] == REML == 0  # the default
    for bad in (2.0, 0.5, -1.0, np.nan):
        opts[_capi.EQERR_OPT_AR_METHOD] = bad
        assert _lib.lib.igea_eqerr_check_opts(_lib.dptr(opts)) == 1 + _capi.EQERR_OPT_AR_METHOD
    assert _lib.lib.igea_opt_name(_capi.MODULE_EQERR, _capi.EQERR_OPT_AR_METHOD) == b"ar_method"
    assert [_lib.choice_name(_capi.CHOICE_NOISE_AR_METHOD, c) for c in (REML, LS)] == ["reml", "ls"]
    fl = igea.simulate(seed=2, ar1=0.6)
    r = igea.eqerr(fl.S, fl.dw, fl.sigma, fl.spec, ar=1, ar_method="reml")
    assert r.ar_method == "reml" and r.ar_order == 1
    assert r.groups[0]["scale_se_reml"] > 0
    assert igea.eqerr(fl.S, fl.dw, fl.sigma, fl.spec, ar=1).ar_method == "reml"
    assert igea.eqerr(fl.S, fl.dw, fl.sigma, fl.spec, ar=1, ar_method="ls").ar_method == "ls"
    assert igea.eqerr(fl.S, fl.dw, fl.sigma, fl.spec, ar_phi=[0.6]).ar_method is None
    for meth in ("reml", "ls"):
        with pytest.raises(ValueError, match="ar_method"):
            igea.eqerr(fl.S, fl.dw, fl.sigma, fl.spec, ar_phi=[0.6], ar_method=meth)
    with pytest.raises(ValueError, match="ar_method"):
        igea.eqerr(fl.S, fl.dw, fl.sigma, fl.spec, ar=1, ar_method="ml")


def test_driver_ar_method(tmp_path):
    """igea eqerr --ar-method reml: the JSON names the estimator and equals
    igea.eqerr(..., ar_method="reml"); reml is the default, ls the other;
    without an estimated phi either is refused (exit 64); igea montecarlo
    refuses it with --ar-given."""
    import json

    import igea
    from test_eqerr_noise_report import driver, make_flight, write_flight
    S, dw, sigma, spec, _ = make_flight(3, M=80, phi=0.7)
    write_flight(tmp_path, S, dw, sigma, spec)
    base = ["eqerr", "--S", "S.txt", "--dw", "dw.txt", "--sigma", "sigma.txt", "--spec",
            "spec.txt", "--lambda-test", "1"]
    r = driver(*base, "--ar", "1", "--ar-method", "reml", "--json", cwd=tmp_path)
    assert r.returncode in (0, 1), r.stderr
    j = json.loads(r.stdout)
    py = igea.eqerr(S, dw, sigma, spec, lambda_test=1, ar=1, ar_method="reml")
    assert j["ar_method"] == "reml" and py.ar_method == "reml"
    np.testing.assert_allclose(np.ravel(j["ar_phi"]), py.ar_phi.ravel(), rtol=1e-9)
    np.testing.assert_allclose(np.ravel(j["ar_se"]), py.ar_se.ravel(), rtol=1e-6)
    assert j["groups"][0]["scale_se_reml"] == pytest.approx(py.groups[0]["scale_se_reml"],
                                                            rel=1e-6)
    dflt = json.loads(driver(*base, "--ar", "1", "--json", cwd=tmp_path).stdout)
    assert dflt["ar_method"] == "reml" and dflt["ar_phi"] == j["ar_phi"]
    ls = json.loads(driver(*base, "--ar", "1", "--ar-method", "ls", "--json", cwd=tmp_path).stdout)
    assert ls["ar_method"] == "ls" and ls["ar_phi"] != j["ar_phi"]
    for meth in ("reml", "ls"):
        bad = driver(*base, "--ar-phi", "0.7", "--ar-method", meth, cwd=tmp_path)
        assert bad.returncode == 64 and "--ar-method" in bad.stderr
    bad = driver("montecarlo", "--flights", "2", "--ar1", "0.5", "--ar", "1", "--ar-given",
                 "--ar-method", "reml")
    assert bad.returncode == 64 and "--ar-method" in bad.stderr
