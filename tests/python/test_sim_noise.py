"""The simulator's noise models (IGEA_SIM_OPT_AR2 .. BIAS1) against their
definitions: sample moments over many flights of a zero geometry (dw is
the noise alone), compared with the AR autocorrelation from the
MA(infinity) weights and with the stated correlation, sigma_w and bias,
within 4.5 standard errors of the Monte Carlo mean (two-sided normal
interval, each check false with probability < 1e-5)."""
import ctypes

import numpy as np
import pytest

from igea import _capi, _lib

lib = _lib.lib


def ar_autocorr(phi, n):
    L = 5000
    psi = np.zeros(L)
    psi[0] = 1
    for j in range(1, L):
        psi[j] = sum(phi[k] * psi[j - 1 - k] for k in range(len(phi)) if j - 1 - k >= 0)
    g = np.array([psi[:L - k] @ psi[k:] for k in range(n)])
    return g / g[0]


def flights(M, F, **slots):
    m = 3 * M
    S = np.zeros((m, 1), order="F")
    h = ctypes.c_void_p()
    _lib.call("t", "igea_sim_model_create", m, 1, _lib.dptr(S), m, ctypes.byref(h))
    sig = np.array([0.01])
    _lib.call("t", "igea_sim_model_set_sigma", h, _lib.dptr(sig), 0, 0.0)
    opts = np.zeros(_capi.SIM_OPT_LEN)
    lib.igea_sim_defaults(_lib.dptr(opts))
    for k, v in slots.items():
        opts[getattr(_capi, "SIM_OPT_" + k.upper())] = v
    _lib.call("t", "igea_sim_model_set_noise", h, _lib.dptr(opts))
    out = np.empty((F, M, 3))
    dw = np.empty(m)
    for f in range(F):
        _lib.call("t", "igea_sim_flight", h, 1, f, None, _lib.dptr(dw))
        out[f] = dw.reshape(M, 3) / 0.01
    lib.igea_sim_model_free(h)
    return out


def close(x, ref, se):
    assert abs(x - ref) <= 4.5 * se, (x, ref, se)


def test_ar2_stationary_from_the_first_epoch():
    phi = [0.5, 0.3]
    F, M = 4000, 12
    e = flights(M, F, ar1=phi[0], ar2=phi[1])
    rho = ar_autocorr(phi, 3)
    for t in (0, 1, 5, 11):  # unit variance at every epoch, the first ones included
        v = e[:, t, :].ravel()
        close(np.mean(v ** 2), 1.0, np.std(v ** 2) / np.sqrt(v.size))
    for k in (1, 2):
        prod = (e[:, 0, :] * e[:, k, :]).ravel()
        close(prod.mean(), rho[k], prod.std() / np.sqrt(prod.size))
        prod = (e[:, 6, :] * e[:, 6 + k, :]).ravel()
        close(prod.mean(), rho[k], prod.std() / np.sqrt(prod.size))


def test_correlation_ramp_and_two_groups():
    F, M = 4000, 10
    e = flights(M, F, corr=0.9, group_split=0.5, sigma_w=1.0, sigma_w2=3.0, bias0=0.5, bias1=-2.0)
    last = e[:, -1, :] - (-2.0)  # group 1: bias -2 stated sigmas, sd 3
    R = np.array([[1, 0.9, 0.81], [0.9, 1, 0.9], [0.81, 0.9, 1]]) * 9.0
    for a in range(3):
        for b in range(3):
            p = last[:, a] * last[:, b]
            close(p.mean(), R[a, b], p.std() / np.sqrt(F))
    first = e[:, 0, :] - 0.5  # group 0, epoch 0: r = 0, sd 1
    p = first[:, 0] * first[:, 1]
    close(p.mean(), 0.0, p.std() / np.sqrt(F))
    v = first.ravel() ** 2
    close(v.mean(), 1.0, v.std() / np.sqrt(v.size))
    close(e[:, :5, :].mean(), 0.5, e[:, :5, :].std() / np.sqrt(e[:, :5, :].size))


def test_general_generator_equals_the_seed_generator():
    # group_split 0.99 of 8 epochs puts none in group 1 but takes the general
    # generator: the same draws, the same AR(1) with outliers
    a = flights(8, 3, ar1=0.6, outlier_prob=0.2)
    b = flights(8, 3, ar1=0.6, outlier_prob=0.2, group_split=0.99)
    np.testing.assert_allclose(a, b, rtol=1e-13, atol=1e-13)


def test_non_stationary_ar_refused():
    opts = np.zeros(_capi.SIM_OPT_LEN)
    lib.igea_sim_defaults(_lib.dptr(opts))
    opts[_capi.SIM_OPT_AR1] = 0.6
    opts[_capi.SIM_OPT_AR2] = 0.5
    assert lib.igea_sim_check_opts(_lib.dptr(opts)) == 1 + _capi.SIM_OPT_AR2
