"""Equivalent-error accuracy assessment (seed 000, METHODS 1.2)."""
from dataclasses import dataclass

import numpy as np

from . import _lib

# indices of the C info array (igea/stats.h)
_N_TEST, _CHI2, _DOF, _CHI2_CRIT, _Z_CRIT, _P_VALUE, _N_REJECT, _PASSED = range(8)
_RANK, _SCALE, _ITERATIONS, _N_SMALL, _FLAG, _N_FLIGHTS = range(8, 14)
_INFO_LEN = 16
_OPT_LEN = 16
_FLAGS = {0: "converged", 1: "not_estimable", 2: "no_convergence", 3: "off"}
_ROUTES = {"eig": 0, "svd": 1}

_RUN_ARGS = ["m", "N", "S", "lds", "dw", "track_sigma", "sigma_inc", "spec_sigma", "opts",
             "lambda", "P", "ldp", "equiv_err", "z", "reject", "info", "residual", "rms"]


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
                    % (i + 1, lam[i], xhat[i], lam[i] ** -0.5,
                       np.sqrt(1 + 1 / lam[i]) * z_crit, z[i], "REJECT" if reject[i] else "pass"))
    return rows


def _attach(obj, **private):
    """Context for .summary() kept off the dataclass fields (the fields are
    exactly those of the documented result)."""
    for k, v in private.items():
        object.__setattr__(obj, "_" + k, v)
    return obj


@dataclass(frozen=True)
class TestResult:
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

    @property
    def n_reject(self):
        return int(np.count_nonzero(self.reject))

    def summary(self):
        lines = []
        xhat = getattr(self, "_equiv_err", None)
        if xhat is not None:
            lines += _component_table(xhat, self._eigenvalues, self.z, self.reject, self.z_crit)
            lines.append("")
        lines += _verdict_lines(self.n_test, self.chi2, self.dof, self.chi2_crit, self.p_value,
                                self.n_reject, self.passed, getattr(self, "_alpha", 0.01))
        return "\n".join(lines)


@dataclass(frozen=True)
class EqerrResult:
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

    @property
    def n_reject(self):
        return int(np.count_nonzero(self.reject))

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
        lines += _verdict_lines(self.n_test, self.chi2, self.dof, self.chi2_crit, self.p_value,
                                self.n_reject, self.passed, getattr(self, "_alpha", 0.01))
        return "\n".join(lines)


def eqerr(S, dw, sigma, spec=None, *, alpha=0.01, lambda_test=10.0, lambda_small=0.1,
          correct_tracking=True, route="eig", n_min=5, tol=0.05, max_iter=10,
          bias_correct=False, clamp=False, z_crit=None, rank_tol=0.0):
    """Equivalent-error accuracy assessment of one flight (METHODS 1.2).

    S: (m, N) environment functions (rows epoch-major x, y, z), dw: (m,)
    velocity differences, sigma: tracking 1-sigma, a number or (m,) per row,
    spec: (N,) 1-sigma specs scaling S's columns, or None.
    Returns an EqerrResult."""
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
    if route not in _ROUTES:
        raise ValueError("route: expected 'eig' or 'svd', got %r" % (route,))
    opts = np.zeros(_OPT_LEN)
    _lib.lib.igea_eqerr_defaults(_lib.dptr(opts))
    opts[0:12] = [alpha, lambda_test, lambda_small, n_min, tol, max_iter,
                  1.0 if correct_tracking else 0.0, rank_tol, 1.0 if bias_correct else 0.0,
                  1.0 if clamp else 0.0, 0.0 if z_crit is None else z_crit, _ROUTES[route]]
    lam = np.empty(N)
    P = np.empty((N, N), order="F")
    xhat = np.empty(N)
    z = np.empty(N)
    rej = np.empty(N, dtype=np.intc)
    info = np.empty(_INFO_LEN)
    res = np.empty(m)
    rms = np.empty(3)
    st = _lib.lib.igea_eqerr_run(m, N, _lib.dptr(S), m, _lib.dptr(dw), _lib.dptr(sig), sigma_inc,
                                 _lib.dptr(spec), _lib.dptr(opts), _lib.dptr(lam), _lib.dptr(P), N,
                                 _lib.dptr(xhat), _lib.dptr(z), _lib.iptr(rej), _lib.dptr(info),
                                 _lib.dptr(res), _lib.dptr(rms))
    if st < 0 and -1000 < st:
        # Python validated shapes; map the bad option to a readable message
        names = {9: "options (alpha in (0,1), lambda_test, lambda_small, tol > 0, n_min >= 1, "
                    "1 <= max_iter <= 1000, 0 <= rank_tol < 1, z_crit >= 0)"}
        raise _lib.IgeaError(st, "invalid argument %d (%s)" % (-st, names.get(-st, _RUN_ARGS[-st - 1])),
                             "igea.eqerr")
    _lib.check(st, "igea.eqerr")
    nt = int(info[_N_TEST])
    return _attach(EqerrResult(
        eigenvalues=lam, eigenvectors=np.ascontiguousarray(P), rank=int(info[_RANK]),
        equiv_err=xhat, n_test=nt, z=z[:nt].copy(), reject=rej[:nt] == 1,
        chi2=float(info[_CHI2]), dof=int(info[_DOF]), chi2_crit=float(info[_CHI2_CRIT]),
        z_crit=float(info[_Z_CRIT]), p_value=float(info[_P_VALUE]), scale=float(info[_SCALE]),
        iterations=int(info[_ITERATIONS]), n_small=int(info[_N_SMALL]),
        flag=_FLAGS[int(info[_FLAG])], passed=bool(info[_PASSED] == 1.0), residual=res, rms=rms),
        alpha=float(alpha), lambda_small=float(lambda_small))


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
    info = np.empty(_INFO_LEN)
    st = _lib.lib.igea_stats_accuracy_test(n, _lib.dptr(x), _lib.dptr(lam), float(alpha),
                                           float(lambda_test), 0.0 if z_crit is None else float(z_crit),
                                           _lib.dptr(z), _lib.iptr(rej), _lib.dptr(info))
    _lib.check(st, "igea.accuracy_test",
               ["n", "equiv_err", "eigenvalues", "alpha", "lambda_test", "z_crit"])
    tested = rej >= 0
    return _attach(TestResult(n_test=int(info[_N_TEST]), z=z[tested], reject=rej[tested] == 1,
                              chi2=float(info[_CHI2]), dof=int(info[_DOF]),
                              chi2_crit=float(info[_CHI2_CRIT]), z_crit=float(info[_Z_CRIT]),
                              p_value=float(info[_P_VALUE]), passed=bool(info[_PASSED] == 1.0)),
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
    info = np.empty(_INFO_LEN)
    st = _lib.lib.igea_stats_pool(len(results), _lib.dptr(chi2), _lib.iptr(dof), _lib.iptr(nrej),
                                  _lib.iptr(uid), float(alpha), _lib.dptr(info))
    _lib.check(st, "igea.pool", ["nflights", "chi2", "dof", "n_reject", "unit_id", "alpha"])
    z = np.concatenate([np.asarray(get(r, "z"), dtype=float) for r in results])
    rej = np.concatenate([np.asarray(get(r, "reject"), dtype=bool) for r in results])
    return _attach(TestResult(n_test=int(info[_N_TEST]), z=z, reject=rej, chi2=float(info[_CHI2]),
                              dof=int(info[_DOF]), chi2_crit=float(info[_CHI2_CRIT]),
                              z_crit=float(info[_Z_CRIT]), p_value=float(info[_P_VALUE]),
                              passed=bool(info[_PASSED] == 1.0)),
                   alpha=float(alpha))
