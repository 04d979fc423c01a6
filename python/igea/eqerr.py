"""Equivalent-error accuracy assessment (seed 000, METHODS 1.2)."""
from dataclasses import dataclass, field
from typing import Optional

import numpy as np

from . import _capi
from . import _frames
from . import _lib
from ._result import result



def _test_fields(info):
    """The fields of a TestResult held in an info array (igea/stats.h)."""
    f = _lib.fields(info, "STATS_INFO_", n_test=int, chi2=float, dof=int, chi2_crit=float,
                    z_crit=float, p_value=float, passed=bool, verdict_z_crit=float,
                    verdict_chi2_crit=float, overall_size=float)
    f["verdict"] = _lib.choice_name(_capi.CHOICE_STATS_VERDICT, info[_capi.STATS_INFO_VERDICT])
    # 0 in the info array: no component test (chi2 rule), size not computed
    for k in ("verdict_z_crit", "overall_size"):
        if f[k] == 0:
            f[k] = None
    return f


# (rule, n, alpha) -> (a, b, size) of igea_stats_verdict_thresholds: pooling
# many groups of the same dof_tot computes a rule's thresholds once.
_THRESHOLDS = {}


def _verdict_opts(where, function, alpha, z_crit, verdict, n=None):
    """eqerr options carrying alpha, z_crit and the verdict rule (and, for n
    tested components, the rule's thresholds: IGEA_EQERR_OPT_VERDICT_N ..)."""
    code = _lib.choice(_capi.CHOICE_STATS_VERDICT, verdict, where, "verdict")
    pre = {}
    if n is not None and z_crit is None and 1 <= n <= _capi.STATS_UNION_N_MAX:
        key = (verdict, int(n), float(alpha))
        if key not in _THRESHOLDS:
            from .stats import verdict_thresholds
            _THRESHOLDS[key] = verdict_thresholds(verdict, int(n), float(alpha))
        a, b, size = _THRESHOLDS[key]
        pre = dict(verdict_n=int(n), verdict_a=a if np.isfinite(a) else 0.0, verdict_b=b,
                   verdict_size=size)
    return _lib.options("eqerr", where, (function, "opts"), alpha=alpha, z_crit=z_crit,
                        verdict=code, overall_size=1, **pre)


def _limits(lam, z_crit):
    """(threshold, precision) of each component (igea_eqerr_limits)."""
    lam = _lib.as_f64(lam, "eigenvalues", ndim=1)
    thr, prec = np.empty(len(lam)), np.empty(len(lam))
    if len(lam):
        _lib.call("igea.summary", "igea_eqerr_limits", len(lam), _lib.dptr(lam),
                  float(z_crit or 0.0), _lib.dptr(thr), _lib.dptr(prec))
    return thr, prec


def _verdict_lines(n_test, chi2, dof, chi2_crit, p_value, n_reject, passed, alpha,
                   verdict="seed", verdict_z_crit=None, overall_size=None):
    if verdict == "seed":
        lines = ["chi-square: T = %.4f with %d dof; chi2_%g(%d) = %.3f; p-value %.4g -> %s"
                 % (chi2, dof, alpha, dof, chi2_crit, p_value,
                    "pass" if chi2 < chi2_crit else "REJECT")]
    else:
        lines = ["chi-square: T = %.4f with %d dof; threshold %.3f (rule %s); p-value %.4g -> %s"
                 % (chi2, dof, chi2_crit, verdict, p_value,
                    "pass" if chi2 < chi2_crit else "REJECT")]
    zt = "none" if verdict_z_crit is None else "%.4f" % verdict_z_crit
    if overall_size is not None:
        lines.append("overall verdict rule %s: |z| threshold %s, chi-square threshold %.3f; "
                     "overall size %.6f at alpha = %g" % (verdict, zt, chi2_crit, overall_size,
                                                          alpha))
    else:
        lines.append("overall verdict rule %s: overall size not computed (more than %d tested "
                     "components)" % (verdict, _capi.STATS_UNION_N_MAX))
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
    thr, prec = _limits(np.asarray(lam, dtype=float)[:len(z)], z_crit)
    for i in range(len(z)):
        if z_crit is None:
            rows.append("%5d %13.6e %13.6f %11.4e %10s %9.4f  %s"
                        % (i, lam[i], xhat[i], prec[i], "-", z[i], "-"))
        else:
            rows.append("%5d %13.6e %13.6f %11.4e %10.4f %9.4f  %s"
                        % (i, lam[i], xhat[i], prec[i], thr[i], z[i],
                           "REJECT" if reject[i] else "pass"))
    return rows


_DIAG_KEYS = dict(n="N", lags="LB_LAGS", ljung_box="LB_Q", ljung_box_p="LB_P", runs="RUNS",
                  n_above="N_ABOVE", n_below="N_BELOW", runs_z="RUNS_Z", runs_p="RUNS_P")
_DIAG_INT = {"n", "lags", "runs", "n_above", "n_below"}


def _whiteness(res, lags):
    """Ljung-Box and runs tests per axis of the residuals (igea_eqerr_diag):
    a list of 3 dicts (None for an axis where they are not defined)."""
    out = np.empty(3 * _capi.STATS_DIAG_LEN)
    st = np.empty(3, dtype=np.intc)
    _lib.call("igea.eqerr", "igea_eqerr_diag", len(res), _lib.dptr(res), int(lags),
              _lib.dptr(out), _lib.iptr(st))
    w = []
    for a in range(3):
        if st[a]:
            w.append(None)
            continue
        d = out[a * _capi.STATS_DIAG_LEN:(a + 1) * _capi.STATS_DIAG_LEN]
        e = {"axis": a}
        for k, slot in _DIAG_KEYS.items():
            v = d[getattr(_capi, "STATS_DIAG_" + slot)]
            e[k] = int(v) if k in _DIAG_INT else float(v)
        w.append(e)
    return w


def _components(P, nt, spec, names, lam, z, reject):
    """The tested components as named patterns of the terms
    (igea_eqerr_components): shares p_ij^2, loadings spec_j p_ij, the
    candidate terms (share >= IGEA_EQERR_CANDIDATE_SHARE)."""
    N = P.shape[0]
    Pf = np.asfortranarray(P)
    share = np.empty((max(nt, 1), N))
    load = np.empty((max(nt, 1), N))
    order = np.empty((max(nt, 1), N), dtype=np.intc)
    _lib.call("igea.eqerr", "igea_eqerr_components", N, _lib.dptr(Pf), N, nt, _lib.dptr(spec),
              _lib.dptr(share), _lib.dptr(load), _lib.iptr(order))
    # the terms of each component in the library's order, built by numpy
    # (nt x N pairs: 5,476 at 74 terms) rather than element by element
    order = order[:nt].astype(np.intp)
    names_o = np.array(names, dtype=object)[order]
    share_o = np.take_along_axis(share[:nt], order, axis=1)
    cand = share_o >= _capi.EQERR_CANDIDATE_SHARE
    lam_l, z_l = np.asarray(lam[:nt], dtype=float).tolist(), np.asarray(z[:nt]).tolist()
    out = []
    for i in range(nt):
        out.append(dict(index=i, **{"lambda": lam_l[i]}, z=z_l[i], reject=bool(reject[i]),
                        terms=list(zip(names_o[i].tolist(), share_o[i].tolist())),
                        loading=load[i].copy(), candidates=names_o[i][cand[i]].tolist()))
    return out


def _component_lines(components, names):
    lines = ["named components (share p_ij^2 of each term >= 1%; loading spec_j p_ij in the "
             "term's units per unit of equiv_error):"]
    col = {}
    for j, n in enumerate(names):
        col.setdefault(n, j)
    for c in components:
        floor = _capi.EQERR_CANDIDATE_SHARE if c["reject"] else 0.01
        parts = ["%s %s %.2f (%+.4g)" % ("," if k else "", n, sh, c["loading"][col[n]])
                 for k, (n, sh) in enumerate(t for t in c["terms"] if t[1] >= floor)]
        lines.append("%5d %s%s" % (c["index"], "REJECT candidates:" if c["reject"] else "terms:",
                                   "".join(parts)))
    return lines


def _whiteness_lines(w, lags, whitened=False):
    lines = ["residual whiteness per axis%s (Ljung-Box over %d lags; runs test on the signs "
             "about the axis mean):"
             % (" of the whitened residuals, epochs with a rejected row left out" if whitened
                else "", lags)]
    for a, e in enumerate(w):
        if e is None:
            lines.append("  %s: not computed" % "xyz"[a])
        else:
            lines.append("  %s: Q = %.4g, p-value %.4g; %d runs (%d above, %d below), z = %.3f, "
                         "p-value %.4g" % ("xyz"[a], e["ljung_box"], e["ljung_box_p"], e["runs"],
                                          e["n_above"], e["n_below"], e["runs_z"], e["runs_p"]))
    return lines


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

    def _json_extra(self):
        return {"n_reject": self.n_reject}    # a key of the driver's --json

    def _verdict(self):
        return _verdict_lines(self.n_test, self.chi2, self.dof, self.verdict_chi2_crit,
                              self.p_value, self.n_reject, self.passed,
                              getattr(self, "_alpha", 0.01), self.verdict, self.verdict_z_crit,
                              self.overall_size)


@result
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
    verdict: str               # the overall verdict rule: seed, chi2, exact, sidak
    verdict_z_crit: float      # its threshold on |z| (None: no component test)
    verdict_chi2_crit: float   # its threshold on T
    overall_size: float        # its false-alarm probability (None: not computed)

    def summary(self):
        lines = []
        xhat = getattr(self, "_equiv_err", None)
        if xhat is not None:
            lines += _component_table(xhat, self._eigenvalues, self.z, self.reject,
                                      self.verdict_z_crit)
            lines.append("")
        return "\n".join(lines + self._verdict())


@result
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
    verdict: str               # the overall verdict rule: seed, chi2, exact, sidak
    verdict_z_crit: float      # its threshold on |z| (None: no component test)
    verdict_chi2_crit: float   # its threshold on T
    overall_size: float        # its false-alarm probability (None: not computed)
    whiteness: list            # per axis x, y, z: dict(axis n lags ljung_box ljung_box_p
                               # runs n_above n_below runs_z runs_p), None if not computed
    components: list           # per tested component: dict(index lambda z reject terms
                               # [(name, share), ...] descending, loading, candidates)
    residual_whitened: bool    # residual, rms and whiteness are of the whitened residuals
                               # (the noise models) or of dw - S D P_t Xhat_t
    # (n_test, 2) downrange, crossrange miss of each tested component (burnout options), m
    component_miss: Optional[np.ndarray] = field(default=None, kw_only=True)

    def summary(self):
        lines = ["rank %d of %d; lambda_1 = %.6e; %d component(s) tested"
                 % (self.rank, len(self.eigenvalues), self.eigenvalues[0], self.n_test), ""]
        lines += _component_table(self.equiv_err, self.eigenvalues, self.z, self.reject,
                                  self.verdict_z_crit)
        if self.verdict_z_crit is not None:
            lines.append("(threshold = sqrt(1 + 1/lambda) z_crit, z_crit = %.6f; precision = "
                         "lambda^-1/2)" % self.verdict_z_crit)
        else:
            lines.append("(no component test under the chi2 rule; precision = lambda^-1/2)")
        lines.append("")
        lines += _component_lines(self.components, getattr(self, "_names", []))
        lines += _miss_lines(self)
        lines.append("")
        if self.flag == "off":
            lines.append("tracking-accuracy correction: off (c = 1)")
        else:
            lines.append("tracking-accuracy correction: c = %.6g (sigma_w = %.4f), %d iteration(s), "
                         "%d small eigenvalue(s) <= %g, %s"
                         % (self.scale, getattr(self, "_sigma_w", np.sqrt(self.scale)),
                            self.iterations, self.n_small,
                            getattr(self, "_lambda_small", 0.1), self.flag))
        lines.append("residual RMS per axis (x, y, z)%s: %.6g %.6g %.6g"
                     % ((" of the whitened residuals" if self.residual_whitened else "",)
                        + tuple(self.rms)))
        lines += _whiteness_lines(self.whiteness, getattr(self, "_lags", 20),
                                  self.residual_whitened)
        lines += self._noise_lines()
        return "\n".join(lines + self._verdict())

    def _json_extra(self):
        # The keys of 'igea eqerr --json' that are not fields: the options
        # the flight was judged with and its sizes (None when not known);
        # with the burnout options the burnout state (and its time).
        d = {"n_reject": self.n_reject, "alpha": getattr(self, "_alpha", None),
             "lambda_test": getattr(self, "_lambda_test", None),
             "route": getattr(self, "_route", None), "rows": len(self.residual),
             "n_terms": len(self.eigenvalues)}
        if self.component_miss is not None:
            d["burnout"] = getattr(self, "_burnout", None)
            if getattr(self, "_burnout_time", None) is not None:
                d["burnout_time"] = self._burnout_time
        return d

    @property
    def _json_omit(self):
        # the driver writes component_miss only with the burnout options
        return () if self.component_miss is not None else ("component_miss",)

    def _noise_lines(self):
        return []


def _miss_lines(r):
    """The miss of each tested component (the driver's lines)."""
    if r.component_miss is None:
        return []
    b = getattr(r, "_burnout", None)
    lines = [] if b is None else [
        "burnout (ECEF): %.3f %.3f %.3f m, %.4f %.4f %.4f m/s" % tuple(b)]
    lines.append("miss at impact of each tested component at its equivalent error (Kepler):")
    for i, (d, c) in enumerate(r.component_miss):
        lines.append("  %3d  %10.4g m downrange  %10.4g m crossrange%s"
                     % (i, d, c, "  (rejected)" if r.reject[i] else ""))
    return lines


def _burnout_miss(res, names, spec, burnout, burnout_errors, burnout_time, traj, lat, lon,
                  height, azimuth, system, axes):
    """res with component_miss (and the burnout state as context): G E p_i
    x_i, G the Kepler miss Jacobian of the burnout state, E given
    (burnout_errors) or the burnout errors of S's named terms at burnout_time
    (igea_impact_burnout, times spec); as 'igea eqerr --burnout-time'."""
    from .impact import _burnout_call, _site, component_miss, impact
    where = "igea.eqerr"
    N = len(res.eigenvalues)
    if burnout_time is not None:
        if burnout is not None or burnout_errors is not None:
            raise ValueError(f"{where}: burnout_time and burnout, burnout_errors are "
                             "alternatives")
        if traj is None:
            raise ValueError(f"{where}: burnout_time needs traj (the trajectory)")
        if names is None:
            raise ValueError(f"{where}: burnout_time needs the term names of S's columns "
                             "(names=, or a data frame's columns)")
        from .envfun import term_codes
        codes = term_codes(list(names), system)
        site = _site(where, lat, lon, height, azimuth)
        state, E = _burnout_call(where, traj, codes, burnout_time, site, system, spec, axes)
    else:
        if burnout is None or burnout_errors is None:
            raise ValueError(f"{where}: burnout and burnout_errors: give both or neither")
        state = np.asarray(_lib.as_f64(burnout, "burnout", ndim=1, shape=(6,)))
        E = _lib.as_f64(burnout_errors, "burnout_errors", ndim=2, shape=(6, N))
    nt = res.n_test
    miss = np.zeros((0, 2))
    if nt > 0:
        G = impact(state).miss_jacobian
        miss = component_miss(G, E, res.eigenvectors[:, :nt], res.equiv_err[:nt])
    object.__setattr__(res, "component_miss", miss)
    return _attach(res, burnout=np.array(state, dtype=float),
                   burnout_time=None if burnout_time is None else float(burnout_time))


def _orientation(S, dw):
    """Refuse S transposed (N x m where dw says m rows) by naming it so."""
    shape, n = np.shape(S), np.size(dw)
    if len(shape) == 2 and np.ndim(dw) == 1 and n != shape[0] and n == shape[1]:
        raise ValueError("S has %d rows and %d columns; dw has %d values: pass S.T?"
                         % (shape[0], shape[1], n))


def eqerr(S, dw, sigma, spec=None, *, alpha=None, lambda_test=None, lambda_small=None,
          correction=None, route="eig", n_min=None, tol=None, max_iter=None,
          bias_correct=None, clamp=None, z_crit=None, rank_tol=None, verdict="seed",
          lags=20, names=None, cov=None, xcov=None, ar=None, ar_phi=None, groups=None,
          group_bias=None,
          robust=None, robust_alpha=None, threads=None, ar_method=None, burnout=None,
          burnout_errors=None, burnout_time=None, traj=None, lat=None, lon=None, height=None,
          azimuth=None, system=None, axes=None):
    """Equivalent-error accuracy assessment of one flight (METHODS 1.2).

    S: (m, N) environment functions (rows epoch-major x, y, z), dw: (m,)
    velocity differences, sigma: tracking 1-sigma, a number or (m,) per row,
    spec: (N,) 1-sigma specs scaling S's columns, or None. The options are
    the slots of igea/eqerr.h (as IGEA_EQERR_OPT_* in lower case); one left
    None keeps the library's default (igea_eqerr_defaults). verdict: the
    overall verdict rule, "seed" (the seed's), "chi2", "exact" (overall size
    alpha) or "sidak"; the result states the rule's thresholds and overall
    size. lags: the Ljung-Box lags of the residual whiteness per axis (the
    result's `whiteness`, with the runs test about each axis's mean).
    names: the N term names (e.g. igea.envfun's terms; default column_j),
    which the result's `components` use. threads: the normal equations on
    that many threads (IGEA_EQERR_OPT_THREADS; None or 1: one, the sums as
    before; 2 or more: the same result for any count, equal to one thread's
    to rounding; route "eig" without a noise model). Returns an EqerrResult.
    With a noise model (cov=(M, 3, 3) instead of sigma, ar=p, ar_phi=,
    groups=(M,) labels, group_bias=, robust=, robust_alpha=) the job is
    igea_noise_eqerr (see igea.noise), judged by the same verdict rule;
    xcov=(M, 3, 3) with cov: the cross blocks X_e = Cov(dW_e, dW_f), f > e,
    of igea.dw's result (its xcov; cov its blocks as 3 x 3 matrices): the
    whole K, not block-diagonal (igea_noise_eqerr_xcov; with robust and
    group_bias, not with ar, ar_phi or groups);
    ar_method ("reml", the default, or "ls"; with ar=p and no ar_phi) is
    how phi is estimated (IGEA_EQERR_OPT_AR_METHOD).
    S may be a data frame (anything with .columns and .to_numpy(), e.g.
    pandas): its columns are the term names unless names is given; dw and
    sigma may then be Series on S's index and spec a Series on its columns
    (put in S's order; other labels refused: igea/_frames.py).
    The miss of each tested component (opt-in; the result's component_miss,
    (n_test, 2) downrange and crossrange, m, Kepler impact): burnout (6,)
    the burnout state (ECEF) with burnout_errors (6, N) the burnout state
    error per unit of each column of S as judged (times its spec), or
    burnout_time (s) of the trajectory traj (as igea.envfun reads it) flown
    from the launch point lat, lon, height, azimuth (degrees, m; height
    None: 0), S's columns named by names as terms of system (None:
    "strapdown"; axes: platform gyro axes): igea.burnout's state and errors
    of those terms at spec (docs/impact.md). traj, lat, lon, height,
    azimuth, system and axes are refused without burnout_time."""
    S, names, v = _frames.inputs(S, names, rows=(("dw", dw), ("sigma", sigma)),
                                 cols=(("spec", spec),))
    dw, sigma, spec = v["dw"], v["sigma"], v["spec"]
    traj_kw = dict(traj=traj, lat=lat, lon=lon, height=height, azimuth=azimuth, system=system,
                   axes=axes)
    given = [k for k, v in traj_kw.items() if v is not None]
    if given and burnout_time is None:
        raise ValueError("igea.eqerr: %s: only with burnout_time (the burnout from a "
                         "trajectory)" % ", ".join(given))
    miss_kw = dict(traj_kw, burnout=burnout, burnout_errors=burnout_errors,
                   burnout_time=burnout_time,
                   height=0.0 if height is None else height,
                   system="strapdown" if system is None else system)
    if burnout is not None or burnout_errors is not None or burnout_time is not None:
        res = eqerr(S, dw, sigma, spec, alpha=alpha, lambda_test=lambda_test,
                    lambda_small=lambda_small, correction=correction, route=route, n_min=n_min,
                    tol=tol, max_iter=max_iter, bias_correct=bias_correct, clamp=clamp,
                    z_crit=z_crit, rank_tol=rank_tol, verdict=verdict, lags=lags, names=names,
                    cov=cov, xcov=xcov, ar=ar, ar_phi=ar_phi, groups=groups,
                    group_bias=group_bias, robust=robust, robust_alpha=robust_alpha,
                    threads=threads, ar_method=ar_method)
        sp = None if spec is None else _lib.as_f64(spec, "spec", ndim=1)
        return _burnout_miss(res, names, sp, **miss_kw)
    _orientation(S, dw)
    if any(v is not None for v in (cov, xcov, ar, ar_phi, groups, group_bias, robust,
                                   robust_alpha, ar_method)):
        if route not in (None, "eig"):
            raise ValueError("route: %r is not available with the noise models (cov, ar, "
                             "ar_phi, groups, group_bias, robust)" % (route,))
        if ar_method is not None and (not ar or ar_phi is not None):
            raise ValueError("ar_method: %r estimates phi: it needs ar=p (not ar_phi)"
                             % (ar_method,))
        return _noise(S, dw, sigma, spec, cov, ar, ar_phi, groups, group_bias, robust,
                      robust_alpha, lags, names, xcov=xcov, ar_method=None if ar_method is None else
                      _lib.choice(_capi.CHOICE_NOISE_AR_METHOD, ar_method, "igea.eqerr",
                                  "ar_method"), alpha=alpha, lambda_test=lambda_test,
                      lambda_small=lambda_small, n_min=n_min, tol=tol, max_iter=max_iter,
                      correction=correction, bias_correct=bias_correct, clamp=clamp,
                      z_crit=z_crit, rank_tol=rank_tol, overall_size=1,
                      verdict=_lib.choice(_capi.CHOICE_STATS_VERDICT, verdict, "igea.eqerr",
                                          "verdict"))
    # a C-order S (numpy's default, np.load of a C-order .npy) is read row
    # by row where it lies (igea_eqerr_run_layout), not transposed into a copy
    S = _lib.as_f64(S, "S", ndim=2, rows=True)
    m, N = S.shape
    if m < 1 or N < 1:
        raise ValueError("S: expected at least one row and one column, got shape %s" % (S.shape,))
    rowmajor = not S.flags.f_contiguous
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
    names = ["column_%d" % j for j in range(N)] if names is None else [str(n) for n in names]
    if len(names) != N:
        raise ValueError("names: %d names, but S has %d columns" % (len(names), N))
    route = _lib.choice(_capi.CHOICE_EQERR_ROUTE, route, "igea.eqerr", "route")
    opts = _lib.options("eqerr", "igea.eqerr", ("igea_eqerr_run", "opts"), alpha=alpha,
                        lambda_test=lambda_test, lambda_small=lambda_small, n_min=n_min, tol=tol,
                        max_iter=max_iter, correction=correction, rank_tol=rank_tol,
                        bias_correct=bias_correct, clamp=clamp, z_crit=z_crit,
                        route=route, overall_size=1, threads=threads,
                        verdict=_lib.choice(_capi.CHOICE_STATS_VERDICT, verdict, "igea.eqerr",
                                            "verdict"))
    lam = np.empty(N)
    P = np.empty((N, N), order="F")
    xhat = np.empty(N)
    z = np.empty(N)
    rej = np.empty(N, dtype=np.intc)
    info = np.empty(_capi.STATS_INFO_LEN)
    res = np.empty(m)
    rms = np.empty(3)
    outs = (_lib.dptr(lam), _lib.dptr(P), N, _lib.dptr(xhat), _lib.dptr(z), _lib.iptr(rej),
            _lib.dptr(info), _lib.dptr(res), _lib.dptr(rms))
    if rowmajor:
        _lib.call("igea.eqerr", "igea_eqerr_run_layout", _capi.ROWMAJOR, m, N, _lib.dptr(S), N,
                  _lib.dptr(dw), _lib.dptr(sig), sigma_inc, _lib.dptr(spec), _lib.dptr(opts),
                  *outs)
    else:
        _lib.call("igea.eqerr", "igea_eqerr_run", m, N, _lib.dptr(S), m, _lib.dptr(dw),
                  _lib.dptr(sig), sigma_inc, _lib.dptr(spec), _lib.dptr(opts), *outs)
    test = _test_fields(info)
    nt = test["n_test"]
    comps = _components(P, nt, spec, names, lam, z, rej == 1)
    return _attach(EqerrResult(
        eigenvalues=lam, eigenvectors=np.ascontiguousarray(P), equiv_err=xhat, z=z[:nt].copy(),
        reject=rej[:nt] == 1,
        flag=_lib.choice_name(_capi.CHOICE_STATS_SIGMAW_FLAG, info[_capi.STATS_INFO_FLAG]),
        residual=res, whiteness=_whiteness(res, lags), components=comps, residual_whitened=False,
        rms=rms, **test, **_lib.fields(info, "STATS_INFO_", rank=int, scale=float,
                                        iterations=int, n_small=int)),
        alpha=opts[_capi.EQERR_OPT_ALPHA], lambda_small=opts[_capi.EQERR_OPT_LAMBDA_SMALL],
        sigma_w=info[_capi.STATS_INFO_SIGMA_W], lags=int(lags), names=names,
        lambda_test=opts[_capi.EQERR_OPT_LAMBDA_TEST],
        route=_lib.choice_name(_capi.CHOICE_EQERR_ROUTE, route))


def _noise(S, dw, sigma, spec, cov, ar, ar_phi, groups, group_bias, robust, robust_alpha,
           lags, names, xcov=None, **slots):
    """igea.eqerr with the noise models (igea/noise.h; python/igea/noise.py)."""
    from .noise import noise_eqerr
    opts = _lib.options("eqerr", "igea.eqerr", ("igea_noise_eqerr", "opts"),
                        group_bias=None if group_bias is None else int(bool(group_bias)),
                        robust=None if robust is None else int(bool(robust)),
                        robust_alpha=robust_alpha, **slots)
    return noise_eqerr(S, dw, sigma, spec, cov, ar, ar_phi, groups, opts, lags=lags,
                       names=names, xcov=xcov)


def accuracy_test(equiv_err, eigenvalues, *, alpha=0.01, lambda_test=10.0, z_crit=None,
                  verdict="seed"):
    """Per-component normal tests and the chi-square test of published
    (equivalent error, eigenvalue) pairs, e.g. the seed's Table 1, judged
    by the overall verdict rule `verdict` (as igea.eqerr's).

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
    zt = np.ascontiguousarray(z[tested])
    opts = _verdict_opts("igea.accuracy_test", "igea_eqerr_pool", alpha, z_crit, verdict)
    T = np.array([info[_capi.STATS_INFO_CHI2]])
    dof = np.array([int(info[_capi.STATS_INFO_N_TEST])], dtype=np.intc)
    rt = np.empty(len(zt), dtype=np.intc)
    _lib.call("igea.accuracy_test", "igea_eqerr_pool", 1, _lib.dptr(T), _lib.iptr(dof),
              _lib.dptr(zt), None, _lib.dptr(opts), _lib.iptr(rt), _lib.dptr(info))
    return _attach(TestResult(z=zt, reject=rt == 1, **_test_fields(info)),
                   alpha=float(alpha), equiv_err=x[tested], eigenvalues=lam[tested])


def pool(results, *, alpha=0.01, unit_ids=None, verdict="seed"):
    """Pool independent flights (METHODS 1.2 step 6): T_tot = sum of T,
    dof_tot = sum of dof; passed iff no component of any flight is rejected
    and T_tot < chi2_alpha(dof_tot). results: EqerrResult/TestResult objects
    (or dicts from 'igea eqerr --json'). unit_ids: the inertial unit of each
    flight; a unit flown twice raises IgeaError (flights not independent).
    verdict: "seed" (the flights' own rejections, as above), or "chi2",
    "exact", "sidak": the rule for dof_tot components applied to all the
    flights' z (igea_eqerr_pool), as 'igea test --results --verdict'."""
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
    opts = _verdict_opts("igea.pool", "igea_eqerr_pool", alpha, None, verdict, int(dof.sum()))
    z = np.concatenate([np.asarray(get(r, "z"), dtype=float) for r in results])
    if verdict == "seed":
        _lib.call("igea.pool", "igea_stats_pool", len(results), _lib.dptr(chi2), _lib.iptr(dof),
                  _lib.iptr(nrej), _lib.iptr(uid), float(alpha), _lib.dptr(info))
        rej = np.concatenate([np.asarray(get(r, "reject"), dtype=bool) for r in results])
        info[_capi.STATS_INFO_VERDICT] = _capi.STATS_VERDICT_SEED
        info[_capi.STATS_INFO_VERDICT_Z_CRIT] = info[_capi.STATS_INFO_Z_CRIT]
        info[_capi.STATS_INFO_VERDICT_CHI2_CRIT] = info[_capi.STATS_INFO_CHI2_CRIT]
        if int(info[_capi.STATS_INFO_DOF]) <= _capi.STATS_UNION_N_MAX:
            info[_capi.STATS_INFO_OVERALL_SIZE] = opts[_capi.EQERR_OPT_VERDICT_SIZE]
    else:
        if z.shape != (int(dof.sum()),):
            raise ValueError("results: the flights' z hold %d values, their dof sum to %d"
                             % (z.size, int(dof.sum())))
        r = np.empty(z.size, dtype=np.intc)
        _lib.call("igea.pool", "igea_eqerr_pool", len(results), _lib.dptr(chi2), _lib.iptr(dof),
                  _lib.dptr(z), _lib.iptr(uid), _lib.dptr(opts), _lib.iptr(r), _lib.dptr(info))
        rej = r == 1
    return _attach(TestResult(z=z, reject=rej, **_test_fields(info)), alpha=float(alpha))
