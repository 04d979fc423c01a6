"""Stability statistics of a sensor record (METHODS 3.4): the block-mean
("100-second") 3-sigma statistic, Allan deviations with EDF confidence
intervals, noise identification from the Allan curve."""
import ctypes
from dataclasses import dataclass

import numpy as np

from . import _capi, _lib



def _record(y):
    a = _lib.as_f64(y, "y", ndim=1)
    if a.size < 2:
        raise ValueError(f"y: at least 2 samples are needed, got {a.size}")
    return np.ascontiguousarray(a)


@dataclass(frozen=True)
class Block3Sigma:
    """Block-mean statistic of METHODS 3.4."""
    three_sigma: float
    sigma: float
    nblock: int
    block_samples: int
    mean: float
    adev: float   # Allan deviation at the block length from the block means

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
                       **_lib.fields(out, "STABILITY_BLOCK_", sigma=float, nblock=int,
                                     mean=float, adev=float))


def octave_taus(n, fs, kind="overlapping"):
    """tau = 2^k / fs while the estimator has at least one term."""
    kind = _lib.choice(_capi.CHOICE_STABILITY_KIND, kind, "igea.octave_taus", "kind")
    tau = np.empty(64)
    nt = ctypes.c_int()
    _lib.call("igea.octave_taus", "igea_stability_octave_taus", int(n), float(fs), kind, 64,
              _lib.dptr(tau), ctypes.byref(nt))
    return tau[:nt.value].copy()


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
    power-law type for the EDF (wpm, fpm, wfm, ffm, rwfm) or auto."""
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
    used = np.round(t * fs) / fs
    return AllanResult(kind, used, dev, lo, hi, edf, cnt.astype(int), float(conf))


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
