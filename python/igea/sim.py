"""Reproducible synthetic flights and the Monte Carlo check of the
equivalent-error test (igea/sim.h)."""
import ctypes
from dataclasses import dataclass

import numpy as np

from . import _capi, _frames, _lib
from .envfun import _system_code, default_terms, term_codes
from ._result import attach, result


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
    trajectory: the truth-model counterpart of S @ X (igea_envfun_nonlinear:
    every term of the catalogue)."""
    sc = _system_code(system)
    tr = _lib.as_f64(traj, "traj", ndim=2)
    if tr.shape[1] != _capi.ENVFUN_TRAJ_COLS:
        raise ValueError(f"traj: expected shape (*, {_capi.ENVFUN_TRAJ_COLS}), got {tr.shape}")
    if not isinstance(errors, dict):
        raise ValueError("errors: a dict {term name: value}")
    err = np.zeros(_lib.lib.igea_envfun_term_count())
    if errors:
        codes = term_codes(list(errors), system)
        err[codes] = [float(v) for v in errors.values()]
    ep = _lib.as_f64(epochs, "epochs", ndim=1)
    ax = None if axes is None else np.ascontiguousarray(axes, dtype=np.intc)
    if ax is not None and ax.shape != (6,):
        raise ValueError(f"axes: expected 6 ints, got shape {ax.shape}")
    out = np.zeros(3 * ep.size)
    _lib.call("igea.sim.nonlinear", "igea_envfun_nonlinear", sc, tr.shape[0], _lib.dptr(tr),
              tr.shape[0], err.size, _lib.dptr(err), _lib.iptr(ax), ep.size, _lib.dptr(ep),
              _lib.dptr(out))
    return out


class _Model:
    """An igea_sim_model handle: created by `create` (the handle its last
    argument), set with set(what, ...) = igea_sim_model_set_<what>, freed on
    leaving a with block."""

    def __init__(self, where, create, *args):
        self.where, self.h = where, ctypes.c_void_p()
        _lib.call(where, create, *args, ctypes.byref(self.h))

    def set(self, what, *args):
        _lib.call(self.where, "igea_sim_model_set_" + what, self.h, *args)

    def noise(self, generator, **slots):
        """The true noise: the library's defaults with the slots given."""
        generator = _lib.choice(_capi.CHOICE_SIM_GENERATOR, generator, self.where, "generator")
        opts = _lib.options("sim", self.where, ("igea_sim_model_set_noise", "opts"),
                            generator=generator, **slots)
        self.set("noise", _lib.dptr(opts))
        return opts

    def get(self, what, n):
        out = np.zeros(n)
        _lib.call(self.where, "igea_sim_model_get_" + what, self.h, _lib.dptr(out))
        return out

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        _lib.lib.igea_sim_model_free(self.h)


def _sigma(sigma, m):
    """(track_sigma, sigma_inc) of a number or (m,) values."""
    if np.ndim(sigma) == 0:
        return _lib.as_f64(sigma, "sigma").reshape(1), 0
    s = _lib.as_f64(sigma, "sigma", ndim=1, shape=(m,))
    return s, 1


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


@result
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
             sigma=0.01, sigma_growth=0.0, sigma_w=None, ar1=None, growth=None,
             outlier_prob=None, outlier_scale=None, x=None, seed=0, flight=0,
             generator="mt19937", nonlinear_truth=False, ar2=None, ar3=None, corr=None,
             group_split=None, sigma_w2=None, bias0=None, bias1=None):
    """One synthetic flight dw = S diag(spec) X + noise.

    traj: None (the reference boost, 120 s at 50 Hz) or (samples x 11);
    terms: names (default the 21-term strapdown model); epochs: default 1,
    2, ..., up to the trajectory's end; spec: "default" or N values;
    sigma: stated tracking 1-sigma (m/s, a number or one per row), grown by
    (1 + sigma_growth e/(M-1)) along the epochs; sigma_w, ar1, growth,
    outlier_prob, outlier_scale: the true noise (igea/sim.h; None: the
    library's default); x: None (X ~ N(0, I)), {name: k} (those terms at k x
    spec, the others drawn) or N values; seed, flight: the stream;
    nonlinear_truth: dw from the full nonlinear navigation error
    (igea.sim.nonlinear) instead of S diag(spec) X, with the same noise.
    The model is the library's (igea_sim_model_*).
    """
    if traj is None:
        traj = reference_trajectory(system=system)
    tr = _lib.as_f64(traj, "traj", ndim=2)
    terms = tuple(default_terms(system) if terms is None else terms)
    codes = term_codes(terms, system)
    if epochs is None:
        epochs = np.arange(1.0, np.floor(tr[-1, 0] - tr[0, 0]) + 1.0) + tr[0, 0]
    ep = _lib.as_f64(epochs, "epochs", ndim=1)
    n = tr.shape[0]
    with _Model("igea.simulate", "igea_sim_model_create_trajectory", _system_code(system), n,
                _lib.dptr(tr), n, len(codes), _lib.iptr(codes), None, ep.size,
                _lib.dptr(ep)) as model:
        m, N = 3 * ep.size, len(codes)
        sig, inc = _sigma(sigma, m)
        model.set("sigma", _lib.dptr(sig), inc, float(sigma_growth))
        if not isinstance(spec, str):
            model.set("spec", _lib.dptr(_lib.as_f64(spec, "spec", ndim=1, shape=(N,))))
        elif spec != "default":
            raise ValueError("spec: 'default' or an array")
        model.noise(generator, sigma_w=sigma_w, ar1=ar1, growth=growth,
                    outlier_prob=outlier_prob, outlier_scale=outlier_scale, ar2=ar2, ar3=ar3,
                    corr=corr, group_split=group_split, sigma_w2=sigma_w2, bias0=bias0,
                    bias1=bias1)
        xv, xf = _x_spec(x, terms, N)
        model.set("truth", _lib.dptr(xv), _lib.iptr(xf))
        model.set("nonlinear", int(bool(nonlinear_truth)))
        dw, xt = np.zeros(m), np.zeros(N)
        _lib.call("igea.simulate", "igea_sim_flight", model.h, int(seed), int(flight),
                  _lib.dptr(xt), _lib.dptr(dw))
        S = np.zeros((m, N), order="F")
        _lib.call("igea.simulate", "igea_sim_model_get_s", model.h, _lib.dptr(S), m)
        return Flight(S, dw, model.get("sigma", m), model.get("spec", N), xt, terms, ep)


@result
@dataclass(frozen=True)
class MonteCarloPool:
    """Pooled verdicts of consecutive groups of `size` flights (igea_sim_pool_ex,
    METHODS 1.2 step 6), each group judged by the run's verdict rule for its
    pooled components: the "pool" object of `igea montecarlo --pool --json`."""
    size: int            # flights per group; a last group of fewer is left out
    pools: int           # groups judged
    failed: int          # groups whose pooled verdict is "out of spec"
    rate: float          # failed / pools (NaN without a group)
    ci99: tuple          # its 99 % Wilson interval (NaN, NaN without a group)
    ci99_cp: tuple = None  # its exact 99 % Clopper-Pearson interval (NaN, NaN without one)
    mean_size: float = 0.0  # the pooled rule's overall size, mean over the groups with a
                            # testable flight (0: not computed; NaN without a group)


@result
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
    scale: np.ndarray    # NaN for a flight with nothing testable
    rates: dict = None   # {"failed": count / flights, ...} of the four counts
    ci99: dict = None    # {"failed": (lo, hi), ...}: their 99 % Wilson intervals
    pool: MonteCarloPool = None  # with pool=F: the pooled verdicts of groups of F flights
    verdict: str = "seed"  # the overall verdict rule counted in `failed`
    mean_size: float = 0.0  # its overall size, mean over the testable flights
    scale_covered: int = 0  # judged with the noise model: flights whose group scales are
                            # within 3 standard errors of the truth
    mean_outliers: float = 0.0  # mean rows rejected by the robust route
    ci99_cp: dict = None  # {"failed": (lo, hi), ...}: the exact 99 % Clopper-Pearson intervals
    sigma_covered: int = 0  # judged with the noise model: flights whose every sigma_w,g-hat
                            # is within 3 REML standard errors of the truth (log scale)
    zmax: np.ndarray = None  # per flight the largest |z_i| of its tested components (0 if
                             # none): what the pooled verdicts read

    _json_omit = ("rates", "ci99", "ci99_cp")  # in the driver's document, inside the counts

    def _json_extra(self):
        # 'igea montecarlo --json' writes each count with its rate and
        # interval, and the inputs of the run (None when not known)
        out = {k: {"count": getattr(self, k), "rate": (self.rates or {}).get(k),
                   "ci99": (self.ci99 or {}).get(k), "ci99_cp": (self.ci99_cp or {}).get(k)}
               for k in ("failed", "chi2_reject", "any_reject", "not_testable")}
        out.update({k: getattr(self, "_" + k, None)
                    for k in ("seed", "first_flight", "alpha", "correction", "sigma_w")})
        return out

    def rate(self, what="failed"):
        return self.rates[what]

    def summary(self):
        return ("%d flights: failed %d (%.4f), chi-square rejected %d (%.4f), a component "
                "rejected %d (%.4f), not testable %d; mean c %.4f, mean |I_t| %.2f"
                % (self.flights, self.failed, self.failed / self.flights, self.chi2_reject,
                   self.chi2_reject / self.flights, self.any_reject,
                   self.any_reject / self.flights, self.not_testable, self.mean_scale,
                   self.mean_tested))


def montecarlo(S, sigma, flights, *, spec=None, terms=None, x=None, sigma_w=None, ar1=None,
               growth=None, outlier_prob=None, outlier_scale=None, generator="mt19937",
               seed=0, first_flight=0, threads=0, alpha=None, lambda_test=None,
               correction=None, bias_correct=None, clamp=None, pool=None, verdict="seed", ar2=None,
               ar3=None, corr=None, group_split=None, sigma_w2=None, bias0=None, bias1=None,
               judge_noise=None, ar=None, ar_given=False, robust=None, robust_alpha=None,
               group_bias=None, progress=False, client=None, chunk=None, ar_method=None):
    """Run flights first_flight .. first_flight + flights - 1 and judge each
    with the seed-000 test; results do not depend on threads (0: one per
    online processor). The flights run in chunks of a tenth (at most 1000;
    the chunks depend on flights only): progress=True shows them on stderr
    (tqdm when installed, else a line per 10 % with the elapsed time and
    ETA), progress=f calls f(done, flights) after each chunk; the result is
    the same with or without progress. S may be a data frame: its columns
    are the terms (unless terms is given), sigma a Series on its index and
    spec one on its columns (igea/_frames.py). Options left None keep the library's defaults
    (igea_sim_defaults, igea_eqerr_defaults). pool=F (> 0; None or 0: no
    pooling) also pools consecutive groups of F flights, each judged by the
    verdict rule for its pooled components at the same alpha (igea_sim_pool_ex,
    as igea.pool): the result's `pool`. verdict: the overall verdict rule
    counted in `failed` and in the pools (as igea.eqerr's). Noise models (igea/sim.h
    IGEA_SIM_OPT_AR2 .. JUDGE_NOISE): ar2, ar3, corr, group_split, sigma_w2,
    bias0, bias1, judge_noise; the judge's (igea/noise.h): ar (phi
    estimated, or the true one with ar_given=True), ar_method ("reml", the
    default, or "ls": how phi is estimated), robust, robust_alpha,
    group_bias. client: a dask.distributed Client or a scheduler address:
    the flights run there in chunks of `chunk` flights (default 10000; see
    igea.campaign_montecarlo and docs/campaign.md), with the same result
    as this process running them with BLAS on one thread."""
    if client is not None:
        if progress is not False and progress is not None:
            raise ValueError("progress: not with client= (Dask shows its own: "
                             "distributed.progress)")
        kw = {k: v for k, v in locals().items() if k not in ("client", "chunk", "progress")}
        from .campaign import campaign_montecarlo
        kw["threads"] = kw["threads"] or 1  # one task per worker thread
        return campaign_montecarlo(client, 10000 if chunk is None else chunk, **kw)
    if chunk is not None:
        raise ValueError("chunk: flights per Dask task, only with client=")
    S, terms, v = _frames.inputs(S, terms, rows=(("sigma", sigma),), cols=(("spec", spec),))
    sigma, spec = v["sigma"], v["spec"]
    S = _lib.as_f64(S, "S", ndim=2)
    m, N = S.shape
    sig, inc = _sigma(sigma, m)
    sp = None if spec is None else _lib.as_f64(spec, "spec", ndim=1, shape=(N,))
    if isinstance(x, dict) and terms is None:
        raise ValueError("x: a dict needs terms")
    xv, xf = _x_spec(x, terms if terms is not None else [], N)
    nflights = int(flights)
    if nflights < 1:
        raise ValueError("flights: must be >= 1")
    where = "igea.montecarlo"
    eq = _lib.options("eqerr", where, ("igea_sim_montecarlo", "eq_opts"), alpha=alpha,
                      lambda_test=lambda_test, correction=correction, bias_correct=bias_correct,
                      clamp=clamp, overall_size=1,
                      verdict=_lib.choice(_capi.CHOICE_STATS_VERDICT, verdict, where, "verdict"),
                      **_judge_slots(ar, ar_given, robust, robust_alpha, group_bias,
                                     ar_method, where))
    counts, rates = np.zeros(_capi.SIM_MC_LEN), np.zeros(_capi.SIM_MC_RATES_LEN)
    ct, cr = np.zeros(N, dtype=np.intc), np.zeros(N, dtype=np.intc)
    table = np.zeros((nflights, _capi.SIM_MC_TABLE_COLS_Z), order="F")
    with _Model(where, "igea_sim_model_create", m, N, _lib.dptr(S), m) as model:
        model.set("sigma", _lib.dptr(sig), inc, 0.0)
        model.set("spec", _lib.dptr(sp))
        nopts = model.noise(generator, sigma_w=sigma_w, ar1=ar1, growth=growth,
                    outlier_prob=outlier_prob, outlier_scale=outlier_scale, ar2=ar2, ar3=ar3,
                    corr=corr, group_split=group_split, sigma_w2=sigma_w2, bias0=bias0,
                    bias1=bias1, judge_noise=None if judge_noise is None else int(bool(judge_noise)))
        model.set("truth", _lib.dptr(xv), _lib.iptr(xf))
        _mc_chunks(where, model.h, eq, int(seed), int(first_flight), nflights, int(threads),
                   counts, rates, ct, cr, table, _progress(progress, nflights))
    pooled = _pool(where, table, pool, eq) if pool else None
    col = _lib.fields(table.T, "SIM_MC_TABLE_", chi2=np.array, dof=np.array, n_reject=np.array,
                      scale=np.array, zmax=np.array)
    # rates[3 (k - 1)] and its interval at [+1], [+2] for the counts k (igea/sim.h)
    at = {k: 3 * (getattr(_capi, "SIM_MC_" + k.upper()) - 1)
          for k in ("failed", "chi2_reject", "any_reject", "not_testable")}
    return attach(MonteCarloResult(
        comp_tested=ct, comp_reject=cr, dof=col.pop("dof").astype(int),
        n_reject=col.pop("n_reject").astype(int), **col,
        rates={k: float(rates[i]) for k, i in at.items()},
        ci99={k: (float(rates[i + 1]), float(rates[i + 2])) for k, i in at.items()}, pool=pooled,
        ci99_cp={k: interval_cp(counts[getattr(_capi, "SIM_MC_" + k.upper())], nflights)
                 for k in at},
        verdict=verdict, mean_size=float(counts[_capi.SIM_MC_MEAN_SIZE]),
        **_lib.fields(counts, "SIM_MC_", flights=int, failed=int, chi2_reject=int,
                      any_reject=int, not_testable=int, mean_scale=float, mean_tested=float,
                      scale_covered=int, mean_outliers=float, sigma_covered=int)),
        seed=int(seed), first_flight=int(first_flight), alpha=eq[_capi.EQERR_OPT_ALPHA],
        correction=bool(eq[_capi.EQERR_OPT_CORRECTION]), sigma_w=nopts[_capi.SIM_OPT_SIGMA_W])


def _pool(where, table, size, eq):
    """The pooled verdicts of the table's groups of `size` flights by the
    rule of the eqerr options eq (igea_sim_pool_ex). A group larger than
    the flights judged is refused (it would leave no pool, a NaN rate), as the
    driver's --pool is."""
    n = table.shape[0]
    if int(size) > n:
        raise ValueError("%s: pool=%d pools more flights than the %d judged" % (where, int(size), n))
    out = np.zeros(_capi.SIM_POOL_LEN)
    _lib.call(where, "igea_sim_pool_ex", n, _lib.dptr(table), n, int(size), _lib.dptr(eq),
              _lib.dptr(out))
    f = _lib.fields(out, "SIM_POOL_", pools=int, failed=int, rate=float, ci99_lo=float,
                    ci99_hi=float, mean_size=float)
    cp = interval_cp(f["failed"], f["pools"]) if f["pools"] else (float("nan"),) * 2
    return MonteCarloPool(size=int(size), pools=f["pools"], failed=f["failed"], rate=f["rate"],
                          ci99=(f["ci99_lo"], f["ci99_hi"]), ci99_cp=cp,
                          mean_size=f["mean_size"])


def _mc_chunk(flights):
    """Flights per library call: a tenth, at most 1000 (as igea montecarlo)."""
    return min(1000, -(-flights // 10))


class _Lines:
    """The progress without tqdm: a line on stderr per 10 %."""

    def __init__(self, total):
        import time
        self.total, self.clock, self.t0, self.decile = total, time.monotonic, time.monotonic(), 0

    def __call__(self, done):
        import sys
        pct = 100 if done >= self.total else int(100 * done / self.total)
        if pct // 10 <= self.decile:
            return
        self.decile = pct // 10
        t = self.clock() - self.t0
        eta = "done" if done >= self.total else "ETA %.1f s" % (t * (self.total - done) / done)
        sys.stderr.write("igea.montecarlo: %3d %% (%d of %d flights), %.1f s elapsed, %s\n"
                         % (pct, done, self.total, t, eta))
        sys.stderr.flush()


def _progress(progress, total):
    """A function of the flights done (None: no progress)."""
    if progress is None or progress is False:
        return None
    if callable(progress):
        return lambda done: progress(done, total)
    if progress is not True:
        raise TypeError("progress: True, False or a function f(done, flights)")
    try:
        from tqdm import tqdm
    except ImportError:
        return _Lines(total)
    bar, last = tqdm(total=total, unit="flight", desc="igea.montecarlo"), [0]

    def update(done):
        bar.update(done - last[0])
        last[0] = done
        if done >= total:
            bar.close()
    return update


def _mc_chunks(where, h, eq, seed, first, nflights, threads, counts, rates, ct, cr, table,
               report):
    """igea_sim_montecarlo over the flights in chunks (_mc_chunk): the counts
    added, the means over the testable flights summed flight by flight from
    the table as the library does (mean_size from the chunks' means, to
    rounding: the library sums it flight by flight within a call), the
    rates and intervals of
    the totals."""
    N = ct.size
    c1, r1 = np.zeros(_capi.SIM_MC_LEN), np.zeros(_capi.SIM_MC_RATES_LEN)
    ct1, cr1 = np.zeros(N, dtype=np.intc), np.zeros(N, dtype=np.intc)
    chunk, size, outliers = _mc_chunk(nflights), 0.0, 0
    for done in range(0, nflights, chunk):
        n = min(chunk, nflights - done)
        _lib.call(where, "igea_sim_montecarlo_ex", h, _lib.dptr(eq), seed, first + done, n,
                  threads, _lib.dptr(c1), _lib.dptr(r1), _lib.iptr(ct1), _lib.iptr(cr1),
                  _lib.dptr(table[done:]), nflights, table.shape[1])
        for k in ("FLIGHTS", "FAILED", "CHI2_REJECT", "ANY_REJECT", "NOT_TESTABLE",
                  "SCALE_COVERED", "SIGMA_COVERED"):
            counts[getattr(_capi, "SIM_MC_" + k)] += c1[getattr(_capi, "SIM_MC_" + k)]
        outliers += int(round(c1[_capi.SIM_MC_MEAN_OUTLIERS] * n))
        size += ((c1[_capi.SIM_MC_FLIGHTS] - c1[_capi.SIM_MC_NOT_TESTABLE])
                 * c1[_capi.SIM_MC_MEAN_SIZE])
        ct += ct1
        cr += cr1
        if report:
            report(done + n)
    scale = table[:, _capi.SIM_MC_TABLE_SCALE]
    ok = np.isfinite(scale)
    nt = int(ok.sum())
    # np.cumsum adds in order, as the library's loop over the flights
    counts[_capi.SIM_MC_MEAN_SCALE] = np.cumsum(scale[ok])[-1] / nt if nt else np.nan
    counts[_capi.SIM_MC_MEAN_TESTED] = float(table[ok, _capi.SIM_MC_TABLE_DOF].sum()) / nt \
        if nt else 0.0
    counts[_capi.SIM_MC_MEAN_SIZE] = size / nt if nt else 0.0
    counts[_capi.SIM_MC_MEAN_OUTLIERS] = outliers / nflights
    for i, k in enumerate(("FAILED", "CHI2_REJECT", "ANY_REJECT", "NOT_TESTABLE")):
        c = counts[getattr(_capi, "SIM_MC_" + k)]
        rates[3 * i] = c / nflights
        _lib.call(where, "igea_sim_interval", float(c), float(nflights),
                  _lib.dptr(rates[3 * i + 1:]))


def interval_cp(k, n, level=0.99):
    """The exact (Clopper-Pearson) interval of k successes in n trials at
    confidence level (igea_sim_interval_cp): (lo, hi)."""
    out = np.zeros(2)
    _lib.call("igea.interval_cp", "igea_sim_interval_cp", float(k), float(n), float(level),
              _lib.dptr(out))
    return float(out[0]), float(out[1])


def _judge_slots(ar, ar_given, robust, robust_alpha, group_bias, ar_method=None,
                 where="igea.montecarlo"):
    """The eqerr option slots of the noise judge (igea/noise.h)."""
    out = dict(robust=None if robust is None else int(bool(robust)), robust_alpha=robust_alpha,
               group_bias=None if group_bias is None else int(bool(group_bias)))
    if ar:
        out.update(ar=int(ar), ar_estimate=0 if ar_given else 1)
    if ar_method is not None:
        if not ar or ar_given:
            raise ValueError("ar_method: %r estimates phi: it needs ar=p (not ar_given)"
                             % (ar_method,))
        out["ar_method"] = _lib.choice(_capi.CHOICE_NOISE_AR_METHOD, ar_method, where,
                                       "ar_method")
    return out


# ---- raw range records of a simulated flight (igea_sim_raw) ----------------

@result
@dataclass(frozen=True)
class RawFlight:
    """The raw records of a simulated flight: what `igea simulate --raw`
    writes (telemetry.txt, tracking.txt, dw_args.txt) and its Flight."""
    telemetry: np.ndarray  # (samples, 7 or 4) t dvx dvy dvz [dthx dthy dthz]
    tracking: np.ndarray   # (epochs, 8) t x y z vx vy vz sigma (m, m/s, in frame)
    lat: float             # the stated launch point, degrees (with pos0 errors)
    lon: float
    height: float          # m
    azimuth: float         # degrees
    q0: np.ndarray         # (4,) stated attitude body -> LI at lift-off
    frame: str
    system: str
    flight: Flight         # the simulator's own S, dw, sigma, spec, x_true

    def dw_kwargs(self):
        """The keywords of igea.dw for these records."""
        return dict(lat=self.lat, lon=self.lon, height=self.height, azimuth=self.azimuth,
                    frame=self.frame, system=self.system, q0=self.q0)


def simulate_raw(traj=None, terms=None, epochs=None, *, system="strapdown", lat=40.96,
                 lon=100.29, height=1000.0, azimuth=30.0, frame="ecef", noise=True,
                 trk_err=None, acc=None, **flight_kw):
    """The raw telemetry and tracking records of the flight that
    igea.simulate(traj, terms, epochs, system=system, **flight_kw) makes
    (same seed and flight: the same true X and the same tracking noise),
    launched from lat, lon (degrees), height (m) at azimuth (degrees), the
    tracking in frame "ecef" or "le"; noise=False leaves the noise out.
    The sigma column is the stated 1-sigma of the epoch's x row (the three
    rows of an epoch have the same stated sigma unless a per-row sigma is
    given). igea_sim_raw, docs/pipeline.md section 8.
    trk_err: (epochs, 6) the tracking's own errors dx dy dz dvx dvy dvz (m,
    m/s, in frame) instead of the simulator's noise; acc: (epochs, k) the
    accuracy columns written after t x y z vx vy vz instead of the sigma
    column, k = 1, 3, 6 (the velocity covariance c_xx c_xy c_xz c_yy c_yz
    c_zz) or 21 (the 6 x 6 position-velocity covariance, upper triangle
    row by row), as igea.dw reads them (igea_sim_raw_track)."""
    if traj is None:
        traj = reference_trajectory(system=system)
    tr = _lib.as_f64(traj, "traj", ndim=2)
    fl = simulate(tr, terms, epochs, system=system, **flight_kw)
    m = fl.dw.size
    nz = None
    if noise:
        kw = dict(flight_kw, x=np.zeros(len(fl.terms)), nonlinear_truth=False)
        nz = np.ascontiguousarray(simulate(tr, fl.terms, fl.epochs, system=system, **kw).dw)
    sc = _system_code(system)
    fc = _lib.choice(_capi.CHOICE_DW_FRAME, frame, "igea.simulate_raw", "frame")
    err = np.zeros(_lib.lib.igea_envfun_term_count())
    err[term_codes(list(fl.terms), system)] = fl.x_true * fl.spec
    from .nav import nav_site
    site = nav_site(np.radians(lat), np.radians(lon), height, np.radians(azimuth))
    ns, ne = tr.shape[0], m // 3
    cols = _capi.SIM_RAW_TEL_STRAPDOWN if sc == _capi.ENVFUN_STRAPDOWN else _capi.SIM_RAW_TEL_PLATFORM
    tel = np.zeros((ns, cols), order="F")
    trk = np.zeros((ne, _capi.SIM_RAW_TRK_COLS), order="F")
    q0, so = np.zeros(4), np.zeros(_capi.NAV_SITE_LEN)
    ep = np.ascontiguousarray(fl.epochs, dtype=float)
    if trk_err is None and acc is None:
        _lib.call("igea.simulate_raw", "igea_sim_raw", sc, ns, _lib.dptr(tr), ns, err.size,
                  _lib.dptr(err), None, _lib.dptr(site), fc, ne, _lib.dptr(ep), _lib.dptr(nz),
                  _lib.dptr(tel), ns, _lib.dptr(trk), ne, _lib.dptr(q0), _lib.dptr(so))
        track = np.column_stack([trk, fl.sigma[0::3]])
    else:
        te = None if trk_err is None else np.ascontiguousarray(
            _lib.as_f64(trk_err, "trk_err", ndim=2, shape=(ne, 6)))
        ac = None if acc is None else np.ascontiguousarray(_lib.as_f64(acc, "acc", ndim=2))
        k = 0 if ac is None else ac.shape[1]
        if ac is not None and ac.shape[0] != ne:
            raise ValueError(f"acc: expected {ne} rows (one per epoch), got {ac.shape[0]}")
        track = np.zeros((ne, _capi.SIM_RAW_TRK_COLS + k), order="F")
        _lib.call("igea.simulate_raw", "igea_sim_raw_track", sc, ns, _lib.dptr(tr), ns, err.size,
                  _lib.dptr(err), None, _lib.dptr(site), fc, ne, _lib.dptr(ep), _lib.dptr(te), k,
                  _lib.dptr(ac), _lib.dptr(tel), ns, _lib.dptr(track), ne, _lib.dptr(q0),
                  _lib.dptr(so))
        track = np.ascontiguousarray(track)
    return RawFlight(telemetry=tel, tracking=track, lat=float(np.degrees(so[0])),
                     lon=float(np.degrees(so[1])), height=float(so[2]),
                     azimuth=float(np.degrees(so[3])), q0=q0, frame=frame, system=system,
                     flight=fl)


def track_errors(sigma_v, sigma_r, *, corr=0.0, cross=0.0, seed=0, flight=0):
    """A tracking error model for simulate_raw(trk_err=, acc=): per epoch the
    6 x 6 covariance of the position and velocity errors (x y z vx vy vz,
    tracking axes) [[s_r^2 R, c s_r s_v R], [c s_r s_v R, s_v^2 R]], R =
    [[1 r r^2], [r 1 r], [r^2 r 1]] (r = corr, c = cross: simulate --raw's
    --track-corr, --track-cross), and one draw of them
    (igea_sim_track_errors; the generator of (seed, flight)).
    sigma_v: (epochs,) velocity 1-sigma per axis (m/s); sigma_r: position
    1-sigma (m). Returns (acc (epochs, 21) the upper triangles row by row,
    err (epochs, 6))."""
    sv = np.ascontiguousarray(_lib.as_f64(sigma_v, "sigma_v", ndim=1))
    ne = sv.size
    if ne < 1:
        raise ValueError("sigma_v: empty")
    acc, err = np.zeros((ne, 21)), np.zeros((ne, 6))
    _lib.call("igea.track_errors", "igea_sim_track_errors", ne, _lib.dptr(sv), float(sigma_r),
              float(corr), float(cross), int(seed), int(flight), _lib.dptr(acc), _lib.dptr(err))
    return acc, err
