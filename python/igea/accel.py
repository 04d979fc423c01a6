"""Dividing-head accelerometer calibration (seed 003, METHODS 4.1-4.3).

Single model (5 coefficients, observation y_A - sin(theta)) and orthogonal
dual g^2 model (9 coefficients, observation (y_A^2 + y_B^2 - 1) / 2, rank 7
for 7 or more equispaced positions), fitted by least squares (minimum norm)
or empirical-Bayes ridge. Every coefficient carries a flag: "data" when the
calibration determines it, "prior" when it loads on the design's null space
and its value is set by the prior (EBR) or the minimum-norm convention (LS).
"""
import ctypes
from dataclasses import dataclass

import numpy as np

from . import _capi, _lib
from ._compat import _UNSET, renamed
from ._result import result

_MODELS = _lib.choice_codes(_capi.CHOICE_ACCEL_MODEL)
_NP = {m: getattr(_capi, "ACCEL_NP_" + m.upper()) for m in _MODELS}
_NC = {m: getattr(_capi, "ACCEL_NC_" + m.upper()) for m in _MODELS}
LOADING_TOL = _capi.ACCEL_LOADING_TOL
ARCSEC = np.pi / 180.0 / 3600.0


def coefficient_names(model="dual", axis="pa"):
    """Names of the coefficients in the design's column order, in the
    notation of IEEE Std 1293: the cross-coupling term is labelled by the
    in-plane axis x that the rotation excites (turning about PA gives Kio,
    about OA gives Kip). The library's names (igea_accel_coef_name)."""
    m, ax = _MODELS[_model(model)], _axis(axis)
    return [_lib.lib.igea_accel_coef_name(m, ax, j).decode() for j in range(_NP[model])]


def coefficient_units(model="dual"):
    """Units of the coefficients ("g", "" for a scale factor, "rad", "g/g^2")."""
    m = _MODELS[_model(model)]
    return [_lib.lib.igea_accel_coef_unit(m, j).decode() for j in range(_NP[model])]


def combination_names(model="dual", axis="pa"):
    """Names of the estimable combinations (columns of accel_combinations)."""
    m, ax = _MODELS[_model(model)], _axis(axis)
    return [_lib.lib.igea_accel_comb_name(m, ax, k).decode() for k in range(_NC[model])]


def _model(model):
    _lib.choice(_capi.CHOICE_ACCEL_MODEL, model, "igea.accel", "model")
    return model


def _axis(axis):
    return _lib.choice(_capi.CHOICE_ACCEL_AXIS, axis, "igea.accel", "axis")


def _theta(theta_deg):
    t = _lib.as_f64(theta_deg, "theta_deg", ndim=1)
    if t.shape[0] < 1:
        raise ValueError("theta_deg: expected at least one angle")
    return t


def _vec(x, name, n):
    return _lib.as_f64(x, name, ndim=1, shape=(n,))


def accel_schedule(n, start_deg=0.0):
    """n equally spaced head angles start_deg + 360 k / n (degrees)."""
    out = np.zeros(max(int(n), 1))
    _lib.call("igea.accel_schedule", "igea_accel_schedule", int(n), float(start_deg),
              _lib.dptr(out))
    return out


def accel_merge(angle_deg, y_a, y_b=None, *, tol_deg=1e-6):
    """Average the readings of one calibration per position (clockwise and
    counter-clockwise runs, and 360 deg with 0 deg).

    Returns (theta_deg, y_a, y_b or None, count), positions ascending."""
    ang = _lib.as_f64(angle_deg, "angle_deg", ndim=1)
    n = ang.shape[0]
    if n < 1:
        raise ValueError("angle_deg: expected at least one reading")
    ya = _vec(y_a, "y_a", n)
    yb = None if y_b is None else _vec(y_b, "y_b", n)
    t, ma = np.zeros(n), np.zeros(n)
    mb = None if yb is None else np.zeros(n)
    cnt = np.zeros(n, dtype=np.intc)
    npos = ctypes.c_int()
    _lib.call("igea.accel_merge", "igea_accel_merge", n, _lib.dptr(ang), _lib.dptr(ya),
              _lib.dptr(yb), float(tol_deg), _lib.dptr(t), _lib.dptr(ma), _lib.dptr(mb),
              _lib.iptr(cnt), ctypes.byref(npos))
    k = npos.value
    return t[:k].copy(), ma[:k].copy(), None if mb is None else mb[:k].copy(), cnt[:k].copy()


def accel_to_g(raw, scale):
    """Raw outputs (e.g. volts) divided by the nominal scale factor (per g)."""
    r = _lib.as_f64(raw, "raw", ndim=1)
    if r.shape[0] < 1:
        raise ValueError("raw: expected at least one value")
    y = np.zeros(r.shape[0])
    _lib.call("igea.accel_to_g", "igea_accel_to_g", r.shape[0], _lib.dptr(r), float(scale),
              _lib.dptr(y))
    return y


def accel_design(theta_deg, *, model="dual"):
    """Design matrix (n x 5 single, n x 9 dual) in METHODS 4.1/4.2 column
    order: single [1, s, c, s^2, sc]; dual [s, c, s^2, c^2, -sc, s^3, c^3,
    s^2 c, -s c^2] with s = sin(theta), c = cos(theta)."""
    m = _model(model)
    t = _theta(theta_deg)
    n = t.shape[0]
    A = np.zeros((n, _NP[m]), order="F")
    _lib.call("igea.accel_design", "igea_accel_design", _MODELS[m], n, _lib.dptr(t), _lib.dptr(A),
              n)
    return A


def accel_combinations(model="dual"):
    """The estimable combinations as columns (np x nc)."""
    m = _model(model)
    C = np.zeros((_NP[m], _NC[m]), order="F")
    _lib.call("igea.accel_combinations", "igea_accel_combinations", _MODELS[m], _lib.dptr(C),
              _NP[m])
    return C


@result
@dataclass(frozen=True)
class AccelDesignInfo:
    """Identifiability of a position schedule (igea.accel_analyze)."""
    model: str
    singular_values: np.ndarray
    rank: int
    null_space: np.ndarray      # np x (np - rank), canonical orthonormal basis
    loading: np.ndarray         # per coefficient, norm of its null-space part
    comb_loading: np.ndarray    # per estimable combination (0: estimable)
    names: list

    def summary(self):
        lines = ["%s model: %d coefficients, rank %d" % (self.model, len(self.names), self.rank),
                 "singular values: " + " ".join("%.6g" % s for s in self.singular_values)]
        for j, name in enumerate(self.names):
            lines.append("  %-8s loading %.3g  %s" % (name, self.loading[j],
                         "prior-determined" if self.loading[j] > LOADING_TOL else "data"))
        for k in range(self.null_space.shape[1]):
            lines.append("null vector %d: " % k + " ".join(
                "%s=%+.4f" % (self.names[j], v) for j, v in enumerate(self.null_space[:, k])
                if abs(v) > 1e-12))
        return "\n".join(lines)


def accel_analyze(theta_deg, *, model="dual", axis="pa"):
    """Singular values, rank, null space and loadings of the design."""
    m = _model(model)
    t = _theta(theta_deg)
    n, npar, nc = t.shape[0], _NP[m], _NC[m]
    sv, nb = np.zeros(npar), np.zeros((npar, npar), order="F")
    ld, cl, r = np.zeros(npar), np.zeros(nc), ctypes.c_int()
    _lib.call("igea.accel_analyze", "igea_accel_analyze", _MODELS[m], n, _lib.dptr(t),
              _lib.dptr(sv), _lib.dptr(nb), npar, _lib.dptr(ld), _lib.dptr(cl), ctypes.byref(r))
    return AccelDesignInfo(m, sv, r.value, nb[:, :npar - r.value].copy(), ld, cl,
                           coefficient_names(m, axis))


@result
@dataclass(frozen=True)
class AccelFit:
    """A calibration fit (igea.accel_fit); field names match
    'igea accel --json'."""
    model: str
    method: str
    names: list
    coef: np.ndarray
    sd: np.ndarray
    flags: list                 # "data" or "prior" per coefficient
    comb_names: list
    comb: np.ndarray
    comb_sd: np.ndarray         # NaN where a combination is not estimable
    rank: int
    sigma: float                # residual sd of the observation equation
    lam: float                  # EBR lambda hat (0 for LS)
    rms: float
    positions: int              # observations used (IGEA_ACCEL_INFO_NOBS)
    dof: int

    def summary(self):
        lines = ["%s model, %s: %d positions, rank %d, residual sd %.3e g, rms %.3e g%s"
                 % (self.model, self.method.upper(), self.positions, self.rank, self.sigma, self.rms,
                    ", lambda %.6g" % self.lam if self.method == "ebr" else ""),
                 "%-10s %15s %12s  %s" % ("coef", "estimate", "sd", "determined by")]
        for j, name in enumerate(self.names):
            lines.append("%-10s %15.6e %12.3e  %s" % (name, self.coef[j], self.sd[j],
                         "data" if self.flags[j] == "data" else
                         "PRIOR (not identifiable; sd is not its uncertainty)"))
        lines.append("estimable combinations:")
        for k, name in enumerate(self.comb_names):
            lines.append("%-10s %15.6e %12.3e" % (name, self.comb[k], self.comb_sd[k]))
        return "\n".join(lines)


def accel_fit(theta_deg, y_a, y_b=None, *, model="dual", method="ls", prior=_UNSET,
              rule="sc", lam_floor=0.0, scale_a=None, scale_b=None, axis="pa",
              prior_scale=_UNSET, history=None, alpha=0.05):
    """Fit one calibration.

    theta_deg: head angles (one per position; see accel_merge); y_a, y_b:
    outputs in g, or raw outputs with the nominal scale factors scale_a,
    scale_b (output units per g); model "single" (A only) or "dual";
    method "ls" (minimum-norm least squares) or "ebr" (empirical-Bayes
    ridge with the prior scales tau_j `prior`, one per coefficient, the
    driver's --prior (prior_scale= is its old name), rule "sc"/"mm"/"ml2"
    and lam_floor), or "joint" (dual: returns accel_joint's AccelJoint).
    method "ebr" with history (earlier calibrations of the type, see
    accel_history) fits with the prior estimated from them and returns
    accel_fit_history's AccelHistoryFit (intervals at 1 - alpha)."""
    prior = renamed("igea.accel_fit", "prior", prior, "prior_scale", prior_scale)
    m = _model(model)
    method_code = _lib.choice(_capi.CHOICE_ACCEL_METHOD, method, "igea.accel_fit", "method")
    rule_code = _lib.choice(_capi.CHOICE_REGRESS_EBR_RULE, rule, "igea.accel_fit", "rule")
    t = _theta(theta_deg)
    n, npar, nc = t.shape[0], _NP[m], _NC[m]
    ya = _vec(y_a, "y_a", n)
    if scale_a is not None:
        ya = accel_to_g(ya, scale_a)
    yb = None
    if m == "dual":
        if y_b is None:
            raise ValueError("y_b: the dual model needs the B outputs")
        yb = _vec(y_b, "y_b", n)
        if scale_b is not None:
            yb = accel_to_g(yb, scale_b)
    if method == "joint":  # the driver's --method joint: a different estimator
        if m != "dual":
            raise ValueError("method: 'joint' needs model='dual'")
        if prior is not None:
            raise ValueError("prior: only for method='ebr'")
        return accel_joint(t, ya, yb, axis=axis)
    if history is not None:
        if method != "ebr" or prior is not None:
            raise ValueError("history: needs method='ebr' and no prior")
        return accel_fit_history(t, ya, yb, history, model=m, axis=axis, alpha=alpha)
    ps = None if prior is None else _vec(prior, "prior", npar)
    coef, sd, flag = np.zeros(npar), np.zeros(npar), np.zeros(npar, dtype=np.intc)
    comb, csd, info = np.zeros(nc), np.zeros(nc), np.zeros(_capi.ACCEL_INFO_LEN)
    _lib.call("igea.accel_fit", "igea_accel_fit", _MODELS[m], method_code, n, _lib.dptr(t),
              _lib.dptr(ya), _lib.dptr(yb), _lib.dptr(ps), rule_code, float(lam_floor),
              _lib.dptr(coef), _lib.dptr(sd), _lib.iptr(flag), _lib.dptr(comb), _lib.dptr(csd),
              _lib.dptr(info))
    return AccelFit(m, method, coefficient_names(m, axis), coef, sd,
                    ["prior" if f == _capi.ACCEL_PRIOR else "data" for f in flag],
                    combination_names(m, axis), comb, csd,
                    lam=float(info[_capi.ACCEL_INFO_LAMBDA]),
                    positions=int(info[_capi.ACCEL_INFO_NOBS]),
                    **_lib.fields(info, "ACCEL_INFO_", rank=int, sigma=float, rms=float,
                                  dof=int))


@result
@dataclass(frozen=True)
class AccelRefine:
    """Gauss-Newton refinement on the exact dual model (igea.accel_refine)."""
    names: list
    coef: np.ndarray
    sd: np.ndarray
    phi_deg: np.ndarray
    comb: np.ndarray
    rank: int
    sigma: float
    rms: float
    iterations: int
    step: float

    def summary(self):
        lines = ["exact-model refinement: %d iterations, last step %.2e, residual sd %.3e g"
                 % (self.iterations, self.step, self.sigma)]
        for j, name in enumerate(self.names):
            lines.append("%-10s %15.6e %12.3e" % (name, self.coef[j], self.sd[j]))
        return "\n".join(lines)


def accel_refine(theta_deg, y_a, y_b, coef0, *, max_iter=50, tol=1e-13, axis="pa"):
    """Gauss-Newton on the exact models (1)-(2) from coef0 (a dual fit's
    coefficients); the null-space part of coef0 stays fixed."""
    t = _theta(theta_deg)
    n = t.shape[0]
    ya, yb = _vec(y_a, "y_a", n), _vec(y_b, "y_b", n)
    npar = _capi.ACCEL_NP_DUAL
    c0 = _vec(coef0, "coef0", npar)
    coef, sd, phi = np.zeros(npar), np.zeros(npar), np.zeros(n)
    info = np.zeros(_capi.ACCEL_INFO_LEN)
    _lib.call("igea.accel_refine", "igea_accel_refine", n, _lib.dptr(t), _lib.dptr(ya),
              _lib.dptr(yb), _lib.dptr(c0), int(max_iter), float(tol), _lib.dptr(coef),
              _lib.dptr(sd), _lib.dptr(phi), _lib.dptr(info))
    comb = np.zeros(_capi.ACCEL_NC_DUAL)
    _lib.call("igea.accel_refine", "igea_accel_combine", _MODELS["dual"], _lib.dptr(coef),
              _lib.dptr(comb))
    return AccelRefine(coefficient_names("dual", axis), coef, sd, phi, comb,
                       iterations=int(info[_capi.ACCEL_INFO_ITER]),
                       **_lib.fields(info, "ACCEL_INFO_", rank=int, sigma=float, rms=float,
                                     step=float))


def accel_simulate(theta_deg, truth, *, head_sd_arcsec=1.0, noise_sd=1e-6, seed=0):
    """One simulated calibration of an orthogonal pair on the exact models.

    truth: the 9 dual coefficients, optionally a 10th value delta0 (rad).
    Returns (y_a, y_b) in g."""
    t = _theta(theta_deg)
    n = t.shape[0]
    tr = _lib.as_f64(truth, "truth", ndim=1)
    if tr.shape[0] == _capi.ACCEL_NP_DUAL:
        tr = np.append(tr, 0.0)  # delta0
    if tr.shape[0] != _capi.ACCEL_NP_SIM:
        raise ValueError(f"truth: expected {_capi.ACCEL_NP_DUAL} or {_capi.ACCEL_NP_SIM} values, "
                         f"got {tr.shape[0]}")
    ya, yb = np.zeros(n), np.zeros(n)
    _lib.call("igea.accel_simulate", "igea_accel_simulate", n, _lib.dptr(t), _lib.dptr(tr),
              float(head_sd_arcsec) * ARCSEC, float(noise_sd), int(seed), _lib.dptr(ya),
              _lib.dptr(yb))
    return ya, yb


@result
@dataclass(frozen=True)
class AccelApplied:
    """Compensated accelerations of igea.accel_apply (g): u along the
    reference (single) or A's (dual) input axis, v the in-plane
    perpendicular towards B (dual; None for single)."""
    u: np.ndarray
    v: np.ndarray = None


def accel_apply(raw_a, coef, raw_b=None, *, model="dual", scale_a=1.0, scale_b=1.0,
                cross=None):
    """Apply a calibration to raw outputs: raw / scale in g, then the fitted
    model (bias, scale, misalignment, cross-coupling, K2) inverted.

    single: coef = (K0, k1, delta0, K2, Kix); cross = the acceleration along
    the cross axis (g, per reading; None: 0). dual: coef = the 9 dual
    coefficients, raw_b the B outputs."""
    m = _model(model)
    ra = _lib.as_f64(raw_a, "raw_a", ndim=1)
    n = ra.shape[0]
    if n < 1:
        raise ValueError("raw_a: expected at least one value")
    c = _vec(coef, "coef", _NP[m])
    dual = m == "dual"
    if dual and raw_b is None:
        raise ValueError("raw_b: the dual model needs the B outputs")
    rb = _vec(raw_b, "raw_b", n) if dual else None
    cr = _vec(cross, "cross", n) if (cross is not None and not dual) else None
    u = np.zeros(n)
    v = np.zeros(n) if dual else None
    _lib.call("igea.accel_apply", "igea_accel_apply", _MODELS[m], n, _lib.dptr(ra),
              _lib.dptr(rb), float(scale_a), float(scale_b), _lib.dptr(c), _lib.dptr(cr),
              _lib.dptr(u), _lib.dptr(v))
    return AccelApplied(u, v)


@result
@dataclass(frozen=True)
class AccelHysteresis:
    """Clockwise minus counter-clockwise mean per position and the F test of
    zero hysteresis (igea.accel_hysteresis); the driver's JSON keys."""
    theta_deg: np.ndarray
    diff: np.ndarray
    diff_sd: np.ndarray
    n_cw: np.ndarray
    n_ccw: np.ndarray
    f: float
    df1: int
    df2: int
    p: float
    sigma: float

    def summary(self):
        lines = ["hysteresis (cw - ccw): F = %.4g on (%d, %d), p = %.4g; pooled sd %.3e"
                 % (self.f, self.df1, self.df2, self.p, self.sigma)]
        for k in range(len(self.theta_deg)):
            lines.append("%9.3f %14.6e %12.3e %4d %4d" % (self.theta_deg[k], self.diff[k],
                                                        self.diff_sd[k], self.n_cw[k],
                                                        self.n_ccw[k]))
        return "\n".join(lines)


def accel_hysteresis(angle_deg, y, direction=None, *, tol_deg=1e-6):
    """CW - CCW per position with its sd from the repeated readings and the
    F test of zero hysteresis. direction: per reading > 0 clockwise, < 0
    counter-clockwise; None: from the row order (angles increasing =
    counter-clockwise)."""
    ang = _lib.as_f64(angle_deg, "angle_deg", ndim=1)
    n = ang.shape[0]
    if n < 1:
        raise ValueError("angle_deg: expected at least one reading")
    yy = _vec(y, "y", n)
    d = None
    if direction is not None:
        d = np.ascontiguousarray(np.asarray(direction), dtype=np.intc)
        if d.shape != (n,):
            raise ValueError(f"direction: expected {n} values, got shape {d.shape}")
    t, df, sd = np.zeros(n), np.zeros(n), np.zeros(n)
    ncw, nccw = np.zeros(n, dtype=np.intc), np.zeros(n, dtype=np.intc)
    test = np.zeros(_capi.ACCEL_HYST_LEN)
    npos = ctypes.c_int()
    _lib.call("igea.accel_hysteresis", "igea_accel_hysteresis", n, _lib.dptr(ang),
              _lib.iptr(d), _lib.dptr(yy), float(tol_deg), _lib.dptr(t), _lib.dptr(df),
              _lib.dptr(sd), _lib.iptr(ncw), _lib.iptr(nccw), ctypes.byref(npos),
              _lib.dptr(test))
    k = npos.value
    return AccelHysteresis(t[:k].copy(), df[:k].copy(), sd[:k].copy(), ncw[:k].copy(),
                           nccw[:k].copy(), f=float(test[_capi.ACCEL_HYST_F]),
                           df1=int(test[_capi.ACCEL_HYST_DF1]),
                           df2=int(test[_capi.ACCEL_HYST_DF2]),
                           p=float(test[_capi.ACCEL_HYST_P]),
                           sigma=float(test[_capi.ACCEL_HYST_SIGMA]))


@result
@dataclass(frozen=True)
class AccelJoint:
    """Joint fit of an orthogonal pair (igea.accel_joint): the 9 dual
    coefficients and delta0, all determined by the data (rank 10)."""
    names: list
    coef: np.ndarray
    sd: np.ndarray
    cov: np.ndarray
    comb: np.ndarray
    comb_sd: np.ndarray
    sd_radial: float
    sd_angle: float
    rank: int
    sigma: float
    rms: float
    dof: int

    def summary(self):
        lines = ["joint fit (radial g^2 + tangential equations): rank %d, dof %d; "
                 "sd radial %.3e g, tangential %.3e g" % (self.rank, self.dof, self.sd_radial,
                                                         self.sd_angle)]
        for j, name in enumerate(self.names):
            lines.append("%-10s %15.6e %12.3e" % (name, self.coef[j], self.sd[j]))
        return "\n".join(lines)


def accel_joint(theta_deg, y_a, y_b, *, axis="pa"):
    """Joint fit: single A, single B and the dual g^2 equation stacked with
    the head-angle errors as random nuisance effects (docs/accel.md)."""
    t = _theta(theta_deg)
    n = t.shape[0]
    ya, yb = _vec(y_a, "y_a", n), _vec(y_b, "y_b", n)
    npar = _capi.ACCEL_NP_JOINT
    coef, sd = np.zeros(npar), np.zeros(npar)
    cov = np.zeros((npar, npar), order="F")
    comp = np.zeros(_capi.ACCEL_JOINT_NCOMP)
    info = np.zeros(_capi.ACCEL_INFO_LEN)
    comb, csd = np.zeros(_capi.ACCEL_NC_DUAL), np.zeros(_capi.ACCEL_NC_DUAL)
    _lib.call("igea.accel_joint", "igea_accel_joint", n, _lib.dptr(t), _lib.dptr(ya),
              _lib.dptr(yb), _lib.dptr(coef), _lib.dptr(sd), _lib.dptr(cov), npar,
              _lib.dptr(comp), _lib.dptr(comb), _lib.dptr(csd), _lib.dptr(info))
    names = coefficient_names("dual", axis) + ["delta0"]
    return AccelJoint(names, coef, sd, np.ascontiguousarray(cov), comb, csd,
                      sd_radial=float(comp[_capi.ACCEL_JOINT_SD_RADIAL]),
                      sd_angle=float(comp[_capi.ACCEL_JOINT_SD_ANGLE]),
                      **_lib.fields(info, "ACCEL_INFO_", rank=int, sigma=float, rms=float,
                                    dof=int))


# ---- the IEEE Std 1293 model and the design criterion ----------------------

_PLANES = {"ia-pa": _capi.ACCEL_PLANE_IAPA, "ia-oa": _capi.ACCEL_PLANE_IAOA}


def _ieee_names():
    """Names and units of the IEEE Std 1293 coefficients (the library's)."""
    m = _capi.ACCEL_IEEE
    return ([_lib.lib.igea_accel_coef_name(m, 0, j).decode() for j in range(_capi.ACCEL_NP_IEEE)],
            [_lib.lib.igea_accel_coef_unit(m, j).decode() for j in range(_capi.ACCEL_NP_IEEE)])


def _planes(plane, n):
    """plane: one of "ia-pa"/"ia-oa" for every reading, or a sequence of
    those names or of the codes 0 (IA-PA) / 1 (IA-OA) per reading."""
    if isinstance(plane, str):
        plane = [plane] * n
    codes = []
    for p in plane:
        if isinstance(p, str):
            if p.lower() not in _PLANES:
                raise ValueError("plane: %r is not ia-pa or ia-oa" % (p,))
            codes.append(_PLANES[p.lower()])
        else:
            codes.append(int(p))
    out = np.ascontiguousarray(codes, dtype=np.intc)
    if out.shape != (n,):
        raise ValueError("plane: expected %d entries, got %d" % (n, out.shape[0]))
    return out


@result
@dataclass(frozen=True)
class AccelIeeeFit:
    """IEEE Std 1293 single-axis model fitted to tumble readings
    (igea.accel_ieee_fit): K0, K1, K2, K3, Kip, Kio, delta_o, delta_p; field
    names match 'igea accel --model ieee --json'."""
    model: str
    method: str
    positions: int
    names: list
    units: list
    coef: np.ndarray
    sd: np.ndarray
    cov: np.ndarray
    flags: list                 # "data", or "prior": not determined by the schedule
    rank: int
    dof: int
    sigma: float
    rms: float

    def summary(self):
        lines = ["IEEE Std 1293 model, %s: %d positions, rank %d of 8, dof %d, sigma %.3e"
                 % (self.method, self.positions, self.rank, self.dof, self.sigma)]
        for j, name in enumerate(self.names):
            lines.append("%-8s %15.6e %12.3e %-6s %s" % (name, self.coef[j], self.sd[j],
                                                      self.units[j], self.flags[j]))
        return "\n".join(lines)


def accel_ieee_fit(theta_deg, e, plane, *, method="ls"):
    """Fit the IEEE Std 1293 model E = K1 (K0 + a_i + K2 a_i^2 + K3 a_i^3 +
    Kip a_i a_p + Kio a_i a_o + delta_o a_p - delta_p a_o) to tumble readings
    e (any unit; K1 in that unit per g) at head angles theta_deg in the
    IA-PA plane (a_i = sin, a_p = cos) and/or the IA-OA plane (a_i = sin,
    a_o = cos); plane: "ia-pa", "ia-oa", or one name or code (0, 1) per
    reading. method "ls" (least squares) or "harmonic" (the Fourier
    method: one reading per position, N >= 7 equispaced positions per
    plane). Coefficients the schedule does not determine are flagged
    "prior" (docs/accel.md)."""
    t = _theta(theta_deg)
    n = t.shape[0]
    y = _vec(e, "e", n)
    pl = _planes(plane, n)
    m = _lib.choice(_capi.CHOICE_ACCEL_IEEE_METHOD, method, "igea.accel_ieee_fit", "method")
    npar = _capi.ACCEL_NP_IEEE
    coef, sd = np.zeros(npar), np.zeros(npar)
    cov = np.zeros((npar, npar), order="F")
    flag = np.zeros(npar, dtype=np.intc)
    info = np.zeros(_capi.ACCEL_INFO_LEN)
    _lib.call("igea.accel_ieee_fit", "igea_accel_ieee_fit", m, n, _lib.dptr(t),
              _lib.iptr(pl), _lib.dptr(y), _lib.dptr(coef), _lib.dptr(sd), _lib.dptr(cov),
              npar, _lib.iptr(flag), _lib.dptr(info))
    return AccelIeeeFit("ieee", method, n, *_ieee_names(),
                        coef, sd, np.ascontiguousarray(cov),
                        ["prior" if f == _capi.ACCEL_PRIOR else "data" for f in flag],
                        **_lib.fields(info, "ACCEL_INFO_", rank=int, dof=int, sigma=float,
                                      rms=float))


@result
@dataclass(frozen=True)
class AccelCriterion:
    """D-criterion of a position schedule (igea.accel_criterion): logdet =
    (1/r) sum log eig(M / n) of the information matrix per reading, det =
    det(M / n) (0 when rank-deficient), and the per-reading variance
    factors varfac (sd_j = sigma sqrt(varfac_j / n)); field names match
    'igea accel --design --json'."""
    model: str
    method: str
    readings: int
    head_ratio: float
    names: list
    logdet: float
    det: float
    varfac: np.ndarray
    flags: list
    rank: int

    def summary(self):
        lines = ["D-criterion: logdet %.6f, det %.6g (rank %d of %d, %d readings)"
                 % (self.logdet, self.det, self.rank, len(self.names), self.readings)]
        for j, name in enumerate(self.names):
            lines.append("%-8s varfac %12.6g %s" % (name, self.varfac[j], self.flags[j]))
        return "\n".join(lines)


def accel_criterion(theta_deg, *, model="dual", method="ls", plane=None, head_ratio=0.0,
                    axis="pa"):
    """D-criterion and variance factors of a schedule for a model: "single",
    "dual" (method "joint": the joint model with head_ratio = sigma_head /
    sigma), or "ieee" (plane per reading as for accel_ieee_fit)."""
    t = _theta(theta_deg)
    n = t.shape[0]
    if model == "ieee" and method == "harmonic":    # the same information as least squares
        method = "ls"
    mod = _lib.choice(_capi.CHOICE_ACCEL_CRIT_MODEL, model, "igea.accel_criterion", "model")
    m = _lib.choice(_capi.CHOICE_ACCEL_METHOD, method, "igea.accel_criterion", "method")
    pl = _planes(plane, n) if model == "ieee" else None
    if model == "ieee":
        names = _ieee_names()[0]
    elif model == "dual" and method == "joint":
        names = coefficient_names("dual", axis) + ["delta0"]
    else:
        names = coefficient_names(model, axis)
    npar = len(names)
    ld, rank = ctypes.c_double(0.0), ctypes.c_int(0)
    vf, flag = np.zeros(npar), np.zeros(npar, dtype=np.intc)
    _lib.call("igea.accel_criterion", "igea_accel_criterion", mod, m, n, _lib.dptr(t),
              None if pl is None else _lib.iptr(pl), float(head_ratio), ctypes.byref(ld),
              _lib.dptr(vf), _lib.iptr(flag), ctypes.byref(rank))
    r = int(rank.value)
    det = float(np.exp(npar * ld.value)) if r == npar else 0.0
    return AccelCriterion(model, method, n, float(head_ratio), names, float(ld.value), det, vf,
                          ["prior" if f == _capi.ACCEL_PRIOR else "data" for f in flag], r)


# ---- priors from the calibration history --------------------------------


def _history_entry(h, npar, k):
    """(coef, cov) of one earlier calibration: an AccelJoint-like object or
    dict with coef and cov, or the path of a JSON file written by
    'igea accel --method joint --json'. The first npar coefficients are used
    (a joint fit's delta0 is not a dual coefficient)."""
    import json
    import os
    src = h
    if isinstance(h, (str, bytes, os.PathLike)):
        with open(h) as f:
            h = json.load(f)
    get = h.get if isinstance(h, dict) else (lambda key, d=None: getattr(h, key, d))
    coef, cov, flags = get("coef"), get("cov"), get("flags")
    if flags is not None and any(f != "data" for f in list(flags)[:npar]):
        raise ValueError("history[%d]: coefficients flagged prior are not estimates of the "
                         "coefficients (use joint fits)" % k)
    if coef is None or cov is None:    # sds alone would drop the correlations
        raise ValueError("history[%d] (%s): needs coef and cov (joint fits, or dicts with "
                         "both)" % (k, str(src)[:60]))
    coef, cov = np.asarray(coef, dtype=float), np.asarray(cov, dtype=float)
    if coef.ndim != 1 or cov.ndim != 2 or coef.shape[0] < npar or min(cov.shape) < npar:
        raise ValueError("history[%d]: %d coefficients, the model has %d"
                         % (k, coef.shape[0], npar))
    return coef[:npar], cov[:npar, :npar]


@result
@dataclass(frozen=True)
class AccelHistory:
    """Prior of an instrument type from earlier calibrations
    (igea.accel_history): REML fit of b_i = beta0 + u_i + e_i. estimates
    (m x p) and covariances (m x p x p) are the calibrations it was fitted
    to; information the expected REML information of the variance
    parameters (Sigma's diagonal, or its lower triangle by columns when
    full), whose inverse is their large-sample covariance."""
    beta0: np.ndarray
    tau: np.ndarray
    sigma_u: np.ndarray
    prior_cov: np.ndarray
    full: bool
    loglik: float
    iterations: int
    calibrations: int
    estimates: np.ndarray = None
    covariances: np.ndarray = None
    information: np.ndarray = None

    def summary(self):
        lines = ["prior from %d calibrations (REML, %s Sigma, %d EM iterations)"
                 % (self.calibrations, "full" if self.full else "diagonal", self.iterations)]
        for j in range(self.beta0.shape[0]):
            lines.append("%2d  beta0 %14.6e  tau %11.3e  prior sd %11.3e" % (
                j, self.beta0[j], self.tau[j], np.sqrt(self.prior_cov[j, j])))
        return "\n".join(lines)


def _history_arrays(b, V):
    return (np.asfortranarray(np.asarray(b, dtype=float).T),
            np.ascontiguousarray(np.concatenate([np.asfortranarray(Vi).ravel(order="F")
                                                 for Vi in V])))


def accel_history(history, *, model="dual", full=False, max_iter=20000, tol=1e-8):
    """REML estimate of the prior mean beta0 and the instrument-to-instrument
    covariance sigma_u (diagonal, sds tau; full=True: the whole matrix) from
    earlier calibrations (see _history_entry for the forms an entry may
    take); prior_cov = sigma_u + Cov(beta0) is the prior of a new
    instrument of the type."""
    m = _model(model)
    npar = _NP[m]
    entries = [_history_entry(h, npar, k) for k, h in enumerate(history)]
    mcal = len(entries)
    if mcal < 2:
        raise ValueError("history: needs at least two calibrations")
    est = np.array([e[0] for e in entries])
    covs = np.array([e[1] for e in entries])
    b, V = _history_arrays(est, covs)
    beta0, tau = np.zeros(npar), np.zeros(npar)
    pc = np.zeros((npar, npar), order="F")
    info = np.zeros(_capi.ACCEL_HIST_LEN)
    su = np.zeros((npar, npar), order="F")
    if full:
        _lib.call("igea.accel_history", "igea_accel_history_full", mcal, npar, _lib.dptr(b),
                  npar, _lib.dptr(V), npar, int(max_iter), float(tol), _lib.dptr(beta0),
                  _lib.dptr(su), npar, _lib.dptr(pc), npar, _lib.dptr(info))
        tau = np.sqrt(np.diag(su))
    else:
        _lib.call("igea.accel_history", "igea_accel_history", mcal, npar, _lib.dptr(b), npar,
                  _lib.dptr(V), npar, int(max_iter), float(tol), _lib.dptr(beta0),
                  _lib.dptr(tau), _lib.dptr(pc), npar, _lib.dptr(info))
        su = np.asfortranarray(np.diag(tau ** 2))
    q = npar * (npar + 1) // 2 if full else npar
    inf = np.zeros((q, q), order="F")
    _lib.call("igea.accel_history", "igea_accel_history_information", mcal, npar, _lib.dptr(b),
              npar, _lib.dptr(V), npar, _lib.dptr(su), npar, int(bool(full)), _lib.dptr(inf), q)
    return AccelHistory(beta0, tau, np.ascontiguousarray(su), np.ascontiguousarray(pc),
                        bool(full), float(info[_capi.ACCEL_HIST_LOGLIK]),
                        int(info[_capi.ACCEL_HIST_ITER]), mcal, est, covs,
                        np.ascontiguousarray(inf))


@result
@dataclass(frozen=True)
class AccelHistoryFit:
    """A calibration fitted with the prior from the calibration history
    (igea.accel_fit_history). sd is the root mean squared error with the
    uncertainty of the estimated prior and of the residual variance
    (docs/accel.md); sd_plugin the posterior sd that treats them as known;
    sd_dof its Satterthwaite degrees of freedom; [conf_int_lower,
    conf_int_upper] the interval coef -+ t(sd_dof, 1 - alpha/2) sd; cov the
    matching covariance; capped the coefficients whose bias correction hit
    its floor."""
    model: str
    method: str
    names: list
    coef: np.ndarray
    sd: np.ndarray
    cov: np.ndarray
    prior_mean: np.ndarray
    prior_sd: np.ndarray
    rank: int
    sigma: float
    rms: float
    positions: int
    dof: int
    sd_plugin: np.ndarray = None
    sd_dof: np.ndarray = None
    conf_int_lower: np.ndarray = None
    conf_int_upper: np.ndarray = None
    alpha: float = 0.05
    capped: int = 0

    def summary(self):
        lines = ["%s model, EBR with the history prior: %d positions, data rank %d; "
                 "intervals at %g %%" % (self.model, self.positions, self.rank,
                                         100 * (1 - self.alpha))]
        for j, name in enumerate(self.names):
            lines.append("%-8s %15.6e %12.3e (plug-in %.3e, dof %5.1f) [%.6e, %.6e]  prior "
                         "%12.4e +- %.3e" % (
                             name, self.coef[j], self.sd[j], self.sd_plugin[j], self.sd_dof[j],
                             self.conf_int_lower[j], self.conf_int_upper[j],
                             self.prior_mean[j], self.prior_sd[j]))
        return "\n".join(lines)


def accel_fit_history(theta_deg, y_a, y_b, history, *, model="dual", axis="pa", alpha=0.05):
    """Fit one calibration with the prior N(beta0, prior_cov) estimated from
    the history (accel_history, or the list of earlier calibrations, then
    fitted with a diagonal Sigma), with the uncertainty of that estimated
    prior (igea_accel_fit_history)."""
    m = _model(model)
    h = history if isinstance(history, AccelHistory) else accel_history(history, model=m)
    if h.estimates is None or h.covariances is None:
        raise ValueError("history: an AccelHistory without its calibrations (estimates, "
                         "covariances)")
    t = _theta(theta_deg)
    n, npar = t.shape[0], _NP[m]
    if h.beta0.shape[0] != npar:
        raise ValueError("history: %d coefficients, the %s model has %d"
                         % (h.beta0.shape[0], m, npar))
    ya = _vec(y_a, "y_a", n)
    yb = _vec(y_b, "y_b", n) if m == "dual" else None
    b, V = _history_arrays(h.estimates, h.covariances)
    coef, sd, sdp, dof = np.zeros(npar), np.zeros(npar), np.zeros(npar), np.zeros(npar)
    ci = np.zeros(2 * npar)
    cov = np.zeros((npar, npar), order="F")
    info = np.zeros(_capi.ACCEL_HFIT_LEN)
    su = np.asfortranarray(h.sigma_u)
    _lib.call("igea.accel_fit_history", "igea_accel_fit_history", _MODELS[m], n, _lib.dptr(t),
              _lib.dptr(ya), _lib.dptr(yb), h.calibrations, _lib.dptr(b), npar, _lib.dptr(V),
              npar, _lib.dptr(su), npar, int(h.full), float(alpha), _lib.dptr(coef),
              _lib.dptr(sd), _lib.dptr(sdp), _lib.dptr(dof), _lib.dptr(ci), _lib.dptr(cov), npar,
              _lib.dptr(info))
    return AccelHistoryFit(m, "ebr", coefficient_names(m, axis), coef, sd,
                           np.ascontiguousarray(cov), h.beta0.copy(),
                           np.sqrt(np.diag(h.prior_cov)),
                           positions=int(info[_capi.ACCEL_INFO_NOBS]),
                           **_lib.fields(info, "ACCEL_INFO_", rank=int, sigma=float, rms=float,
                                         dof=int),
                           sd_plugin=sdp, sd_dof=dof, conf_int_lower=ci[:npar].copy(),
                           conf_int_upper=ci[npar:].copy(), alpha=float(alpha),
                           capped=int(info[_capi.ACCEL_HFIT_CAPPED]))
