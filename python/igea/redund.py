"""Redundant sensor sets (METHODS 3.1-3.3): reliability, the confidence-
distance consistency check, fusion set and fused output, parity-space fault
detection and isolation, the windowed check of a multi-sensor record."""
import ctypes
from dataclasses import dataclass

import numpy as np

from . import _capi, _lib
from ._compat import _UNSET, renamed
from ._result import result



def _vec(x, name, n=None):
    if np.ndim(x) == 0:
        if n is None:
            raise ValueError(f"{name}: expected a 1-D array, got a scalar")
        a = np.full(n, _lib.as_f64(x, name).ravel()[0])
    else:
        a = _lib.as_f64(x, name)
    if a.ndim != 1 or (n is not None and a.shape[0] != n):
        want = "(*)" if n is None else f"({n},)"
        raise ValueError(f"{name}: expected shape {want}, got {a.shape}")
    return np.ascontiguousarray(a)


def _square(D, name):
    a = _lib.as_f64(D, name, ndim=2)
    if a.shape[0] != a.shape[1] or a.shape[0] < 1:
        raise ValueError(f"{name}: expected a square (n, n) matrix, got {a.shape}")
    return a


def _alpha(alpha, n):
    """(array, lda): a scalar becomes lda 0, a matrix must be (n, n)."""
    if np.ndim(alpha) == 0:
        return np.ascontiguousarray(_lib.as_f64(alpha, "alpha").ravel()[:1]), 0
    a = _lib.as_f64(alpha, "alpha")
    if a.shape != (n, n):
        raise ValueError(f"alpha: expected a scalar or shape ({n}, {n}), got {a.shape}")
    return a, n


def _dout():
    return ctypes.c_double()


# ---- reliability -----------------------------------------------------------

def reliability_exponential(lam, t):
    """(R, MTBF) of an exponential component: R = exp(-lam t), MTBF = 1/lam."""
    R, m = _dout(), _dout()
    _lib.call("igea.reliability_exponential", "igea_redund_exponential", float(lam), float(t),
              ctypes.byref(R), ctypes.byref(m))
    return R.value, m.value


def _rel_fn(fn, where, R, *extra):
    r = _vec(R, "R")
    out = _dout()
    _lib.call(where, fn, r.size, *extra, _lib.dptr(r), ctypes.byref(out))
    return out.value


def reliability_series(R):
    """All components must work."""
    return _rel_fn("igea_redund_reliability_series", "igea.reliability_series", R)


def reliability_parallel(R):
    """One working component suffices."""
    return _rel_fn("igea_redund_reliability_parallel", "igea.reliability_parallel", R)


def reliability_kofn(R, k):
    """At least k of the independent components work (exact for unequal R)."""
    return _rel_fn("igea_redund_reliability_kofn", "igea.reliability_kofn", R, int(k))


def reliability_diagram(R, blocks):
    """Reliability block diagram.

    R: component reliabilities (ncomp,). blocks: a list of (kind, members)
    or (kind, members, k) with kind "series", "parallel" or "kofn";
    a member j < ncomp is component j, j >= ncomp is block j - ncomp (an
    earlier block). Returns the block reliabilities (the system is normally
    the last)."""
    r = _vec(R, "R")
    if len(blocks) < 1:
        raise ValueError("blocks: at least one block is needed")
    types, ks, first, members = [], [], [0], []
    for b in blocks:
        if len(b) not in (2, 3):
            raise ValueError("blocks: each block is (kind, members[, k])")
        types.append(_lib.choice(_capi.CHOICE_REDUND_RBD, b[0], "igea.reliability_diagram",
                                 "blocks"))
        ks.append(int(b[2]) if len(b) == 3 else 0)
        members.extend(int(m) for m in b[1])
        first.append(len(members))
    ti, ki, fi, mi = (np.array(v, dtype=np.intc) for v in (types, ks, first, members))
    out = np.empty(len(blocks))
    _lib.call("igea.reliability_diagram", "igea_redund_diagram", r.size, _lib.dptr(r), len(blocks),
              _lib.iptr(ti), _lib.iptr(ki), _lib.iptr(fi), _lib.iptr(mi), _lib.dptr(out))
    return out


@result
@dataclass(frozen=True)
class Seed002Reliability:
    """The figures of seed 002 (METHODS 3.1 table, 3.2)."""
    gyro: float
    acc_eq7: float
    system_eq7: float
    system_without_skew: float
    non_redundant: float
    system_exact: float
    acc_exact: float

    def summary(self):
        return "\n".join([
            "redundant gyros (6)                      %.10f" % self.gyro,
            "accelerometers by eq. (7)                %.12f" % self.acc_eq7,
            "system by (8) with (7)                   %.10f" % self.system_eq7,
            "system without the skew sensor  (10)     %.10f" % self.system_without_skew,
            "non-redundant (9)                        %.10f" % self.non_redundant,
            "system, exact geometric (METHODS 3.2)    %.10f" % self.system_exact,
        ])


def reliability_seed002(Re1=0.992, Re2=0.995):
    out = np.empty(_capi.REDUND_SEED002_LEN)
    _lib.call("igea.reliability_seed002", "igea_redund_seed002", float(Re1), float(Re2),
              _lib.dptr(out))
    return Seed002Reliability(**{f: float(out[getattr(_capi, "REDUND_SEED002_" + s)]) for f, s in (
        ("gyro", "GYRO"), ("acc_eq7", "ACC_EQ7"), ("system_eq7", "SYS_EQ7"),
        ("system_without_skew", "SYS_NO_D"), ("non_redundant", "NONREDUND"),
        ("system_exact", "SYS_EXACT"), ("acc_exact", "ACC_EXACT"))})


@result
@dataclass(frozen=True)
class GeometryReliability:
    """Exact reliability of a sensor geometry (METHODS 3.2)."""
    span: float      # surviving axes span 3-D
    detect: float    # ... and a further single fault is detectable (NaN if not computed)
    isolate: float   # ... and isolable
    classes: int     # direction classes

    def summary(self):
        return ("P(span 3-D) = %.12f\nP(span, detect a further fault) = %.12f\n"
                "P(span, isolate a further fault) = %.12f\n(%d direction classes)"
                % (self.span, self.detect, self.isolate, self.classes))


def reliability_geometry(axes, R, *, fdi=True):
    """Exact reliability of n sensors with input axes (n, 3) and survival
    probabilities R (scalar or (n,)): P(the survivors span 3-D) and, with
    fdi, P(... and can still detect / isolate a further single fault)."""
    a = _lib.as_f64(axes, "axes", ndim=2, shape=(None, 3))
    n = a.shape[0]
    if n < 1:
        raise ValueError("axes: at least one sensor is needed")
    r = _vec(R, "R", n)
    out = np.empty(_capi.REDUND_GEOM_LEN)
    _lib.call("igea.reliability_geometry", "igea_redund_geometry", n, _lib.dptr(a), n,
              _lib.dptr(r), int(bool(fdi)), _lib.dptr(out))
    return GeometryReliability(**_lib.fields(out, "REDUND_GEOM_", span=float, detect=float,
                                             isolate=float, classes=int))


# ---- consistency and fusion --------------------------------------------------

def erfinv(y):
    """Inverse error function, -1 < y < 1."""
    out = _dout()
    _lib.call("igea.erfinv", "igea_stats_erfinv", float(y), ctypes.byref(out))
    return out.value


def confidence_distance(x, sigma):
    """D_ij = |erf((x_j - x_i) / (sqrt2 sigma_i))| (METHODS 3.3 (13))."""
    xv = _vec(x, "x")
    n = xv.size
    if n < 1:
        raise ValueError("x: at least one measurement is needed")
    s = _vec(sigma, "sigma", n)
    D = np.empty((n, n), order="F")
    _lib.call("igea.confidence_distance", "igea_redund_confidence_distance", n, _lib.dptr(xv),
              _lib.dptr(s), _lib.dptr(D), n)
    return D


def thresholds(sigma, alpha=0.7, n=None):
    """delta_ij = sqrt2 sigma_i erfinv(alpha_ij): |x_j - x_i| <= delta_ij is
    the same test as d_ij <= alpha_ij, in the measurement's units."""
    s = _vec(sigma, "sigma", n)
    m = s.size
    a, lda = _alpha(alpha, m)
    delta = np.empty((m, m), order="F")
    _lib.call("igea.thresholds", "igea_redund_thresholds", m, _lib.dptr(s), _lib.dptr(a), lda,
              _lib.dptr(delta), m)
    return delta


def relation(D, alpha=0.7):
    """Relation matrix r_ij = [d_ij <= alpha_ij] ("i supports j"), ints."""
    d = _square(D, "D")
    n = d.shape[0]
    a, lda = _alpha(alpha, n)
    r = np.empty((n, n), dtype=np.intc, order="F")
    _lib.call("igea.relation", "igea_redund_relation", n, _lib.dptr(d), n, _lib.dptr(a), lda,
              _lib.iptr(r), n)
    return r.astype(int)


def _one_shot(where, one_shot, iterative):
    """one_shot, or the old keyword iterative (its negation)."""
    old = _UNSET if iterative is _UNSET else not iterative
    return bool(renamed(where, "one_shot", one_shot, "iterative", old, default=False))


def _average(where, average, weighted):
    """average, or the old keyword weighted (its negation)."""
    old = _UNSET if weighted is _UNSET else not weighted
    return bool(renamed(where, "average", average, "weighted", old, default=False))


def _fusion(D, alpha, iterative):
    d = _square(D, "D")
    n = d.shape[0]
    a, lda = _alpha(alpha, n)
    keep = np.empty(n, dtype=np.intc)
    sup = np.empty(n, dtype=np.intc)
    _lib.call("igea.fusion_set", "igea_redund_fusion_set", n, _lib.dptr(d), n, _lib.dptr(a), lda,
              int(bool(iterative)), _lib.iptr(keep), _lib.iptr(sup))
    return keep.astype(bool), sup.astype(int)


def fusion_set(D, alpha=0.7, *, one_shot=_UNSET, iterative=_UNSET):
    """Boolean mask of the fusion set (METHODS 3.3): the iterative majority,
    or the one-shot set (one_shot=True, the driver's --one-shot;
    iterative=False is its old spelling)."""
    return _fusion(D, alpha, not _one_shot("igea.fusion_set", one_shot, iterative))[0]


def support(D, alpha=0.7):
    """Support counts sup_j = #{i != j: d_ij <= alpha_ij} on the full set."""
    return _fusion(D, alpha, True)[1]


def fuse(x, sigma, mask=None, *, average=_UNSET, weighted=_UNSET):
    """(value, sigma) fused over mask (None: all): inverse-variance weights,
    or the plain average with sigma = sqrt(sum sigma^2) / |F| (average=True,
    the driver's --average; weighted=False is its old spelling)."""
    weighted = not _average("igea.fuse", average, weighted)
    xv = _vec(x, "x")
    n = xv.size
    if n < 1:
        raise ValueError("x: at least one measurement is needed")
    s = _vec(sigma, "sigma", n)
    keep = None
    if mask is not None:
        m = np.asarray(mask)
        if m.shape != (n,):
            raise ValueError(f"mask: expected shape ({n},), got {m.shape}")
        keep = np.ascontiguousarray(m.astype(bool), dtype=np.intc)
    v, fs = _dout(), _dout()
    _lib.call("igea.fuse", "igea_redund_fuse", n, _lib.dptr(xv), _lib.dptr(s), _lib.iptr(keep),
              int(bool(weighted)), ctypes.byref(v), ctypes.byref(fs))
    return v.value, fs.value


def false_alarm(sigma_i, noise_i, noise_j=None, alpha=0.7):
    """P(healthy i does not support healthy j) for tolerance sigma_i and true
    noises noise_i, noise_j (default noise_i)."""
    if noise_j is None:
        noise_j = noise_i
    p = _dout()
    _lib.call("igea.false_alarm", "igea_redund_false_alarm", float(sigma_i), float(noise_i),
              float(noise_j), float(alpha), ctypes.byref(p))
    return p.value


def transform(C, v):
    """out_g = C_g v_g for groups g: C (g, 3, 3), v (g, 3) -> (g, 3)."""
    c = np.asarray(_lib.as_f64(C, "C", ndim=3, shape=(None, 3, 3)))
    g = c.shape[0]
    if g < 1:
        raise ValueError("C: at least one group is needed")
    vv = _lib.as_f64(v, "v", ndim=2, shape=(g, 3))
    cf = np.ascontiguousarray(np.transpose(c, (0, 2, 1)))  # each 3x3 column-major
    vf = np.ascontiguousarray(vv)
    out = np.empty((g, 3))
    _lib.call("igea.transform", "igea_redund_transform", g, _lib.dptr(cf), _lib.dptr(vf),
              _lib.dptr(out))
    return out


# ---- parity space --------------------------------------------------------------

def parity_matrix(H):
    """V ((m - q) x m) with V H = 0 and orthonormal rows, for H (m, q)."""
    h = _lib.as_f64(H, "H", ndim=2)
    m, q = h.shape
    if q < 1 or m <= q:
        raise ValueError(f"H: expected shape (m, q) with m > q >= 1, got {h.shape}")
    V = np.empty((m - q, m), order="F")
    _lib.call("igea.parity_matrix", "igea_redund_parity", m, q, _lib.dptr(h), m, _lib.dptr(V),
              m - q)
    return V


@result
@dataclass(frozen=True)
class FdiResult:
    """Parity-space test of one epoch."""
    statistic: float
    threshold: float
    dof: int
    p_value: float
    detected: bool
    isolated: int        # 0-based sensor, -1 if none
    isolation_statistic: float
    isolable: bool       # the geometry can isolate any single fault
    parity: np.ndarray   # whitened parity vector (m - q)

    def summary(self):
        s = ("parity statistic %.6g vs chi2 threshold %.6g (dof %d, p = %.4g): %s"
             % (self.statistic, self.threshold, self.dof, self.p_value,
                "FAULT DETECTED" if self.detected else "no fault"))
        if self.detected:
            s += ("\nisolated sensor: %d (statistic %.6g)" % (self.isolated, self.isolation_statistic)
                  if self.isolable else "\nthe geometry cannot isolate a single fault")
        return s


def fdi(H, y, sigma, pfa=0.01):
    """Generalized likelihood test in parity space for y = H x + e,
    e ~ N(0, diag(sigma^2)), false-alarm probability pfa."""
    h = _lib.as_f64(H, "H", ndim=2)
    m, q = h.shape
    if q < 1 or m <= q:
        raise ValueError(f"H: expected shape (m, q) with m > q >= 1, got {h.shape}")
    yv = _vec(y, "y", m)
    s = _vec(sigma, "sigma", m)
    par = np.empty(m - q)
    info = np.empty(_capi.REDUND_FDI_LEN)
    iso = ctypes.c_int()
    _lib.call("igea.fdi", "igea_redund_fdi", m, q, _lib.dptr(h), m, _lib.dptr(yv), _lib.dptr(s),
              float(pfa), _lib.dptr(par), _lib.dptr(info), ctypes.byref(iso))
    return FdiResult(statistic=float(info[_capi.REDUND_FDI_STAT]),
                     isolation_statistic=float(info[_capi.REDUND_FDI_ISO_STAT]),
                     isolated=int(iso.value), parity=par,
                     **_lib.fields(info, "REDUND_FDI_", threshold=float, dof=int, p_value=float,
                                   detected=bool, isolable=bool))


@result
@dataclass(frozen=True)
class SkewCheck:
    """Skew-sensor check of the Y and Z pairs (METHODS 3.3)."""
    residual: np.ndarray    # (ny, nz): a_D - (cy a_y,i + cz a_z,j)
    faulty_y: np.ndarray    # bool (ny,)
    faulty_z: np.ndarray    # bool (nz,)
    faulty_d: bool          # every pair failed: the skew sensor is the suspect

    def summary(self):
        bad = (["Y%d" % (i + 1) for i in np.flatnonzero(self.faulty_y)]
               + ["Z%d" % (j + 1) for j in np.flatnonzero(self.faulty_z)]
               + (["D"] if self.faulty_d else []))
        return "faulty: " + (", ".join(bad) if bad else "none")


def skew_check(ay, sy, az, sz, ad, sd, *, axis=(0.7071067811865476, 0.7071067811865476),
               kappa=3.0):
    """Every (Y_i, Z_j) pair against the skew sensor D with axis (cy, cz):
    pairs failing |a_D - (cy a_y + cz a_z)| <= kappa sigma; a sensor whose
    every pair fails is faulty (all pairs failing: D)."""
    y = _vec(ay, "ay")
    z = _vec(az, "az")
    syv = _vec(sy, "sy", y.size)
    szv = _vec(sz, "sz", z.size)
    if y.size < 1 or z.size < 1:
        raise ValueError("ay, az: at least one sensor each")
    if len(axis) != 2:
        raise ValueError("axis: expected (cy, cz)")
    res = np.empty((y.size, z.size), order="F")
    fy = np.empty(y.size, dtype=np.intc)
    fz = np.empty(z.size, dtype=np.intc)
    fd = ctypes.c_int()
    _lib.call("igea.skew_check", "igea_redund_skew_check", y.size, _lib.dptr(y), _lib.dptr(syv),
              z.size, _lib.dptr(z), _lib.dptr(szv), float(ad), float(sd), float(axis[0]),
              float(axis[1]), float(kappa), _lib.dptr(res), _lib.iptr(fy), _lib.iptr(fz),
              ctypes.byref(fd))
    return SkewCheck(res, fy.astype(bool), fz.astype(bool), bool(fd.value))


# ---- windowed check --------------------------------------------------------------

@result
@dataclass(frozen=True)
class SeriesCheck:
    """Windowed consistency check of a record (nwin windows, nsens sensors)."""
    t: np.ndarray            # window start times (s)
    window: float
    means: np.ndarray        # (nwin, nsens)
    excluded: np.ndarray     # (nwin, nsens) bool
    fused: np.ndarray        # (nwin,)
    fused_sigma: np.ndarray  # (nwin,)
    exclusions: list         # [(sensor, from, to)]: the library's intervals, sensor 0-based

    def intervals(self):
        """[(sensor, t_start, t_end)] of the exclusions."""
        return list(self.exclusions)

    def summary(self):
        iv = self.intervals()
        lines = ["%d windows of %g s, %d sensors" % (self.fused.size, self.window,
                                                     self.excluded.shape[1])]
        if not iv:
            lines.append("no sensor excluded")
        for s, a, b in iv:
            lines.append("sensor %d excluded from %g s to %g s" % (s, a, b))
        return "\n".join(lines)


def series_check(y, fs, window, sigma, alpha=0.7, *, one_shot=_UNSET, average=_UNSET,
                 iterative=_UNSET, weighted=_UNSET):
    """Per window of round(window fs) samples: window means of the columns of
    y (nsamp, nsens), confidence distances with sigma (tolerances of the
    means), the fusion set (one_shot as fusion_set) and the fused value
    (average as fuse). SeriesCheck.window is the length used, round(window
    fs) / fs seconds (igea_redund_window_length)."""
    iterative = not _one_shot("igea.series_check", one_shot, iterative)
    weighted = not _average("igea.series_check", average, weighted)
    a = _lib.as_f64(y, "y", ndim=2)
    nsamp, nsens = a.shape
    if nsamp < 1 or nsens < 1:
        raise ValueError(f"y: expected a non-empty (nsamp, nsens) array, got {a.shape}")
    s = _vec(sigma, "sigma", nsens)
    al, lda = _alpha(alpha, nsens)
    nwin = ctypes.c_int()
    _lib.call("igea.series_check", "igea_redund_window_count", nsamp, float(fs), float(window),
              ctypes.byref(nwin))
    nw = nwin.value
    if nw < 1:
        raise ValueError("y: shorter than one window")
    means = np.empty((nsens, nw), order="F")
    ex = np.empty((nsens, nw), dtype=np.intc, order="F")
    fused = np.empty(nw)
    fsig = np.empty(nw)
    _lib.call("igea.series_check", "igea_redund_monitor", nsamp, nsens, _lib.dptr(a), nsamp,
              float(fs), float(window), _lib.dptr(s), _lib.dptr(al), lda, int(bool(iterative)),
              int(bool(weighted)), nw, _lib.dptr(means), _lib.iptr(ex), _lib.dptr(fused),
              _lib.dptr(fsig))
    cap = nsens * ((nw + 1) // 2)
    sensor, w0, w1 = (np.zeros(cap, dtype=np.intc) for _ in range(3))
    t0, t1 = np.zeros(cap), np.zeros(cap)
    niv = ctypes.c_int()
    _lib.call("igea.series_check", "igea_redund_monitor_intervals", nsens, nw, _lib.iptr(ex),
              float(fs), float(window), cap, ctypes.byref(niv), _lib.iptr(sensor), _lib.iptr(w0),
              _lib.iptr(w1), _lib.dptr(t0), _lib.dptr(t1))
    step = ctypes.c_double()
    _lib.call("igea.series_check", "igea_redund_window_length", float(fs), float(window), None,
              ctypes.byref(step))
    step = step.value
    k = niv.value
    return SeriesCheck(np.arange(nw) * step, step, means.T.copy(), ex.T.astype(bool), fused,
                       fsig, [(int(a), float(b), float(c)) for a, b, c in
                              zip(sensor[:k], t0[:k], t1[:k])])


def simulate_redundant(nsamp, fs, level, noise, *, fault_sensor=-1, t0=0.0, t1=0.0, bias=0.0,
                       seed=0):
    """Static record (nsamp, nsens): level + noise N(0,1) per sensor, plus
    bias on fault_sensor for t0 <= t < t1 (GSL mt19937, seed)."""
    lv = _vec(level, "level")
    n = lv.size
    nz = _vec(noise, "noise", n)
    y = np.empty((nsamp, n), order="F")
    _lib.call("igea.simulate_redundant", "igea_redund_simulate", int(nsamp), n, float(fs),
              _lib.dptr(lv), _lib.dptr(nz), int(fault_sensor), float(t0), float(t1), float(bias),
              int(seed), _lib.dptr(y), max(1, int(nsamp)))
    return y


# ---- virtual IMUs ----------------------------------------------------------

GROUP_FUSIONS = {"average": _capi.REDUND_GROUP_AVERAGE, "weighted": _capi.REDUND_GROUP_WEIGHTED,
                 "gls": _capi.REDUND_GROUP_GLS}
# seed 002: Ax1..Ax4 (sensors 0..3), Ay1, Ay2 (4, 5), Az1, Az2 (6, 7)
SEED002_GROUPS = ((0, 4, 6), (1, 5, 7), (2, 4, 6), (3, 5, 7))


@result
@dataclass(frozen=True)
class RedundGroup:
    """igea.redund_group: virtual IMUs unified into group 0's body frame and
    fused; cov counts a sensor that several groups share once, cov_indep is
    what treating the groups as independent would state."""
    fusion: str
    frames: np.ndarray
    group_out: np.ndarray
    fused: np.ndarray
    cov: np.ndarray
    cov_indep: np.ndarray


def redund_group(axes, sigma, y, groups=SEED002_GROUPS, *, fusion="weighted"):
    """Virtual IMUs of single-axis sensors (igea_redund_group): axes (n, 3)
    each sensor's calibrated input axis in the calibration's reference frame
    (its length the scale factor), sigma (n,) noise sd, y (n,) readings,
    groups (g, 3) the x, y, z sensor of each group (default: seed 002's four
    groups of 8 sensors Ax1..Ax4, Ay1, Ay2, Az1, Az2), fusion "average",
    "weighted" (per axis, inverse variance of the groups' outputs) or "gls"
    (generalised least squares of the distinct sensors). Returns frames
    (g, 3, 3) C_g (group g frame -> body frame), group_out (g, 3), fused (3,),
    cov (3, 3), cov_indep (3, 3)."""
    where = "igea.redund_group"
    if fusion not in GROUP_FUSIONS:
        raise ValueError(f"{where}: fusion: expected one of {sorted(GROUP_FUSIONS)}, got {fusion!r}")
    a = _lib.as_f64(axes, "axes", ndim=2, shape=(None, 3))
    n = a.shape[0]
    af = np.ascontiguousarray(a)          # row i = axis i: the 3 x n column-major layout
    s = _vec(sigma, "sigma", n)
    yy = _vec(y, "y", n)
    gm = np.asarray(groups)
    if gm.ndim != 2 or gm.shape[1] != 3 or gm.shape[0] < 1:
        raise ValueError(f"{where}: groups: expected shape (g, 3), got {gm.shape}")
    mem = np.ascontiguousarray(gm, dtype=np.intc)
    g = mem.shape[0]
    frames, gout = np.zeros((g, 3, 3)), np.zeros((g, 3))
    fused, cov, ci = np.zeros(3), np.zeros((3, 3)), np.zeros((3, 3))
    _lib.call(where, "igea_redund_group", n, _lib.dptr(af), _lib.dptr(s), g, _lib.iptr(mem),
              _lib.dptr(yy), GROUP_FUSIONS[fusion], _lib.dptr(frames), _lib.dptr(gout),
              _lib.dptr(fused), _lib.dptr(cov), _lib.dptr(ci))
    # column-major 3 x 3 blocks read as row-major are transposed
    return RedundGroup(fusion, np.ascontiguousarray(np.transpose(frames, (0, 2, 1))), gout,
                       fused, cov.T.copy(), ci.T.copy())


@result
@dataclass(frozen=True)
class RedundStability:
    """igea.redund_stability: seed 002's Table 1, the block statistic
    (block_seconds blocks, 3 sigma of the block means) of every sensor and
    of every fused channel."""
    block_seconds: float
    channel: np.ndarray
    three_sigma: np.ndarray
    sigma: np.ndarray
    fused_three_sigma: np.ndarray
    fused_sigma: np.ndarray
    fused: np.ndarray


def redund_stability(y, fs, channel, *, block=100.0, average=False):
    """Table 1 of seed 002 (igea_redund_stability): y (nsamp, nsens) a
    multi-sensor record at fs Hz, channel (nsens,) each sensor's channel
    0 .. nchan - 1 (-1: not fused), block seconds; the fused channel is the
    weighted mean of its sensors (weights 1 / each sensor's block variance)
    or, average=True, their plain mean."""
    where = "igea.redund_stability"
    a = np.asfortranarray(_lib.as_f64(y, "y", ndim=2))
    n, ns = a.shape
    ch = np.ascontiguousarray(np.asarray(channel), dtype=np.intc)
    if ch.shape != (ns,):
        raise ValueError(f"{where}: channel: expected shape ({ns},), got {ch.shape}")
    nc = int(ch.max()) + 1 if ch.size else 0
    L = _capi.STABILITY_BLOCK_LEN
    so, fo = np.zeros((max(ns, 1), L)), np.zeros((max(nc, 1), L))
    fused = np.zeros((max(nc, 1), n))
    _lib.call(where, "igea_redund_stability", n, ns, _lib.dptr(a), n, float(fs), float(block),
              _lib.iptr(ch), nc, 0 if average else 1, _lib.dptr(so), _lib.dptr(fo),
              _lib.dptr(fused))
    sec = so[0, _capi.STABILITY_BLOCK_NSAMP] / float(fs)
    return RedundStability(sec, ch.astype(int), so[:, _capi.STABILITY_BLOCK_3SIGMA].copy(),
                           so[:, _capi.STABILITY_BLOCK_SIGMA].copy(),
                           fo[:, _capi.STABILITY_BLOCK_3SIGMA].copy(),
                           fo[:, _capi.STABILITY_BLOCK_SIGMA].copy(), fused.T.copy())
