"""The equivalent-error job with the noise models (igea/noise.h): per-epoch
3x3 tracking covariance, AR(p) per axis, groups with one sigma_w each,
per-group bias columns and the robust route; the whole K of igea.dw (its
diagonal blocks and the cross blocks X_e between epochs). Reached through
igea.eqerr (cov=, xcov=, ar=, ar_phi=, ar_method=, groups=, group_bias=,
robust=, robust_alpha=)."""
from dataclasses import dataclass

import numpy as np

from . import _capi
from . import _lib
from ._result import result
from .eqerr import EqerrResult, _attach, _components, _test_fields, _whiteness


@result
@dataclass(frozen=True)
class NoiseEqerrResult(EqerrResult):
    """Result of igea.eqerr with a noise model: every field of EqerrResult
    (residual, rms and whiteness of the whitened residuals,
    residual_whitened True), then the noise models' own; fields match
    'igea eqerr --cov/--ar/--groups/--robust --json'."""
    ar_order: int
    ar_method: object        # "reml" or "ls" (how phi was estimated); None: given or p = 0
    ar_phi: np.ndarray       # (3, p): phi of lag k + 1 of axis a
    ar_se: np.ndarray        # (3, p): standard errors (0 when phi was given)
    groups: list             # [{"scale", "scale_se", "scale_se_reml", "redundancy", "rows",
                             #   "bias"}]
    robust_crit: float
    rejected_rows: list      # [{"row": i, "w": w}] of the robust route
    noise_iterations: int
    noise_converged: bool

    def _noise_lines(self):
        lines = []
        if getattr(self, "_xcov", False):
            lines.append("the whole K: cross blocks between epochs from xcov (rows differenced "
                         "between epochs, block-tridiagonal Cholesky; the whitened rows are "
                         "each epoch's innovations)")
        for a in range(3 if self.ar_order else 0):
            lines.append("AR(%d) axis %s%s: phi" % (self.ar_order, "xyz"[a],
                                                   " (REML)" if self.ar_method == "reml" else "")
                         + "".join(
                " %.5f (se %.5f)" % (self.ar_phi[a, k], self.ar_se[a, k])
                for k in range(self.ar_order)))
        for g, o in enumerate(self.groups):
            lines.append("group %d: c = %.6g (se %.3g, REML se %.3g, sigma_w = %.4f), redundancy "
                         "%.1f, %g rows, bias %.4g %.4g %.4g"
                         % ((g, o["scale"], o["scale_se"], o["scale_se_reml"],
                             np.sqrt(o["scale"]), o["redundancy"], o["rows"]) + tuple(o["bias"])))
        if getattr(self, "_robust", False):
            lines.append("robust: %d row(s) rejected by data snooping, |w| > %.4f:"
                         % (len(self.rejected_rows), self.robust_crit)
                         + "".join(" row %d (w = %.2f)" % (r["row"], r["w"])
                                   for r in self.rejected_rows))
        lines.append("noise iterations %d, %s" % (self.noise_iterations, "settled"
                                                  if self.noise_converged else "NOT settled"))
        return lines


def _kept_epochs(res, row_w):
    """The whitened residuals of the epochs without a rejected row (the
    series closed up), as the driver's whiteness and RMS use them."""
    keep = ~(row_w.reshape(-1, 3) != 0).any(axis=1)
    return np.ascontiguousarray(res.reshape(-1, 3)[keep].ravel())


def _rms(res):
    """Per-axis RMS (igea_eqerr_axis_rms) of epoch-major residuals."""
    r3 = res.reshape(-1, 3)
    ss = np.concatenate([(r3 ** 2).sum(axis=0), np.full(3, float(r3.shape[0]))])
    rms = np.empty(3)
    _lib.call("igea.eqerr", "igea_eqerr_axis_rms", _lib.dptr(ss), _lib.dptr(rms))
    return rms


def _cov6(cov, M):
    c = _lib.as_f64(cov, "cov", ndim=3, shape=(M, 3, 3))
    if not np.allclose(c, np.transpose(c, (0, 2, 1)), rtol=1e-12, atol=0):
        raise ValueError("cov: each epoch's 3x3 block must be symmetric")
    return np.ascontiguousarray(np.stack([c[:, 0, 0], c[:, 1, 0], c[:, 1, 1], c[:, 2, 0],
                                          c[:, 2, 1], c[:, 2, 2]], axis=1).ravel())


def _phi(ar_phi):
    a = np.asarray(ar_phi, dtype=float)
    if a.ndim == 1 and 1 <= a.size <= 3:
        a = np.tile(a, (3, 1))
    if a.ndim != 2 or a.shape[0] != 3 or not 1 <= a.shape[1] <= 3:
        raise ValueError("ar_phi: expected p (1..3) coefficients or shape (3, p), got %s"
                         % (np.shape(ar_phi),))
    return np.ascontiguousarray(a.ravel()), a.shape[1]


def _groups(groups, M):
    g = np.asarray(groups)
    if g.shape != (M,) or not np.issubdtype(g.dtype, np.integer) or (g < 0).any():
        raise ValueError("groups: expected %d integer labels 0..G-1 (one per epoch)" % M)
    return np.ascontiguousarray(g, dtype=np.intc), int(g.max()) + 1


def _xcov9(xcov, M):
    x = _lib.as_f64(xcov, "xcov", ndim=3, shape=(M, 3, 3))
    return np.ascontiguousarray(x.reshape(M, 9).ravel())


def noise_eqerr(S, dw, sigma, spec, cov, ar, ar_phi, groups, opts, where="igea.eqerr",
                lags=20, names=None, xcov=None):
    """igea_noise_eqerr_resid on whole arrays (igea_noise_eqerr_xcov with
    xcov); opts from _lib.options (slots set)."""
    S = _lib.as_f64(S, "S", ndim=2)
    m, N = S.shape
    if m < 3 or m % 3:
        raise ValueError("S: rows are epoch-major x, y, z: a multiple of 3, got %d" % m)
    M = m // 3
    dw = _lib.as_f64(dw, "dw", ndim=1, shape=(m,))
    if (cov is None) == (sigma is None):
        raise ValueError("sigma, cov: give exactly one of them")
    if xcov is not None:
        if cov is None:
            raise ValueError("xcov: the cross blocks need cov=, the diagonal blocks K_ee of "
                             "the same K (igea.dw's cov as 3 x 3 matrices)")
        if ar or ar_phi is not None:
            raise ValueError("xcov: K with its cross blocks is the noise's whole covariance; "
                             "AR noise on top of it (ar, ar_phi) is not supported")
        if groups is not None:
            raise ValueError("xcov: the cross blocks couple every epoch with every later one, "
                             "across stations; one scale per group (groups) is not supported "
                             "with them")
    names = ["column_%d" % j for j in range(N)] if names is None else [str(n) for n in names]
    if len(names) != N:
        raise ValueError("names: %d names, but S has %d columns" % (len(names), N))
    sig = None
    if sigma is not None:
        sig = np.broadcast_to(_lib.as_f64(sigma, "sigma"), (m,)).copy()
    c6 = None if cov is None else _cov6(cov, M)
    sp = None if spec is None else _lib.as_f64(spec, "spec", ndim=1, shape=(N,))
    phi, p = (None, int(ar or 0)) if ar_phi is None else _phi(ar_phi)
    if ar_phi is not None and ar not in (None, p):
        raise ValueError("ar=%r but ar_phi holds %d lags" % (ar, p))
    opts[_capi.EQERR_OPT_AR] = p
    opts[_capi.EQERR_OPT_AR_ESTIMATE] = 1 if p > 0 and ar_phi is None else 0
    grp, G = (None, 1) if groups is None else _groups(groups, M)
    lam, P, xh, z = np.empty(N), np.empty((N, N), order="F"), np.empty(N), np.empty(N)
    rej, info = np.empty(N, dtype=np.intc), np.empty(_capi.STATS_INFO_LEN)
    ar_out = np.zeros(_capi.NOISE_AR_OUT_LEN)
    go = np.zeros((G, _capi.NOISE_GROUP_COLS))
    row_w, res = np.zeros(m), np.empty(m)
    if xcov is not None:
        _lib.call(where, "igea_noise_eqerr_xcov", m, N, _lib.dptr(S), m, _lib.dptr(dw),
                  _lib.dptr(c6), _lib.dptr(_xcov9(xcov, M)), _lib.dptr(sp), _lib.dptr(opts),
                  _lib.dptr(lam), _lib.dptr(P), N, _lib.dptr(xh), _lib.dptr(z), _lib.iptr(rej),
                  _lib.dptr(info), _lib.dptr(go), _lib.dptr(row_w), _lib.dptr(res))
    else:
        _lib.call(where, "igea_noise_eqerr_resid", m, N, _lib.dptr(S), m, _lib.dptr(dw),
                  _lib.dptr(sig), 1, _lib.dptr(c6), _lib.iptr(grp), G, _lib.dptr(sp),
                  _lib.dptr(phi), _lib.dptr(opts), _lib.dptr(lam), _lib.dptr(P), N,
                  _lib.dptr(xh), _lib.dptr(z), _lib.iptr(rej), _lib.dptr(info),
                  _lib.dptr(ar_out), _lib.dptr(go), _lib.dptr(row_w), _lib.dptr(res))
    test = _test_fields(info)
    nt = test["n_test"]
    gs = [{"scale": float(r[_capi.NOISE_GROUP_SCALE]), "scale_se": float(r[_capi.NOISE_GROUP_SE]),
           "scale_se_reml": float(r[_capi.NOISE_GROUP_SE_REML]),
           "redundancy": float(r[_capi.NOISE_GROUP_REDUND]),
           "rows": int(r[_capi.NOISE_GROUP_ROWS]),
           "bias": r[_capi.NOISE_GROUP_BIAS:_capi.NOISE_GROUP_BIAS + 3].copy()} for r in go]
    kept = _kept_epochs(res, row_w)
    whiteness = _whiteness(kept, lags) if kept.size else [None, None, None]
    rms = _rms(kept) if kept.size else np.zeros(3)
    return _attach(NoiseEqerrResult(
        eigenvalues=lam, eigenvectors=np.ascontiguousarray(P), equiv_err=xh, z=z[:nt].copy(),
        reject=rej[:nt] == 1,
        flag=_lib.choice_name(_capi.CHOICE_STATS_SIGMAW_FLAG, info[_capi.STATS_INFO_FLAG]),
        residual=res, rms=rms, whiteness=whiteness,
        components=_components(P, nt, sp, names, lam, z, rej == 1), residual_whitened=True,
        **test, **_lib.fields(info, "STATS_INFO_", rank=int, scale=float, iterations=int,
                              n_small=int),
        ar_order=p, ar_method=_lib.choice_name(_capi.CHOICE_NOISE_AR_METHOD,
                                               opts[_capi.EQERR_OPT_AR_METHOD])
        if p > 0 and ar_phi is None else None, ar_phi=ar_out[:9].reshape(3, 3)[:, :p].copy(),
        ar_se=ar_out[9:].reshape(3, 3)[:, :p].copy(), groups=gs,
        robust_crit=float(info[_capi.STATS_INFO_ROBUST_CRIT]),
        rejected_rows=[{"row": int(i), "w": float(row_w[i])} for i in np.flatnonzero(row_w)],
        noise_iterations=int(info[_capi.STATS_INFO_NOISE_ITERATIONS]),
        noise_converged=bool(info[_capi.STATS_INFO_NOISE_CONVERGED] == 1)),
        alpha=opts[_capi.EQERR_OPT_ALPHA], lambda_small=opts[_capi.EQERR_OPT_LAMBDA_SMALL],
        sigma_w=info[_capi.STATS_INFO_SIGMA_W], lags=int(lags), names=names,
        robust=opts[_capi.EQERR_OPT_ROBUST] == 1, xcov=xcov is not None)
