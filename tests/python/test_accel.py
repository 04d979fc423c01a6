"""igea.accel_* against an independent numpy implementation of METHODS 4.1-4.3."""
import json
import os
import subprocess

import numpy as np
import pytest

import igea

TH20 = np.arange(20) * 18.0
BETA = np.array([2, -1.5, 3, -2, 0.5, 0.2, -0.1, 0.1, -0.2]) * 1e-4


def ref_design(theta, model):
    t = np.deg2rad(theta)
    s, c = np.sin(t), np.cos(t)
    if model == "single":
        return np.column_stack([np.ones_like(s), s, c, s * s, s * c])
    return np.column_stack([s, c, s * s, c * c, -s * c, s ** 3, c ** 3, s * s * c, -s * c * c])


def outputs_for(theta, y):
    rho = np.sqrt(1 + 2 * y)
    t = np.deg2rad(theta)
    return rho * np.sin(t), rho * np.cos(t)


def ebr_vector(a):
    t = np.deg2rad(TH20)
    y = ref_design(TH20, "dual") @ BETA + a * np.cos(7 * t + 0.3) + a / 2 * np.sin(5 * t)
    return outputs_for(TH20, y)


def test_design_matches_numpy_and_methods():
    for model in ("single", "dual"):
        th = np.array([0, 17.5, 90, 200, -33.0, 359])
        np.testing.assert_allclose(igea.accel_design(th, model=model), ref_design(th, model),
                                   atol=1e-15)
    A = igea.accel_design(TH20)
    assert A.shape == (20, 9)
    G = A.T @ A
    want = np.array([[10, 0, 0, 0, 0, 7.5, 0, 0, -2.5], [0, 10, 0, 0, 0, 0, 7.5, 2.5, 0],
                     [0, 0, 7.5, 2.5, 0, 0, 0, 0, 0], [0, 0, 2.5, 7.5, 0, 0, 0, 0, 0],
                     [0, 0, 0, 0, 2.5, 0, 0, 0, 0], [7.5, 0, 0, 0, 0, 6.25, 0, 0, -1.25],
                     [0, 7.5, 0, 0, 0, 0, 6.25, 1.25, 0], [0, 2.5, 0, 0, 0, 0, 1.25, 1.25, 0],
                     [-2.5, 0, 0, 0, 0, -1.25, 0, 0, 1.25]])
    np.testing.assert_allclose(G, want, atol=1e-13)
    Gs = igea.accel_design(TH20, model="single")
    np.testing.assert_allclose(Gs.T @ Gs, [[20, 0, 0, 10, 0], [0, 10, 0, 0, 0], [0, 0, 10, 0, 0],
                                           [10, 0, 0, 7.5, 0], [0, 0, 0, 0, 2.5]], atol=1e-13)


def test_analyze_against_numpy_svd():
    info = igea.accel_analyze(TH20)
    sv = np.linalg.svd(ref_design(TH20, "dual"), compute_uv=False)
    np.testing.assert_allclose(info.singular_values, sv, atol=1e-13)
    assert info.rank == 7
    r3 = 1 / np.sqrt(3)
    np.testing.assert_allclose(info.null_space[:, 0], [r3, 0, 0, 0, 0, -r3, 0, 0, r3], atol=1e-13)
    np.testing.assert_allclose(info.null_space[:, 1], [0, r3, 0, 0, 0, 0, -r3, -r3, 0], atol=1e-13)
    # the null space really is the numpy one (projector equality)
    _, _, vt = np.linalg.svd(ref_design(TH20, "dual"))
    Pn = vt[7:].T @ vt[7:]
    np.testing.assert_allclose(info.null_space @ info.null_space.T, Pn, atol=1e-12)
    np.testing.assert_allclose(info.loading, np.sqrt(np.diag(Pn)), atol=1e-12)
    assert np.all(info.comb_loading < 1e-12)
    assert "KBio" in info.summary() and "prior-determined" in info.summary()


def test_combinations():
    C = igea.accel_combinations()
    # every combination is orthogonal to the null space: estimable
    info = igea.accel_analyze(TH20)
    np.testing.assert_allclose(info.null_space.T @ C, 0, atol=1e-13)
    assert np.linalg.matrix_rank(C) == 7
    np.testing.assert_array_equal(igea.accel_combinations("single"), np.eye(5))


def test_fit_ls_dual_min_norm_against_pinv():
    ya, yb = ebr_vector(3e-4)
    f = igea.accel_fit(TH20, ya, yb)
    A = ref_design(TH20, "dual")
    y = 0.5 * (ya ** 2 + yb ** 2 - 1)
    x = np.linalg.pinv(A) @ y
    np.testing.assert_allclose(f.coef, x, rtol=1e-9, atol=1e-16)
    s2 = np.sum((y - A @ x) ** 2) / 13
    cov = s2 * np.linalg.pinv(A.T @ A)
    np.testing.assert_allclose(f.sd, np.sqrt(np.diag(cov)), rtol=1e-8)
    C = igea.accel_combinations()
    np.testing.assert_allclose(f.comb, C.T @ x, rtol=1e-9, atol=1e-16)
    np.testing.assert_allclose(f.comb_sd, np.sqrt(np.diag(C.T @ cov @ C)), rtol=1e-8)
    assert f.flags == ["prior", "prior", "data", "data", "data", "prior", "prior", "prior", "prior"]
    assert (f.rank, f.dof, f.positions) == (7, 13, 20)
    assert "PRIOR" in f.summary() and "KA0+KA2" in f.summary()


def ref_ebr_sc(A, y):
    """METHODS 4.3 steps 1-7 with D_s = I, rule (17), independent of the C code."""
    from scipy.optimize import brentq
    U, s, vt = np.linalg.svd(A, full_matrices=False)
    r = int(np.sum(s > max(A.shape) * np.finfo(float).eps * s[0]))
    z = U[:, :r].T @ y
    d = s[:r] ** 2
    S = y @ y - z @ z
    N = len(y)
    rhs = (r - 2) / (N - r + 2)
    G = lambda lam: np.sum(z ** 2 / (1 + lam * d)) / S - rhs  # noqa: E731
    hi = 1.0
    while G(hi) > 0:
        hi *= 10
    lam = brentq(G, 0, hi, xtol=1e-300, rtol=1e-15)
    theta = lam * d / (1 + lam * d) * (z / np.sqrt(d))
    return vt[:r].T @ theta, lam


def test_fit_ebr_against_reference():
    for a, lam_methods in [(1e-6, 4.3191821286e4), (3e-5, 4.7812680709e1), (3e-4, 3.1903350644e-1)]:
        ya, yb = ebr_vector(a)
        f = igea.accel_fit(TH20, ya, yb, method="ebr")
        A = ref_design(TH20, "dual")
        beta, lam = ref_ebr_sc(A, 0.5 * (ya ** 2 + yb ** 2 - 1))
        assert f.lam == pytest.approx(lam, rel=1e-8)
        assert f.lam == pytest.approx(lam_methods, rel=1e-8)
        np.testing.assert_allclose(f.coef, beta, rtol=1e-7, atol=1e-14)
    np.testing.assert_allclose(
        f.coef, [1.156185e-4, -8.07093e-5, 1.917349e-4, -1.155993e-4, 2.21849e-5, 7.84732e-5,
                 -5.76305e-5, -2.30789e-5, -3.71453e-5], rtol=5e-6)


def test_fit_single_against_lstsq_and_volts():
    rng = np.random.default_rng(3)
    truth = np.append(BETA, 2e-5)
    ya, _ = igea.accel_simulate(TH20, truth, head_sd_arcsec=1.0, noise_sd=1e-6, seed=4)
    f = igea.accel_fit(TH20, ya, model="single")
    A = ref_design(TH20, "single")
    y = ya - np.sin(np.deg2rad(TH20))
    x, *_ = np.linalg.lstsq(A, y, rcond=None)
    np.testing.assert_allclose(f.coef, x, rtol=1e-9)
    s2 = np.sum((y - A @ x) ** 2) / 15
    np.testing.assert_allclose(f.sd, np.sqrt(s2 * np.diag(np.linalg.inv(A.T @ A))), rtol=1e-8)
    assert f.flags == ["data"] * 5
    assert f.names == ["K0", "k1", "delta0", "K2", "Kio"]
    # raw volts with a nominal scale factor give the same fit
    scale = 2.4995 + rng.random() * 0.001
    g = igea.accel_fit(TH20, ya * scale, model="single", scale_a=scale)
    np.testing.assert_allclose(g.coef, f.coef, rtol=1e-9, atol=1e-15)
    assert igea.accel_fit(TH20, ya, model="single", axis="oa").names[-1] == "Kip"


def test_noise_free_simulation_recovers_combinations():
    truth = np.append(BETA * 1e-7, 0.0)
    ya, yb = igea.accel_simulate(TH20, truth, head_sd_arcsec=1.0, noise_sd=0.0, seed=9)
    f = igea.accel_fit(TH20, ya, yb)
    C = igea.accel_combinations()
    np.testing.assert_allclose(f.comb, C.T @ truth[:9], atol=2e-15)


def test_simulate_matches_models():
    truth = np.array([1e-3, -2e-4, 3e-4, -2e-4, 5e-5, 2e-5, -1e-5, 1e-5, -2e-5, 3e-4])
    ya, yb = igea.accel_simulate(TH20, truth, head_sd_arcsec=0, noise_sd=0)
    phi = np.deg2rad(TH20) + truth[9]
    b = phi + truth[4]
    fa = truth[0] + (1 + truth[2]) * np.sin(phi) + truth[5] * np.sin(phi) ** 2 \
        + truth[7] * np.sin(phi) * np.cos(phi)
    fb = truth[1] + (1 + truth[3]) * np.cos(b) + truth[6] * np.cos(b) ** 2 \
        - truth[8] * np.cos(b) * np.sin(b)
    np.testing.assert_allclose(ya, fa, atol=1e-15)
    np.testing.assert_allclose(yb, fb, atol=1e-15)
    a1, _ = igea.accel_simulate(TH20, truth, seed=5)
    a2, _ = igea.accel_simulate(TH20, truth, seed=5)
    np.testing.assert_array_equal(a1, a2)


def test_merge_and_schedule():
    np.testing.assert_allclose(igea.accel_schedule(20), TH20, atol=1e-13)
    ang = np.concatenate([np.arange(21) * 18.0, 360 - np.arange(21) * 18.0])
    ya = np.sin(np.deg2rad(ang)) + np.where(np.arange(42) < 21, 1e-6, -1e-6)
    yb = np.cos(np.deg2rad(ang))
    th, ma, mb, cnt = igea.accel_merge(ang, ya, yb)
    np.testing.assert_allclose(th, TH20, atol=1e-12)
    np.testing.assert_allclose(ma, np.sin(np.deg2rad(TH20)), atol=1e-15)
    np.testing.assert_allclose(mb, np.cos(np.deg2rad(TH20)), atol=1e-15)
    assert cnt[0] == 4 and np.all(cnt[1:] == 2)
    th1, ma1, mb1, _ = igea.accel_merge(ang, ya)
    assert mb1 is None and len(th1) == 20


def test_refine_from_truth_null_part():
    truth = np.array([1.2e-3, -0.9e-3, 3e-4, -2e-4, 0.5e-4, 0.2e-4, -0.1e-4, 0.1e-4, -0.2e-4,
                      4e-4])
    ya, yb = igea.accel_simulate(TH20, truth, head_sd_arcsec=1.0, noise_sd=0.0, seed=21)
    start = truth[:9].copy()
    start[2] += 1e-5
    r = igea.accel_refine(TH20, ya, yb, start)
    np.testing.assert_allclose(r.coef, truth[:9], atol=1e-13)
    assert "refinement" in r.summary()


def test_shapes_and_errors():
    with pytest.raises(ValueError, match="theta_deg"):
        igea.accel_design(np.zeros((2, 2)))
    with pytest.raises(ValueError, match="model"):
        igea.accel_design(TH20, model="triple")
    with pytest.raises(ValueError, match="y_a"):
        igea.accel_fit(TH20, np.zeros(19), np.zeros(20))
    with pytest.raises(ValueError, match="y_b"):
        igea.accel_fit(TH20, np.zeros(20))
    with pytest.raises(ValueError, match="y_b"):
        igea.accel_fit(TH20, np.zeros(20), np.zeros(3))
    with pytest.raises(ValueError, match="method"):
        igea.accel_fit(TH20, np.zeros(20), np.zeros(20), method="pcr")
    with pytest.raises(ValueError, match="rule"):
        igea.accel_fit(TH20, np.zeros(20), np.zeros(20), rule="x")
    with pytest.raises(ValueError, match="prior"):
        igea.accel_fit(TH20, np.zeros(20), np.zeros(20), method="ebr", prior=np.ones(5))
    with pytest.raises(ValueError, match="truth"):
        igea.accel_simulate(TH20, np.zeros(4))
    ya, yb = ebr_vector(3e-5)
    with pytest.raises(igea.IgeaError) as e:
        igea.accel_fit(TH20, ya, yb, method="ebr", prior=-np.ones(9))
    assert e.value.code == -1012
    bad = ya.copy()
    bad[3] = np.nan
    with pytest.raises(igea.IgeaError) as e:
        igea.accel_fit(TH20, bad, yb)
    assert e.value.code == -1011
    with pytest.raises(igea.IgeaError, match="lam_floor"):
        igea.accel_fit(TH20, ya, yb, method="ebr", lam_floor=-1)
    with pytest.raises(igea.IgeaError, match="tol_deg"):
        igea.accel_merge(TH20, ya, tol_deg=50)
    with pytest.raises(igea.IgeaError, match="scale"):
        igea.accel_to_g(ya, 0.0)
    with pytest.raises(igea.IgeaError, match="head_sd"):
        igea.accel_simulate(TH20, BETA, head_sd_arcsec=-1)
    with pytest.raises(igea.IgeaError, match="max_iter"):
        igea.accel_refine(TH20, ya, yb, np.zeros(9), max_iter=0)


def test_frozen():
    ya, yb = ebr_vector(3e-5)
    f = igea.accel_fit(TH20, ya, yb)
    with pytest.raises(Exception):
        f.rank = 3


# ---- the driver ------------------------------------------------------------
DRIVER = os.environ.get("IGEA_DRIVER")
needs_driver = pytest.mark.skipif(not DRIVER or not os.path.exists(DRIVER),
                                  reason="IGEA_DRIVER not set")


def _write_experiment(path, truth, seed=5, volts=1.0):
    ccw = np.arange(21) * 18.0
    ang = np.concatenate([ccw, ccw[::-1]])
    ya, yb = igea.accel_simulate(ang, truth, head_sd_arcsec=1.0, noise_sd=1e-6, seed=seed)
    np.savetxt(path, np.column_stack([ang, ya * volts, yb * volts]), fmt="%.15g",
               header="angle A B")
    return ang, ya, yb


@needs_driver
def test_driver_json_matches_python(tmp_path):
    truth = np.append(BETA, 2e-4)
    f = tmp_path / "cal.txt"
    ang, ya, yb = _write_experiment(f, truth, volts=2.5)
    prior = tmp_path / "prior.txt"
    tau = np.array([1e-4] * 5 + [1e-5] * 4)
    np.savetxt(prior, tau)
    th, ma, mb, _ = igea.accel_merge(ang, ya, yb)
    for extra, kw in [([], {}), (["--method", "ebr", "--prior", str(prior)],
                                 dict(method="ebr", prior=tau))]:
        out = subprocess.run([DRIVER, "accel", "--json", "--scale-a", "2.5", "--scale-b", "2.5",
                              *extra, "--data", str(f)], capture_output=True, text=True)
        assert out.returncode == 0, out.stderr
        js = json.loads(out.stdout)
        ref = igea.accel_fit(th, ma, mb, **kw)
        np.testing.assert_allclose(js["coef"], ref.coef, rtol=1e-8, atol=1e-15)
        np.testing.assert_allclose(js["comb_sd"], ref.comb_sd, rtol=1e-6)
        assert js["flags"] == ref.flags
        assert js["names"][7] == "KAio" and js["positions"] == 20 and js["readings"] == 42
        assert js["readings_per_position"][0] == 4


@needs_driver
def test_driver_table_single_refine_and_errors(tmp_path):
    f = tmp_path / "cal.txt"
    _write_experiment(f, np.append(BETA, 0.0))
    out = subprocess.run([DRIVER, "accel", "--data", str(f)], capture_output=True, text=True)
    assert out.returncode == 0 and "PRIOR" in out.stdout and "KA0+KA2" in out.stdout
    out = subprocess.run([DRIVER, "accel", "--model", "single", "--axis", "oa", "--data", str(f)],
                         capture_output=True, text=True)
    assert out.returncode == 0 and "Kip" in out.stdout and "PRIOR" not in out.stdout
    o = tmp_path / "rep.json"
    out = subprocess.run([DRIVER, "accel", "--refine", "--json", "--out", str(o), "--data", str(f)],
                         capture_output=True, text=True)
    assert out.returncode == 0 and out.stdout == ""
    assert "refined" in json.loads(o.read_text())
    h = subprocess.run([DRIVER, "accel", "--help"], capture_output=True, text=True)
    assert h.returncode == 0 and "igea accel" in h.stdout
    for args, code in [(["--bogus"], 64), (["--model", "triple", "--data", str(f)], 64),
                       (["--refine", "--model", "single", "--data", str(f)], 64),
                       (["--prior", str(f), "--data", str(f)], 64),
                       (["--data", str(tmp_path / "missing.txt")], 66)]:
        r = subprocess.run([DRIVER, "accel", *args], capture_output=True, text=True)
        assert r.returncode == code, (args, r.stderr)
    bad = tmp_path / "bad.txt"
    bad.write_text("0 0.1\n18 0.3\n")
    r = subprocess.run([DRIVER, "accel", "--data", str(bad)], capture_output=True, text=True)
    assert r.returncode == 65
    bad.write_text("0 0.1 1\n18 x 1\n")
    r = subprocess.run([DRIVER, "accel", "--data", str(bad)], capture_output=True, text=True)
    assert r.returncode == 65 and "2:" in r.stderr


def test_names_units_and_combinations_are_the_librarys():
    """The driver's --json names and the Python names are one list (the
    library's), and comb = C^T coef with C of accel_combinations."""
    assert igea.accel.coefficient_names("dual", "oa")[7:] == ["KAip", "KBip"]
    assert igea.accel.combination_names("dual", "pa")[4] == "KA2+KBio"
    assert igea.accel.coefficient_units("single") == ["g", "", "rad", "g/g^2", "g/g^2"]
    with pytest.raises(ValueError, match="axis"):
        igea.accel.coefficient_names("dual", "ia")
    ya, yb = ebr_vector(3e-5)
    fit = igea.accel_fit(TH20, ya, yb)
    ref = igea.accel_refine(TH20, ya, yb, fit.coef, axis="oa")
    C = igea.accel_combinations("dual")
    np.testing.assert_allclose(ref.comb, C.T @ ref.coef, rtol=1e-15, atol=1e-18)
    assert ref.names == igea.accel.coefficient_names("dual", "oa")
