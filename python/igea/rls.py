"""Recursive least squares for guidance tool-error coefficients (seed 001,
METHODS 2): standard, iterated and polynomial RLS, anomaly handling,
forgetting, the honest (Joseph) covariance and Q_p."""
import ctypes
from dataclasses import dataclass

import numpy as np

from . import _capi
from . import _lib
from ._compat import _UNSET, renamed
from ._result import result

VARIANTS = _lib.choice_codes(_capi.CHOICE_RLS_VARIANT)
ACTIONS = {c: n for n, c in _lib.choice_codes(_capi.CHOICE_RLS_ACTION).items()}
FLAGS = _lib.choice_codes(_capi.CHOICE_RLS_FLAG)
FLAG_INNOVATION, FLAG_JUMP, FLAG_MISSING, FLAG_UNUSED = (
    _capi.RLS_FLAG_INNOVATION, _capi.RLS_FLAG_JUMP, _capi.RLS_FLAG_MISSING, _capi.RLS_FLAG_UNUSED)


def _flag_names(f):
    f = int(f)
    out = [n for n, b in FLAGS.items() if f & b]
    return "+".join(out) if out else "-"


@result
@dataclass(frozen=True)
class RlsEpoch:
    """What RLS.update did at one epoch: action name and the per-row flag
    bits (FLAG_INNOVATION 1, FLAG_JUMP 2, FLAG_MISSING 4, FLAG_UNUSED 8)."""
    action: str
    flags: np.ndarray

    def summary(self):
        return "%s; rows: %s" % (self.action, ", ".join(_flag_names(f) for f in self.flags))


@result
@dataclass(frozen=True)
class RlsResult:
    """Result of igea.rls_run.

    x (epochs x m): the estimate after each epoch; gamma, covariance (m x m):
    the final Gamma and the honest covariance of x (Joseph form with the
    gain used; equals Gamma for p = 1); sd (m,): the square roots of its
    diagonal (None with covariance); q: Q_p (whitened); flags (epochs x k)
    and actions (epochs, codes of ACTIONS); residual (epochs x k): the
    compensated telemetry y - c x after each epoch (physical units)."""
    x: np.ndarray
    gamma: np.ndarray
    covariance: np.ndarray
    sd: np.ndarray
    q: float
    flags: np.ndarray
    actions: np.ndarray
    residual: np.ndarray
    variant: str
    p: int
    counts: dict

    def summary(self):
        n, m = self.x.shape
        sd = self.sd if self.sd is not None else np.full(m, np.nan)
        lines = ["rls: %s, p = %d, %d epochs, %d coefficients" % (self.variant, self.p, n, m),
                 "epochs updated %d, anomalous %d; Q_p = %.6g over %d rows"
                 % (self.counts["updates"], self.counts["anomalous"], self.q,
                    self.counts["rows"]),
                 "%5s %16s %14s %14s" % ("coef", "estimate", "sd (honest)", "sd (Gamma)")]
        gsd = np.sqrt(np.diag(self.gamma))
        for i in range(m):
            lines.append("%5d %16.8g %14.6g %14.6g" % (i, self.x[-1, i] if n else np.nan,
                                                       sd[i], gsd[i]))
        return "\n".join(lines)


def _prior(x0, gamma0):
    g = _lib.as_f64(gamma0, "gamma0", ndim=2)
    m = g.shape[0]
    if g.shape != (m, m) or m < 1:
        raise ValueError(f"gamma0: expected a square (m, m) array, got {g.shape}")
    x = None if x0 is None else _lib.as_f64(x0, "x0", ndim=1, shape=(m,))
    return m, x, g


def _sigma(sigma, k, n=None):
    """None, a scalar, (k,) or (n, k) -> (array or None, sigma_inc)."""
    if sigma is None:
        return None, 0
    s = np.asarray(sigma, dtype=np.float64)
    if s.ndim == 0:
        return np.full(k, float(s)), 0
    if s.ndim == 1:
        return _lib.as_f64(s, "sigma", ndim=1, shape=(k,)), 0
    if n is not None and s.ndim == 2:
        return np.ascontiguousarray(_lib.as_f64(s, "sigma", shape=(n, k))), 1
    raise ValueError(f"sigma: expected a scalar or shape ({k},)"
                     + (f" or ({n}, {k})" if n is not None else "") + f", got {s.shape}")


def _c_order(x, name, shape):
    """x as a C-order float64 array of the given shape (None: any), without
    a copy when it already is one; ValueError naming the argument."""
    try:
        a = np.asarray(x, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{name}: not an array of numbers ({exc})") from None
    if a.ndim != len(shape) or any(s is not None and s != d for s, d in zip(shape, a.shape)):
        want = "(" + ", ".join("*" if s is None else str(s) for s in shape) + ")"
        raise ValueError(f"{name}: expected shape {want}, got {a.shape}")
    return np.ascontiguousarray(a)


class RLS:
    """Recursive estimator state (an igea_rls handle).

    RLS(x0, gamma0, k, variant="standard"|"iterated"|"polynomial", p=1,
    anomaly=None|"replace"|"skip"|"isolate", kappa=4.0, jump=None,
    forget=1.0, covariance=True). x0 (m,) or None (zeros), gamma0 (m, m)
    symmetric positive definite (whitened units), k rows per epoch;
    covariance=False skips the honest covariance (then .covariance raises
    IgeaError once a p > 1 gain was used). Then .update(c, y, sigma=None)
    per epoch; .x, .gamma, .covariance, .sd, .q, .counts. jump (k,) or one
    number: the jump test's bounds (the driver's --jump); jump_max= is its old name."""

    def __init__(self, x0, gamma0, k, *, variant="standard", p=1, anomaly=None, kappa=4.0,
                 jump=_UNSET, forget=1.0, covariance=True, jump_max=_UNSET):
        jump = renamed("igea.RLS", "jump", jump, "jump_max", jump_max)
        self._h = ctypes.c_void_p()
        m, x, g = _prior(x0, gamma0)
        k = int(k)
        if k < 1:
            raise ValueError(f"k: expected a positive number of rows, got {k}")
        v = _lib.choice(_capi.CHOICE_RLS_VARIANT, variant, "igea.RLS", "variant")
        pol = (_capi.RLS_ANOMALY_NONE if anomaly is None else
               _lib.choice(_capi.CHOICE_RLS_ANOMALY, anomaly, "igea.RLS", "anomaly"))
        jm = (None if jump is None else
              _lib.as_f64(np.broadcast_to(np.asarray(jump, dtype=float), (k,)) if np.ndim(jump) == 0
                          else jump, "jump", ndim=1, shape=(k,)))
        h = ctypes.c_void_p()
        _lib.call("igea.RLS", "igea_rls_create", m, k, _lib.dptr(x), _lib.dptr(g), m,
                  ctypes.byref(h))
        self._h = h
        self.m, self.k = m, k
        self.variant, self.p = variant, int(p) if v else 1
        _lib.call("igea.RLS", "igea_rls_set_variant", h, v, int(p))
        _lib.call("igea.RLS", "igea_rls_set_anomaly", h, pol, float(kappa), _lib.dptr(jm))
        _lib.call("igea.RLS: forget", "igea_rls_set_forget", h, float(forget))
        _lib.call("igea.RLS", "igea_rls_set_covariance", h, 1 if covariance else 0)
        self.track_covariance = bool(covariance)
        self._flags = np.zeros(k, dtype=np.intc)

    def close(self):
        """Free the handle (also done when the object is collected)."""
        h, self._h = getattr(self, "_h", None), ctypes.c_void_p()
        if h is not None and h.value:
            _lib.lib.igea_rls_free(h)

    def __del__(self):
        try:
            self.close()
        except Exception:  # interpreter shutdown: the library may be gone
            pass

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def _handle(self):
        if not self._h.value:
            raise ValueError("RLS: the handle has been closed")
        return self._h

    def update(self, c, y, sigma=_UNSET, track_sigma=_UNSET):
        """One epoch: c (k, m), y (k,) (NaN = dropout, with a policy set),
        sigma None (unit), a scalar or (k,). Returns RlsEpoch(action, flags)."""
        sigma = renamed("igea.RLS.update", "sigma", sigma, "track_sigma", track_sigma)
        h = self._handle()
        ca = _lib.as_f64(c, "c", ndim=2, shape=(self.k, self.m))
        ya = np.ascontiguousarray(_lib.as_f64(y, "y", ndim=1, shape=(self.k,)))
        sa, _ = _sigma(sigma, self.k)
        st = _lib.call("igea.RLS.update", "igea_rls_update", h, _lib.dptr(ca), self.k,
                       _lib.dptr(ya), _lib.dptr(sa), _lib.iptr(self._flags))
        return RlsEpoch(ACTIONS[st], self._flags.copy())

    def run(self, C, Y, sigma=_UNSET, track_sigma=_UNSET):
        """Many epochs at once: C (n, k, m), Y (n, k), sigma as in update or
        (n, k). Returns (x (n, m), flags (n, k), actions (n,))."""
        sigma = renamed("igea.RLS.run", "sigma", sigma, "track_sigma", track_sigma)
        h = self._handle()
        Ca = _c_order(C, "C", (None, self.k, self.m))  # the blocks layout, no copy if C-order
        n = Ca.shape[0]
        Ya = _c_order(Y, "Y", (n, self.k))
        sa, inc = _sigma(sigma, self.k, n)
        X = np.zeros((n, self.m))
        flags = np.zeros((n, self.k), dtype=np.intc)
        actions = np.zeros(n, dtype=np.intc)
        done = ctypes.c_int(0)
        st = _lib.lib.igea_rls_run(h, n, _capi.ROWMAJOR, _lib.dptr(Ca), self.m,
                                   _lib.dptr(Ya), _lib.dptr(sa), inc, _lib.dptr(X), self.m,
                                   _lib.iptr(flags), _lib.iptr(actions), ctypes.byref(done))
        _lib.check(st, "igea.rls_run (epoch %d)" % done.value, "igea_rls_run")
        return X, flags, actions

    @property
    def x(self):
        out = np.zeros(self.m)
        _lib.call("igea.RLS.x", "igea_rls_get_x", self._handle(), _lib.dptr(out))
        return out

    def _sym(self, fn, where):
        out = np.zeros((self.m, self.m), order="F")
        _lib.call(where, fn, self._handle(), _lib.dptr(out), self.m)
        return np.ascontiguousarray(out)

    @property
    def gamma(self):
        return self._sym("igea_rls_get_gamma", "igea.RLS.gamma")

    @property
    def covariance(self):
        return self._sym("igea_rls_get_covariance", "igea.RLS.covariance")

    @property
    def sd(self):
        """sqrt of the honest covariance's diagonal (igea_rls_get_sd)."""
        out = np.zeros(self.m)
        _lib.call("igea.RLS.sd", "igea_rls_get_sd", self._handle(), _lib.dptr(out))
        return out

    @property
    def q(self):
        q = ctypes.c_double()
        _lib.call("igea.RLS.q", "igea_rls_get_q", self._handle(), ctypes.byref(q))
        return q.value

    @property
    def counts(self):
        c = np.zeros(_capi.RLS_COUNT_LEN, dtype=np.intc)
        _lib.call("igea.RLS.counts", "igea_rls_get_counts", self._handle(), _lib.iptr(c))
        f = _lib.fields(c, "RLS_COUNT_", epochs=int, updates=int, anomalous=int, rows=int)
        return {"n_epochs": f.pop("epochs"), **f}

    def compensate(self, c, y):
        """Compensated telemetry y - c x with the current estimate (METHODS 2.5)."""
        ca = _lib.as_f64(c, "c", ndim=2, shape=(self.k, self.m))
        ya = np.ascontiguousarray(_lib.as_f64(y, "y", ndim=1, shape=(self.k,)))
        out = np.zeros(self.k)
        _lib.call("igea.RLS.compensate", "igea_rls_compensate", self._handle(), _lib.dptr(ca),
                  self.k, _lib.dptr(ya), _lib.dptr(out))
        return out


def rls_run(C, Y, x0, gamma0, *, variant="standard", p=1, anomaly=None, kappa=4.0, forget=1.0,
            sigma=_UNSET, jump=_UNSET, covariance=True, track_sigma=_UNSET,
            jump_max=_UNSET):
    """Run RLS over a whole record.

    C (epochs, k, m) environment functions, Y (epochs, k) telemetry minus
    tracking (NaN marks a dropout when an anomaly policy is set), x0 (m,) or
    None, gamma0 (m, m); sigma None (unit), a scalar, (k,) or (epochs, k)
    (the driver's --sigma; track_sigma= is its old name); jump (k,) the jump
    test's bounds (--jump; jump_max= is its old name); covariance=False: do
    not track the honest covariance (RlsResult.covariance and .sd are then
    None unless p = 1). Returns RlsResult."""
    sigma = renamed("igea.rls_run", "sigma", sigma, "track_sigma", track_sigma)
    jump = renamed("igea.rls_run", "jump", jump, "jump_max", jump_max)
    Ca = _c_order(C, "C", (None, None, None))
    n, k, m = Ca.shape
    Ya = _c_order(Y, "Y", (n, k))
    g = _lib.as_f64(gamma0, "gamma0", ndim=2)
    if g.shape != (m, m):
        raise ValueError(f"gamma0: expected shape ({m}, {m}), got {g.shape}")
    if x0 is not None:
        _lib.as_f64(x0, "x0", ndim=1, shape=(m,))
    _sigma(sigma, k, n)
    with RLS(x0, g, k, variant=variant, p=p, anomaly=anomaly, kappa=kappa,
             jump=jump, forget=forget, covariance=covariance) as est:
        X, flags, actions = est.run(Ca, Ya, sigma)
        resid = Ya - np.einsum("ekm,em->ek", Ca, X)
        try:
            cov, sd = est.covariance, est.sd
        except _lib.IgeaError:
            cov = sd = None
        return RlsResult(x=X, gamma=est.gamma, covariance=cov, sd=sd, q=est.q,
                         flags=flags, actions=actions, residual=resid, variant=variant,
                         p=est.p, counts=est.counts)
