"""Seed 002's Table 1 (100-s variance, 3 sigma) per sensor and per fused
channel (igea.redund_stability, igea redund stability) against numpy
written here: block means of 100-s blocks, 3 x their sample sd (ddof 1);
the fused channel as the plain mean, or the weighted mean with weights
1 / each sensor's block variance; seed 002's layout (4 X, 2 Y, 2 Z
accelerometers, 6 gyros two per axis)."""
import json
import os
import subprocess

import numpy as np
import pytest

import igea


def blocks3(y, fs, block):
    nb = int(round(block * fs))
    B = len(y) // nb
    m = y[:B * nb].reshape(B, nb).mean(axis=1)
    return 3 * m.std(ddof=1)


def record(rng, n=20000, fs=10.0):
    """14 channels of a 2000-s static record: white noise plus a slow random
    walk (so that the block statistic is not only white), the noise levels
    differing from sensor to sensor."""
    sd = np.array([3, 4, 5, 3.5, 6, 7, 6, 8, 1, 1.2, 1, 1.5, 2, 1.8]) * 1e-5
    w = sd * rng.standard_normal((n, 14))
    rw = np.cumsum(0.02 * sd * rng.standard_normal((n, 14)), axis=0)
    return w + rw + np.arange(14) * 1e-3, fs


CHANNEL = [0, 0, 0, 0, 1, 1, 2, 2, 3, 3, 4, 4, 5, 5]


@pytest.mark.parametrize("average", [True, False])
def test_against_numpy(average):
    rng = np.random.default_rng(20)
    y, fs = record(rng)
    r = igea.redund_stability(y, fs, CHANNEL, block=100.0, average=average)
    assert r.block_seconds == 100.0
    want = [blocks3(y[:, i], fs, 100.0) for i in range(14)]
    np.testing.assert_allclose(r.three_sigma, want, rtol=1e-10)
    ch = np.array(CHANNEL)
    wts = 1.0 / (np.array(want) / 3) ** 2
    for c in range(6):
        cols = np.flatnonzero(ch == c)
        w = np.ones(len(cols)) if average else wts[cols]
        fused = y[:, cols] @ (w / w.sum())
        np.testing.assert_allclose(r.fused[:, c], fused, rtol=1e-12)
        assert r.fused_three_sigma[c] == pytest.approx(blocks3(fused, fs, 100.0), rel=1e-9)


def test_unfused_sensor_and_refusals():
    rng = np.random.default_rng(3)
    y, fs = record(rng, n=4000)
    r = igea.redund_stability(y[:, :3], fs, [0, -1, 0], block=100.0, average=True)
    np.testing.assert_allclose(r.fused[:, 0], (y[:, 0] + y[:, 2]) / 2, rtol=1e-12)
    with pytest.raises(igea.IgeaError):          # channel 1 has no sensor
        igea.redund_stability(y[:, :3], fs, [0, 2, 0])
    with pytest.raises(igea.IgeaError):          # one 100-s block only
        igea.redund_stability(y[:1500, :3], fs, [0, 0, 0])
    with pytest.raises(igea.IgeaError):          # a constant sensor cannot be weighted
        flat = y[:, :2].copy()
        flat[:, 1] = 1.0
        igea.redund_stability(flat, fs, [0, 0])


def test_driver(tmp_path):
    rng = np.random.default_rng(4)
    y, fs = record(rng, n=6000)
    np.save(tmp_path / "rec.npy", y)
    out = subprocess.run([os.environ["IGEA_DRIVER"], "redund", "stability", "--data",
                          str(tmp_path / "rec.npy"), "--fs", "10", "--channels",
                          ",".join(map(str, CHANNEL)), "--json"],
                         capture_output=True, text=True, check=True)
    js = json.loads(out.stdout)
    r = igea.redund_stability(y, fs, CHANNEL)
    np.testing.assert_allclose(js["three_sigma"], r.three_sigma, rtol=1e-12)
    np.testing.assert_allclose(js["fused_three_sigma"], r.fused_three_sigma, rtol=1e-12)
    assert js["block_seconds"] == 100.0 and js["channel"] == CHANNEL
    bad = subprocess.run([os.environ["IGEA_DRIVER"], "redund", "stability", "--data",
                          str(tmp_path / "rec.npy"), "--fs", "10", "--channels", "0,1"],
                         capture_output=True, text=True)
    assert bad.returncode in (64, 65) and "--channels" in bad.stderr
