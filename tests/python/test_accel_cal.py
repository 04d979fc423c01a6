"""igea.accel_apply, accel_hysteresis and accel_joint against models and
statistics written here in numpy/scipy."""
import json
import os
import subprocess

import numpy as np
import pytest
from scipy import stats

import igea

ARCSEC = np.pi / 180 / 3600


def exact_pair(K, phi):
    """METHODS 4.2 eqs. (1)-(2): A at phi, B at phi + eta."""
    sa, ca = np.sin(phi), np.cos(phi)
    sb, cb = np.sin(phi + K[4]), np.cos(phi + K[4])
    ya = K[0] + (1 + K[2]) * sa + K[5] * sa ** 2 + K[7] * sa * ca
    yb = K[1] + (1 + K[3]) * cb + K[6] * cb ** 2 - K[8] * cb * sb
    return ya, yb


def test_apply_dual_round_trip():
    K = np.array([2e-3, -1.5e-3, 3e-3, -2e-3, 5e-3, 2e-3, -1e-3, 1e-3, -2e-3])
    phi = np.deg2rad(np.linspace(-170, 175, 40))
    ya, yb = exact_pair(K, phi)
    out = igea.accel_apply(4.0 * ya, K, 4.0 * yb, scale_a=4.0, scale_b=4.0)
    np.testing.assert_allclose(out.u, np.sin(phi), rtol=0, atol=2e-15)
    np.testing.assert_allclose(out.v, np.cos(phi), rtol=0, atol=2e-15)
    # the simulator, noise-free, with an installation angle
    th = igea.accel_schedule(20)
    truth = np.append(K, 1e-3)
    sa, sb = igea.accel_simulate(th, truth, head_sd_arcsec=0, noise_sd=0)
    out = igea.accel_apply(sa, K, sb)
    np.testing.assert_allclose(out.u, np.sin(np.deg2rad(th) + 1e-3), atol=2e-15)


def test_apply_single_and_errors():
    K = np.array([1e-3, -2e-3, 3e-4, 4e-3, -3e-3])
    u = np.linspace(-1, 1, 15)
    v = np.sqrt(1 - u ** 2)
    y = K[0] + (1 + K[1]) * u + K[2] * v + K[3] * u ** 2 + K[4] * u * v
    out = igea.accel_apply(2.5 * y, K, model="single", scale_a=2.5, cross=v)
    np.testing.assert_allclose(out.u, u, atol=2e-15)
    assert out.v is None
    # without the cross axis: the quadratic's root closest to y, numpy
    r = np.array([np.roots([K[3], 1 + K[1], K[0] - yi]) for yi in y])
    want = r[np.arange(len(y)), np.argmin(np.abs(r - y[:, None]), axis=1)].real
    np.testing.assert_allclose(igea.accel_apply(y, K, model="single").u, want, atol=1e-15)
    with pytest.raises(igea.IgeaError):
        igea.accel_apply(y, K, model="single", scale_a=0.0)
    with pytest.raises(ValueError):
        igea.accel_apply(y, np.zeros(9))
