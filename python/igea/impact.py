"""The impact point of a ballistic free flight, the miss budget and the CEP
(include/igea/impact.h, docs/impact.md).

The burnout state is ECEF position (m) and velocity relative to the Earth
(m/s) at burnout; the impact point is ECEF at impact. Models "kepler"
(spherical Earth, closed form, exact Jacobian) and "j2" (integrated,
Jacobian by central differences)."""
import ctypes
from dataclasses import dataclass

import numpy as np

from . import _capi, _lib
from ._result import attach, result


@result
@dataclass(frozen=True)
class ImpactResult:
    """igea.impact: the impact and its sensitivity to the burnout state.

    point (3,), velocity (3,) ECEF at impact; time: time of flight (s);
    jacobian (7, 6): d(point, velocity, time) / d(burnout x y z vx vy vz);
    down, cross (3,): the miss axes at the impact point; miss_jacobian
    (2, 6): downrange and crossrange miss per unit of the burnout state."""
    model: str
    point: np.ndarray
    velocity: np.ndarray
    time: float
    jacobian: np.ndarray
    down: np.ndarray
    cross: np.ndarray
    miss_jacobian: np.ndarray

    def _json_extra(self):
        # 'igea impact --json' also writes the burnout state it started from
        return {"burnout": getattr(self, "_burnout", None)}

    def summary(self):
        g = self.miss_jacobian
        lines = ["impact (%s): time of flight %.3f s, point %.3f %.3f %.3f m"
                 % (self.model, self.time, *self.point),
                 "miss per unit burnout error    x         y         z        vx        vy        vz"]
        for name, row in (("downrange", g[0]), ("crossrange", g[1])):
            lines.append("%-28s" % name + "".join("%10.4g" % v for v in row))
        return "\n".join(lines)


def _opts(where, mu, radius, omega, j2, re, step, tmax):
    return _lib.options("impact", where, ("igea_impact_point", "opts"), mu=mu, radius=radius,
                        omega=omega, j2=j2, re=re, step=step, tmax=tmax)


def impact(burnout, *, model="kepler", mu=None, radius=None, omega=None, j2=None, re=None,
           step=None, tmax=None):
    """The impact of the free flight from burnout (6,): x y z vx vy vz in
    ECEF. Options left None keep the library's defaults (WGS-84 mu, J2, re,
    Earth rate; the impact sphere at the mean radius 6371008.8 m)."""
    where = "igea.impact"
    code = _lib.choice(_capi.CHOICE_IMPACT_MODEL, model, where, "model")
    s = np.ascontiguousarray(_lib.as_f64(burnout, "burnout", ndim=1, shape=(6,)))
    o = _opts(where, mu, radius, omega, j2, re, step, tmax)
    rf, vf, tf = np.zeros(3), np.zeros(3), ctypes.c_double()
    jac = np.zeros((_capi.IMPACT_JAC_ROWS, 6), order="F")
    _lib.call(where, "igea_impact_point", code, _lib.dptr(o), _lib.dptr(s[:3]),
              _lib.dptr(s[3:]), _lib.dptr(rf), _lib.dptr(vf), ctypes.byref(tf), _lib.dptr(jac),
              _capi.IMPACT_JAC_ROWS)
    down, cross = np.zeros(3), np.zeros(3)
    _lib.call(where, "igea_impact_axes", _lib.dptr(rf), _lib.dptr(vf), _lib.dptr(down),
              _lib.dptr(cross))
    G = np.zeros((2, 6), order="F")
    _lib.call(where, "igea_impact_miss_jacobian", _lib.dptr(jac), _capi.IMPACT_JAC_ROWS,
              _lib.dptr(rf), _lib.dptr(vf), _lib.dptr(G), 2)
    return attach(ImpactResult(model, rf, vf, tf.value, np.ascontiguousarray(jac), down, cross,
                               np.ascontiguousarray(G)), burnout=s.copy())


@result
@dataclass(frozen=True)
class ImpactBudget:
    """igea.impact_budget: the miss of each term (n, 2: downrange,
    crossrange), the impact covariance (2, 2), each term's share of its
    trace, and the CEP of that covariance (exact)."""
    names: list
    miss: np.ndarray
    covariance: np.ndarray
    share: np.ndarray
    cep: float

    def summary(self):
        lines = ["%-16s %12s %12s %8s" % ("term", "downrange", "crossrange", "share")]
        for j in np.argsort(-self.share):
            lines.append("%-16s %12.4g %12.4g %7.1f%%" % (self.names[j], self.miss[j, 0],
                                                          self.miss[j, 1], 100 * self.share[j]))
        lines.append("CEP %.4g m" % self.cep)
        return "\n".join(lines)


def impact_budget(miss_jacobian, E, names=None):
    """The error budget in miss distance: miss_jacobian (2, 6) of
    igea.impact, E (6, n) the burnout state error of each of n independent
    terms at 1 sigma (e.g. the position and velocity environment functions
    at burnout times the specs)."""
    where = "igea.impact_budget"
    G = _lib.as_f64(miss_jacobian, "miss_jacobian", ndim=2, shape=(2, 6))
    e = _lib.as_f64(E, "E", ndim=2, shape=(6, None))
    n = e.shape[1]
    if n < 1:
        raise ValueError("E: expected at least one term (column)")
    names = list(names) if names is not None else ["term_%d" % j for j in range(n)]
    if len(names) != n:
        raise ValueError(f"names: expected {n} names, got {len(names)}")
    miss, cov, share = np.zeros((n, 2)), np.zeros((2, 2), order="F"), np.zeros(n)
    _lib.call(where, "igea_impact_budget", n, _lib.dptr(G), 2, _lib.dptr(e), 6, _lib.dptr(miss),
              _lib.dptr(cov), _lib.dptr(share))
    return ImpactBudget(names, miss, np.ascontiguousarray(cov), share, cep(cov))


def _cov(cov):
    return _lib.as_f64(cov, "cov", ndim=2, shape=(2, 2))


def circle_prob(cov, radius, mean=None):
    """Probability that a normal 2-vector of covariance cov lies within
    radius of its mean (exact); with mean=(m1, m2), within radius of the
    origin (the aim point) when its mean is there (igea_impact_circle_prob_offset)."""
    p = ctypes.c_double()
    if mean is None:
        _lib.call("igea.circle_prob", "igea_impact_circle_prob", _lib.dptr(_cov(cov)),
                  float(radius), ctypes.byref(p))
    else:
        m = np.ascontiguousarray(_lib.as_f64(mean, "mean", ndim=1, shape=(2,)))
        _lib.call("igea.circle_prob", "igea_impact_circle_prob_offset", _lib.dptr(_cov(cov)),
                  _lib.dptr(m), float(radius), ctypes.byref(p))
    return p.value


def cep(cov, prob=0.5, mean=None):
    """The radius about the mean holding probability prob (0.5: the CEP);
    with mean=(m1, m2) the miss's mean offset, the radius about the origin
    (the aim point): the biased CEP (igea_impact_cep_offset)."""
    r = ctypes.c_double()
    if mean is None:
        _lib.call("igea.cep", "igea_impact_cep", _lib.dptr(_cov(cov)), float(prob),
                  ctypes.byref(r))
    else:
        m = np.ascontiguousarray(_lib.as_f64(mean, "mean", ndim=1, shape=(2,)))
        _lib.call("igea.cep", "igea_impact_cep_offset", _lib.dptr(_cov(cov)), _lib.dptr(m),
                  float(prob), ctypes.byref(r))
    return r.value


def cep_approx(cov, rule="sum"):
    """A usual approximation of the CEP: "sum" 0.5887 (sigma_1 + sigma_2) or
    "rms" 1.1774 sqrt((sigma_1^2 + sigma_2^2) / 2)."""
    code = _lib.choice(_capi.CHOICE_IMPACT_CEP, rule, "igea.cep_approx", "rule")
    r = ctypes.c_double()
    _lib.call("igea.cep_approx", "igea_impact_cep_approx", _lib.dptr(_cov(cov)), code,
              ctypes.byref(r))
    return r.value


def component_miss(miss_jacobian, E, directions, equiv_err):
    """The miss (n, 2: downrange, crossrange, m) that each equivalent-error
    component corresponds to: G E p_i x_i, with miss_jacobian G (2, 6) of
    igea.impact, E (6, N) the burnout state error (x y z vx vy vz, ECEF) per
    unit of each of S's N columns, directions (N, n) the components'
    eigenvectors and equiv_err (n,) their equivalent errors (as
    igea.eqerr's eigenvectors[:, :n] and equiv_err[:n]);
    igea_impact_component_miss."""
    where = "igea.component_miss"
    G = np.asfortranarray(_lib.as_f64(miss_jacobian, "miss_jacobian", ndim=2, shape=(2, 6)))
    e = np.asfortranarray(_lib.as_f64(E, "E", ndim=2, shape=(6, None)))
    N = e.shape[1]
    P = np.asfortranarray(_lib.as_f64(directions, "directions", ndim=2, shape=(N, None)))
    n = P.shape[1]
    x = np.ascontiguousarray(_lib.as_f64(equiv_err, "equiv_err", ndim=1, shape=(n,)))
    if N < 1 or n < 1:
        raise ValueError("E, directions: at least one term and one component")
    miss = np.zeros((n, 2))
    _lib.call(where, "igea_impact_component_miss", N, n, _lib.dptr(G), 2, _lib.dptr(e), 6,
              _lib.dptr(P), N, _lib.dptr(x), _lib.dptr(miss))
    return miss


@result
@dataclass(frozen=True)
class Burnout:
    """igea.burnout: the burnout state of a trajectory flown from its
    launch point and the burnout state error of each error term
    (igea_impact_burnout, docs/impact.md "From a burnout time")."""
    burnout_time: float
    burnout: np.ndarray
    terms: list
    burnout_errors: np.ndarray

    def summary(self):
        b = self.burnout
        lines = ["burnout at %g s (ECEF): %.3f %.3f %.3f m, %.4f %.4f %.4f m/s"
                 % (self.burnout_time, *b),
                 "%-16s" % "term" + "".join("%11s" % c for c in
                                            ("x", "y", "z", "vx", "vy", "vz"))]
        for j, name in enumerate(self.terms):
            lines.append("%-16s" % name + "".join("%11.4g" % v for v in self.burnout_errors[:, j]))
        return "\n".join(lines)


def _site(where, lat, lon, height, azimuth):
    if lat is None or lon is None or azimuth is None:
        raise ValueError(f"{where}: the launch point needs lat, lon and azimuth (degrees)")
    from .nav import nav_site
    return nav_site(np.radians(float(lat)), np.radians(float(lon)), float(height),
                    np.radians(float(azimuth)))


def _burnout_call(where, traj, codes, burnout_time, site, system, spec, axes):
    """igea_impact_burnout: the state (6,) and E (6, N)."""
    from .envfun import _system_code
    sc = _system_code(system)
    tr = np.asfortranarray(_lib.as_f64(traj, "traj", ndim=2))
    if tr.shape[1] != _capi.ENVFUN_TRAJ_COLS or tr.shape[0] < 2:
        raise ValueError(f"traj: expected shape (n >= 2, {_capi.ENVFUN_TRAJ_COLS}), "
                         f"got {tr.shape}")
    n = len(codes)
    c = np.ascontiguousarray(codes, dtype=np.intc)
    sp = None if spec is None else np.ascontiguousarray(
        _lib.as_f64(spec, "spec", ndim=1, shape=(n,)))
    ax = None
    if axes is not None:
        ax = np.ascontiguousarray(axes, dtype=np.intc)
        if ax.shape != (6,):
            raise ValueError(f"axes: expected 6 ints, got shape {ax.shape}")
    state, E = np.zeros(6), np.zeros((6, max(n, 1)), order="F")
    _lib.call(where, "igea_impact_burnout", sc, tr.shape[0], _lib.dptr(tr), tr.shape[0], n,
              _lib.iptr(c) if n else None, _lib.iptr(ax),
              _lib.dptr(sp), _lib.dptr(site), float(burnout_time), _lib.dptr(state),
              _lib.dptr(E) if n else None, 6)
    return state, np.ascontiguousarray(E[:, :n])


def burnout(traj, terms, burnout_time, *, lat=None, lon=None, height=0.0, azimuth=None,
            system="strapdown", spec=None, axes=None):
    """The burnout at burnout_time (s) of the trajectory traj (samples x
    11, as igea.envfun reads it; t_0 the lift-off) flown by the nav core
    from the launch point lat, lon (degrees), height (m) at azimuth
    (degrees): the state burnout (6,: x y z m, vx vy vz m/s relative to the
    Earth, ECEF), and for the error terms (names, 'default' or 'all'; may be
    empty) their burnout errors (6, N) in ECEF: the gravity-coupled position
    and velocity environment functions at burnout_time per unit of each
    term, times spec (None: per unit; "default": the catalogue's 1-sigma;
    or one per term); axes: platform gyro axes as igea.envfun's.
    igea.impact(b.burnout) and igea.impact_budget(miss_jacobian,
    b.burnout_errors, b.terms) give the miss budget."""
    where = "igea.burnout"
    from .envfun import STRAPDOWN_21, PLATFORM_21, _system_code, default_spec, term_codes
    sc = _system_code(system)
    if isinstance(terms, str) and terms in ("default", "all"):
        if terms == "default":
            names = list(STRAPDOWN_21 if sc == _capi.ENVFUN_STRAPDOWN else PLATFORM_21)
        else:
            from .envfun import term_table
            names = list(term_table(system))
    elif isinstance(terms, str):
        raise ValueError(f"{where}: terms: 'default', 'all' or a list of term names, got "
                         f"{terms!r}")
    else:
        names = [str(t) for t in terms]
    codes = term_codes(names, system) if names else np.zeros(0, dtype=np.intc)
    if isinstance(spec, str):
        if spec != "default":
            raise ValueError(f"spec: None, 'default' or one 1-sigma per term, got {spec!r}")
        spec = default_spec(names, system) if names else None
    site = _site(where, lat, lon, height, azimuth)
    state, E = _burnout_call(where, traj, codes, burnout_time, site, system, spec, axes)
    return Burnout(float(burnout_time), state, names, E)
