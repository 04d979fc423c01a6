"""Stability statistics of a sensor record (METHODS 3.4): the block-mean
("100-second") 3-sigma statistic, Allan deviations with EDF confidence
intervals, noise identification from the Allan curve."""
import ctypes
from dataclasses import dataclass

import numpy as np

from . import _capi, _lib
from ._result import result



def _record(y):
    a = _lib.as_f64(y, "y", ndim=1)
    if a.size < 2:
        raise ValueError(f"y: at least 2 samples are needed, got {a.size}")
    return np.ascontiguousarray(a)


@result
@dataclass(frozen=True)
class Block3Sigma:
    """Block-mean statistic of METHODS 3.4: the fields of the driver's JSON
    `block` (seconds: the block length used, round(block fs) / fs) and
    block_samples, the samples per block."""
    three_sigma: float
    sigma: float
    nblock: int
    block_samples: int
    mean: float
    adev: float   # Allan deviation at the block length from the block means
    seconds: float = float("nan")

    def summary(self):
        return ("3 sigma = %.6g (sigma of %d block means of %d samples = %.6g); mean %.10g; "
                "Allan deviation at the block length %.6g"
                % (self.three_sigma, self.nblock, self.block_samples, self.sigma, self.mean,
                   self.adev))


def block_3sigma(y, fs, block=100.0):
    """3 sigma of the means of non-overlapping blocks of `block` seconds."""
    a = _record(y)
    out = np.empty(_capi.STABILITY_BLOCK_LEN)
    _lib.call("igea.block_3sigma", "igea_stability_block", a.size, _lib.dptr(a), float(fs),
              float(block), _lib.dptr(out))
    return Block3Sigma(three_sigma=float(out[_capi.STABILITY_BLOCK_3SIGMA]),
                       block_samples=int(out[_capi.STABILITY_BLOCK_NSAMP]),
                       seconds=out[_capi.STABILITY_BLOCK_NSAMP] / float(fs),
                       **_lib.fields(out, "STABILITY_BLOCK_", sigma=float, nblock=int,
                                     mean=float, adev=float))


def octave_taus(n, fs, kind="overlapping"):
    """tau = 2^k / fs while the estimator has at least one term (the kinds
    of `stability`: stability_taus on frequency data)."""
    code = _lib.choice(_capi.CHOICE_STABILITY_KIND, kind, "igea.octave_taus", "kind")
    if kind not in _LEGACY:
        return stability_taus(n, fs, kind)
    kind = code
    tau = np.empty(64)
    nt = ctypes.c_int()
    _lib.call("igea.octave_taus", "igea_stability_octave_taus", int(n), float(fs), kind, 64,
              _lib.dptr(tau), ctypes.byref(nt))
    return tau[:nt.value].copy()


_LEGACY = ("overlapping", "modified", "nonoverlapping")
_NO_INTERVAL = ("mtie", "tierms")


@result
@dataclass(frozen=True)
class AllanResult:
    """Allan deviation with confidence intervals (field names as in
    'igea stability --json')."""
    kind: str
    taus: np.ndarray
    dev: np.ndarray
    lo: np.ndarray
    hi: np.ndarray
    edf: np.ndarray
    count: np.ndarray
    conf: float

    def summary(self):
        lines = ["%s Allan deviation, %.1f %% intervals" % (self.kind, 100 * self.conf),
                 "%12s %14s %14s %14s %10s %10s" % ("tau", "dev", "lo", "hi", "edf", "terms")]
        for row in zip(self.taus, self.dev, self.lo, self.hi, self.edf, self.count):
            lines.append("%12.6g %14.6e %14.6e %14.6e %10.1f %10d" % row)
        return "\n".join(lines)


def allan(y, fs, taus=None, *, kind="overlapping", noise="auto", conf=0.683):
    """Allan deviation of the rate record y at averaging times taus (None:
    octaves). kind: overlapping, modified or nonoverlapping; noise: the
    power-law type for the EDF (wpm, fpm, wfm, ffm, rwfm) or auto. The
    other kinds (adev, oadev, mdev, tdev, hdev, ohdev, totdev, mtotdev,
    ttotdev, htotdev, theo1, theobr, theoh, mtie, tierms) are those of
    `stability`."""
    if kind not in _LEGACY:
        return stability(y, fs, taus, kind=kind, noise=noise, conf=conf)
    a = _record(y)
    kind_code = _lib.choice(_capi.CHOICE_STABILITY_KIND, kind, "igea.allan", "kind")
    noise = _lib.choice(_capi.CHOICE_STABILITY_NOISE, noise, "igea.allan", "noise")
    t = octave_taus(a.size, fs, kind) if taus is None else np.ascontiguousarray(
        _lib.as_f64(np.atleast_1d(taus), "taus", ndim=1))
    nt = t.size
    if nt < 1:
        raise ValueError("taus: at least one averaging time is needed")
    dev, lo, hi, edf = (np.empty(nt) for _ in range(4))
    cnt = np.empty(nt, dtype=np.intc)
    _lib.call("igea.allan", "igea_stability_allan", a.size, _lib.dptr(a), float(fs), nt,
              _lib.dptr(t), kind_code, noise, float(conf), _lib.dptr(dev), _lib.dptr(lo),
              _lib.dptr(hi), _lib.dptr(edf), _lib.iptr(cnt))
    used = np.empty(nt)
    _lib.call("igea.allan", "igea_stability_taus_used", float(fs), nt, _lib.dptr(t),
              _lib.dptr(used))
    return AllanResult(kind, used, dev, lo, hi, edf, cnt.astype(int), float(conf))


@result
@dataclass(frozen=True)
class NoiseTerms:
    """Noise coefficients read from an Allan curve (NaN: not identified)."""
    random_walk: float          # N: sigma at 1 s of the -1/2 line
    random_walk_tau: float
    bias_instability: float     # B: min sigma / 0.6643
    bias_instability_tau: float
    rate_random_walk: float     # K: sigma at 3 s of the +1/2 line
    rate_random_walk_tau: float
    quantization: float         # Q: sigma at sqrt3 s of the -1 line
    quantization_tau: float

    def summary(self):
        rows = [("random walk N", self.random_walk, self.random_walk_tau),
                ("bias instability B", self.bias_instability, self.bias_instability_tau),
                ("rate random walk K", self.rate_random_walk, self.rate_random_walk_tau),
                ("quantisation Q", self.quantization, self.quantization_tau)]
        return "\n".join("%-20s %12.6g   (read at tau %.6g)" % r for r in rows)


def noise_id(taus, adev):
    """Random walk, bias instability, rate random walk and quantisation from
    an Allan deviation curve (IEEE 952 slope method)."""
    t = np.ascontiguousarray(_lib.as_f64(taus, "taus", ndim=1))
    d = np.ascontiguousarray(_lib.as_f64(adev, "adev", ndim=1, shape=(t.size,)))
    if t.size < 2:
        raise ValueError("taus: at least 2 points are needed")
    out = np.empty(_capi.STABILITY_NOISEID_LEN)
    _lib.call("igea.noise_id", "igea_stability_noise_id", t.size, _lib.dptr(t), _lib.dptr(d),
              _lib.dptr(out))
    slot = {"random_walk": "N", "bias_instability": "B", "rate_random_walk": "K",
            "quantization": "Q"}
    return NoiseTerms(**{f + t: float(out[getattr(_capi, "STABILITY_NOISEID_" + s + t.upper())])
                         for f, s in slot.items() for t in ("", "_tau")})


def stability_taus(n, fs, kind="oadev", *, data_type="freq", spacing="octave"):
    """Averaging times of a spacing (octave, decade, all) for n samples of
    data_type while the kind has at least one term (THEO1: 0.75 m / fs)."""
    where = "igea.stability_taus"
    k = _lib.choice(_capi.CHOICE_STABILITY_KIND, kind, where, "kind")
    dt = _lib.choice(_capi.CHOICE_STABILITY_DATA, data_type, where, "data_type")
    sp = _lib.choice(_capi.CHOICE_STABILITY_TAUS, spacing, where, "spacing")
    cap = 64 if spacing != "all" else max(64, int(n) + 1)
    tau = np.empty(cap)
    nt = ctypes.c_int()
    _lib.call(where, "igea_stability_taus", int(n), float(fs), dt, k, sp, cap, _lib.dptr(tau),
              ctypes.byref(nt))
    return tau[:nt.value].copy()


@result
@dataclass(frozen=True)
class StabilityResult:
    """A Stable32 statistic at its averaging times (field names as in
    'igea stability --json'); lo, hi, edf None for mtie and tierms; alpha:
    the noise exponent used at each tau."""
    kind: str
    data_type: str
    taus: np.ndarray
    dev: np.ndarray
    lo: object
    hi: object
    edf: object
    alpha: np.ndarray
    count: np.ndarray
    conf: float

    def summary(self):
        lines = ["%s (%s data), %.1f %% intervals" % (self.kind, self.data_type, 100 * self.conf),
                 "%12s %14s %14s %14s %10s %6s %10s" % ("tau", "dev", "lo", "hi", "edf", "alpha",
                                                         "terms")]
        for j in range(self.taus.size):
            ci = ("%14.6e %14.6e %10.1f" % (self.lo[j], self.hi[j], self.edf[j])
                  if self.lo is not None else "%14s %14s %10s" % ("-", "-", "-"))
            lines.append("%12.6g %14.6e %s %6d %10d" % (self.taus[j], self.dev[j], ci,
                                                         self.alpha[j], self.count[j]))
        return "\n".join(lines)


def stability(data, fs, taus=None, *, kind="oadev", data_type="freq", noise="auto", conf=0.683):
    """Stable32's statistic `kind` (adev oadev mdev tdev hdev ohdev totdev
    mtotdev ttotdev htotdev theo1 theobr theoh mtie tierms) of phase
    (seconds) or frequency data sampled at fs, at the averaging times taus
    (None or 'octave', 'decade', 'all': generated; theo1 and theobr: tau =
    0.75 m / fs, m even; theoh: the Allan deviation below its switch, theobr
    from it on), with the kind's EDF (Greenhall's, Howe's total-family
    tables, Theo1's) and chi-square intervals at confidence conf; noise
    'auto' identifies the type at each tau on its own (theobr: from its bias
    factor)."""
    where = "igea.stability"
    a = _record(data)
    k = _lib.choice(_capi.CHOICE_STABILITY_KIND, kind, where, "kind")
    if kind in _LEGACY:
        raise ValueError(f"{where}: kind: {kind!r} is a rate-data kind of igea.allan; use adev, "
                         "oadev or mdev")
    dt = _lib.choice(_capi.CHOICE_STABILITY_DATA, data_type, where, "data_type")
    nz = _lib.choice(_capi.CHOICE_STABILITY_NOISE, noise, where, "noise")
    if taus is None or isinstance(taus, str):
        t = stability_taus(a.size, fs, kind, data_type=data_type, spacing=taus or "octave")
    else:
        t = np.ascontiguousarray(_lib.as_f64(np.atleast_1d(taus), "taus", ndim=1))
    nt = t.size
    if nt < 1:
        raise ValueError(f"{where}: taus: at least one averaging time is needed")
    ci = kind not in _NO_INTERVAL
    dev, lo, hi, edf, used = (np.empty(nt) for _ in range(5))
    alpha, cnt = np.empty(nt, dtype=np.intc), np.empty(nt, dtype=np.intc)
    _lib.call(where, "igea_stability_dev", a.size, _lib.dptr(a), float(fs), dt, nt, _lib.dptr(t),
              k, nz, float(conf), _lib.dptr(dev), _lib.dptr(lo) if ci else None,
              _lib.dptr(hi) if ci else None, _lib.dptr(edf) if ci else None, _lib.iptr(alpha),
              _lib.iptr(cnt), _lib.dptr(used))
    return StabilityResult(kind, data_type, used, dev, lo if ci else None, hi if ci else None,
                           edf if ci else None, alpha.astype(int), cnt.astype(int), float(conf))


FIT_TERMS = ("quantization", "random_walk", "bias_instability", "rate_random_walk", "rate_ramp")


@result
@dataclass(frozen=True)
class NoiseFit:
    """IEEE Std 952 noise model fitted to an Allan curve: value and se of
    Q, N, B, K, R (units of the data times s, sqrt(s), 1, 1/sqrt(s), 1/s);
    supported: the terms the data support (likelihood ratio)."""
    terms: tuple
    value: np.ndarray
    se: np.ndarray
    supported: np.ndarray
    chi2: float
    boot: int = 0   # bootstrap records behind se (0: the fit's independent-point se)
    lo: object = None   # bootstrap interval at conf (None without the bootstrap)
    hi: object = None
    conf: float = float("nan")

    def summary(self):
        return "\n".join("%-18s %12.6g +- %-12.3g %s" % (t, v, e, "" if s else "(not supported)")
                         for t, v, e, s in zip(self.terms, self.value, self.se, self.supported))


_BOOT_KINDS = ("overlapping", "nonoverlapping", "adev", "oadev", "totdev")


def noise_fit(taus, adev, edf, *, n=None, fs=None, kind="adev", boot=200, seed=0, conf=0.95):
    """Weighted least-squares fit (non-negative coefficients) of the whole
    Allan variance curve adev(taus)^2 with equivalent degrees of freedom
    edf to quantisation, random walk, bias instability, rate random walk
    and rate ramp. With n and fs (the rate record's samples and rate behind
    the curve, of `kind`), se comes from `boot` records simulated from the
    fitted model (igea_stability_fit_boot), which carries the correlation of
    the points, with the interval [lo, hi] at confidence conf; without them,
    from the fit's weights (independent points, optimistic)."""
    where = "igea.noise_fit"
    if (n is None) != (fs is None):
        raise ValueError(f"{where}: n and fs go together (the record behind the curve)")
    t = np.ascontiguousarray(_lib.as_f64(taus, "taus", ndim=1))
    d = np.ascontiguousarray(_lib.as_f64(adev, "adev", ndim=1, shape=(t.size,)))
    e = np.ascontiguousarray(_lib.as_f64(edf, "edf", ndim=1, shape=(t.size,)))
    if t.size < 5:
        raise ValueError(f"{where}: taus: at least 5 points are needed, got {t.size}")
    p = _capi.STABILITY_FIT_LEN
    v, se = np.empty(p), np.empty(p)
    sup = np.empty(p, dtype=np.intc)
    c2 = ctypes.c_double()
    if n is None:
        _lib.call(where, "igea_stability_fit", t.size, _lib.dptr(t), _lib.dptr(d), _lib.dptr(e),
                  _lib.dptr(v), _lib.dptr(se), _lib.iptr(sup), ctypes.byref(c2))
        return NoiseFit(FIT_TERMS, v, se, sup.astype(bool), float(c2.value))
    if kind not in _BOOT_KINDS:
        raise ValueError(f"{where}: kind: one of {', '.join(_BOOT_KINDS)}, got {kind!r}")
    k = _lib.choice(_capi.CHOICE_STABILITY_KIND, kind, where, "kind")
    lo, hi = np.empty(p), np.empty(p)
    _lib.call(where, "igea_stability_fit_boot", int(n), float(fs), k, t.size, _lib.dptr(t),
              _lib.dptr(d), _lib.dptr(e), int(boot), int(seed), float(conf), _lib.dptr(v),
              _lib.dptr(se), _lib.dptr(lo), _lib.dptr(hi), _lib.iptr(sup), ctypes.byref(c2))
    return NoiseFit(FIT_TERMS, v, se, sup.astype(bool), float(c2.value), int(boot), lo, hi,
                    float(conf))
