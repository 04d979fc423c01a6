"""What every result class shares: a concise repr, to_dict() and to_json().

A result is a frozen dataclass whose fields are the JSON keys of the
driver's command of the same name (docs/vocabulary.md). The decorator
`result` gives it

- a repr of one line: scalars and short strings shown, arrays as
  <dtype shape>, nested results and long lists abbreviated;
- to_dict(): the fields as JSON types, as the driver writes them (numpy
  arrays as nested lists, numpy scalars as Python numbers, NaN and
  +-Inf as None, which the driver writes as null; nested results as
  their to_dict());
- to_json(**kw): json.dumps(to_dict(), **kw).

The decorator goes above @dataclass, which would otherwise write its own
(field-by-field, array-printing) repr over the one given here."""
import dataclasses
import json
import math

import numpy as np

__all__ = ["attach", "result", "to_json_value"]

_LIST_SHOWN = 6      # lists of at most this many scalars are shown whole
_STR_SHOWN = 40      # longer strings are cut


def to_json_value(v):
    """v as the value the driver's JSON writer gives it (see module doc)."""
    if dataclasses.is_dataclass(v) and not isinstance(v, type):
        return v.to_dict() if hasattr(v, "to_dict") else {
            f.name: to_json_value(getattr(v, f.name)) for f in dataclasses.fields(v)}
    if isinstance(v, np.ndarray):
        return to_json_value(v.tolist())
    if isinstance(v, (bool, np.bool_)):
        return bool(v)
    if isinstance(v, (int, np.integer)):
        return int(v)
    if isinstance(v, (float, np.floating)):
        v = float(v)
        return v if math.isfinite(v) else None
    if isinstance(v, dict):
        return {str(k): to_json_value(x) for k, x in v.items()}
    if isinstance(v, (list, tuple)):
        return [to_json_value(x) for x in v]
    return v


def _is_scalar(v):
    return v is None or isinstance(v, (bool, int, float, str, np.bool_, np.number))


def _short(v):
    """The repr of one field value: at most a few dozen characters."""
    if dataclasses.is_dataclass(v) and not isinstance(v, type):
        return "<%s>" % type(v).__name__
    if isinstance(v, np.ndarray):
        if v.size == 1 and v.ndim <= 1:
            return "<%s %s: %s>" % (v.dtype, v.shape, _short(v.reshape(-1)[0]))
        return "<%s %s>" % (v.dtype, v.shape)
    if isinstance(v, (bool, np.bool_)):
        return repr(bool(v))
    if isinstance(v, (float, np.floating)):
        return "%.6g" % float(v)
    if isinstance(v, (int, np.integer)):
        return repr(int(v))
    if isinstance(v, str):
        return repr(v if len(v) <= _STR_SHOWN else v[:_STR_SHOWN - 3] + "...")
    if isinstance(v, (list, tuple)):
        if len(v) <= _LIST_SHOWN and all(_is_scalar(x) for x in v):
            inner = ", ".join(_short(x) for x in v)
            return ("[%s]" if isinstance(v, list) else "(%s)") % inner
        kinds = sorted({type(x).__name__ for x in v})
        return "[%d %s]" % (len(v), "/".join(kinds) if kinds else "items")
    if isinstance(v, dict):
        return "{%d keys}" % len(v)
    if v is None:
        return "None"
    return "<%s>" % type(v).__name__


def _repr(self):
    parts = ["%s=%s" % (f.name, _short(getattr(self, f.name)))
             for f in dataclasses.fields(self) if f.repr]
    return "%s(%s)" % (type(self).__name__, ", ".join(parts))


def _to_dict(self):
    """The fields as JSON types: the driver's --json document of the same
    command (arrays as lists, NaN/Inf as None = JSON null)."""
    omit = getattr(self, "_json_omit", ())      # fields the driver writes elsewhere
    d = {f.name: to_json_value(getattr(self, f.name)) for f in dataclasses.fields(self)
         if f.name not in omit}
    extra = getattr(self, "_json_extra", None)   # the driver's keys that are not fields
    if extra is not None:
        d.update({k: to_json_value(v) for k, v in extra().items()})
    return d


def _to_json(self, **kw):
    """json.dumps(self.to_dict(), **kw): the driver's --json document."""
    return json.dumps(self.to_dict(), allow_nan=False, **kw)


def attach(obj, **private):
    """obj with private attributes _name (context for to_dict and summary
    kept off the dataclass fields); returns obj."""
    for k, v in private.items():
        object.__setattr__(obj, "_" + k, v)
    return obj


def result(cls):
    """Class decorator (above @dataclass): concise repr, to_dict, to_json."""
    if not dataclasses.is_dataclass(cls):
        raise TypeError("igea._result.result: %s is not a dataclass (put the decorator "
                        "above @dataclass)" % cls.__name__)
    cls.__repr__ = _repr
    _document(cls)
    if cls.__name__ in PLOTS and "plot" not in cls.__dict__:
        cls.plot = _plot
    if "to_dict" not in cls.__dict__:
        cls.to_dict = _to_dict
    if "to_json" not in cls.__dict__:
        cls.to_json = _to_json
    return cls


# ---------------------------------------------------------------------------
# Field descriptions. A field name means the same in every result (the
# vocabulary of docs/vocabulary.md), so most are described once under
# SHARED; CLASS holds what a class means differently. `result` appends a
# "Fields" section built from them to the class docstring.

SHARED = {
    "x": "the estimate, (N,)",
    "cov": "its covariance, (N, N)",
    "sd": "standard deviations: the square roots of the covariance's diagonal",
    "rank": "numerical rank of the design (or normal matrix)",
    "rank_tol": "the singular-value cut that decided the rank",
    "sigma2": "residual variance factor: weighted residual sum of squares / residual dof",
    "residual": "residuals y - A x per row, in the units of dw",
    "names": "term (coefficient) names, one per column",
    "eigenvalues": "eigenvalues lambda of the normal matrix, descending",
    "eigenvectors": "its eigenvectors, column k for eigenvalue k, (N, N)",
    "equiv_err": "equivalent errors: the estimate in the eigenvector basis, spec units",
    "n_test": "number of components tested (eigenvalue >= lambda_test)",
    "z": "normal statistic of each tested component, (n_test,)",
    "reject": "per tested component, True where |z| exceeds its threshold",
    "chi2": "chi-square statistic T = sum z^2 of the tested components",
    "dof": "degrees of freedom of T",
    "chi2_crit": "chi-square critical value at alpha for dof",
    "z_crit": "normal critical value z_{1-alpha/2} of the component test",
    "p_value": "upper-tail probability of T",
    "passed": "True when the verdict is \"in spec\"",
    "verdict": "the overall verdict rule: seed, chi2, exact or sidak",
    "verdict_z_crit": "the rule's threshold on |z| (None: no component test)",
    "verdict_chi2_crit": "the rule's threshold on T",
    "overall_size": "the rule's false-alarm probability (None: not computed)",
    "scale": "c, the sigma_w^2 estimate the tracking 1-sigma was corrected by (1: off)",
    "iterations": "iterations run",
    "n_small": "number of small eigenvalues (<= lambda_small) used for sigma_w",
    "flag": "how sigma_w was found: ok, clamped, not_estimable, off, ...",
    "rms": "residual RMS per axis x, y, z",
    "whiteness": "per axis x, y, z: dict(axis, n, lags, ljung_box, ljung_box_p, runs, "
                 "n_above, n_below, runs_z, runs_p) of the residuals; None if not computed",
    "components": "per tested component: dict(index, lambda, z, reject, terms [(name, share), "
                  "...] descending, loading, candidates)",
    "n_reject": "number of rejected components",
    "component_miss": "(n_test, 2) downrange and crossrange miss of each tested component "
                      "at its equivalent error (Kepler impact from the burnout), m; None "
                      "without the burnout options",
    "residual_whitened": "True when residual, rms and whiteness are of the whitened rows "
                         "(the noise models)",
    "model": "the model name",
    "method": "the estimation method (ls or ebr)",
    "coef": "the coefficient estimates, in the order of names",
    "comb_names": "names of the estimable combinations",
    "comb": "the estimable combinations' estimates",
    "comb_sd": "their standard deviations (NaN where a combination is not estimable)",
    "sigma": "residual standard deviation of the observation equation",
    "lam": "the empirical-Bayes ridge parameter lambda (0 for least squares)",
    "positions": "observations (positions) used",
    "flags": "per coefficient, \"data\" or \"prior\": what determined it",
    "k": "the ridge parameter",
    "rule": "the rule that chose the ridge parameter",
    "kind": "the statistic (e.g. allan, modified, overlapping)",
    "taus": "averaging times tau, s",
    "dev": "the deviation at each tau",
    "lo": "lower confidence limit of dev at each tau",
    "hi": "upper confidence limit of dev at each tau",
    "edf": "equivalent degrees of freedom at each tau",
    "count": "number of terms averaged at each tau",
    "conf": "confidence level of lo and hi",
    "covariance": "covariance of the estimate",
    "threshold": "the detection threshold",
    "statistic": "the test statistic",
    "terms": "term names",
    "t": "times, s",
    "epochs": "epoch times, s",
    "flights": "flights simulated",
    "failed": "flights whose verdict is \"out of spec\" (any component or chi-square)",
    "window": "window length, s",
    "share": "each term's share of the trace of the covariance",
    "ncomp": "principal components kept",
    "scaled": "True when the columns were scaled to unit norm internally (norms more than "
              "1e8 apart)",
    "prior_sd": "prior standard deviation of each coefficient",
    "value": "fitted value of each noise term",
    "se": "standard error of each noise term",
    "supported": "per term, True where the data support it (likelihood ratio)",
}

CLASS = {
    "AccelDesignInfo": {
        "model": "accelerometer model: single or dual",
        "singular_values": "singular values of the design, descending",
        "null_space": "(np, np - rank): canonical orthonormal basis of the null space",
        "loading": "per coefficient, the norm of its null-space part (0: data-determined)",
        "comb_loading": "per estimable combination, its null-space loading (0: estimable)",
        "names": "coefficient names"},
    "AccelFit": {
        "model": "accelerometer model: single or dual",
        "sigma": "residual standard deviation of the observation equation, g",
        "rms": "RMS of the residuals, g",
        "positions": "observations used (IGEA_ACCEL_INFO_NOBS)",
        "dof": "residual degrees of freedom"},
    "AccelRefine": {
        "phi_deg": "refined position angles, degrees",
        "comb": "the estimable combinations at the refined angles",
        "sigma": "residual standard deviation, g",
        "rms": "RMS of the residuals, g",
        "iterations": "Gauss-Newton iterations run",
        "step": "norm of the last Gauss-Newton step"},
    "DwResult": {
        "dw": "(3 n_epochs,) velocity differences epoch-major x, y, z, m/s",
        "cov": "(n_epochs, 6) c_xx c_xy c_xz c_yy c_yz c_zz in LI, or None",
        "xcov": "(n_epochs, 3, 3) Cov(dW_e, dW_f) for every later epoch f, or None",
        "sigma": "(3 n_epochs,) square roots of the covariance's diagonal, or None",
        "dw_dtau": "(3 n_epochs,) dW / dtau, m/s^2 (the time_offset term's column)",
        "n_epochs": "epochs compared",
        "rows": "rows of dw (3 n_epochs)",
        "samples": "samples of the record used",
        "max_abs": "largest |dw|, m/s",
        "rms": "(3,) RMS of dw per axis, m/s"},
    "NoiseEqerrResult": {
        "scale": "c, the overall tracking-variance factor",
        "ar_order": "p of the AR(p) whitening (0: none)",
        "ar_method": "how phi was estimated, \"reml\" or \"ls\" (None: phi given or p = 0)",
        "ar_phi": "(3, p): phi of lag k + 1 of axis a",
        "ar_se": "(3, p): their standard errors (0 when phi was given)",
        "groups": "per group: dict(scale, scale_se, scale_se_reml, redundancy, rows, bias)",
        "robust_crit": "critical |w| of the robust route's data snooping",
        "rejected_rows": "rows rejected by the robust route: [{\"row\": i, \"w\": w}]",
        "noise_iterations": "iterations of the noise-model estimation",
        "noise_converged": "True when the noise-model estimation converged"},
    "AccelApplied": {
        "u": "compensated acceleration along the reference (single) or A's (dual) axis, g",
        "v": "the in-plane perpendicular towards B (dual; None for single), g"},
    "AccelHysteresis": {
        "theta_deg": "(P,) head angle of each position, degrees",
        "diff": "(P,) clockwise minus counter-clockwise mean output, g",
        "diff_sd": "(P,) its standard deviation from the repeated readings, g",
        "n_cw": "(P,) clockwise readings", "n_ccw": "(P,) counter-clockwise readings",
        "f": "F = sum (diff/diff_sd)^2 / P, the test of zero hysteresis",
        "df1": "numerator degrees of freedom (P)", "df2": "denominator degrees of freedom",
        "p": "P(F(df1, df2) > f)", "sigma": "pooled sd of one reading, g"},
    "AccelIeeeFit": {
        "model": "\"ieee\": the IEEE Std 1293 single-axis model",
        "method": "ls (least squares) or harmonic (the Fourier method)",
        "positions": "readings (positions) fitted",
        "names": "K0 K1 K2 K3 Kip Kio delta_o delta_p",
        "units": "unit of each coefficient (K1 in output units per g)",
        "coef": "(8,) the estimates", "sd": "(8,) their standard deviations (delta method)",
        "cov": "(8, 8) their covariance",
        "flags": "per coefficient, \"data\" or \"prior\" (not determined by the schedule)",
        "rank": "rank of the linear design (8 with both planes)",
        "dof": "residual degrees of freedom", "sigma": "residual sd, output units",
        "rms": "RMS of the residuals, output units"},
    "AccelCriterion": {
        "model": "single, dual or ieee", "method": "ls, ebr or joint (dual)",
        "readings": "readings of the schedule (n)",
        "head_ratio": "sigma_head / sigma (joint model only)",
        "names": "coefficient names",
        "logdet": "(1/r) sum log eig(M / n): the D-criterion per coefficient",
        "det": "det(M / n), 0 when rank-deficient",
        "varfac": "n [M^+]_jj: sd_j = sigma sqrt(varfac_j / n)",
        "flags": "per coefficient, \"data\" or \"prior\" (not determined by the schedule)",
        "rank": "rank of the information matrix"},
    "AccelHistory": {
        "beta0": "(p,) prior mean: the GLS mean of the earlier calibrations",
        "tau": "(p,) instrument-to-instrument sds (REML; sqrt of sigma_u's diagonal)",
        "sigma_u": "(p, p) instrument-to-instrument covariance Sigma (diagonal unless full)",
        "full": "True when Sigma was estimated as a full matrix",
        "prior_cov": "(p, p) prior of a new instrument: diag(tau^2) + Cov(beta0)",
        "loglik": "restricted log-likelihood at the estimate (without its constant)",
        "iterations": "EM iterations", "calibrations": "earlier calibrations used",
        "estimates": "(m, p) the earlier calibrations' coefficient estimates",
        "covariances": "(m, p, p) their covariances",
        "information": "expected REML information of the variance parameters (Sigma's "
                       "diagonal, or its lower triangle by columns when full)"},
    "AccelHistoryFit": {
        "model": "single or dual", "method": "\"ebr\" (with the history prior)",
        "names": "coefficient names", "coef": "posterior means",
        "sd": "root mean squared errors: the posterior sd with the uncertainty of the "
              "estimated prior and residual variance",
        "cov": "the covariance matching sd",
        "sd_plugin": "posterior sds that take the prior and residual variance as known",
        "sd_dof": "Satterthwaite degrees of freedom of each sd",
        "conf_int_lower": "coef - t(sd_dof, 1 - alpha/2) sd",
        "conf_int_upper": "coef + t(sd_dof, 1 - alpha/2) sd",
        "alpha": "the intervals' level is 1 - alpha",
        "capped": "coefficients whose bias correction reached its floor",
        "prior_mean": "the prior mean used (beta0)",
        "prior_sd": "the prior sds used (sqrt of prior_cov's diagonal)",
        "rank": "rank of the calibration's own design",
        "sigma": "residual sd of the least-squares fit, g",
        "rms": "RMS of the posterior residuals, g", "positions": "observations used",
        "dof": "residual degrees of freedom of the least-squares fit"},
    "AccelJoint": {
        "names": "the 9 dual coefficients and delta0", "coef": "(10,) the estimates",
        "sd": "(10,) their standard deviations", "cov": "(10, 10) their covariance",
        "comb": "the estimable combinations", "comb_sd": "their standard deviations",
        "sd_radial": "residual sd of the radial (dual g^2) equation, g",
        "sd_angle": "residual sd of the tangential equation (noise and head error), g",
        "rank": "rank of the joint design (10)", "sigma": "overall residual sd, g",
        "rms": "rms residual, g", "dof": "residual degrees of freedom"},
    "RawFlight": {
        "telemetry": "(samples, 7 or 4): t dvx dvy dvz [dthx dthy dthz] increments",
        "tracking": "(epochs, 8): t x y z vx vy vz sigma (m, m/s) in the frame",
        "lat": "stated launch latitude, degrees", "lon": "stated launch longitude, degrees",
        "height": "stated launch height, m", "azimuth": "stated firing azimuth, degrees",
        "q0": "(4,) stated attitude body -> LI at lift-off", "frame": "tracking frame (le, ecef)",
        "system": "inertial system", "flight": "the simulator's own Flight (S, dw, sigma, spec, x_true)"},
    "NavErrors": {
        "lat": "latitude, degrees",
        "duration": "propagation time, s",
        "acc_bias": "(3,) accelerometer biases north, east, down, m/s^2",
        "gyro_drift": "(3,) gyro drifts north, east, down, rad/s",
        "time": "(n,) epochs, s",
        "position": "(n, 3) position errors north, east, down, m",
        "velocity": "(n, 3) velocity errors north, east, down, m/s",
        "attitude": "(n, 3) attitude errors about north, east, down, rad",
        "covariance": "(n, 15, 15) covariance of the whole error state, or None"},
    "RedundStability": {
        "block_seconds": "length of one block, s",
        "channel": "(nsens,) each sensor's fused channel (-1: not fused)",
        "three_sigma": "(nsens,) 3 sigma of each sensor's block means",
        "sigma": "(nsens,) sample sd of each sensor's block means",
        "fused_three_sigma": "(nchan,) 3 sigma of each fused channel's block means",
        "fused_sigma": "(nchan,) sample sd of each fused channel's block means",
        "fused": "(nsamp, nchan) the fused series"},
    "RedundGroup": {
        "fusion": "fusion rule (average, weighted, gls)",
        "frames": "(g, 3, 3) C_g: group g's frame to the body frame (group 0's)",
        "group_out": "(g, 3) each group's compensated output in the body frame",
        "fused": "(3,) fused output in the body frame",
        "cov": "(3, 3) covariance of fused, each shared sensor counted once",
        "cov_indep": "(3, 3) the covariance stated if the groups were independent"},
    "NavErrorsLI": {
        "system": "inertial system (strapdown, platform)",
        "time": "(n,) epochs, s since the record's start",
        "position": "(n, 3) position errors in the launch-inertial frame, m",
        "velocity": "(n, 3) velocity errors in the launch-inertial frame, m/s",
        "attitude": "(n, 3) attitude errors phi in the launch-inertial frame, rad",
        "acc_bias": "(n, 3) accelerometer biases in instrument axes, m/s^2",
        "gyro_drift": "(n, 3) gyro drifts in instrument axes, rad/s",
        "covariance": "(n, 15, 15) covariance of the whole error state, or None"},
    "ImpactResult": {
        "model": "gravity model of the ballistic flight (e.g. point, j2)",
        "point": "(3,) impact point, ECEF, m",
        "velocity": "(3,) velocity at impact, ECEF, m/s",
        "time": "time of flight, s",
        "jacobian": "(7, 6): d(point, velocity, time) / d(burnout x y z vx vy vz)",
        "down": "(3,) the downrange miss axis at the impact point",
        "cross": "(3,) the crossrange miss axis at the impact point",
        "miss_jacobian": "(2, 6): downrange and crossrange miss per unit of the burnout state"},
    "Burnout": {
        "burnout_time": "the burnout time, s of the trajectory",
        "burnout": "(6,) burnout state x y z (m), vx vy vz (m/s, relative to the Earth), ECEF",
        "terms": "the error terms' names",
        "burnout_errors": "(6, N) burnout state error (navigation computed minus true, ECEF) "
                          "per unit of each term times its spec"},
    "ImpactBudget": {
        "names": "the error terms' names",
        "miss": "(n, 2): downrange and crossrange miss of each term, m",
        "covariance": "(2, 2) impact covariance, m^2",
        "cep": "circular error probable of that covariance (exact), m"},
    "NavResult": {
        "t": "(n,) time of each state, s",
        "r": "(n, 3) LI position, m",
        "v": "(n, 3) LI velocity, m/s",
        "q": "(n, 4) attitude quaternion body -> LI (1 0 0 0 for a platform)",
        "w": "(n, 3) apparent velocity (integral of f dt) in LI, m/s"},
    "Seed002Reliability": {
        "gyro": "reliability of the gyro subsystem",
        "acc_eq7": "accelerometer subsystem reliability, seed 002 eq. (7)",
        "system_eq7": "system reliability, seed 002 eq. (7)",
        "system_without_skew": "system reliability without the skew sensor",
        "non_redundant": "reliability of the non-redundant system",
        "system_exact": "system reliability, exact enumeration",
        "acc_exact": "accelerometer subsystem reliability, exact enumeration"},
    "GeometryReliability": {
        "span": "probability that the surviving axes span 3-D",
        "detect": "... and a further single fault is detectable (NaN if not computed)",
        "isolate": "... and isolable",
        "classes": "number of direction classes"},
    "FdiResult": {
        "statistic": "parity detection statistic",
        "threshold": "its chi-square threshold",
        "dof": "its degrees of freedom (m - q)",
        "p_value": "upper-tail probability of the statistic",
        "detected": "True when the statistic exceeds the threshold",
        "isolated": "0-based sensor isolated, -1 if none",
        "isolation_statistic": "statistic of the isolated sensor",
        "isolable": "True when the geometry can isolate any single fault",
        "parity": "whitened parity vector (m - q)"},
    "SkewCheck": {
        "residual": "(ny, nz): a_D - (cy a_y,i + cz a_z,j)",
        "faulty_y": "bool (ny,): Y sensors found faulty",
        "faulty_z": "bool (nz,): Z sensors found faulty",
        "faulty_d": "every pair failed: the skew sensor is the suspect"},
    "SeriesCheck": {
        "t": "window start times, s",
        "means": "(nwin, nsens) window means",
        "excluded": "(nwin, nsens) bool: sensors excluded per window",
        "fused": "(nwin,) fused value per window",
        "fused_sigma": "(nwin,) its 1-sigma",
        "exclusions": "[(sensor, from, to)]: exclusion intervals, sensor 0-based"},
    "LsResult": {
        "refine_steps": "extended-precision refinement steps run",
        "r2": "coefficient of determination (statsmodels OLS; None when not defined)",
        "r2_adj": "adjusted R^2",
        "fvalue": "F statistic of the regression",
        "f_pvalue": "its p-value",
        "tvalues": "t statistic x / sd per coefficient",
        "pvalues": "two-sided p-value of each t statistic",
        "conf_int_lower": "lower 1 - alpha confidence limit per coefficient",
        "conf_int_upper": "upper 1 - alpha confidence limit per coefficient",
        "alpha": "level of the confidence limits",
        "llf": "Gaussian log-likelihood",
        "aic": "Akaike information criterion",
        "bic": "Bayesian information criterion",
        "leverage": "diagonal of the hat matrix per row",
        "cooks_d": "Cook's distance per row",
        "press": "PRESS: sum of the squared leave-one-out residuals",
        "durbin_watson": "Durbin-Watson statistic of the residuals",
        "df_model": "model degrees of freedom",
        "df_resid": "residual degrees of freedom"},
    "EbrResult": {
        "shrink": "lambda d_i / (1 + lambda d_i) of the first rank canonical components (d_i descending), 0 beyond",
        "sd_frequentist": "frequentist standard deviations of x with lambda fixed (sd: the posterior ones)",
        "rule": "the rule that chose lambda (e.g. sc, mm)"},
    "RidgeTrace": {
        "k": "the grid of ridge parameters",
        "X": "(N, len(k)): X[:, j] = x(k[j])",
        "edf": "effective degrees of freedom tr H(k) = sum d_i / (d_i + k) at each k"},
    "Collinearity": {
        "cond": "condition number of B",
        "cond_estimable": "condition number over the estimable directions",
        "eigenvalues": "eigenvalues of B, descending",
        "eigenvectors": "its eigenvectors, column k for eigenvalue k",
        "vif": "uncentred variance-inflation factor B_jj pinv(B)_jj per term (Inf: prior-determined)",
        "sd_comb": "standard deviation s / s_i of the estimable combination v_i^T x for i < rank, Inf beyond",
        "prior_determined": "per term, True where it has a null-space component: the data do not determine it"},
    "RlsEpoch": {
        "action": "what the update did (a name of ACTIONS)",
        "flags": "per row, flag bits (FLAG_INNOVATION 1, FLAG_JUMP 2, FLAG_MISSING 4, "
                 "FLAG_UNUSED 8)"},
    "RlsResult": {
        "x": "(epochs, m): the estimate after each epoch",
        "gamma": "(m, m): the final Gamma",
        "covariance": "(m, m): the honest covariance of x (Joseph form with the gain used)",
        "sd": "(m,): square roots of its diagonal (None with covariance)",
        "q": "Q_p, the a-posteriori whitened residual sum of squares (METHODS 2.6)",
        "flags": "(epochs, k) per-row flag bits",
        "actions": "(epochs,) action codes (ACTIONS)",
        "residual": "(epochs, k): compensated telemetry y - c x after each epoch",
        "variant": "the RLS variant run",
        "p": "the order p of polynomial RLS (iterations of iterated RLS)",
        "counts": "dict of counts: updates, anomalous, rows (summed into Q_p), ..."},
    "Flight": {
        "S": "(3M, N) raw environment functions (SI units)",
        "dw": "(3M,) velocity differences, m/s",
        "sigma": "(3M,) stated tracking 1-sigma, m/s",
        "spec": "(N,) 1-sigma specs",
        "x_true": "(N,) the true X in spec units",
        "terms": "the N term names",
        "epochs": "(M,) epoch times, s"},
    "MonteCarloPool": {
        "size": "flights per group; a last group of fewer is left out",
        "pools": "groups judged",
        "failed": "groups whose pooled verdict is \"out of spec\"",
        "rate": "failed / pools (NaN without a group)",
        "ci99": "its 99 % Wilson interval (NaN, NaN without a group)",
        "ci99_cp": "its exact 99 % Clopper-Pearson interval (NaN, NaN without a group)",
        "mean_size": "the overall size of the verdict rule for the pooled components, mean "
                     "over the groups with a testable flight (0: not computed; NaN without a "
                     "group)"},
    "MonteCarloResult": {
        "chi2_reject": "flights whose chi-square test rejects",
        "any_reject": "flights with a rejected component",
        "not_testable": "flights with no component precise enough to be tested",
        "mean_scale": "mean final c (sigma_w^2 estimate)",
        "mean_tested": "mean number of components tested",
        "comp_tested": "per component, flights in which it was tested",
        "comp_reject": "per component, flights in which it was rejected",
        "chi2": "per flight, T",
        "dof": "per flight, the dof of T",
        "n_reject": "per flight, the rejected components",
        "scale": "per flight, c (NaN for a flight with nothing testable)",
        "rates": "{\"failed\": count / flights, ...} of the four counts",
        "ci99": "{\"failed\": (lo, hi), ...}: their 99 % Wilson intervals",
        "ci99_cp": "{\"failed\": (lo, hi), ...}: their exact 99 % Clopper-Pearson intervals",
        "pool": "with pool=F: the pooled verdicts of groups of F flights (MonteCarloPool)",
        "verdict": "the overall verdict rule counted in failed",
        "mean_size": "its overall size, mean over the testable flights",
        "scale_covered": "judged with the noise model: flights whose group scales are "
                         "within 3 standard errors of the truth",
        "mean_outliers": "mean rows rejected by the robust route",
        "sigma_covered": "judged with the noise model: flights whose every sigma_w,g-hat is "
                         "within 3 REML standard errors of the truth (log scale)",
        "zmax": "per flight, the largest |z| of its tested components (0 for a flight with "
                "nothing testable): what the pooled verdicts read"},
    "Block3Sigma": {
        "three_sigma": "3 sigma of the block means",
        "sigma": "standard deviation of the block means",
        "nblock": "blocks",
        "block_samples": "samples per block",
        "seconds": "the block length used, round(block fs) / fs (s)",
        "mean": "mean of the record",
        "adev": "Allan deviation at the block length from the block means"},
    "NoiseTerms": {
        "random_walk": "N: sigma at 1 s of the -1/2 line (NaN: not identified)",
        "random_walk_tau": "tau at which N was read, s",
        "bias_instability": "B: min sigma / 0.6643",
        "bias_instability_tau": "tau of that minimum, s",
        "rate_random_walk": "K: sigma at 3 s of the +1/2 line",
        "rate_random_walk_tau": "tau at which K was read, s",
        "quantization": "Q: sigma at sqrt 3 s of the -1 line",
        "quantization_tau": "tau at which Q was read, s"},
    "StabilityResult": {
        "data_type": "phase or frequency data",
        "lo": "lower confidence limit at each tau (None for mtie and tierms)",
        "hi": "upper confidence limit at each tau (None as lo)",
        "edf": "equivalent degrees of freedom at each tau (None as lo)",
        "alpha": "the noise exponent used at each tau"},
    "NoiseFit": {
        "terms": "the IEEE Std 952 terms Q, N, B, K, R",
        "value": "fitted value of each term (units of the data times s, sqrt(s), 1, "
                 "1/sqrt(s), 1/s)",
        "chi2": "chi-square of the fit",
        "boot": "bootstrap records behind se, lo, hi (0: se from the fit's weights, the "
                "points taken as independent)",
        "lo": "lower bootstrap confidence limit of each term (None without the bootstrap)",
        "hi": "upper bootstrap confidence limit of each term (inf: unbounded; None as lo)",
        "conf": "confidence level of lo and hi (NaN without the bootstrap)"},
    "TriadResult": {
        "theta": "(9,) the calibration parameters in the order of NAMES",
        "covariance": "(9, 9) their covariance",
        "sd": "(9,) their standard deviations",
        "k": "the threshold multiple used",
        "threshold": "the static-interval threshold",
        "intervals": "number of static intervals",
        "rms_before": "RMS of |a| - g at the start values",
        "rms_after": "RMS of |a| - g after the fit",
        "sigma": "sqrt(sum r^2 / (n - 9))",
        "iterations": "iterations run",
        "misfit": "sigma over the sd the noise of the first static period predicts (about 1; "
                  "NaN from triad_fit)",
        "static_intervals": "[(start, end)] sample ranges of the static intervals, from 0",
        "gyro": "the gyro's GyroResult (triad_calibrate with gyro=; else None)"},
    "GyroResult": {
        "theta": "(12,) the gyro parameters in the order of GYRO_NAMES",
        "covariance": "(12, 12) their covariance",
        "sd": "(12,) their standard deviations",
        "pairs": "number of rotations fitted (static intervals - 1)",
        "rms_before": "RMS of |v_{k+1} - R_k^T v_k| (rad) at K = I, M = I",
        "rms_after": "the same after the fit",
        "sigma": "sqrt(sum r^2 / (2 pairs - 9)) (rad)",
        "iterations": "iterations run",
        "static_samples": "samples the biases are the mean of",
        "noise": "(3,) pooled within-interval sd per axis (raw units)",
        "misfit": "sigma over the sd the gyro noise of the first interval predicts (about 1)",
        "lat": "the latitude (deg) the Earth's rate was modelled at (None: not modelled)",
        "earth_rate": "the Earth's rate used, in the gyro's unit (None without lat)",
        "earth_h": "the horizontal Earth rate the static intervals show (about W cos lat)",
        "earth_h_sd": "its standard deviation",
        "heading": "heading of the calibrated x axis in the first static interval, deg from "
                   "north towards east",
        "heading_sd": "its standard deviation, deg"},
}


def _field_docs(cls):
    """The "Fields" section of cls's docstring, or "" when no field is known."""
    own = CLASS.get(cls.__name__, {})
    lines = []
    for f in dataclasses.fields(cls):
        text = own.get(f.name, SHARED.get(f.name))
        if text:
            lines.append("    %s: %s" % (f.name, text))
    return "\n\nFields:\n" + "\n".join(lines) \
        if lines else ""


def _document(cls):
    doc = (cls.__doc__ or "").rstrip()
    if doc.startswith(cls.__name__ + "("):     # the signature @dataclass writes
        doc = ""
    cls.__doc__ = (doc or "Result %s." % cls.__name__) + _field_docs(cls)
    fn = cls.__dict__.get("summary")
    if fn is not None and not fn.__doc__:
        fn.__doc__ = "A readable report of this %s: several lines of text." % cls.__name__


# ---------------------------------------------------------------------------
# r.plot(ax=None): matplotlib pictures of the results that have one (the
# pictures the driver draws with --plot). matplotlib is an optional extra.

def _pyplot():
    try:
        import matplotlib.pyplot as plt
    except ImportError as e:
        raise ImportError("plot() needs matplotlib, which is not installed: pip install "
                          "matplotlib (or the extra: pip install 'igea[plots]'); to_dict() "
                          "gives the numbers without it") from e
    return plt


def _plot_eqerr(r, ax):
    """Residual curves per axis against the epoch (seed 000 Fig. 1)."""
    res = np.asarray(r.residual).reshape(-1, 3)
    for a in range(3):
        ax.plot(np.arange(res.shape[0]), res[:, a], label="xyz"[a])
    ax.set_xlabel("epoch")
    ax.set_ylabel("residual dw - S x (units of dw)")
    ax.set_title("eqerr: %s, T = %.4g (dof %d), c = %.4g"
                 % ("passed" if r.passed else "out of spec", r.chi2, r.dof, r.scale))
    ax.legend()


def _plot_deviation(r, ax):
    """The deviation against tau, log-log, with its confidence interval."""
    taus, dev = np.asarray(r.taus, float), np.asarray(r.dev, float)
    if r.lo is not None and r.hi is not None:
        lo, hi = np.asarray(r.lo, float), np.asarray(r.hi, float)
        ax.errorbar(taus, dev, yerr=[dev - lo, hi - dev], fmt="o-", capsize=2,
                    label="%s (%g %% interval)" % (r.kind, 100 * r.conf))
    else:
        ax.plot(taus, dev, "o-", label=r.kind)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("tau (s)")
    ax.set_ylabel("%s deviation (units of the data)" % r.kind)
    ax.legend()


def _plot_montecarlo(r, ax):
    """The rejection rate of each component over the flights that tested
    it, with its 99 % Wilson interval (igea_sim_interval), and the level
    alpha (as igea montecarlo --plot); a component never tested is left out."""
    from . import _lib
    ct, cr = np.asarray(r.comp_tested), np.asarray(r.comp_reject)
    idx = np.flatnonzero(ct > 0)
    rate = cr[idx] / ct[idx]
    lohi = np.zeros((idx.size, 2))
    for k, j in enumerate(idx):
        _lib.call("plot", "igea_sim_interval", float(cr[j]), float(ct[j]), _lib.dptr(lohi[k]))
    ax.errorbar(idx, rate, yerr=[rate - lohi[:, 0], lohi[:, 1] - rate], fmt="o", capsize=2,
                label="rate, 99 % Wilson interval")
    alpha = getattr(r, "_alpha", None)
    if alpha is not None:
        ax.axhline(alpha, linestyle="--", color="C3", label="alpha = %g" % alpha)
    ax.set_xlim(-0.5, ct.size - 0.5)
    ax.set_xlabel("component i (from 0)")
    ax.set_ylabel("rejection rate (fraction of the flights testing it)")
    ax.set_title("per-component rejection rates, %d flights" % r.flights)
    ax.legend()


# The units of the nav picture, as igea nav --plot chooses them (src/cli/svg.c):
# tick labels below 1e4 (and velocities above 1e-2 where mm/s exists).
_ARCSEC = 206264.80624709636


def _time_unit(tend):
    """The factor from s and the axis label for a run ending at tend (s)."""
    if tend >= 3 * 3600.0:
        return 1 / 3600.0, "time (h)"
    if tend >= 600:
        return 1 / 60.0, "time (min)"
    return 1.0, "time (s)"


def _nav_unit(q, big):
    """The factor from SI and the axis label of panel q (0 position, 1
    velocity, 2 attitude) for errors up to big (SI)."""
    if q == 0:
        return (1.0, "position error (m)") if big < 1e4 else (1e-3, "position error (km)")
    if q == 1:
        return (1e3, "velocity error (mm/s)") if big < 1e-2 else (1.0, "velocity error (m/s)")
    if big * _ARCSEC < 1e4:
        return _ARCSEC, "attitude error phi (arcsec)"
    return 180 / math.pi, "attitude error phi (deg)"


_NAV_COLORS = ("C0", "C3", "C2")      # the driver's palette: blue, red, green
_NAV_BAND = "shaded: \u00b11\u03c3 of the sensor noise"


def _panels(ax, n):
    """The n Axes to draw on: ax a sequence of n Axes, or one Axes (the
    first panel only)."""
    if hasattr(ax, "plot"):
        return [ax] + [None] * (n - 1)
    axes = list(np.ravel(np.asarray(ax, dtype=object)))
    if len(axes) != n:
        raise ValueError("plot: ax: one Axes or a sequence of %d, got %d" % (n, len(axes)))
    return axes


def _headroom(ax, frac):
    """Room above the data for a legend row: the top frac of the panel."""
    lo, hi = ax.get_ylim()
    ax.set_ylim(lo, lo + (hi - lo) / (1 - frac))


def _plot_nav(r, ax):
    """The position, velocity and attitude errors against time, one panel
    each (north east down, or launch-inertial x y z), with the +-1 sigma
    band of each where the covariance was computed (as igea nav --plot)."""
    li = type(r).__name__ == "NavErrorsLI"
    names = ("x", "y", "z") if li else ("north", "east", "down")
    what = ("along the trajectory, launch-inertial axes" if li
            else "latitude %g deg, north east down" % r.lat)
    t = np.asarray(r.time, float)
    tf, tlabel = _time_unit(t[-1] if t.size else 0.0)
    sd = None
    if r.covariance is not None:
        cov = np.asarray(r.covariance, float)
        sd = np.sqrt(np.maximum(np.diagonal(cov, axis1=1, axis2=2)[:, :9], 0))
    keys = ("position", "velocity", "attitude")
    for q, a in enumerate(_panels(ax, 3)):
        if a is None:
            continue
        e = np.asarray(getattr(r, keys[q]), float)
        s = sd[:, 3 * q:3 * q + 3] if sd is not None else np.zeros_like(e)
        f, label = _nav_unit(q, float(np.max(np.abs(e) + s)) if e.size else 0.0)
        for k in range(3):
            if sd is not None:
                a.fill_between(t * tf, f * (e[:, k] - s[:, k]), f * (e[:, k] + s[:, k]),
                               color=_NAV_COLORS[k], alpha=0.25, linewidth=0)
            a.plot(t * tf, f * e[:, k], color=_NAV_COLORS[k], label=names[k])
        if sd is not None:   # the legend's entry for the three bands
            a.fill_between([], [], [], color="0.5", alpha=0.25, linewidth=0, label=_NAV_BAND)
        a.set_xlabel(tlabel)
        a.set_ylabel(label)
        a.set_title(keys[q] + " error" + (", " + what if q == 0 else
                                          ", launch-inertial axes" if li else ""))
        _headroom(a, 0.2)
        a.legend(loc="upper right", ncol=4, fontsize="small")


def _nav_figure(plt):
    return plt.subplots(3, 1, figsize=(7.2, 8.1), layout="constrained")[1]


def _patches():
    _pyplot()   # the ImportError that names the extra
    import matplotlib.patches
    return matplotlib.patches


_BARS = 15   # the terms drawn as bars; the rest summed (CLI_SVG_IMPACT_BARS)


def _cut(name):
    """A bar's label: at most 24 characters (21 and "...")."""
    return name if len(name) <= 24 else name[:21] + "..."


def _plot_budget(r, ax):
    """The miss budget (as igea impact --plot): the impact plane, crossrange
    right and downrange up, with the 1 and 3 sigma ellipses of the impact
    covariance and the CEP circle about the mean impact point; and each
    term's share of the covariance's trace as a bar split into its
    downrange and crossrange parts, largest first, the first 15 terms and
    the rest summed."""
    patches = _patches()
    plane, bars = _panels(ax, 2)
    C = np.asarray(r.covariance, float)
    a, c, b = C[1, 1], C[0, 0], 0.5 * (C[0, 1] + C[1, 0])   # x crossrange, y downrange
    h = math.hypot(0.5 * (a - c), b)
    l1, l2 = 0.5 * (a + c) + h, max(0.5 * (a + c) - h, 0.0)
    ang = 0.5 * math.atan2(2 * b, a - c)
    hx = max(3 * math.sqrt(max(a, 0)), r.cep)
    hy = max(3 * math.sqrt(max(c, 0)), r.cep)
    if not (hx > 0 and hy > 0):
        hx = hy = max(hx, hy, 1.0)
    f = 1e-3 if max(hx, hy) >= 1e4 else 1.0
    unit = "km" if f < 1 else "m"
    if plane is not None:
        for k, color in ((1, "C0"), (3, "C2")):
            plane.add_patch(patches.Ellipse(
                (0, 0), 2 * k * f * math.sqrt(l1), 2 * k * f * math.sqrt(l2),
                angle=math.degrees(ang), fill=False, color=color, linewidth=1.5,
                label="%d\u03c3 ellipse (%.1f %%)" % (k, 100 * (1 - math.exp(-k * k / 2)))))
        plane.add_patch(patches.Circle((0, 0), f * r.cep, fill=False, color="C3", linewidth=1.5,
                                       linestyle="--", label="CEP %.4g m (50 %%)" % r.cep))
        plane.plot([0], [0], "k+")
        # at least as wide as high (equal scales): the legend fits above the data
        wx = max(1.05 * hx, 1.2 * hy)
        plane.set_xlim(-f * wx, f * wx)
        plane.set_ylim(-1.05 * f * hy, 1.35 * f * hy)
        plane.set_aspect("equal", adjustable="box")
        plane.set_xlabel("crossrange (%s, right of the flight)" % unit)
        plane.set_ylabel("downrange (%s)" % unit)
        plane.set_title("miss about the mean impact point")
        plane.legend(loc="upper center", ncol=2, fontsize="small")
    if bars is None:
        return
    share, miss = np.asarray(r.share, float), np.asarray(r.miss, float)
    n = share.size
    order = np.argsort(-share, kind="stable")
    m2 = np.sum(miss ** 2, axis=1)
    down = 100 * share * np.divide(miss[:, 0] ** 2, m2, out=np.zeros(n), where=m2 > 0)
    top = order[:_BARS]
    sh, dn = list(100 * share[top]), list(down[top])
    labels = [_cut(str(r.names[j])) for j in top]
    if n > _BARS:
        rest = order[_BARS:]
        sh.append(100 * share[rest].sum())
        dn.append(down[rest].sum())
        labels.append("the other %d terms" % rest.size)
    sh, dn = np.array(sh), np.array(dn)
    y = np.arange(sh.size)[::-1].astype(float)      # the largest at the top
    bars.barh(y, dn, height=0.7, color="C0", label="downrange part")
    bars.barh(y, sh - dn, left=dn, height=0.7, color="C3", label="crossrange part")
    for yi, v in zip(y, sh):
        bars.text(v, yi, " < 0.01 %" if 0 < v < 0.01 else " %.3g %%" % v, va="center",
                  fontsize="small")
    bars.set_yticks(y, labels)
    bars.set_ylim(sh.size - 0.5 - max(sh.size, 8) - 1.0, sh.size - 0.5)
    bars.set_xlim(0, 1.2 * max(float(sh.max()), 1e-300))
    bars.set_xlabel("share of the trace of the impact covariance (%)")
    bars.set_title("shares, largest first" + (": %d of %d terms and the rest" % (_BARS, n)
                                               if n > _BARS else ""))
    bars.legend(loc="lower right", ncol=2, fontsize="small")


def _budget_figure(plt):
    return plt.subplots(1, 2, figsize=(10.8, 5.0), layout="constrained",
                        gridspec_kw={"width_ratios": [1, 1.2]})[1]


PLOTS = {"EqerrResult": _plot_eqerr, "AllanResult": _plot_deviation,
         "StabilityResult": _plot_deviation, "MonteCarloResult": _plot_montecarlo,
         "NavErrors": _plot_nav, "NavErrorsLI": _plot_nav, "ImpactBudget": _plot_budget}

# ax=None: the axes of a new figure of several panels (one Axes otherwise)
_FIGURES = {"NavErrors": _nav_figure, "NavErrorsLI": _nav_figure,
            "ImpactBudget": _budget_figure}


def _plot(self, ax=None):
    """Draw this result with matplotlib on ax (a new figure's axes when
    None) and return ax. Raises ImportError naming the extra without
    matplotlib. A picture of several panels (NavErrors, NavErrorsLI: the
    position, velocity and attitude errors; ImpactBudget: the impact plane
    and the shares) takes a sequence of as many Axes, or one Axes for its
    first panel alone; with ax None it returns the new figure's array of
    Axes."""
    name = next(c.__name__ for c in type(self).__mro__ if c.__name__ in PLOTS)
    if ax is None:   # (a subclass, NoiseEqerrResult, draws as its base)
        make = _FIGURES.get(name)
        ax = make(_pyplot()) if make else _pyplot().subplots()[1]
    PLOTS[name](self, ax)
    return ax
