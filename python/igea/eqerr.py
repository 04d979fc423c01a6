"""Equivalent-error accuracy assessment (seed 000, METHODS 1.2)."""
from dataclasses import dataclass

import numpy as np

from . import _capi
from . import _lib



def _test_fields(info):
    """The fields of a TestResult held in an info array (igea/stats.h)."""
    return _lib.fields(info, "STATS_INFO_", n_test=int, chi2=float, dof=int, chi2_crit=float,
                       z_crit=float, p_value=float, passed=bool)


def _verdict_lines(n_test, chi2, dof, chi2_crit, p_value, n_reject, passed, alpha):
    lines = ["chi-square: T = %.4f with %d dof; chi2_%g(%d) = %.3f; p-value %.4g -> %s"
             % (chi2, dof, alpha, dof, chi2_crit, p_value, "pass" if chi2 < chi2_crit else "REJECT")]
    if passed:
        lines.append("verdict: ACCEPTED - no component rejected and T < chi2 critical value "
                     "(alpha = %g)" % alpha)
    else:
        lines.append("verdict: REJECTED - %d component(s) rejected%s (alpha = %g)"
                     % (n_reject, "" if chi2 < chi2_crit else ", chi-square test failed", alpha))
    return lines


def _component_table(xhat, lam, z, reject, z_crit):
    rows = ["%5s %13s %13s %11s %10s %9s  %s" % ("comp", "eigenvalue", "equiv_error",
                                                 "precision", "threshold", "z", "verdict")]
    for i in range(len(z)):
        rows.append("%5d %13.6e %13.6f %11.4e %10.4f %9.4f  %s"
                    % (i, lam[i], xhat[i], lam[i] ** -0.5,
                       np.sqrt(1 + 1 / lam[i]) * z_crit, z[i], "REJECT" if reject[i] else "pass"))
    return rows


def _attach(obj, **private):
    """Context for .summary() kept off the dataclass fields (the fields are
    exactly those of the documented result)."""
    for k, v in private.items():
        object.__setattr__(obj, "_" + k, v)
    return obj


class _Verdict:
    """The verdict part of a result (n_test, z, reject, chi2, ... passed)."""

    @property
    def n_reject(self):
        return int(np.count_nonzero(self.reject))

    def _verdict(self):
        return _verdict_lines(self.n_test, self.chi2, self.dof, self.chi2_crit, self.p_value,
                              self.n_reject, self.passed, getattr(self, "_alpha", 0.01))


@dataclass(frozen=True)
class TestResult(_Verdict):
    """Per-component and chi-square verdicts (igea.accuracy_test, igea.pool)."""
    n_test: int
    z: np.ndarray
    reject: np.ndarray
    chi2: float
    dof: int
    chi2_crit: float
    z_crit: float
    p_value: float
    passed: bool

    def summary(self):
        lines = []
        xhat = getattr(self, "_equiv_err", None)
        if xhat is not None:
            lines += _component_table(xhat, self._eigenvalues, self.z, self.reject, self.z_crit)
            lines.append("")
        return "\n".join(lines + self._verdict())


@dataclass(frozen=True)
class EqerrResult(_Verdict):
    """Result of igea.eqerr; field names match 'igea eqerr --json'."""
    eigenvalues: np.ndarray
    eigenvectors: np.ndarray
    rank: int
    equiv_err: np.ndarray
    n_test: int
    z: np.ndarray
    reject: np.ndarray
    chi2: float
    dof: int
    chi2_crit: float
    z_crit: float
    p_value: float
    scale: float
    iterations: int
    n_small: int
    flag: str
    passed: bool
    residual: np.ndarray
    rms: np.ndarray

    def summary(self):
        lines = ["rank %d of %d; lambda_1 = %.6e; %d component(s) tested"
                 % (self.rank, len(self.eigenvalues), self.eigenvalues[0], self.n_test), ""]
        lines += _component_table(self.equiv_err, self.eigenvalues, self.z, self.reject,
                                  self.z_crit)
        lines.append("(threshold = sqrt(1 + 1/lambda) z_crit, z_crit = %.6f; precision = "
                     "lambda^-1/2)" % self.z_crit)
        lines.append("")
        if self.flag == "off":
            lines.append("tracking-accuracy correction: off (c = 1)")
        else:
            lines.append("tracking-accuracy correction: c = %.6g (sigma_w = %.4f), %d iteration(s), "
                         "%d small eigenvalue(s) <= %g, %s"
                         % (self.scale, np.sqrt(self.scale), self.iterations, self.n_small,
                            getattr(self, "_lambda_small", 0.1), self.flag))
        lines.append("residual RMS per axis (x, y, z): %.6g %.6g %.6g" % tuple(self.rms))
        return "\n".join(lines + self._verdict())


def eqerr(S, dw, sigma, spec=None, *, alpha=None, lambda_test=None, lambda_small=None,
          correction=None, route="eig", n_min=None, tol=None, max_iter=None,
          bias_correct=None, clamp=None, z_crit=None, rank_tol=None, cov=None, ar=None,
          ar_phi=None, groups=None, group_bias=None, robust=None, robust_alpha=None):
    """Equivalent-error accuracy assessment of one flight (METHODS 1.2).

    S: (m, N) environment functions (rows epoch-major x, y, z), dw: (m,)
    velocity differences, sigma: tracking 1-sigma, a number or (m,) per row,
    spec: (N,) 1-sigma specs scaling S's columns, or None. The options are
    the slots of igea/eqerr.h (as IGEA_EQERR_OPT_* in lower case); one left
    None keeps the library's default (igea_eqerr_defaults).
    Returns an EqerrResult. With a noise model (cov=(M, 3, 3) instead of
    sigma, ar=p, ar_phi=, groups=(M,) labels, group_bias=, robust=,
    robust_alpha=) the job is igea_noise_eqerr: see igea.noise."""
    if any(v is not None for v in (cov, ar, ar_phi, groups, group_bias, robust, robust_alpha)):
        return _noise(S, dw, sigma, spec, cov, ar, ar_phi, groups, group_bias, robust,
                      robust_alpha, alpha=alpha, lambda_test=lambda_test,
                      lambda_small=lambda_small, n_min=n_min, tol=tol, max_iter=max_iter,
                      correction=correction, bias_correct=bias_correct, clamp=clamp,
                      z_crit=z_crit, rank_tol=rank_tol)
    S = _lib.as_f64(S, "S", ndim=2)
    m, N = S.shape
    if m < 1 or N < 1:
        raise ValueError("S: expected at least one row and one column, got shape %s" % (S.shape,))
    dw = _lib.as_f64(dw, "dw", ndim=1, shape=(m,))
    scalar_sigma = np.ndim(sigma) == 0
    sig = _lib.as_f64(sigma, "sigma")
    if scalar_sigma:
        sig = sig.reshape(1)
        sigma_inc = 0
    elif sig.shape == (m,):
        sigma_inc = 1
    else:
        raise ValueError("sigma: expected a number or shape (%d,), got %s" % (m, sig.shape))
    if spec is not None:
        spec = _lib.as_f64(spec, "spec", ndim=1, shape=(N,))
    route = _lib.choice(_capi.CHOICE_EQERR_ROUTE, route, "igea.eqerr", "route")
    opts = _lib.options("eqerr", "igea.eqerr", ("igea_eqerr_run", "opts"), alpha=alpha,
                        lambda_test=lambda_test, lambda_small=lambda_small, n_min=n_min, tol=tol,
                        max_iter=max_iter, correction=correction, rank_tol=rank_tol,
                        bias_correct=bias_correct, clamp=clamp, z_crit=z_crit,
                        route=route)
    lam = np.empty(N)
    P = np.empty((N, N), order="F")
    xhat = np.empty(N)
    z = np.empty(N)
    rej = np.empty(N, dtype=np.intc)
    info = np.empty(_capi.STATS_INFO_LEN)
    res = np.empty(m)
    rms = np.empty(3)
    _lib.call("igea.eqerr", "igea_eqerr_run", m, N, _lib.dptr(S), m, _lib.dptr(dw),
              _lib.dptr(sig), sigma_inc, _lib.dptr(spec), _lib.dptr(opts), _lib.dptr(lam),
              _lib.dptr(P), N, _lib.dptr(xhat), _lib.dptr(z), _lib.iptr(rej), _lib.dptr(info),
              _lib.dptr(res), _lib.dptr(rms))
    test = _test_fields(info)
    nt = test["n_test"]
    return _attach(EqerrResult(
        eigenvalues=lam, eigenvectors=np.ascontiguousarray(P), equiv_err=xhat, z=z[:nt].copy(),
        reject=rej[:nt] == 1,
        flag=_lib.choice_name(_capi.CHOICE_STATS_SIGMAW_FLAG, info[_capi.STATS_INFO_FLAG]),
        residual=res,
        rms=rms, **test, **_lib.fields(info, "STATS_INFO_", rank=int, scale=float,
                                        iterations=int, n_small=int)),
        alpha=opts[_capi.EQERR_OPT_ALPHA], lambda_small=opts[_capi.EQERR_OPT_LAMBDA_SMALL])


def _noise(S, dw, sigma, spec, cov, ar, ar_phi, groups, group_bias, robust, robust_alpha,
           **slots):
    """igea.eqerr with the noise models (igea/noise.h; python/igea/noise.py)."""
    from .noise import noise_eqerr
    opts = _lib.options("eqerr", "igea.eqerr", ("igea_noise_eqerr", "opts"),
                        group_bias=None if group_bias is None else int(bool(group_bias)),
                        robust=None if robust is None else int(bool(robust)),
                        robust_alpha=robust_alpha, **slots)
    return noise_eqerr(S, dw, sigma, spec, cov, ar, ar_phi, groups, opts)


def accuracy_test(equiv_err, eigenvalues, *, alpha=0.01, lambda_test=10.0, z_crit=None):
    """Per-component normal tests and the chi-square test of published
    (equivalent error, eigenvalue) pairs, e.g. the seed's Table 1.

    Only components with eigenvalue >= lambda_test are tested; z and reject
    list those, in input order."""
    x = _lib.as_f64(equiv_err, "equiv_err", ndim=1)
    n = x.shape[0]
    if n < 1:
        raise ValueError("equiv_err: empty")
    lam = _lib.as_f64(eigenvalues, "eigenvalues", ndim=1, shape=(n,))
    z = np.empty(n)
    rej = np.empty(n, dtype=np.intc)
    info = np.empty(_capi.STATS_INFO_LEN)
    _lib.call("igea.accuracy_test", "igea_stats_accuracy_test", n, _lib.dptr(x), _lib.dptr(lam),
              float(alpha), float(lambda_test), 0.0 if z_crit is None else float(z_crit),
              _lib.dptr(z), _lib.iptr(rej), _lib.dptr(info))
    tested = rej >= 0
    return _attach(TestResult(z=z[tested], reject=rej[tested] == 1, **_test_fields(info)),
                   alpha=float(alpha), equiv_err=x[tested], eigenvalues=lam[tested])


def pool(results, *, alpha=0.01, unit_ids=None):
    """Pool independent flights (METHODS 1.2 step 6): T_tot = sum of T,
    dof_tot = sum of dof; passed iff no component of any flight is rejected
    and T_tot < chi2_alpha(dof_tot). results: EqerrResult/TestResult objects
    (or dicts from 'igea eqerr --json'). unit_ids: the inertial unit of each
    flight; a unit flown twice raises IgeaError (flights not independent)."""
    results = list(results)
    if not results:
        raise ValueError("results: no flights to pool")

    def get(r, k):
        return r[k] if isinstance(r, dict) else getattr(r, k)

    chi2 = np.array([float(get(r, "chi2")) for r in results])
    dof = np.array([int(get(r, "dof")) for r in results], dtype=np.intc)
    nrej = np.array([int(np.count_nonzero(get(r, "reject"))) for r in results], dtype=np.intc)
    uid = None
    if unit_ids is not None:
        uid = np.asarray(unit_ids, dtype=np.intc)
        if uid.shape != (len(results),):
            raise ValueError("unit_ids: expected %d ids, got shape %s" % (len(results), uid.shape))
    info = np.empty(_capi.STATS_INFO_LEN)
    _lib.call("igea.pool", "igea_stats_pool", len(results), _lib.dptr(chi2), _lib.iptr(dof),
              _lib.iptr(nrej), _lib.iptr(uid), float(alpha), _lib.dptr(info))
    z = np.concatenate([np.asarray(get(r, "z"), dtype=float) for r in results])
    rej = np.concatenate([np.asarray(get(r, "reject"), dtype=bool) for r in results])
    return _attach(TestResult(z=z, reject=rej, **_test_fields(info)), alpha=float(alpha))
