"""Classical error separation: least squares, ridge, principal-component,
Bayesian and empirical-Bayes ridge estimators, collinearity diagnostics
(seeds 000 and 003; METHODS 0.3, 4.3). All work on the SVD of the weighted
design, never on the normal matrix. The design A may be a data frame: its
columns name the terms, and y, sigma and spec given as Series are aligned
to its labels as igea.eqerr aligns them (igea/_frames.py)."""
from dataclasses import dataclass

import numpy as np

from . import _capi, _frames, _lib
from ._result import result



def _design(A, y, sigma=None, spec=None, y_optional=False, names=None):
    """A, m, N, y, sigma (m,) or None, spec (N,) or None, names: the arrays
    of the igea_regress_* arguments A, y, sigma and spec_sigma. A may be a
    data frame (igea/_frames.py): its columns are the names unless names is
    given, and y, sigma (Series on its index) and spec (a Series on its
    columns) are aligned to it."""
    A, names, v = _frames.inputs(A, names, rows=(("y", y), ("sigma", sigma)),
                                 cols=(("spec", spec),))
    y, sigma, spec = v["y"], v["sigma"], v["spec"]
    A = _lib.as_f64(A, "A", ndim=2)
    m, N = A.shape
    if m < 1 or N < 1:
        raise ValueError("A: expected at least one row and one column, got shape %s" % (A.shape,))
    if y is None and y_optional:
        yv = None
    else:
        yv = _lib.as_f64(y, "y", ndim=1, shape=(m,))
    sg = None
    if sigma is not None:
        if np.ndim(sigma) == 0:
            sg = np.full(m, float(sigma))
        else:
            sg = _lib.as_f64(sigma, "sigma", ndim=1, shape=(m,))
    sp = None if spec is None else _lib.as_f64(spec, "spec", ndim=1, shape=(N,))
    return A, m, N, yv, sg, sp, names


def _names(N, names):
    if names is None:
        return ["x%d" % j for j in range(N)]
    names = [str(s) for s in names]
    if len(names) != N:
        raise ValueError("names: expected %d names, got %d" % (N, len(names)))
    return names


def _rank_fields(info):
    return dict(rank=int(info[_capi.REGRESS_INFO_RANK]),
                rank_tol=float(info[_capi.REGRESS_INFO_TOL]),
                scaled=bool(info[_capi.REGRESS_INFO_SCALED]))


def _given(N, names):
    return None if names is None else tuple(_names(N, names))


def _coef_table(names, x, sd, extra=None, sd_name="sd"):
    head = "%-10s %16s %14s" % ("term", "estimate", sd_name)
    if extra:
        head += "".join(" %14s" % e[0] for e in extra)
    rows = [head]
    for j, nm in enumerate(names):
        row = "%-10s %16.8e %14.6e" % (nm, x[j], sd[j])
        if extra:
            row += "".join(" %14.6e" % e[1][j] for e in extra)
        rows.append(row)
    return rows


class _Estimate:
    """An estimate x with covariance cov (and term names)."""

    @property
    def sd(self):
        return np.sqrt(np.diag(self.cov))

    def _table(self, extra=None, sd_name="sd"):
        return _coef_table(_names(len(self.x), self.names), self.x, self.sd, extra, sd_name)


@result
@dataclass(frozen=True)
class LsResult(_Estimate):
    """Weighted least squares (minimum norm when rank-deficient), refined in
    extended precision at full rank; sd = sqrt(diag(cov)) from the library,
    rank_tol the singular-value cut of the column-scaled design, refine_steps
    the refinement steps run."""
    x: np.ndarray
    cov: np.ndarray
    rank: int
    sigma2: float
    residual: np.ndarray
    names: tuple = None
    sd: np.ndarray = None
    rank_tol: float = 0.0
    refine_steps: int = 0
    # statsmodels-OLS diagnostics (igea_regress_ls_diag; None when they are
    # not defined: no residual dof, an exact fit, a leverage of 1)
    r2: float = None
    r2_adj: float = None
    fvalue: float = None
    f_pvalue: float = None
    tvalues: np.ndarray = None
    pvalues: np.ndarray = None
    conf_int_lower: np.ndarray = None
    conf_int_upper: np.ndarray = None
    alpha: float = 0.05
    llf: float = None
    aic: float = None
    bic: float = None
    leverage: np.ndarray = None
    cooks_d: np.ndarray = None
    press: float = None
    durbin_watson: float = None
    df_model: int = None
    df_resid: int = None

    def conf_int(self):
        """(N, 2) array of the 1 - alpha confidence limits, as statsmodels."""
        return np.column_stack([self.conf_int_lower, self.conf_int_upper])

    def summary(self):
        N = len(self.x)
        lines = ["least squares: rank %d of %d, residual variance %.6e (%d dof)"
                 % (self.rank, N, self.sigma2, len(self.residual) - self.rank)]
        if self.rank < N:
            lines.append("rank-deficient: minimum-norm solution; see igea.collinearity for the "
                         "estimable combinations")
        lines += self._table()
        return "\n".join(lines)


@result
@dataclass(frozen=True)
class EbrResult(_Estimate):
    """Empirical-Bayes ridge (METHODS 4.3); sd: the posterior sds."""
    x: np.ndarray
    cov: np.ndarray
    lam: float
    rank: int
    sigma2: float
    residual: np.ndarray
    shrink: np.ndarray
    sd_frequentist: np.ndarray
    rule: str = "sc"
    names: tuple = None
    rank_tol: float = 0.0

    def summary(self):
        N = len(self.x)
        lines = ["empirical-Bayes ridge (%s rule): lambda = %.10e, rank %d of %d"
                 % (self.rule.upper(), self.lam, self.rank, N),
                 "shrink factors (canonical components): "
                 + " ".join("%.5f" % s for s in self.shrink[:self.rank])]
        if self.rank < N:
            lines.append("%d null direction(s): the coefficients touching them are set by the "
                         "prior, not by the data (METHODS 4.3 caveat)" % (N - self.rank))
        lines += self._table([("sd_frequentist", self.sd_frequentist)], "sd_posterior")
        return "\n".join(lines)


@result
@dataclass(frozen=True)
class RidgeResult(_Estimate):
    """Ridge regression x(k) = (A^T W A + k I)^-1 A^T W y; rank and rank_tol
    of the design worked on, scaled: its columns were scaled to unit norm
    internally (norms more than 1e8 apart; k is then of the scaled design)."""
    x: np.ndarray
    cov: np.ndarray
    k: float
    rule: str
    sigma2: float
    residual: np.ndarray
    names: tuple = None
    rank: int = 0
    rank_tol: float = 0.0
    scaled: bool = False

    def summary(self):
        lines = ["ridge (%s): k = %.6e, least-squares residual variance %.6e"
                 % (self.rule, self.k, self.sigma2)]
        lines += self._table()
        return "\n".join(lines)


@result
@dataclass(frozen=True)
class RidgeTrace:
    """x(k) for a grid of k: X[:, j] = x(k[j])."""
    k: np.ndarray
    X: np.ndarray
    edf: np.ndarray

    def summary(self):
        rows = ["%14s %8s  %s" % ("k", "edf", "coefficients")]
        for j in range(len(self.k)):
            rows.append("%14.6e %8.4f  %s" % (self.k[j], self.edf[j],
                                              " ".join("%12.5e" % v for v in self.X[:, j])))
        return "\n".join(rows)


@result
@dataclass(frozen=True)
class PceResult(_Estimate):
    """Principal-component estimate (truncated SVD); rank, rank_tol and
    scaled as RidgeResult (eig_min is then of the scaled design)."""
    x: np.ndarray
    cov: np.ndarray
    ncomp: int
    sigma2: float
    residual: np.ndarray
    names: tuple = None
    rank: int = 0
    rank_tol: float = 0.0
    scaled: bool = False

    def summary(self):
        lines = ["principal-component estimate: %d component(s) kept, least-squares residual "
                 "variance %.6e" % (self.ncomp, self.sigma2)]
        lines += self._table()
        return "\n".join(lines)


@result
@dataclass(frozen=True)
class BayesResult(_Estimate):
    """Posterior mean and covariance with a normal prior and known noise."""
    x: np.ndarray
    cov: np.ndarray
    residual: np.ndarray
    prior_sd: np.ndarray
    names: tuple = None

    def summary(self):
        ratio = self.sd / self.prior_sd
        lines = ["Bayesian estimate (normal prior, known noise); sd ratio = posterior / prior sd "
                 "(near 1: the data add little, the prior decides)"]
        lines += self._table([("prior_sd", self.prior_sd), ("sd_ratio", ratio)])
        return "\n".join(lines)


@result
@dataclass(frozen=True)
class Collinearity:
    """Collinearity diagnostics of the weighted normal matrix B = A^T W A."""
    cond: float
    cond_estimable: float
    rank: int
    eigenvalues: np.ndarray
    eigenvectors: np.ndarray
    vif: np.ndarray
    sd_comb: np.ndarray
    prior_determined: np.ndarray
    names: tuple = None

    @property
    def null_space(self):
        return self.eigenvectors[:, self.rank:]

    @property
    def estimable(self):
        """The estimable combinations v_i (columns), i < rank."""
        return self.eigenvectors[:, :self.rank]

    def summary(self):
        N = len(self.eigenvalues)
        names = _names(N, self.names)
        lines = ["condition number %.6e (estimable part %.6e), rank %d of %d"
                 % (self.cond, self.cond_estimable, self.rank, N), "",
                 "%4s %14s %14s  %s" % ("i", "eigenvalue", "sd(v_i^T x)", "combination v_i")]
        for i in range(N):
            v = self.eigenvectors[:, i]
            big = np.argsort(-np.abs(v))[:4]
            comb = " ".join("%+.3f*%s" % (v[j], names[j]) for j in big if abs(v[j]) > 1e-3)
            lines.append("%4d %14.6e %14s  %s" % (i, self.eigenvalues[i],
                                                  "%.6e" % self.sd_comb[i] if i < self.rank
                                                  else "(null space)", comb))
        lines += ["", "%-10s %14s  %s" % ("term", "VIF", "determined by")]
        for j in range(N):
            lines.append("%-10s %14.6g  %s" % (names[j], self.vif[j],
                                               "PRIOR (null-space component)"
                                               if self.prior_determined[j] else "data"))
        return "\n".join(lines)


def _ls_diag(status, alpha, t, pv, lo, hi, lev, cd, dg):
    """The diagnostics fields of LsResult (empty when not defined:
    igea_regress_ls_full's IGEA_REGRESS_NO_DIAG)."""
    if status == _capi.REGRESS_NO_DIAG:
        return dict(alpha=float(alpha))
    g = lambda k: float(dg[getattr(_capi, "REGRESS_DIAG_" + k)])  # noqa: E731
    return dict(r2=g("R2"), r2_adj=g("R2_ADJ"), fvalue=g("FVALUE"), f_pvalue=g("F_PVALUE"),
                tvalues=t, pvalues=pv, conf_int_lower=lo, conf_int_upper=hi,
                alpha=float(alpha), llf=g("LLF"), aic=g("AIC"), bic=g("BIC"), leverage=lev,
                cooks_d=cd, press=g("PRESS"), durbin_watson=g("DURBIN_WATSON"),
                df_model=int(g("DF_MODEL")), df_resid=int(g("DF_RESID")))


def ls(A, y, sigma=None, *, spec=None, rcond=0.0, names=None, alpha=0.05):
    """Weighted least squares by SVD; minimum-norm solution if rank-deficient.

    A: (m, N), y: (m,), sigma: None, a number or (m,) row sds; spec: None
    or (N,) column scales (the 1-sigma specs: every estimator then works on
    A diag(spec) and returns x, cov in A's units); rcond <= 0 for the
    default rank cut max(m, N) eps. Returns LsResult(x, cov, rank,
    sigma2, residual, sd, rank_tol, refine_steps) with the statsmodels-OLS/WLS
    diagnostics of that fit (one factorisation: igea_regress_ls_full): r2,
    r2_adj, fvalue, f_pvalue, tvalues, pvalues, conf_int_lower,
    conf_int_upper (level 1 - alpha; conf_int() stacks them), llf, aic, bic,
    leverage, cooks_d, press, durbin_watson, df_model, df_resid (None where
    they are not defined: no residual dof, an exact fit, a leverage 1)."""
    A, m, N, y, sg, sp, names = _design(A, y, sigma, spec, names=names)
    x, sd = np.empty(N), np.empty(N)
    cov = np.empty((N, N), order="F")
    s2 = np.zeros(1)
    res = np.empty(m)
    info = np.zeros(_capi.REGRESS_INFO_LEN)
    t, pv, lo, hi = (np.empty(N) for _ in range(4))
    lev, cd = np.empty(m), np.empty(m)
    dg = np.zeros(_capi.REGRESS_DIAG_LEN)
    st = _lib.call("igea.ls", "igea_regress_ls_full", m, N, _lib.dptr(A), m, _lib.dptr(y),
                   _lib.dptr(sg), _lib.dptr(sp), float(rcond), 0, float(alpha), _lib.dptr(x),
                   _lib.dptr(cov), N, _lib.dptr(sd), _lib.dptr(s2), _lib.dptr(res),
                   _lib.dptr(info), _lib.dptr(t), _lib.dptr(pv), _lib.dptr(lo), _lib.dptr(hi),
                   _lib.dptr(lev), _lib.dptr(cd), _lib.dptr(dg))
    return LsResult(x=x, cov=np.ascontiguousarray(cov), rank=int(info[_capi.REGRESS_INFO_RANK]),
                    sigma2=float(s2[0]), residual=res, names=_given(N, names), sd=sd,
                    rank_tol=float(info[_capi.REGRESS_INFO_TOL]),
                    refine_steps=int(info[_capi.REGRESS_INFO_REFINE_STEPS]),
                    **_ls_diag(st, alpha, t, pv, lo, hi, lev, cd, dg))


def ebr(A, y, sigma=None, *, spec=None, rule="sc", lam_floor=0.0, names=None):
    """Empirical-Bayes ridge exactly as METHODS 4.3.

    sigma: None, a number or (m,) row sds; spec: (N,) prior scales (the
    1-sigma specs, D of METHODS 4.3) or None; rule: "sc" (Shinozaki-Chang,
    eq. 17), "mm" or "ml2"; lam_floor >= 0. Returns EbrResult(x, cov, lam,
    rank, sigma2, residual, shrink, sd_frequentist; sd the posterior sds)."""
    A, m, N, y, sg, sp, names = _design(A, y, sigma, spec, names=names)
    rule_code = _lib.choice(_capi.CHOICE_REGRESS_EBR_RULE, rule, "igea.ebr", "rule")
    x, cov = np.empty(N), np.empty((N, N), order="F")
    lam, s2 = np.zeros(1), np.zeros(1)
    rank = np.zeros(1, dtype=np.intc)
    res, sh, sf = np.empty(m), np.empty(N), np.empty(N)
    _lib.call("igea.ebr", "igea_regress_ebr", m, N, _lib.dptr(A), m, _lib.dptr(y), _lib.dptr(sg),
              _lib.dptr(sp), rule_code, float(lam_floor), _lib.dptr(x), _lib.dptr(cov), N,
              _lib.dptr(lam), _lib.iptr(rank), _lib.dptr(s2), _lib.dptr(res), _lib.dptr(sh),
              _lib.dptr(sf))
    info = np.zeros(_capi.REGRESS_INFO_LEN)
    _lib.call("igea.ebr", "igea_regress_rank_info", m, N, _lib.dptr(A), m, _lib.dptr(sg),
              _lib.dptr(sp), 0.0, _lib.dptr(info))
    return EbrResult(x=x, cov=np.ascontiguousarray(cov), lam=float(lam[0]), rank=int(rank[0]),
                     sigma2=float(s2[0]), residual=res, shrink=sh, sd_frequentist=sf, rule=rule,
                     names=_given(N, names), rank_tol=float(info[_capi.REGRESS_INFO_TOL]))


def ridge(A, y, sigma=None, *, spec=None, k=None, rule=None, names=None):
    """Ridge regression on the design as given (scale the columns first).

    Either k (a number >= 0) or rule in "hkb" (Hoerl-Kennard-Baldwin), "lw"
    (Lawless-Wang), "gcv", "loo". Returns RidgeResult(x, cov, k, rule,
    sigma2, residual)."""
    A, m, N, y, sg, sp, names = _design(A, y, sigma, spec, names=names)
    if (k is None) == (rule is None):
        raise ValueError("k, rule: give exactly one of them")
    if rule is None:
        rule = "fixed"
    rule_code = _lib.choice(_capi.CHOICE_REGRESS_RIDGE_RULE, rule, "igea.ridge", "rule")
    x = np.empty(N)
    cov = np.empty((N, N), order="F")
    ku = np.zeros(1)
    s2 = np.zeros(1)
    res = np.empty(m)
    info = np.zeros(_capi.REGRESS_INFO_LEN)
    _lib.call("igea.ridge", "igea_regress_ridge_ex", m, N, _lib.dptr(A), m, _lib.dptr(y),
              _lib.dptr(sg), _lib.dptr(sp), rule_code, float(k) if k is not None else 0.0,
              _lib.dptr(x), _lib.dptr(cov), N, _lib.dptr(ku), _lib.dptr(s2), _lib.dptr(res),
              _lib.dptr(info))
    return RidgeResult(x=x, cov=np.ascontiguousarray(cov), k=float(ku[0]), rule=rule,
                       sigma2=float(s2[0]), residual=res,
                       names=_given(N, names), **_rank_fields(info))


def ridge_trace(A, y, k, sigma=None, *, spec=None):
    """The ridge trace: RidgeTrace(k, X (N, len(k)), edf)."""
    A, m, N, y, sg, sp, _ = _design(A, y, sigma, spec)
    kv = _lib.as_f64(k, "k", ndim=1)
    nk = kv.shape[0]
    if nk < 1:
        raise ValueError("k: empty")
    X = np.empty((N, nk), order="F")
    edf = np.empty(nk)
    _lib.call("igea.ridge_trace", "igea_regress_ridge_trace", m, N, _lib.dptr(A), m, _lib.dptr(y),
              _lib.dptr(sg), _lib.dptr(sp), nk, _lib.dptr(kv), _lib.dptr(X), N, _lib.dptr(edf))
    return RidgeTrace(k=np.array(kv), X=np.ascontiguousarray(X), edf=edf)


def pce(A, y, sigma=None, *, spec=None, ncomp=None, eig_min=None, names=None):
    """Principal-component estimation: keep the ncomp largest components, or
    those with eigenvalue >= eig_min. Returns PceResult."""
    A, m, N, y, sg, sp, names = _design(A, y, sigma, spec, names=names)
    if (ncomp is None) == (eig_min is None):
        raise ValueError("ncomp, eig_min: give exactly one of them")
    if ncomp is not None and int(ncomp) < 1:
        raise ValueError("ncomp: expected >= 1, got %r" % (ncomp,))
    x = np.empty(N)
    cov = np.empty((N, N), order="F")
    nu = np.zeros(1, dtype=np.intc)
    s2 = np.zeros(1)
    res = np.empty(m)
    info = np.zeros(_capi.REGRESS_INFO_LEN)
    _lib.call("igea.pce", "igea_regress_pce_ex", m, N, _lib.dptr(A), m, _lib.dptr(y),
              _lib.dptr(sg), _lib.dptr(sp), int(ncomp) if ncomp is not None else 0,
              float(eig_min) if eig_min is not None else 0.0, _lib.dptr(x), _lib.dptr(cov), N,
              _lib.iptr(nu), _lib.dptr(s2), _lib.dptr(res), _lib.dptr(info))
    return PceResult(x=x, cov=np.ascontiguousarray(cov), ncomp=int(nu[0]), sigma2=float(s2[0]),
                     residual=res, names=_given(N, names), **_rank_fields(info))


def bayes(A, y, prior_cov, prior_mean=None, sigma=None, *, spec=None, names=None):
    """Bayesian estimate with prior x ~ N(prior_mean, prior_cov) and known
    noise sds sigma (None: 1). prior_cov: (N, N) SPD. Returns BayesResult."""
    A, m, N, y, sg, sp, names = _design(A, y, sigma, spec, names=names)
    P = _lib.as_f64(prior_cov, "prior_cov", ndim=2, shape=(N, N))
    mu = None if prior_mean is None else _lib.as_f64(prior_mean, "prior_mean", ndim=1,
                                                     shape=(N,))
    x = np.empty(N)
    cov = np.empty((N, N), order="F")
    res = np.empty(m)
    _lib.call("igea.bayes", "igea_regress_bayes", m, N, _lib.dptr(A), m, _lib.dptr(y),
              _lib.dptr(sg), _lib.dptr(sp), _lib.dptr(mu), _lib.dptr(P), N, _lib.dptr(x),
              _lib.dptr(cov), N, _lib.dptr(res))
    return BayesResult(x=x, cov=np.ascontiguousarray(cov), residual=res,
                       prior_sd=np.sqrt(np.diag(P)).copy(),
                       names=_given(N, names))


def collinearity(A, y=None, sigma=None, *, spec=None, rcond=0.0, names=None):
    """Condition number, eigenvalue table, VIFs, null space, estimable
    combinations with their sds (scaled by the residual sd when y is given)
    and the prior-determined flags. Returns Collinearity."""
    A, m, N, y, sg, sp, names = _design(A, y, sigma, spec, y_optional=True, names=names)
    cond = np.empty(_capi.REGRESS_COND_LEN)
    rank = np.zeros(1, dtype=np.intc)
    eig = np.empty(N)
    V = np.empty((N, N), order="F")
    vif = np.empty(N)
    sd = np.empty(N)
    pd = np.empty(N, dtype=np.intc)
    _lib.call("igea.collinearity", "igea_regress_collinearity", m, N, _lib.dptr(A), m,
              _lib.dptr(y), _lib.dptr(sg), _lib.dptr(sp), float(rcond), _lib.dptr(cond),
              _lib.iptr(rank), _lib.dptr(eig), _lib.dptr(V), N, _lib.dptr(vif), _lib.dptr(sd),
              _lib.iptr(pd))
    c = _lib.fields(cond, "REGRESS_COND_", all=float, estimable=float)
    return Collinearity(cond=c["all"], cond_estimable=c["estimable"], rank=int(rank[0]),
                        eigenvalues=eig, eigenvectors=np.ascontiguousarray(V), vif=vif,
                        sd_comb=sd, prior_determined=pd.astype(bool),
                        names=_given(N, names))


def bias_mse(estimate, A, x_true, sigma_true):
    """Bias and MSE of a linear estimator at fixed tuning (k, ncomp, lambda),
    given the true coefficients: estimate(y) -> x for y in R^m, A (m, N),
    sigma_true: noise sd (number or (m,)). Uses linearity: E x = estimate(A
    x_true) and Cov x = L diag(sigma^2) L^T with L's columns estimate(e_i).
    Returns (bias (N,), mse (N,))."""
    A = _lib.as_f64(A, "A", ndim=2)
    m, N = A.shape
    xt = _lib.as_f64(x_true, "x_true", ndim=1, shape=(N,))
    sg = np.broadcast_to(np.asarray(sigma_true, dtype=float), (m,))
    mean = np.asarray(estimate(A @ xt), dtype=float)
    L = np.column_stack([np.asarray(estimate(np.eye(m)[:, i]), dtype=float) for i in range(m)])
    var = np.einsum("ji,i,ji->j", L, sg ** 2, L)
    bias = mean - xt
    return bias, var + bias ** 2
