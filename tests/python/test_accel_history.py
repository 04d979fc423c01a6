"""igea.accel_history (REML of the random-effects model of earlier
calibrations) and igea.accel_fit(..., history=) against a REML written here
with scipy, the normal posterior in numpy, and a Monte Carlo coverage check
with its binomial interval."""
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

    r = optimize.minimize(nll, np.zeros(3), method="Nelder-Mead",
                          options=dict(xatol=1e-11, fatol=1e-14, maxiter=40000, maxfev=80000))
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
    np.testing.assert_allclose(fit.sd, np.sqrt(np.diag(C)), rtol=1e-6)
    with pytest.raises(ValueError):
        igea.accel_fit(TH, ya, yb, method="ls", history=h)
    with pytest.raises(ValueError):  # minimum-norm values are not estimates
        igea.accel_history([igea.accel_fit(TH, ya, yb)] * 3)


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
    igea.accel_fit(method="ebr", history=files); a dual LS result is refused
    with its file named; --history needs --method ebr."""
    import subprocess
    rng = np.random.default_rng(3)
    files = []
    for i in range(6):
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
    p = subprocess.run([DRIVER, "accel", "--method", "ebr", "--history", ",".join(files),
                        "--json", "--data", str(new)], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    out = json.loads(p.stdout)
    fit = igea.accel_fit(TH, ya, yb, method="ebr", history=files)
    np.testing.assert_allclose(out["coef"], fit.coef, rtol=1e-12, atol=1e-18)
    np.testing.assert_allclose(out["sd"], fit.sd, rtol=1e-12)
    np.testing.assert_allclose(out["prior_mean"], fit.prior_mean, rtol=1e-12)
    assert out["history"] == 6 and out["flags"][2] == "data" and out["flags"][5] == "prior"
    ls = tmp_path / "ls.json"
    subprocess.run([DRIVER, "accel", "--json", "--data", str(new), "--out", str(ls)], check=True)
    p = subprocess.run([DRIVER, "accel", "--method", "ebr", "--history", "%s,%s" % (ls, files[0]),
                        "--data", str(new)], capture_output=True, text=True)
    assert p.returncode == 65 and "ls.json" in p.stderr and "flagged prior" in p.stderr
    p = subprocess.run([DRIVER, "accel", "--history", ",".join(files), "--data", str(new)],
                       capture_output=True, text=True)
    assert p.returncode == 64 and "--method ebr" in p.stderr
