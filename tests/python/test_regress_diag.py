"""igea.ls diagnostics against statsmodels' OLS/WLS formulas written here
in numpy/scipy (statsmodels itself is not a dependency):
  e = W^(1/2) (y - X b); SSR = e'e; TSS centred (weighted mean) when X has a
  constant column, else uncentred; R2 = 1 - SSR/TSS;
  R2_adj = 1 - (n - k_const) / df_resid (1 - R2); F = (ESS/df_model) /
  (SSR/df_resid), p = F.sf; t = b / bse, p = 2 t.sf(|t|, df_resid);
  conf_int = b -+ t.ppf(1 - alpha/2, df_resid) bse;
  llf = -n/2 (log(2 pi SSR/n) + 1) + 1/2 sum log w; aic = -2 llf + 2 k,
  bic = -2 llf + log(n) k, k = df_model + k_const;
  h = diag(H), H = Xw (Xw'Xw)^-1 Xw'; Cook's d = e^2/(s2 (1-h)) h/(1-h)/p;
  PRESS = sum (e/(1-h))^2; Durbin-Watson = sum diff(e)^2 / SSR.
"""
import numpy as np
import pytest
from scipy import stats

import igea


def _reference(X, y, w, alpha):
    n, p = X.shape
    sw = np.sqrt(w)
    Xw, yw = X * sw[:, None], y * sw
    b = np.linalg.solve(Xw.T @ Xw, Xw.T @ yw)
    e = yw - Xw @ b
    ssr = e @ e
    kc = int(any(np.all(X[:, j] == X[0, j]) and X[0, j] != 0 for j in range(p)))
    ybar = np.sum(w * y) / np.sum(w)
    tss = np.sum(w * (y - ybar) ** 2) if kc else np.sum(w * y ** 2)
    dfm, dfr = p - kc, n - p
    s2 = ssr / dfr
    cov = s2 * np.linalg.inv(Xw.T @ Xw)
    bse = np.sqrt(np.diag(cov))
    F = ((tss - ssr) / dfm) / (ssr / dfr)
    llf = -n / 2 * (np.log(2 * np.pi * ssr / n) + 1) + 0.5 * np.sum(np.log(w))
    h = np.diag(Xw @ np.linalg.inv(Xw.T @ Xw) @ Xw.T)
    tc = stats.t.ppf(1 - alpha / 2, dfr)
    t = b / bse
    return dict(x=b, sd=bse, r2=1 - ssr / tss, r2_adj=1 - (n - kc) / dfr * (ssr / tss),
                fvalue=F, f_pvalue=stats.f.sf(F, dfm, dfr), tvalues=t,
                pvalues=2 * stats.t.sf(np.abs(t), dfr), conf_int_lower=b - tc * bse,
                conf_int_upper=b + tc * bse, llf=llf, aic=-2 * llf + 2 * p,
                bic=-2 * llf + np.log(n) * p, leverage=h,
                cooks_d=e ** 2 / (s2 * (1 - h)) * h / (1 - h) / p,
                press=np.sum((e / (1 - h)) ** 2), durbin_watson=np.sum(np.diff(e) ** 2) / ssr)


@pytest.mark.parametrize("weighted, const", [(False, True), (True, True), (False, False)])
def test_diagnostics_match_formulas(weighted, const):
    rng = np.random.default_rng(11)
    n = 40
    t = np.linspace(0, 3, n)
    cols = [np.ones(n)] if const else []
    X = np.column_stack(cols + [t, np.sin(2 * t), rng.standard_normal(n)])
    y = X @ np.arange(1.0, X.shape[1] + 1) + 0.3 * rng.standard_normal(n)
    sig = rng.uniform(0.5, 2.0, n) if weighted else None
    w = 1 / sig ** 2 if weighted else np.ones(n)
    r = igea.ls(X, y, sig, alpha=0.1)
    ref = _reference(X, y, w, 0.1)
    for k, v in ref.items():
        np.testing.assert_allclose(getattr(r, k), v, rtol=1e-9, atol=1e-300, err_msg=k)
    assert r.conf_int().shape == (X.shape[1], 2)
    assert r.df_resid == n - X.shape[1]


def test_diagnostics_undefined_exact_fit():
    x = np.arange(21.0)
    A = np.vander(x, 3, increasing=True)
    r = igea.ls(A, A @ np.ones(3))
    assert r.r2 is None and r.tvalues is None


def test_driver_json_norris(tmp_path):
    """igea regress --method ls --json on NIST StRD Norris: R2 and F against
    the certified ANOVA table, the rest against the formulas above."""
    import json
    import os
    import subprocess
    exe = os.environ.get("IGEA_DRIVER")
    if not exe or not os.path.exists(exe):
        pytest.skip("IGEA_DRIVER not built")
    here = os.path.dirname(os.path.abspath(__file__))
    lines = open(os.path.join(here, "..", "data", "strd", "Norris.dat")).read().splitlines()
    start = max(i for i, l in enumerate(lines) if l.startswith("Data:"))
    yx = np.array([[float(v) for v in l.split()] for l in lines[start + 1:] if l.strip()])
    y, x = yx[:, 0], yx[:, 1]
    X = np.column_stack([np.ones_like(x), x])
    np.savetxt(tmp_path / "S.txt", X, fmt="%.17g")
    np.savetxt(tmp_path / "dw.txt", y, fmt="%.17g")
    out = subprocess.run([exe, "regress", "--method", "ls", "--S", str(tmp_path / "S.txt"),
                          "--dw", str(tmp_path / "dw.txt"), "--json", "--alpha", "0.01"],
                         capture_output=True, text=True, check=True)
    j = json.loads(out.stdout)
    assert j["r2"] == pytest.approx(0.999993745883712, rel=1e-13)
    assert j["fvalue"] == pytest.approx(5436385.54079785, rel=1e-10)
    ref = _reference(X, y, np.ones(len(y)), 0.01)
    for k in ("tvalues", "pvalues", "conf_int_lower", "conf_int_upper", "aic", "bic", "leverage",
              "cooks_d", "press", "durbin_watson", "r2_adj"):
        np.testing.assert_allclose(j[k], ref[k], rtol=1e-9, err_msg=k)
    assert j["df_model"] == 1 and j["df_resid"] == 34 and j["alpha"] == 0.01


def _full(A, y, sig, spec, alpha, flags=0):
    """igea_regress_ls_full by hand: (status, fit outputs, diagnostics)."""
    from igea import _capi, _lib
    A = np.asfortranarray(A)
    m, N = A.shape
    fit = dict(x=np.full(N, 7.0), cov=np.full((N, N), 7.0, order="F"), sd=np.full(N, 7.0),
               sigma2=np.full(1, 7.0), residual=np.full(m, 7.0),
               info=np.full(_capi.REGRESS_INFO_LEN, 7.0))
    dg = dict(tvalues=np.full(N, 7.0), pvalues=np.full(N, 7.0), lo=np.full(N, 7.0),
              hi=np.full(N, 7.0), leverage=np.full(m, 7.0), cooks_d=np.full(m, 7.0),
              diag=np.full(_capi.REGRESS_DIAG_LEN, 7.0))
    p = _lib.dptr
    st = _lib.lib.igea_regress_ls_full(
        m, N, p(A), m, p(y), p(sig), p(spec), 0.0, flags, alpha, p(fit["x"]), p(fit["cov"]), N,
        p(fit["sd"]), p(fit["sigma2"]), p(fit["residual"]), p(fit["info"]), p(dg["tvalues"]),
        p(dg["pvalues"]), p(dg["lo"]), p(dg["hi"]), p(dg["leverage"]), p(dg["cooks_d"]),
        p(dg["diag"]))
    return st, fit, dg


@pytest.mark.parametrize("weighted", [False, True])
def test_ls_full_is_one_fit(weighted):
    """igea_regress_ls_full fits once: its fit is igea_regress_ls_ex's and,
    without spec, its diagnostics igea_regress_ls_diag's, bit for bit (the
    same fit); with spec the diagnostics are the formulas above on X to
    1e-9 (t and the leverages do not depend on the columns' scale)."""
    from igea import _capi, _lib
    rng = np.random.default_rng(5)
    n = 60
    t = np.linspace(0, 2, n)
    X = np.asfortranarray(np.column_stack([np.ones(n), t, t ** 2, np.cos(3 * t)]))
    y = X @ np.array([1.0, -2.0, 0.5, 3.0]) + 0.2 * rng.standard_normal(n)
    sig = rng.uniform(0.5, 2.0, n) if weighted else None
    N = X.shape[1]
    st, fit, dg = _full(X, y, sig, None, 0.1)
    assert st == 0
    x, cov, sd, res = np.empty(N), np.empty((N, N), order="F"), np.empty(N), np.empty(n)
    s2, info = np.zeros(1), np.zeros(_capi.REGRESS_INFO_LEN)
    p = _lib.dptr
    assert _lib.lib.igea_regress_ls_ex(n, N, p(X), n, p(y), p(sig), None, 0.0, 0, p(x), p(cov),
                                       N, p(sd), p(s2), p(res), p(info)) == 0
    for k, v in dict(x=x, cov=cov, sd=sd, sigma2=s2, residual=res, info=info).items():
        np.testing.assert_array_equal(fit[k], v, err_msg=k)
    d = {k: np.empty(N) for k in ("x", "sd", "t", "p", "lo", "hi")}
    lev, cd, dd = np.empty(n), np.empty(n), np.empty(_capi.REGRESS_DIAG_LEN)
    assert _lib.lib.igea_regress_ls_diag(n, N, p(X), n, p(y), p(sig), 0.0, 0.1, p(d["x"]),
                                         p(d["sd"]), p(d["t"]), p(d["p"]), p(d["lo"]),
                                         p(d["hi"]), p(lev), p(cd), p(dd)) == 0
    for k, v in dict(tvalues=d["t"], pvalues=d["p"], lo=d["lo"], hi=d["hi"], leverage=lev,
                     cooks_d=cd, diag=dd).items():
        np.testing.assert_array_equal(dg[k], v, err_msg=k)
    spec = np.array([10.0, 0.01, 3.0, 1e3])
    st, fit, dg = _full(X, y, sig, spec, 0.1)
    assert st == 0
    ref = _reference(X, y, 1 / sig ** 2 if weighted else np.ones(n), 0.1)
    for k in ("x", "sd"):
        np.testing.assert_allclose(fit[k], ref[k], rtol=1e-9, err_msg=k)
    for k, r in (("tvalues", "tvalues"), ("pvalues", "pvalues"), ("lo", "conf_int_lower"),
                 ("hi", "conf_int_upper"), ("leverage", "leverage"), ("cooks_d", "cooks_d")):
        np.testing.assert_allclose(dg[k], ref[r], rtol=1e-9, err_msg=k)
    np.testing.assert_allclose(dg["diag"][_capi.REGRESS_DIAG_R2], ref["r2"], rtol=1e-12)
    r = igea.ls(X, y, sig, spec=spec, alpha=0.1)
    np.testing.assert_allclose(r.tvalues, ref["tvalues"], rtol=1e-9)
    np.testing.assert_allclose(r.press, ref["press"], rtol=1e-9)


def test_ls_full_no_diagnostics():
    """An exact fit: IGEA_REGRESS_NO_DIAG, the fit written (x = 1, 1, 1),
    the diagnostics left as they were; an invalid alpha is -10 and writes
    nothing."""
    from igea import _capi
    x = np.arange(21.0)
    A = np.vander(x, 3, increasing=True)
    st, fit, dg = _full(A, A @ np.ones(3), None, None, 0.05)
    assert st == _capi.REGRESS_NO_DIAG
    np.testing.assert_allclose(fit["x"], np.ones(3), rtol=1e-12)
    for k, v in dg.items():
        assert np.all(v == 7.0), k
    st, fit, dg = _full(A, A @ np.ones(3) + np.sin(x), None, None, 1.5)
    assert st == -10
    assert all(np.all(v == 7.0) for v in fit.values())
