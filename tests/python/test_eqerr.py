"""igea.eqerr against an independent numpy/scipy implementation of
METHODS 1.2 written here, on synthetic flights; the driver's JSON against
the Python result on the same files."""
import json
import os
import subprocess

import numpy as np
import pytest
from scipy import stats

import igea

EPS = np.finfo(float).eps


def reference(S, dw, sigma, spec=None, alpha=0.01, lambda_test=10.0, lambda_small=0.1,
              n_min=5, tol=0.05, max_iter=10, correct=True):
    """METHODS 1.2 steps 0-5 in numpy (eigh), the pseudo-code verbatim."""
    m, N = S.shape
    sigma = np.broadcast_to(np.asarray(sigma, float), (m,))
    D = np.ones(N) if spec is None else np.asarray(spec, float)
    St = S * D / sigma[:, None]
    wt = dw / sigma
    A = St.T @ St
    b = St.T @ wt
    lam0, V = np.linalg.eigh(A)
    lam0, V = lam0[::-1], V[:, ::-1]
    for i in range(N):
        if V[np.argmax(np.abs(V[:, i])), i] < 0:
            V[:, i] *= -1
    r = int(np.sum(lam0 > N * 10 * EPS * lam0[0]))
    pb = V.T @ b
    xhat = np.zeros(N)
    xhat[:r] = pb[:r] / lam0[:r]
    g0 = pb[:r] / np.sqrt(lam0[:r])
    c, flag, iters, nsmall, prev = 1.0, "off", 0, 0, None
    if correct:
        flag = "no_convergence"
        for it in range(max_iter):
            iters = it + 1
            small = np.nonzero(lam0[:r] / c <= lambda_small)[0]
            nsmall = len(small)
            if nsmall < n_min:
                flag = "not_estimable"
                break
            sw2 = np.mean(g0[small] ** 2 / c)
            if abs(sw2 - 1) <= tol and (it == 0 or np.array_equal(small, prev)):
                flag = "converged"
                break
            prev = small
            c *= sw2
    lam = lam0 / c
    test = np.nonzero(lam[:r] >= lambda_test)[0]
    z = xhat[test] / np.sqrt(1 + 1 / lam[test])
    zc = stats.norm.isf(alpha / 2)
    T = float(np.sum(z ** 2))
    crit = stats.chi2.isf(alpha, len(test))
    coef = D * (V[:, test] @ xhat[test])
    res = dw - S @ coef
    rms = [np.sqrt(np.mean(res[a::3] ** 2)) for a in range(3)]
    return dict(eigenvalues=lam, eigenvectors=V, rank=r, equiv_err=xhat, z=z, reject=np.abs(z) > zc,
                chi2=T, dof=len(test), chi2_crit=crit, z_crit=zc, p_value=stats.chi2.sf(T, len(test)),
                scale=c, iterations=iters, n_small=nsmall, flag=flag,
                passed=bool(not np.any(np.abs(z) > zc) and T < crit), residual=res, rms=np.array(rms))


def flight(seed, m=300, N=14, sv_hi=3.0, sv_lo=-2.5, sigma_w=1.0, x=None, ar=0.0, rank_def=0):
    """S = U diag(s) V^T with chosen singular values (eigenvalues s^2 spread
    from 1e6 to 1e-5), X ~ N(0, I), tracking noise sigma_w * e (AR(1) if ar)."""
    rng = np.random.default_rng(seed)
    U, _ = np.linalg.qr(rng.standard_normal((m, N)))
    V, _ = np.linalg.qr(rng.standard_normal((N, N)))
    s = np.logspace(sv_hi, sv_lo, N)
    if rank_def:
        s[-rank_def:] = 0.0
    sigma = 0.01 * (1 + rng.random(m))
    spec = 10.0 ** rng.uniform(-1, 1, N)
    S_scaled = (U * s) @ V.T                     # weighted, spec-scaled
    S = S_scaled * sigma[:, None] / spec          # raw environment functions
    X = rng.standard_normal(N) if x is None else np.asarray(x, float)
    e = rng.standard_normal(m)
    if ar:
        for i in range(1, m):
            e[i] = ar * e[i - 1] + np.sqrt(1 - ar * ar) * e[i]
    dw = S @ (X * spec) + sigma_w * sigma * e
    return S, dw, sigma, spec, X


FIELDS_F = ["chi2", "chi2_crit", "z_crit", "p_value", "scale"]
FIELDS_I = ["rank", "dof", "iterations", "n_small"]


def assert_matches(res, ref, rtol=1e-6):
    for k in FIELDS_I:
        assert getattr(res, k) == ref[k], k
    assert res.flag == ref["flag"]
    assert res.passed == ref["passed"]
    for k in FIELDS_F:
        assert np.isclose(getattr(res, k), ref[k], rtol=rtol, atol=0), (k, getattr(res, k), ref[k])
    r = res.rank
    big = ref["eigenvalues"] > 1e-8 * ref["eigenvalues"][0]
    # eigenvalues at c = 1 to rounding; the final scale c to the accuracy
    # with which the small eigenvalues are known (METHODS 1.3)
    np.testing.assert_allclose(res.eigenvalues[big] * res.scale, ref["eigenvalues"][big] * ref["scale"],
                               rtol=1e-10, atol=len(big) * EPS * ref["eigenvalues"][0] * ref["scale"])
    np.testing.assert_allclose(res.eigenvalues[big], ref["eigenvalues"][big], rtol=rtol)
    np.testing.assert_allclose(res.equiv_err[:r][big[:r]], ref["equiv_err"][:r][big[:r]], rtol=1e-6, atol=1e-9)
    np.testing.assert_allclose(res.z, ref["z"], rtol=1e-8, atol=1e-12)
    np.testing.assert_array_equal(res.reject, ref["reject"])
    np.testing.assert_allclose(res.residual, ref["residual"], rtol=1e-7, atol=1e-10 * np.abs(ref["residual"]).max())
    np.testing.assert_allclose(res.rms, ref["rms"], rtol=1e-7)


@pytest.mark.parametrize("route", ["eig", "svd"])
@pytest.mark.parametrize("case", ["nominal", "sigma_w", "ar1", "out_of_spec", "rank_deficient"])
def test_against_reference(route, case):
    kw = {"nominal": {}, "sigma_w": {"sigma_w": 1.8}, "ar1": {"ar": 0.6, "sigma_w": 1.3},
          "out_of_spec": {"x": [0, 0, 0, 0, 0, 0, 0, 0, 6.0, 0, 0, 0, 0, 0]},
          "rank_deficient": {"rank_def": 2}}[case]
    S, dw, sigma, spec, X = flight(7, **kw)
    res = igea.eqerr(S, dw, sigma, spec, route=route)
    ref = reference(S, dw, sigma, spec)
    assert_matches(res, ref)
    if case == "sigma_w":
        assert res.flag == "converged" and 1.2 < np.sqrt(res.scale) < 2.6
    if case == "rank_deficient":
        assert res.rank == 12 and np.all(res.equiv_err[12:] == 0)
    if case == "out_of_spec":
        assert not res.passed


def test_sigma_w_corrects_misstated_tracking():
    """True sigma_w = 1.8: without correction the small eigenvalues' g_i
    have variance 3.24; with it the scale estimate is near 3.24."""
    scales = []
    for seed in range(40):
        S, dw, sigma, spec, _ = flight(seed, sigma_w=1.8)
        scales.append(igea.eqerr(S, dw, sigma, spec).scale)
    # mean of c over 40 flights with ~6 small eigenvalues: sd ~ 3.24*sqrt(2/6)/sqrt(40) ~ 0.3
    assert abs(np.mean(scales) - 3.24) < 1.2


def test_options_and_no_correction():
    S, dw, sigma, spec, _ = flight(3, sigma_w=1.5)
    res = igea.eqerr(S, dw, sigma, spec, correction=False, alpha=0.05, lambda_test=100.0)
    ref = reference(S, dw, sigma, spec, alpha=0.05, lambda_test=100.0, correct=False)
    assert_matches(res, ref)
    assert res.flag == "off" and res.scale == 1.0
    # scalar sigma
    res = igea.eqerr(S, dw, 0.015, spec)
    assert_matches(res, reference(S, dw, 0.015, spec))
    assert "verdict" in res.summary()


def test_errors():
    S, dw, sigma, spec, _ = flight(1)
    with pytest.raises(ValueError, match="dw"):
        igea.eqerr(S, dw[:-1], sigma, spec)
    with pytest.raises(ValueError, match="S"):
        igea.eqerr(S[:, 0], dw, sigma, spec)
    with pytest.raises(ValueError, match="sigma"):
        igea.eqerr(S, dw, sigma[:5], spec)
    with pytest.raises(ValueError, match="spec"):
        igea.eqerr(S, dw, sigma, spec[:3])
    with pytest.raises(ValueError, match="route"):
        igea.eqerr(S, dw, sigma, spec, route="qr")
    bad = sigma.copy()
    bad[4] = 0
    with pytest.raises(igea.IgeaError) as e:
        igea.eqerr(S, dw, bad, spec)
    assert e.value.code == -1012
    bad = dw.copy()
    bad[3] = np.nan
    with pytest.raises(igea.IgeaError) as e:
        igea.eqerr(S, bad, sigma, spec)
    assert e.value.code == -1011
    with pytest.raises(igea.IgeaError, match="options"):
        igea.eqerr(S, dw, sigma, spec, alpha=1.5)
    with pytest.raises(igea.IgeaError) as e:   # nothing precise enough
        igea.eqerr(S, dw, sigma * 1e6, spec, correction=False)
    assert e.value.code == -1018


def test_seed_table_and_pool():
    x = [0.2833, -1.0819, 0.8138, 0.4933, 0.0526, 0.1372, 0.8714, -0.8370, 2.5527, 1.7403, -0.3456]
    lam = [2.42E+05, 9.03E+04, 7.24E+04, 1.56E+04, 2.05E+03, 1.79E+03, 1.38E+03, 6.51E+02,
           5.01E+02, 1.85E+02, 8.62E+01]
    t = igea.accuracy_test(x, lam, z_crit=2.58)
    assert round(t.chi2, 4) == 13.2699 and t.dof == 11 and t.passed
    assert round(t.chi2_crit, 3) == 24.725
    np.testing.assert_allclose(t.chi2, np.sum(np.array(x) ** 2 / (1 + 1 / np.array(lam))), rtol=1e-14)
    flights = [igea.eqerr(*flight(s)[:4]) for s in (11, 12, 13)]
    p = igea.pool(flights)
    assert p.dof == sum(f.dof for f in flights)
    assert np.isclose(p.chi2, sum(f.chi2 for f in flights), rtol=1e-14)
    assert np.isclose(p.chi2_crit, stats.chi2.isf(0.01, p.dof), rtol=1e-12)
    assert p.passed == (all(f.n_reject == 0 for f in flights) and p.chi2 < p.chi2_crit)
    with pytest.raises(igea.IgeaError) as e:
        igea.pool(flights, unit_ids=[1, 2, 1])
    assert e.value.code == -1019
    with pytest.raises(ValueError):
        igea.pool([])
    with pytest.raises(ValueError, match="eigenvalues"):
        igea.accuracy_test(x, lam[:3])


def test_stats_functions():
    assert np.isclose(igea.chi2_upper(0.01, 11), 24.72497031131828, rtol=1e-13)
    assert np.isclose(igea.chi2_quantile(0.3, 7.5), stats.chi2.ppf(0.3, 7.5), rtol=1e-12)
    assert np.isclose(igea.chi2_sf(30.0, 20), stats.chi2.sf(30.0, 20), rtol=1e-12)
    assert np.isclose(igea.normal_quantile(0.995), 2.5758293035489004, rtol=1e-15)
    with pytest.raises(igea.IgeaError):
        igea.chi2_quantile(0.5, 0)          # aborts the process in plain GSL
    with pytest.raises(igea.IgeaError):
        igea.chi2_quantile(1.5, 3)


def driver(*args, cwd=None):
    return subprocess.run([os.environ["IGEA_DRIVER"], *map(str, args)], capture_output=True,
                          text=True, cwd=cwd)


@pytest.mark.parametrize("fmt", ["txt", "npy"])
@pytest.mark.parametrize("route", ["eig", "svd"])
def test_driver_json_equals_python(tmp_path, fmt, route):
    S, dw, sigma, spec, _ = flight(21, sigma_w=1.4)
    files = {}
    for name, a in [("S", S), ("dw", dw), ("sigma", sigma), ("spec", spec)]:
        p = tmp_path / f"{name}.{fmt}"
        if fmt == "npy":
            np.save(p, a)
        else:
            np.savetxt(p, a, fmt="%.17g")
        files[name] = p
    r = driver("eqerr", "--S", files["S"], "--dw", files["dw"], "--sigma", files["sigma"],
               "--spec", files["spec"], "--route", route, "--json")
    assert r.returncode in (0, 1), r.stderr
    js = json.loads(r.stdout)
    res = igea.eqerr(S, dw, sigma, spec, route=route)
    assert r.returncode == (0 if res.passed else 1)
    for k in FIELDS_I + ["n_test", "flag", "passed"]:
        assert js[k] == getattr(res, k), k
    # The driver streams row blocks, so its normal matrix is summed in another
    # order: the small eigenvalues and with them c agree to ~eps*lambda_1
    # (METHODS 1.3); the SVD route runs the same in-memory code.
    rtol = 1e-6 if route == "eig" else 1e-12
    for k in FIELDS_F:
        assert np.isclose(js[k], getattr(res, k), rtol=rtol), k
    np.testing.assert_allclose(np.array(js["eigenvalues"]) * js["scale"], res.eigenvalues * res.scale,
                               rtol=1e-10, atol=1e-13 * res.eigenvalues[0] * res.scale)
    nt = res.n_test
    np.testing.assert_allclose(js["equiv_err"][:nt], res.equiv_err[:nt], rtol=1e-9)
    np.testing.assert_allclose(js["equiv_err"][:res.rank], res.equiv_err[:res.rank], rtol=1e-4 if route == "eig" else 1e-9)
    np.testing.assert_allclose(js["z"], res.z, rtol=rtol)
    assert js["reject"] == list(res.reject)
    np.testing.assert_allclose(js["residual"], res.residual, rtol=1e-8, atol=1e-12)
    np.testing.assert_allclose(js["rms"], res.rms, rtol=1e-9)
    np.testing.assert_allclose(np.array(js["eigenvectors"])[:, :nt], res.eigenvectors[:, :nt], atol=1e-9)
    np.testing.assert_allclose(np.array(js["eigenvectors"])[:, :res.rank], res.eigenvectors[:, :res.rank],
                               atol=1e-5 if route == "eig" else 1e-9)


def test_driver_errors_and_pool(tmp_path):
    S, dw, sigma, spec, _ = flight(5)
    np.savetxt(tmp_path / "S.txt", S, fmt="%.17g")
    np.savetxt(tmp_path / "dw.txt", dw, fmt="%.17g")
    np.savetxt(tmp_path / "short.txt", dw[:-3], fmt="%.17g")
    np.savetxt(tmp_path / "spec.txt", spec, fmt="%.17g")
    bad = (tmp_path / "S.txt").read_text().splitlines()
    bad[6] = bad[6].replace(" ", " 1.2.3 ", 1)
    (tmp_path / "bad.txt").write_text("\n".join(bad) + "\n")
    (tmp_path / "empty.txt").write_text("# nothing\n")
    r = driver("eqerr", "--S", "bad.txt", "--dw", "dw.txt", "--sigma", "0.01", cwd=tmp_path)
    assert r.returncode == 65 and "bad.txt:7:" in r.stderr
    r = driver("eqerr", "--S", "S.txt", "--dw", "short.txt", "--sigma", "0.01", cwd=tmp_path)
    assert r.returncode == 65 and "short.txt" in r.stderr
    r = driver("eqerr", "--S", "empty.txt", "--dw", "dw.txt", "--sigma", "0.01", cwd=tmp_path)
    assert r.returncode == 65 and "no data" in r.stderr
    r = driver("eqerr", "--S", "missing.txt", "--dw", "dw.txt", "--sigma", "0.01", cwd=tmp_path)
    assert r.returncode == 66
    r = driver("eqerr", "--S", "S.txt", "--dw", "dw.txt", "--sigma", "-1", cwd=tmp_path)
    assert r.returncode == 64
    r = driver("eqerr", "--S", "S.txt", "--dw", "dw.txt", "--sigma", "0.01", "--bogus", cwd=tmp_path)
    assert r.returncode == 64
    # --out is atomic: a failing run leaves no file
    r = driver("eqerr", "--S", "bad.txt", "--dw", "dw.txt", "--sigma", "0.01", "--out", "rep.txt", cwd=tmp_path)
    assert r.returncode == 65 and not (tmp_path / "rep.txt").exists()
    assert not list(tmp_path.glob("rep.txt.tmp*"))
    # pooled flights
    outs = []
    for s in (31, 32):
        S, dw, sigma, spec, _ = flight(s)
        for name, a in [("S", S), ("dw", dw), ("sig", sigma), ("spec", spec)]:
            np.savetxt(tmp_path / f"{name}{s}.txt", a, fmt="%.17g")
        r = driver("eqerr", "--S", f"S{s}.txt", "--dw", f"dw{s}.txt", "--sigma", f"sig{s}.txt",
                   "--spec", f"spec{s}.txt", "--json", "--out", f"r{s}.json", cwd=tmp_path)
        assert r.returncode in (0, 1), r.stderr
        outs.append(igea.eqerr(S, dw, sigma, spec))
    r = driver("test", "--json", "--results", "r31.json,r32.json", cwd=tmp_path)
    js = json.loads(r.stdout)
    p = igea.pool(outs)
    assert js["dof"] == p.dof and np.isclose(js["chi2"], p.chi2, rtol=1e-6)
    assert r.returncode == (0 if p.passed else 1)
    r = driver("test", "--unit-ids", "4,4", "--results", "r31.json,r32.json", cwd=tmp_path)
    assert r.returncode == 65 and "independent" in r.stderr
    for cmd in ("eqerr", "test", "version"):
        r = driver(cmd, "--help")
        assert r.returncode == 0 and "usage" in r.stdout


def test_driver_npy_layouts_and_faults(tmp_path):
    S, dw, sigma, spec, _ = flight(8)
    np.save(tmp_path / "S.npy", S)                       # C order
    np.save(tmp_path / "SF.npy", np.asfortranarray(S))   # Fortran order
    np.save(tmp_path / "dw.npy", dw)
    np.save(tmp_path / "spec.npy", spec)
    a = driver("eqerr", "--S", "S.npy", "--dw", "dw.npy", "--sigma", "0.01", "--spec", "spec.npy",
               "--json", "--residuals", "res.txt", cwd=tmp_path)
    b = driver("eqerr", "--S", "SF.npy", "--dw", "dw.npy", "--sigma", "0.01", "--spec", "spec.npy",
               "--json", cwd=tmp_path)
    assert a.returncode in (0, 1) and a.returncode == b.returncode, a.stderr + b.stderr
    ja, jb = json.loads(a.stdout), json.loads(b.stdout)
    assert ja["chi2"] == jb["chi2"] and ja["eigenvalues"] == jb["eigenvalues"]
    # the residuals file: epoch, axis, residual per row
    np.testing.assert_allclose(np.loadtxt(tmp_path / "res.txt")[:, 2], ja["residual"], rtol=0, atol=0)
    # truncated .npy: the header promises more than the file holds
    raw = (tmp_path / "S.npy").read_bytes()
    (tmp_path / "trunc.npy").write_bytes(raw[:-800])
    r = driver("eqerr", "--S", "trunc.npy", "--dw", "dw.npy", "--sigma", "0.01", cwd=tmp_path)
    assert r.returncode == 65 and "truncated" in r.stderr
    # NaN inside a .npy and in a text file
    Sn = S.copy()
    Sn[17, 3] = np.nan
    np.save(tmp_path / "nan.npy", Sn)
    r = driver("eqerr", "--S", "nan.npy", "--dw", "dw.npy", "--sigma", "0.01", cwd=tmp_path)
    assert r.returncode == 65 and "row 18, column 4" in r.stderr
    np.savetxt(tmp_path / "nan.txt", Sn, fmt="%.17g")
    r = driver("eqerr", "--S", "nan.txt", "--dw", "dw.npy", "--sigma", "0.01", cwd=tmp_path)
    assert r.returncode == 65 and "nan.txt:18:" in r.stderr
    # float32 .npy is refused with a hint
    np.save(tmp_path / "f32.npy", S.astype(np.float32))
    r = driver("eqerr", "--S", "f32.npy", "--dw", "dw.npy", "--sigma", "0.01", cwd=tmp_path)
    assert r.returncode == 65 and "float64" in r.stderr
    # a zero tracking sigma in a file names its row
    sg = np.full(len(dw), 0.01)
    sg[40] = 0.0
    np.savetxt(tmp_path / "sg.txt", sg)
    r = driver("eqerr", "--S", "S.npy", "--dw", "dw.npy", "--sigma", "sg.txt", cwd=tmp_path)
    assert r.returncode == 65 and "row 41" in r.stderr
    # comma-separated text with comments reads the same as .npy
    with open(tmp_path / "S.csv", "w") as f:
        f.write("# environment functions\n\n")
        for row in S:
            f.write(", ".join("%.17g" % v for v in row) + "  # row\n")
    c = driver("eqerr", "--S", "S.csv", "--dw", "dw.npy", "--sigma", "0.01", "--spec", "spec.npy",
               "--json", cwd=tmp_path)
    assert json.loads(c.stdout)["chi2"] == ja["chi2"]


EXTRA = ["whiteness", "components", "residual_whitened", "component_miss"]  # after the verdict's


def test_result_fields_are_the_documented_ones():
    import dataclasses
    want = ["eigenvalues", "eigenvectors", "rank", "equiv_err", "n_test", "z", "reject", "chi2",
            "dof", "chi2_crit", "z_crit", "p_value", "scale", "iterations", "n_small", "flag",
            "passed", "residual", "rms"]
    # the overall verdict rule's fields follow the seed's
    verdict = ["verdict", "verdict_z_crit", "verdict_chi2_crit", "overall_size"]
    assert [f.name for f in dataclasses.fields(igea.EqerrResult)] == want + verdict + EXTRA
    assert [f.name for f in dataclasses.fields(igea.TestResult)] == [
        "n_test", "z", "reject", "chi2", "dof", "chi2_crit", "z_crit", "p_value", "passed"] + verdict
    r = igea.eqerr(*flight(2)[:4], alpha=0.05)
    assert "alpha = 0.05" in r.summary()
    with pytest.raises(dataclasses.FrozenInstanceError):
        r.chi2 = 0.0


@pytest.mark.parametrize("route, threads", [("eig", None), ("eig", 2), ("svd", None)])
def test_c_order_S_is_read_in_place(route, threads):
    """A C-order S (numpy's default) goes to igea_eqerr_run_layout row by
    row: no transposed copy is made (tracemalloc sees numpy's allocations:
    the peak stays far below S's size), and the result equals the
    Fortran-order one (igea_eqerr_run) to rounding; the Fortran-order call
    is the same bits whatever the input's order was before."""
    import tracemalloc
    S, dw, sigma, spec, _ = flight(21, m=30000, N=20)
    Sc, Sf = np.ascontiguousarray(S), np.asfortranarray(S)
    rf = igea.eqerr(Sf, dw, sigma, spec, route=route, threads=threads)
    tracemalloc.start()
    rc = igea.eqerr(Sc, dw, sigma, spec, route=route, threads=threads)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert peak < Sc.nbytes / 4, (peak, Sc.nbytes)
    lam = rf.eigenvalues
    assert np.allclose(rc.eigenvalues, lam, rtol=0, atol=1e-11 * lam[0])
    assert rc.rank == rf.rank and rc.n_test == rf.n_test and rc.passed == rf.passed
    assert rc.chi2 == pytest.approx(rf.chi2, rel=1e-8)
    assert np.allclose(rc.residual, rf.residual, rtol=0, atol=1e-9 * np.abs(dw).max())
    assert np.allclose(rc.rms, rf.rms, rtol=1e-9)
    # the same Fortran-order input gives the same bits again
    again = igea.eqerr(np.asfortranarray(Sc), dw, sigma, spec, route=route, threads=threads)
    assert np.array_equal(again.residual, rf.residual) and again.chi2 == rf.chi2
