"""igea.accel_ieee_fit (IEEE Std 1293 model, least squares and harmonic
method) and igea.accel_criterion against fits and information matrices
written here in numpy/scipy, and the driver's --model ieee / --design."""
import json
import os
import subprocess

import numpy as np
import pytest
from scipy.optimize import least_squares

import igea

# K0 K1 K2 K3 Kip Kio delta_o delta_p
KTRUE = np.array([2e-4, 2.5, 3e-5, -4e-6, 1e-5, -2e-5, 5e-5, -3e-5])


def model(K, theta_deg, plane):
    """IEEE Std 1293: E = K1 (K0 + ai + K2 ai^2 + K3 ai^3 + Kip ai ap +
    Kio ai ao + do ap - dp ao); IA-PA: ap = cos, IA-OA: ao = cos."""
    t = np.deg2rad(theta_deg)
    ai, x = np.sin(t), np.cos(t)
    ap = np.where(plane == 0, x, 0.0)
    ao = np.where(plane == 1, x, 0.0)
    return K[1] * (K[0] + ai + K[2] * ai ** 2 + K[3] * ai ** 3 + K[4] * ai * ap
                   + K[5] * ai * ao + K[6] * ap - K[7] * ao)


def tumble(n_pa, n_oa, start_oa=0.0, noise=0.0, seed=0):
    th = np.concatenate([igea.accel_schedule(n_pa)] +
                        ([igea.accel_schedule(n_oa, start_oa)] if n_oa else []))
    pl = np.array([0] * n_pa + [1] * n_oa)
    e = model(KTRUE, th, pl)
    if noise:
        e = e + np.random.default_rng(seed).normal(0.0, noise, e.size)
    return th, pl, e


def nonlinear_reference(th, pl, e):
    """Least squares on the coefficients themselves (scipy), covariance
    sigma^2 (J^T J)^-1 from the Jacobian at the solution."""
    r = least_squares(lambda K: model(K, th, pl) - e, x0=np.r_[0, 1.0 * np.sign(e.max()), 0, 0,
                                                                0, 0, 0, 0] +
                      np.r_[0, abs(e).max() - 1, 0, 0, 0, 0, 0, 0], xtol=1e-15, ftol=1e-15,
                      gtol=1e-15, method="lm")
    J = r.jac
    s2 = np.sum(r.fun ** 2) / (e.size - 8)
    return r.x, np.sqrt(np.diag(s2 * np.linalg.inv(J.T @ J)))


@pytest.mark.parametrize("method", ["ls", "harmonic"])
def test_against_nonlinear_least_squares(method):
    th, pl, e = tumble(16, 12, 7.5, noise=2e-6, seed=3)
    fit = igea.accel_ieee_fit(th, e, pl, method=method)
    K, sd = nonlinear_reference(th, pl, e)
    np.testing.assert_allclose(fit.coef, K, rtol=1e-7, atol=1e-13)
    np.testing.assert_allclose(fit.sd, sd, rtol=1e-5)
    assert fit.flags == ["data"] * 8 and fit.rank == 8 and fit.dof == 28 - 8
    assert fit.names == ["K0", "K1", "K2", "K3", "Kip", "Kio", "delta_o", "delta_p"]


def test_noise_free_recovery_and_plane_names():
    th, pl, e = tumble(9, 11, 3.0)
    names = np.where(pl == 0, "ia-pa", "IA-OA")
    for method in ("ls", "harmonic"):
        fit = igea.accel_ieee_fit(th, e, names, method=method)
        np.testing.assert_allclose(fit.coef, KTRUE, rtol=0, atol=1e-13 * KTRUE[1])


def test_one_plane_and_schedule_identifiability():
    th, pl, e = tumble(12, 0)
    fit = igea.accel_ieee_fit(th, e, "ia-pa")
    assert fit.flags == ["data"] * 5 + ["prior", "data", "prior"]
    assert fit.coef[5] == 0 and fit.coef[7] == 0
    # the rank against numpy on the linear design of K1 * (K0, 1, K2, ...)
    th6 = igea.accel_schedule(6)
    s, c = np.sin(np.deg2rad(th6)), np.cos(np.deg2rad(th6))
    A = np.c_[np.ones(6), s, s ** 2, s ** 3, s * c, 0 * s, c, 0 * s]
    crit = igea.accel_criterion(th6, model="ieee", plane="ia-pa")
    assert crit.rank == np.linalg.matrix_rank(A) == 5
    assert crit.flags == ["data", "prior", "data", "prior", "data", "prior", "data", "prior"]
    with pytest.raises(igea.IgeaError):
        igea.accel_ieee_fit(th6, model(KTRUE, th6, np.zeros(6)), "ia-pa", method="harmonic")
    with pytest.raises(ValueError):
        igea.accel_ieee_fit(th6, th6, "ia-xx")


def info_reference(model_name, th, head_ratio=0.0, plane=None):
    """Design rows written here; logdet = (1/r) sum log eig(M/n), varfac =
    n diag(pinv(M))."""
    t = np.deg2rad(th)
    s, c = np.sin(t), np.cos(t)
    if model_name == "single":
        A = np.c_[np.ones_like(s), s, c, s * s, s * c]
    elif model_name == "ieee":
        pa, oa = (plane == 0) * 1.0, (plane == 1) * 1.0
        A = np.c_[np.ones_like(s), s, s ** 2, s ** 3, pa * s * c, oa * s * c, pa * c, oa * c]
    else:
        R = np.c_[s, c, s * s, c * c, -s * c, s ** 3, c ** 3, s * s * c, -s * c * c]
        if model_name == "dual":
            A = R
        else:  # joint: radial rows and the tangential rows z = c r_A - s r_B
            T = np.c_[c, -s, s * c, -s * c, s * s, s * s * c, -s * c * c, s * c * c, s * s * c,
                      np.ones_like(s)]
            A = np.r_[np.c_[R, np.zeros_like(s)], T / np.sqrt(1 + head_ratio ** 2)]
    M = A.T @ A / th.size
    w = np.linalg.eigvalsh(M)
    w = w[w > 1e-12 * w.max()]
    return np.mean(np.log(w)), np.diag(np.linalg.pinv(M, rcond=1e-12))


@pytest.mark.parametrize("case", ["single", "dual", "joint", "ieee", "irregular"])
def test_criterion_against_numpy(case):
    rng = np.random.default_rng(7)
    th = igea.accel_schedule(20)
    plane = None
    if case == "irregular":
        th = np.sort(rng.uniform(0, 360, 15))
    if case == "ieee":
        th = np.r_[igea.accel_schedule(10), igea.accel_schedule(14, 5.0)]
        plane = np.r_[np.zeros(10, int), np.ones(14, int)]
    name = "single" if case == "irregular" else case
    kw = dict(model="dual", method="joint", head_ratio=4.85) if name == "joint" else \
        dict(model=name, plane=plane)
    crit = igea.accel_criterion(th, **kw)
    ld, vf = info_reference(name, th, 4.85, plane)
    np.testing.assert_allclose(crit.logdet, ld, rtol=1e-10)
    keep = np.array(crit.flags) == "data"
    np.testing.assert_allclose(crit.varfac[keep], vf[keep], rtol=1e-8)


def test_single_equispaced_det_is_constant():
    """Every equispaced N >= 5 gives det(M/n) = 1/256 for the single model."""
    for N in (5, 6, 7, 8, 12, 20, 36, 37):
        crit = igea.accel_criterion(igea.accel_schedule(N, 11.0), model="single")
        np.testing.assert_allclose(crit.det, 1 / 256, rtol=1e-11)
        np.testing.assert_allclose(crit.varfac, [3, 2, 2, 8, 8], rtol=1e-11)


DRIVER = os.environ.get("IGEA_DRIVER")
needs_driver = pytest.mark.skipif(not DRIVER or not os.path.exists(DRIVER),
                                  reason="IGEA_DRIVER not set")


def run(*args):
    return subprocess.run([DRIVER, "accel", *args], capture_output=True, text=True)


@needs_driver
def test_driver_ieee_and_design(tmp_path):
    th, pl, e = tumble(12, 12, 7.5, noise=1e-6, seed=5)
    # two readings per position (CW and CCW), merged per plane by the driver
    rows = np.r_[np.c_[th, pl, e], np.c_[th, pl, e][::-1]]
    f = tmp_path / "tumble.txt"
    np.savetxt(f, rows)
    for method in ("ls", "harmonic"):
        p = run("--ieee", method, "--json", "--data", str(f))
        assert p.returncode == 0, p.stderr
        out = json.loads(p.stdout)
        fit = igea.accel_ieee_fit(th, e, pl, method=method)
        np.testing.assert_allclose(out["coef"], fit.coef, rtol=1e-12, atol=1e-18)
        assert out["positions"] == 24 and out["readings"] == 48
        for key in ("names", "units", "flags", "rank", "dof", "method", "model"):
            assert out[key] == getattr(fit, key), key
    p = run("--ieee", "ls", "--data", str(f))
    assert p.returncode == 0 and "delta_p" in p.stdout
    p = run("--design", "--ieee", "ls", "--json", "--data", str(f))
    assert p.returncode == 0, p.stderr
    crit = igea.accel_criterion(rows[:, 0], model="ieee", plane=rows[:, 1].astype(int))
    np.testing.assert_allclose(json.loads(p.stdout)["varfac"], crit.varfac, rtol=1e-13)
    pos = tmp_path / "pos.txt"
    np.savetxt(pos, igea.accel_schedule(20))
    p = run("--design", "--model", "dual", "--method", "joint", "--head-ratio", "4.85", "--json",
            "--data", str(pos))
    assert p.returncode == 0, p.stderr
    out = json.loads(p.stdout)
    crit = igea.accel_criterion(igea.accel_schedule(20), model="dual", method="joint",
                                head_ratio=4.85)
    np.testing.assert_allclose(out["varfac"], crit.varfac, rtol=1e-13)
    assert out["rank"] == 10 and out["names"][-1] == "delta0"
    np.testing.assert_allclose(out["logdet"], crit.logdet, rtol=1e-13)
    # refused input: a plane that is neither 0 nor 1; harmonic on an uneven schedule
    bad = tmp_path / "bad.txt"
    np.savetxt(bad, np.c_[th, np.where(pl == 1, 2, 0), e])
    p = run("--ieee", "ls", "--data", str(bad))
    assert p.returncode == 65 and "row 13 column 2" in p.stderr
    uneven = tmp_path / "uneven.txt"
    th2 = th.copy()
    th2[3] += 2.0
    np.savetxt(uneven, np.c_[th2, pl, e])
    p = run("--ieee", "harmonic", "--data", str(uneven))
    assert p.returncode != 0 and "equispaced" in p.stderr
    p = run("--ieee", "ls", "--method", "ebr", "--data", str(f))
    assert p.returncode == 64 and "--ieee takes its method" in p.stderr
