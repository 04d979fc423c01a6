"""Reproducible synthetic flights and the Monte Carlo check of the
equivalent-error test (igea/sim.h)."""
import ctypes
from dataclasses import dataclass

import numpy as np

from . import _capi, _lib
from .envfun import _system_code, default_spec, default_terms, envfun, term_codes

_GENERATORS = _lib.choices("SIM_", "mt19937 ranlxd2")

def reference_trajectory(duration=120.0, rate=50.0, *, system="strapdown"):
    """The reference boost trajectory (samples x 11), METHODS 5.6."""
    sc = _system_code(system)
    n = _lib.c_int(0)
    _lib.call("igea.reference_trajectory", "igea_sim_trajectory_length", float(duration),
              float(rate), _lib.ctypes.byref(n))
    tr = np.zeros((n.value, _capi.ENVFUN_TRAJ_COLS), order="F")
    _lib.call("igea.reference_trajectory", "igea_sim_trajectory", sc, float(duration), float(rate),
              n.value, _lib.dptr(tr), n.value)
    return tr


def nonlinear(traj, errors, epochs, *, system="strapdown", axes=None):
    """Velocity error (3 len(epochs),) of a full nonlinear navigation with the
    instrument errors `errors` ({term name: value in SI units}) on the
    trajectory: the truth-model counterpart of S @ X (igea_sim_nonlinear)."""
    sc = _system_code(system)
    tr = _lib.as_f64(traj, "traj", ndim=2)
    if tr.shape[1] != _capi.ENVFUN_TRAJ_COLS:
        raise ValueError(f"traj: expected shape (*, {_capi.ENVFUN_TRAJ_COLS}), got {tr.shape}")
    if not isinstance(errors, dict):
        raise ValueError("errors: a dict {term name: value}")
    err = np.zeros(_capi.ENVFUN_TERM_COUNT)
    if errors:
        codes = term_codes(list(errors), system)
        err[codes] = [float(v) for v in errors.values()]
    ep = _lib.as_f64(epochs, "epochs", ndim=1)
    ax = None if axes is None else np.ascontiguousarray(axes, dtype=np.intc)
    if ax is not None and ax.shape != (6,):
        raise ValueError(f"axes: expected 6 ints, got shape {ax.shape}")
    out = np.zeros(3 * ep.size)
    _lib.call("igea.sim.nonlinear", "igea_sim_nonlinear", sc, tr.shape[0], _lib.dptr(tr),
              tr.shape[0], _lib.dptr(err), _lib.iptr(ax), ep.size, _lib.dptr(ep), _lib.dptr(out))
    return out


def _sim_opts(where, at, generator, **slots):
    if generator not in _GENERATORS:
        raise ValueError(f"generator: one of {sorted(_GENERATORS)}, got {generator!r}")
    return _lib.options("sim", where, at, generator=_GENERATORS[generator], **slots)


def _sigma(sigma, m):
    if np.ndim(sigma) == 0:
        return _lib.as_f64(sigma, "sigma").reshape(1), 0
    s = _lib.as_f64(sigma, "sigma", ndim=1, shape=(m,))
    return s, 1


def _model(where, create, *args, sigma, sigma_inc, growth=0.0, spec=None, xv=None, xf=None,
           opts=None, nonlinear=False):
    """An igea_sim_model handle (create: the constructor, args: its
    arguments before the handle) with these settings; free it with
    _lib.lib.igea_sim_model_free."""
    h = ctypes.c_void_p()
    _lib.call(where, create, *args, ctypes.byref(h))
    try:
        _lib.call(where, "igea_sim_model_set_sigma", h, _lib.dptr(sigma), int(sigma_inc),
                  float(growth))
        if spec is not None:
            _lib.call(where, "igea_sim_model_set_spec", h, _lib.dptr(spec))
        _lib.call(where, "igea_sim_model_set_truth", h, _lib.dptr(xv), _lib.iptr(xf))
        _lib.call(where, "igea_sim_model_set_noise", h, _lib.dptr(opts))
        _lib.call(where, "igea_sim_model_set_nonlinear", h, int(bool(nonlinear)))
    except BaseException:
        _lib.lib.igea_sim_model_free(h)
        raise
    return h


def _x_spec(x, terms, N):
    """x: None (all N(0,1)), a dict name -> value (others drawn), or an
    array of N values (all fixed)."""
    if x is None:
        return None, None
    if isinstance(x, dict):
        val, fix = np.zeros(N), np.zeros(N, dtype=np.intc)
        for k, v in x.items():
            if k not in terms:
                raise ValueError(f"x: {k!r} is not one of the terms")
            i = list(terms).index(k)
            val[i], fix[i] = float(v), 1
        return val, fix
    val = _lib.as_f64(x, "x", ndim=1, shape=(N,))
    return val, np.ones(N, dtype=np.intc)


@dataclass(frozen=True)
class Flight:
    """A synthetic flight: what `igea simulate` writes."""
    S: np.ndarray        # (3M, N) raw environment functions (SI units)
    dw: np.ndarray       # (3M,) velocity differences
    sigma: np.ndarray    # (3M,) stated tracking 1-sigma
    spec: np.ndarray     # (N,) 1-sigma specs
    x_true: np.ndarray   # (N,) the true X in spec units
    terms: tuple
    epochs: np.ndarray

    def summary(self):
        return ("flight: %d epochs x 3 axes, %d terms; |x_true| max %.3f; dw rms %.4g m/s"
                % (len(self.epochs), len(self.terms), np.max(np.abs(self.x_true)),
                   float(np.sqrt(np.mean(self.dw ** 2)))))


def simulate(traj=None, terms=None, epochs=None, *, system="strapdown", spec="default",
             sigma=0.01, sigma_growth=0.0, sigma_w=1.0, ar1=0.0, growth=0.0,
             outlier_prob=0.0, outlier_scale=10.0, x=None, seed=0, flight=0,
             generator="mt19937", nonlinear_truth=False):
    """One synthetic flight dw = S diag(spec) X + noise.

    traj: None (the reference boost, 120 s at 50 Hz) or (samples x 11);
    terms: names (default the 21-term strapdown model); epochs: default 1,
    2, ..., up to the trajectory's end; spec: "default" or N values;
    sigma: stated tracking 1-sigma (m/s), grown by (1 + sigma_growth e/(M-1))
    along the epochs; sigma_w, ar1, growth, outlier_prob, outlier_scale: the
    true noise (igea/sim.h); x: None (X ~ N(0, I)), {name: k} (those terms
    at k x spec, the others drawn) or N values; seed, flight: the stream;
    nonlinear_truth: dw from the full nonlinear navigation error
    (igea.sim.nonlinear) instead of S diag(spec) X, with the same noise.
    """
    if traj is None:
        traj = reference_trajectory(system=system)
    tr = _lib.as_f64(traj, "traj", ndim=2)
    terms = tuple(default_terms(system) if terms is None else terms)
    if epochs is None:
        epochs = np.arange(1.0, np.floor(tr[-1, 0] - tr[0, 0]) + 1.0) + tr[0, 0]
    ep = _lib.as_f64(epochs, "epochs", ndim=1)
    if isinstance(spec, str):
        if spec != "default":
            raise ValueError("spec: 'default' or an array")
        sp = default_spec(terms, system)
    else:
        sp = _lib.as_f64(spec, "spec", ndim=1, shape=(len(terms),))
    codes = term_codes(terms, system)
    m, N = 3 * ep.size, len(codes)
    sig0 = float(sigma)
    if not sig0 > 0:
        raise ValueError("sigma: must be > 0")
    xv, xf = _x_spec(x, terms, N)
    opts = _sim_opts("igea.simulate", ("igea_sim_model_set_noise", "opts"), generator,
                     sigma_w=sigma_w, ar1=ar1, growth=growth, outlier_prob=outlier_prob,
                     outlier_scale=outlier_scale)
    n = tr.shape[0]
    h = _model("igea.simulate", "igea_sim_model_create_trajectory", _system_code(system), n,
               _lib.dptr(tr), n, N, _lib.iptr(codes), None, ep.size, _lib.dptr(ep),
               sigma=np.array([sig0]), sigma_inc=0, growth=sigma_growth, spec=sp, xv=xv, xf=xf,
               opts=opts, nonlinear=nonlinear_truth)
    try:
        S, sig, dw, xt = np.zeros((m, N), order="F"), np.zeros(m), np.zeros(m), np.zeros(N)
        _lib.call("igea.simulate", "igea_sim_flight", h, int(seed), int(flight), _lib.dptr(xt),
                  _lib.dptr(dw))
        _lib.call("igea.simulate", "igea_sim_model_get_s", h, _lib.dptr(S), m)
        _lib.call("igea.simulate", "igea_sim_model_get_sigma", h, _lib.dptr(sig))
    finally:
        _lib.lib.igea_sim_model_free(h)
    return Flight(S, dw, sig, sp, xt, terms, ep)


@dataclass(frozen=True)
class MonteCarloResult:
    """Rejection counts of many simulated flights (igea_sim_montecarlo)."""
    flights: int
    failed: int          # verdict "out of spec" (any component or chi-square)
    chi2_reject: int
    any_reject: int
    not_testable: int
    mean_scale: float    # mean final c (sigma_w^2 estimate)
    mean_tested: float
    comp_tested: np.ndarray
    comp_reject: np.ndarray
    chi2: np.ndarray
    dof: np.ndarray
    n_reject: np.ndarray
    scale: np.ndarray

    def rate(self, what="failed"):
        return getattr(self, what) / self.flights

    def summary(self):
        return ("%d flights: failed %d (%.4f), chi-square rejected %d (%.4f), a component "
                "rejected %d (%.4f), not testable %d; mean c %.4f, mean |I_t| %.2f"
                % (self.flights, self.failed, self.failed / self.flights, self.chi2_reject,
                   self.chi2_reject / self.flights, self.any_reject,
                   self.any_reject / self.flights, self.not_testable, self.mean_scale,
                   self.mean_tested))


def montecarlo(S, sigma, nflights, *, spec=None, terms=None, x=None, sigma_w=1.0, ar1=0.0,
               growth=0.0, outlier_prob=0.0, outlier_scale=10.0, generator="mt19937",
               seed=0, first_flight=0, nthreads=0, alpha=0.01, lambda_test=10.0,
               correct_tracking=True, bias_correct=False, clamp=False):
    """Run flights first_flight .. first_flight + nflights - 1 and judge each
    with the seed-000 test; results do not depend on nthreads."""
    S = _lib.as_f64(S, "S", ndim=2)
    m, N = S.shape
    sig, inc = _sigma(sigma, m)
    sp = None if spec is None else _lib.as_f64(spec, "spec", ndim=1, shape=(N,))
    if isinstance(x, dict) and terms is None:
        raise ValueError("x: a dict needs terms")
    xv, xf = _x_spec(x, terms if terms is not None else [], N)
    at = ("igea_sim_model_set_noise", "opts")
    opts = _sim_opts("igea.montecarlo", at, generator, sigma_w=sigma_w, ar1=ar1, growth=growth,
                     outlier_prob=outlier_prob, outlier_scale=outlier_scale)
    eq = _lib.options("eqerr", "igea.montecarlo", ("igea_sim_montecarlo", "eq_opts"),
                      alpha=alpha, lambda_test=lambda_test, correct=bool(correct_tracking),
                      bias_correct=bool(bias_correct), clamp=bool(clamp))
    nflights = int(nflights)
    if nflights < 1:
        raise ValueError("nflights: must be >= 1")
    counts = np.zeros(_capi.SIM_MC_LEN)
    ct, cr = np.zeros(N, dtype=np.intc), np.zeros(N, dtype=np.intc)
    table = np.zeros((nflights, _capi.SIM_MC_TABLE_COLS), order="F")
    h = _model("igea.montecarlo", "igea_sim_model_create", m, N, _lib.dptr(S), m,
               sigma=sig, sigma_inc=inc, spec=sp, xv=xv, xf=xf, opts=opts)
    try:
        _lib.call("igea.montecarlo", "igea_sim_montecarlo", h, _lib.dptr(eq), int(seed),
                  int(first_flight), nflights, int(nthreads), _lib.dptr(counts), None,
                  _lib.iptr(ct), _lib.iptr(cr), _lib.dptr(table), nflights)
    finally:
        _lib.lib.igea_sim_model_free(h)
    chi2, scale = table[:, _capi.SIM_MC_TABLE_CHI2].copy(), table[:, _capi.SIM_MC_TABLE_SCALE].copy()
    dof = table[:, _capi.SIM_MC_TABLE_DOF].astype(np.intc)
    nrej = table[:, _capi.SIM_MC_TABLE_N_REJECT].astype(np.intc)
    return MonteCarloResult(comp_tested=ct, comp_reject=cr, chi2=chi2, dof=dof, n_reject=nrej,
                            scale=scale, **_lib.fields(
                                counts, "SIM_MC_", flights=int, failed=int, chi2_reject=int,
                                any_reject=int, not_testable=int, mean_scale=float,
                                mean_tested=float))
