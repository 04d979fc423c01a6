"""One report for both routes of igea eqerr: the noise models (--cov,
--ar-phi, --groups, --robust) report the verdict rule, the whiteness of
the whitened residuals and the named components as the plain route does,
and write --residuals. Checked against computations written here: the
whitening by the lower Cholesky factor of each epoch's covariance and of
the AR(1) correlation matrix (the Prais-Winsten transform is that factor's
inverse: the unique lower-triangular W with W R W' = I and a positive
diagonal), generalised least squares by numpy, the seed's equivalent
errors from numpy's eigendecomposition, Ljung-Box and runs tests, chi2
and normal quantiles from scipy, and the pooled chi-square test."""
import json
import os
import subprocess

import numpy as np
import pytest
from scipy import linalg, stats

import igea
from test_eqerr_diag import ljung_box, runs_test

N_TERMS = 5
NAMES = ["acc_bias_x", "acc_bias_y", "gyro_bias_z", "acc_scale_x", "align0_y"]


def driver(*args, cwd=None):
    return subprocess.run([os.environ["IGEA_DRIVER"], *map(str, args)], capture_output=True,
                          text=True, cwd=cwd)


def make_flight(seed, M=80, phi=0.0, cov=False):
    """M epochs (rows epoch-major x, y, z), N_TERMS columns; tracking noise
    AR(1) along epochs per axis (phi) or correlated within the epoch (cov)."""
    rng = np.random.default_rng(seed)
    m = 3 * M
    t = np.repeat(np.arange(M, dtype=float), 3) / M
    S = np.column_stack([np.ones(m), t, t ** 2, np.sin(7 * t + np.arange(m) % 3),
                         rng.standard_normal(m)]) * 0.02
    spec = np.array([0.5, 1.0, 2.0, 0.7, 1.5])
    sigma = 0.01 * (1 + 0.5 * rng.random(m))
    C = None
    if cov:
        C = np.empty((M, 3, 3))
        for e in range(M):
            A = rng.standard_normal((3, 3)) * 0.004
            C[e] = A @ A.T + np.diag(rng.uniform(0.5, 1.5, 3)) * 1e-4
        noise = np.concatenate([np.linalg.cholesky(C[e]) @ rng.standard_normal(3)
                                for e in range(M)])
    else:
        u = rng.standard_normal((M, 3))
        for k in range(1, M):
            u[k] = phi * u[k - 1] + np.sqrt(1 - phi * phi) * u[k]
        noise = sigma * u.ravel()
    X = rng.standard_normal(N_TERMS)
    dw = S @ (X * spec) + noise
    return S, dw, sigma, spec, C


def whiten(S, dw, sigma=None, phi=0.0, C=None):
    """[S w] whitened: per epoch by L_e^-1 (C), or per row by 1/sigma, then
    per axis by L^-1 with L L' = R, R_st = phi_a^|s - t| (AR(1), unit variance;
    phi one number or one per axis)."""
    m = len(dw)
    M = m // 3
    Z = np.column_stack([S, dw])
    if C is not None:
        for e in range(M):
            Z[3 * e:3 * e + 3] = linalg.solve_triangular(np.linalg.cholesky(C[e]),
                                                         Z[3 * e:3 * e + 3], lower=True)
    else:
        Z = Z / sigma[:, None]
    phis = np.broadcast_to(np.asarray(phi, float), (3,))
    idx = np.arange(M)
    for a in range(3):
        if phis[a]:
            L = np.linalg.cholesky(phis[a] ** np.abs(idx[:, None] - idx[None, :]))
            Z[a::3] = linalg.solve_triangular(L, Z[a::3], lower=True)
    return Z[:, :-1], Z[:, -1]


def gls_residual(Sw, ww):
    x, *_ = np.linalg.lstsq(Sw, ww, rcond=None)
    return ww - Sw @ x


def seed_test(Sw, ww, spec, lambda_test=10.0):
    """The seed's equivalent errors (correction off): eigen-decomposition of
    (Sw D)'(Sw D), Xhat_i = p_i'b / lambda_i, z_i = Xhat_i / sqrt(1 + 1/lambda_i),
    T over lambda_i >= lambda_test; eigenvalues descending."""
    SD = Sw * spec
    lam, P = np.linalg.eigh(SD.T @ SD)
    lam, P = lam[::-1], P[:, ::-1]
    xhat = P.T @ (SD.T @ ww) / lam
    z = xhat / np.sqrt(1 + 1 / lam)
    t = lam >= lambda_test
    return lam, P, z[t], float(np.sum(z[t] ** 2))


def write_flight(d, S, dw, sigma, spec, C=None, tag=""):
    np.savetxt(d / ("S%s.txt" % tag), S, header=" ".join(NAMES))
    np.savetxt(d / ("dw%s.txt" % tag), dw)
    np.savetxt(d / ("sigma%s.txt" % tag), sigma)
    np.savetxt(d / ("spec%s.txt" % tag), spec)
    if C is not None:
        np.savetxt(d / ("cov%s.txt" % tag), np.stack([C[:, 0, 0], C[:, 1, 0], C[:, 1, 1],
                                                       C[:, 2, 0], C[:, 2, 1], C[:, 2, 2]], 1))


def plain_keys(tmp_path):
    S, dw, sigma, spec, _ = make_flight(1)
    write_flight(tmp_path, S, dw, sigma, spec, tag="p")
    r = driver("eqerr", "--S", "Sp.txt", "--dw", "dwp.txt", "--sigma", "sigmap.txt", "--spec",
               "specp.txt", "--json", cwd=tmp_path)
    assert r.returncode in (0, 1), r.stderr
    return set(json.loads(r.stdout))


@pytest.mark.parametrize("kind", ["ar", "cov"])
def test_whitened_residuals_and_whiteness_against_numpy(tmp_path, kind):
    phi = 0.6 if kind == "ar" else 0.0
    S, dw, sigma, spec, C = make_flight(11, M=90, phi=phi, cov=kind == "cov")
    write_flight(tmp_path, S, dw, sigma, spec, C)
    noise = ["--ar-phi", "0.6", "--sigma", "sigma.txt"] if kind == "ar" else ["--cov", "cov.txt"]
    r = driver("eqerr", "--S", "S.txt", "--dw", "dw.txt", "--spec", "spec.txt", *noise,
               "--lags", "8", "--json", "--residuals", "res.txt", cwd=tmp_path)
    assert r.returncode in (0, 1), r.stderr
    j = json.loads(r.stdout)
    Sw, ww = whiten(S, dw, sigma if kind == "ar" else None, phi, C)
    e = gls_residual(Sw, ww)
    assert j["residual_whitened"] is True
    np.testing.assert_allclose(j["residual"], e, rtol=1e-7, atol=1e-9 * np.abs(e).max())
    f = np.loadtxt(tmp_path / "res.txt")
    assert (tmp_path / "res.txt").read_text().startswith("# epoch axis whitened_residual")
    np.testing.assert_array_equal(f[:, 0], np.repeat(np.arange(90), 3))
    np.testing.assert_array_equal(f[:, 1], np.tile(np.arange(3), 90))
    np.testing.assert_array_equal(f[:, 2], j["residual"])
    for a in range(3):
        w = j["whiteness"][a]
        q, p = ljung_box(e[a::3], 8)
        runs, n1, n2, z, pr = runs_test(e[a::3])
        assert w["axis"] == a and w["n"] == 90 and w["lags"] == 8
        assert w["ljung_box"] == pytest.approx(q, rel=1e-6)
        assert w["ljung_box_p"] == pytest.approx(p, rel=1e-5, abs=1e-12)
        assert (w["runs"], w["n_above"], w["n_below"]) == (runs, n1, n2)
        assert w["runs_z"] == pytest.approx(z, rel=1e-9, abs=1e-12)
        np.testing.assert_allclose(j["rms"][a], np.sqrt(np.mean(e[a::3] ** 2)), rtol=1e-7)
    # the same keys as the plain route, and the noise route's own
    assert plain_keys(tmp_path) <= set(j)
    assert {"ar_order", "ar_phi", "ar_se", "groups", "robust_crit", "rejected_rows",
            "noise_iterations", "noise_converged"} <= set(j)


def test_named_components_against_numpy(tmp_path):
    S, dw, sigma, spec, _ = make_flight(12, M=120, phi=0.5)
    write_flight(tmp_path, S, dw, sigma, spec)
    r = driver("eqerr", "--S", "S.txt", "--dw", "dw.txt", "--sigma", "sigma.txt", "--spec",
               "spec.txt", "--ar-phi", "0.5", "--lambda-test", "1", "--json", cwd=tmp_path)
    assert r.returncode in (0, 1), r.stderr
    j = json.loads(r.stdout)
    Sw, ww = whiten(S, dw, sigma, 0.5)
    lam, P, _, _ = seed_test(Sw, ww, spec)
    assert j["n_test"] >= 2
    for c in j["components"]:
        i = c["index"]
        shares = dict(c["terms"])
        assert set(shares) == set(NAMES)   # the '# names' header of S.txt
        np.testing.assert_allclose([shares[n] for n in NAMES], P[:, i] ** 2, atol=1e-8)
        np.testing.assert_allclose(np.abs(c["loading"]), np.abs(spec * P[:, i]), rtol=1e-6,
                                   atol=1e-10)
        assert c["candidates"] == [n for n, s in c["terms"] if s >= 0.10]
    # --names overrides the header, the same as the plain route
    alt = ["t%d" % k for k in range(N_TERMS)]
    r = driver("eqerr", "--S", "S.txt", "--dw", "dw.txt", "--sigma", "sigma.txt", "--spec",
               "spec.txt", "--ar-phi", "0.5", "--names", ",".join(alt), "--json", cwd=tmp_path)
    assert {n for c in json.loads(r.stdout)["components"] for n, _ in c["terms"]} == set(alt)
    r = driver("eqerr", "--S", "S.txt", "--dw", "dw.txt", "--sigma", "sigma.txt", "--spec",
               "spec.txt", "--ar-phi", "0.5", "--names", "a,b", cwd=tmp_path)
    assert r.returncode == 64 and "--names" in r.stderr


@pytest.mark.parametrize("rule", ["chi2", "sidak"])
def test_verdict_rule_with_noise_models(tmp_path, rule):
    S, dw, sigma, spec, _ = make_flight(13, M=100, phi=0.4)
    write_flight(tmp_path, S, dw, sigma, spec)
    r = driver("eqerr", "--S", "S.txt", "--dw", "dw.txt", "--sigma", "sigma.txt", "--spec",
               "spec.txt", "--ar-phi", "0.4", "--no-correction", "--verdict", rule, "--alpha",
               "0.05", "--json", cwd=tmp_path)
    assert r.returncode in (0, 1), r.stderr
    j = json.loads(r.stdout)
    Sw, ww = whiten(S, dw, sigma, 0.4)
    lam, _, z, T = seed_test(Sw, ww, spec)
    n = len(z)
    assert j["n_test"] == n and j["verdict"] == rule
    assert j["chi2"] == pytest.approx(T, rel=1e-7)
    np.testing.assert_allclose(np.abs(j["z"]), np.abs(z), rtol=1e-7)
    assert j["verdict_chi2_crit"] == pytest.approx(stats.chi2.isf(0.05, n), rel=1e-9)
    if rule == "chi2":
        assert j["verdict_z_crit"] is None
        assert j["overall_size"] == pytest.approx(0.05, abs=1e-8)   # the chi2 test alone
        assert j["passed"] == (T < stats.chi2.isf(0.05, n))
    else:
        a = stats.norm.isf((1 - 0.95 ** (1 / n)) / 2)
        assert j["verdict_z_crit"] == pytest.approx(a, rel=1e-8)
        # the union is larger than either test's size, at most their sum
        assert 0.05 < j["overall_size"] <= 0.10 + 1e-12
    # the text report states the rule and its overall size, as the plain route's
    t = driver("eqerr", "--S", "S.txt", "--dw", "dw.txt", "--sigma", "sigma.txt", "--spec",
               "spec.txt", "--ar-phi", "0.4", "--no-correction", "--verdict", rule, "--alpha",
               "0.05", cwd=tmp_path).stdout
    assert "overall verdict rule %s" % rule in t and "overall size" in t
    assert "of the whitened residuals" in t and "AR(1) axis x: phi 0.40000" in t


def test_plain_residuals_file_columns(tmp_path):
    S, dw, sigma, spec, _ = make_flight(14, M=60)
    write_flight(tmp_path, S, dw, sigma, spec)
    r = driver("eqerr", "--S", "S.txt", "--dw", "dw.txt", "--sigma", "sigma.txt", "--spec",
               "spec.txt", "--lambda-test", "1e-12", "--no-correction", "--json",
               "--residuals", "res.txt", cwd=tmp_path)
    assert r.returncode in (0, 1), r.stderr
    j = json.loads(r.stdout)
    assert j["n_test"] == N_TERMS and j["residual_whitened"] is False
    # every component tested: dw - S D P Xhat is the weighted LS residual, in dw units
    x, *_ = np.linalg.lstsq(S / sigma[:, None], dw / sigma, rcond=None)
    f = np.loadtxt(tmp_path / "res.txt")
    assert (tmp_path / "res.txt").read_text().startswith("# epoch axis residual\n")
    np.testing.assert_array_equal(f[:, :2], np.column_stack([np.repeat(np.arange(60), 3),
                                                             np.tile(np.arange(3), 60)]))
    np.testing.assert_allclose(f[:, 2], dw - S @ x, rtol=1e-6, atol=1e-12)


def test_robust_rejected_rows_left_out_of_whiteness(tmp_path):
    S, dw, sigma, spec, _ = make_flight(15, M=100)
    dw[3 * 40 + 1] += 40 * sigma[3 * 40 + 1]   # one 40-sigma outlier, epoch 40, axis y
    write_flight(tmp_path, S, dw, sigma, spec)
    r = driver("eqerr", "--S", "S.txt", "--dw", "dw.txt", "--sigma", "sigma.txt", "--spec",
               "spec.txt", "--robust", "--json", "--lags", "5", "--residuals", "res.txt",
               cwd=tmp_path)
    assert r.returncode in (0, 1), r.stderr
    j = json.loads(r.stdout)
    assert [w["row"] for w in j["rejected_rows"]] == [121]
    assert abs(j["rejected_rows"][0]["w"]) > j["robust_crit"]
    # white noise, one group: the whitened residuals are those of the GLS fit
    # without the rejected row, divided by sigma
    keep = np.ones(len(dw), bool)
    keep[121] = False
    Sw, ww = S / sigma[:, None], dw / sigma
    x, *_ = np.linalg.lstsq(Sw[keep], ww[keep], rcond=None)
    e = ww - Sw @ x
    np.testing.assert_allclose(j["residual"], e, rtol=1e-6, atol=1e-9)
    ek = np.delete(e.reshape(-1, 3), 40, axis=0)   # epoch 40 left out
    for a in range(3):
        assert j["whiteness"][a]["n"] == 99
        assert j["whiteness"][a]["ljung_box"] == pytest.approx(ljung_box(ek[:, a], 5)[0],
                                                               rel=1e-6)
    assert np.loadtxt(tmp_path / "res.txt").shape == (300, 3)


def test_python_noise_result_matches_driver(tmp_path):
    S, dw, sigma, spec, _ = make_flight(16, M=90, phi=0.6)
    write_flight(tmp_path, S, dw, sigma, spec)
    r = driver("eqerr", "--S", "S.txt", "--dw", "dw.txt", "--sigma", "sigma.txt", "--spec",
               "spec.txt", "--ar", "1", "--verdict", "exact", "--lags", "6", "--json",
               cwd=tmp_path)
    assert r.returncode in (0, 1), r.stderr
    j = json.loads(r.stdout)
    p = igea.eqerr(S, dw, sigma, spec, ar=1, verdict="exact", lags=6, names=NAMES)
    assert isinstance(p, igea.EqerrResult) and p.residual_whitened
    import dataclasses
    fields = [f.name for f in dataclasses.fields(p)]
    assert fields[:len(dataclasses.fields(igea.EqerrResult))] == [
        f.name for f in dataclasses.fields(igea.EqerrResult)]
    for k in ("chi2", "overall_size", "verdict_z_crit", "verdict_chi2_crit", "p_value"):
        assert getattr(p, k) == pytest.approx(j[k], rel=1e-9), k
    assert p.verdict == j["verdict"] == "exact" and p.n_reject == j["n_reject"]
    np.testing.assert_allclose(p.residual, j["residual"], rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(p.ar_phi, j["ar_phi"], rtol=1e-9)
    np.testing.assert_allclose(p.ar_se, j["ar_se"], rtol=1e-9)
    for a in range(3):
        for k in ("ljung_box", "ljung_box_p", "runs_z"):
            assert p.whiteness[a][k] == pytest.approx(j["whiteness"][a][k], rel=1e-9, abs=1e-14)
    assert [c["candidates"] for c in p.components] == [c["candidates"] for c in j["components"]]
    # phi estimated: the whitened residuals are those of numpy's whitening at that phi
    e = gls_residual(*whiten(S, dw, sigma, p.ar_phi[:, 0]))
    np.testing.assert_allclose(p.residual, e, rtol=1e-6, atol=1e-9)
    text = p.summary()
    assert "overall verdict rule exact" in text and "whitened residuals" in text
    assert "AR(1) axis x" in text


def test_pool_of_noise_flights_against_numpy(tmp_path):
    """igea test --results and igea.pool of flights judged with AR(1) given:
    the pooled chi-square of each flight's whitened equivalent errors."""
    files, T, n, z_all, py = [], 0.0, 0, [], []
    for k, phi in enumerate([0.3, 0.6, 0.8]):
        S, dw, sigma, spec, _ = make_flight(30 + k, M=70, phi=phi)
        write_flight(tmp_path, S, dw, sigma, spec, tag=str(k))
        r = driver("eqerr", "--S", "S%d.txt" % k, "--dw", "dw%d.txt" % k, "--sigma",
                   "sigma%d.txt" % k, "--spec", "spec%d.txt" % k, "--ar-phi", str(phi),
                   "--no-correction", "--json", "--out", "f%d.json" % k, cwd=tmp_path)
        assert r.returncode in (0, 1), r.stderr
        files.append("f%d.json" % k)
        _, _, z, t = seed_test(*whiten(S, dw, sigma, phi), spec)
        T, n = T + t, n + len(z)
        z_all.append(z)
        py.append(igea.eqerr(S, dw, sigma, spec, ar_phi=[phi], correction=0))
    z_all = np.concatenate(z_all)
    crit = stats.chi2.isf(0.01, n)
    for rule in ("seed", "chi2", "sidak"):
        r = driver("test", "--results", ",".join(files), "--verdict", rule, "--json",
                   cwd=tmp_path)
        assert r.returncode in (0, 1), r.stderr
        j = json.loads(r.stdout)
        assert j["dof"] == n and j["chi2"] == pytest.approx(T, rel=1e-7)
        assert j["p_value"] == pytest.approx(stats.chi2.sf(T, n), rel=1e-6)
        assert j["verdict_chi2_crit"] == pytest.approx(crit, rel=1e-9)
        a = stats.norm.isf(0.005) if rule == "seed" else (
            None if rule == "chi2" else stats.norm.isf((1 - 0.99 ** (1 / n)) / 2))
        want = T < crit and (a is None or np.all(np.abs(z_all) <= a))
        assert j["passed"] == want, rule
        p = igea.pool(py, verdict=rule)
        assert p.chi2 == pytest.approx(T, rel=1e-7) and p.dof == n and p.passed == want


def helmert(Sw, ww, grp, G, iters=500):
    """Helmert's variance components written here: c_g <- Omega_g / r_g,
    Omega_g = |w_g - S_g x|^2, r_g = n_g - tr(N^-1 N_g) / c_g, N = sum N_g / c_g,
    x = N^-1 sum S_g'w_g / c_g, from c = 1."""
    c = np.ones(G)
    for _ in range(iters):
        Ng = [Sw[grp == g].T @ Sw[grp == g] for g in range(G)]
        Nm = sum(Ng[g] / c[g] for g in range(G))
        x = np.linalg.solve(Nm, sum(Sw[grp == g].T @ ww[grp == g] / c[g] for g in range(G)))
        Ni = np.linalg.inv(Nm)
        r = np.array([np.sum(grp == g) - np.trace(Ni @ Ng[g]) / c[g] for g in range(G)])
        om = np.array([np.sum((ww[grp == g] - Sw[grp == g] @ x) ** 2) for g in range(G)])
        cn = om / r
        if np.max(np.abs(cn / c - 1)) < 1e-13:
            c = cn
            break
        c = cn
    return c, r, x


def test_groups_scales_and_whitened_residuals_against_numpy(tmp_path):
    S, dw, sigma, spec, _ = make_flight(17, M=120)
    M = 120
    labels = (np.arange(M) >= 50).astype(int)          # two stations
    rows = np.repeat(labels, 3)
    dw = dw + np.where(rows == 1, 2.0, 0.0) * sigma * np.random.default_rng(5).standard_normal(
        3 * M)                                          # station 1 noisier (sd ~ sqrt 5)
    write_flight(tmp_path, S, dw, sigma, spec)
    np.savetxt(tmp_path / "groups.txt", labels, fmt="%d")
    r = driver("eqerr", "--S", "S.txt", "--dw", "dw.txt", "--sigma", "sigma.txt", "--spec",
               "spec.txt", "--groups", "groups.txt", "--json", "--residuals", "res.txt",
               cwd=tmp_path)
    assert r.returncode in (0, 1), r.stderr
    j = json.loads(r.stdout)
    Sw, ww = S * spec / sigma[:, None], dw / sigma
    c, red, x = helmert(Sw, ww, rows, 2)
    got = [g["scale"] for g in j["groups"]]
    np.testing.assert_allclose(got, c, rtol=1e-5)      # the library settles at tol 1e-4
    np.testing.assert_allclose([g["redundancy"] for g in j["groups"]], red, rtol=1e-6)
    np.testing.assert_allclose([g["scale_se"] for g in j["groups"]], c * np.sqrt(2 / red),
                               rtol=1e-5)
    assert [g["rows"] for g in j["groups"]] == [150, 210]
    # whitened residuals: (w - S x) / sqrt(c_g), at the scales that numpy finds
    e = (ww - Sw @ x) / np.sqrt(c[rows])
    np.testing.assert_allclose(j["residual"], e, rtol=1e-5, atol=1e-5 * np.abs(e).max())
    np.testing.assert_allclose(np.loadtxt(tmp_path / "res.txt")[:, 2], j["residual"])
    # the group scales divided out: both stations' residuals of unit scale
    for g in range(2):
        assert 0.7 < np.std(np.asarray(j["residual"])[rows == g]) < 1.3


def test_svd_route_refused_with_noise_models(tmp_path):
    S, dw, sigma, spec, _ = make_flight(18, M=30)
    write_flight(tmp_path, S, dw, sigma, spec)
    r = driver("eqerr", "--S", "S.txt", "--dw", "dw.txt", "--sigma", "sigma.txt", "--ar", "1",
               "--route", "svd", cwd=tmp_path)
    assert r.returncode == 64 and "--route svd" in r.stderr
    with pytest.raises(ValueError, match="route"):
        igea.eqerr(S, dw, sigma, spec, ar=1, route="svd")
