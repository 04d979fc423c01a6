"""igea.rls_run / igea.RLS against an independent numpy implementation of
METHODS 2.2-2.7 (explicit inverses and sums, no eigen form)."""
import os
import subprocess

import numpy as np
import pytest

import igea
from igea import _lib


# ---- the reference ---------------------------------------------------------

def ref_rls(C, Y, x0, gamma0, variant="standard", p=1, forget=1.0, sigma=None):
    """Straight from METHODS 2.2-2.4: K by a k x k solve, K_p as the series
    sum_j (I + A)^-j, Gamma by the textbook Gamma - K c Gamma, P by Joseph."""
    n, k, m = C.shape
    x = np.zeros(m) if x0 is None else np.array(x0, float)
    G = np.array(gamma0, float)
    P = G.copy()
    q = 0.0
    xs = np.zeros((n, m))
    for e in range(n):
        c, y = C[e], Y[e]
        if sigma is not None:
            c, y = c / sigma[:, None], y / sigma
        G, P = G / forget, P / forget
        A = c @ G @ c.T
        Se = np.eye(k) + A
        K = G @ c.T @ np.linalg.inv(Se)
        if variant == "standard" or p == 1:
            x = x + K @ (y - c @ x)
            Kp = K
        elif variant == "iterated":
            for _ in range(p):
                x = x + K @ (y - c @ x)
            B = np.eye(k) - c @ K
            S, Bi = np.zeros((k, k)), np.eye(k)
            for _ in range(p):
                S, Bi = S + Bi, Bi @ B
            Kp = K @ S
        else:
            Si = np.linalg.inv(Se)
            S, Pw = np.zeros((k, k)), np.eye(k)
            for _ in range(p):
                Pw = Pw @ Si
                S = S + Pw
            Kp = G @ c.T @ S
            x = x + Kp @ (y - c @ x)
        IK = np.eye(m) - Kp @ c
        P = IK @ P @ IK.T + Kp @ Kp.T
        G = G - K @ c @ G
        G = 0.5 * (G + G.T)
        r = y - c @ x
        q += r @ r
        xs[e] = x
    return xs, G, P, q


def flight(m=6, k=3, n=150, noise=0.1, seed=1, smooth=False):
    rng = np.random.default_rng(seed)
    X = rng.normal(size=m)
    if smooth:  # environment functions growing from zero, as in flight
        t = np.linspace(0.0, 1.0, n)[:, None, None]
        C = t * rng.normal(size=(1, k, m)) + t ** 2 * rng.normal(size=(1, k, m)) \
            + 0.05 * rng.normal(size=(n, k, m))
    else:
        C = rng.normal(size=(n, k, m))
    Y = np.einsum("ekm,m->ek", C, X) + noise * rng.normal(size=(n, k))
    return C, Y, X


# ---- values ------------------------------------------------------------------

def test_methods_2_9_vector():
    X = np.array([1, -2, 0.5])
    C = np.array([[[1, 0, .5], [0, 1, 1]], [[1, 1, 0], [.5, 0, 1]], [[2, 0, 1], [0, 1, -1]]], float)
    Y = np.einsum("ekm,m->ek", C, X)
    Y[1] += [0.01, -0.02]
    want = {1: ([0.9698200160, -1.9225225858, 0.5047218280], 0.0497347972),
            2: ([1.0015784781, -2.0000818017, 0.4946678785], 0.0003977279),
            3: ([1.0031741050, -2.0047921672, 0.4937185816], 0.0000182639)}
    for variant in ("polynomial", "iterated"):
        for p, (wx, wq) in want.items():
            r = igea.rls_run(C, Y, np.zeros(3), 10 * np.eye(3), variant=variant, p=p)
            np.testing.assert_allclose(r.x[-1], wx, rtol=0, atol=6e-11)
            assert abs(r.q - wq) < 6e-11
            np.testing.assert_allclose(np.diag(r.gamma), [0.2526238883, 0.3488682506,
                                                          0.3500391066], rtol=0, atol=6e-11)


@pytest.mark.parametrize("variant", ["standard", "iterated", "polynomial"])
@pytest.mark.parametrize("p", [1, 2, 5])
@pytest.mark.parametrize("forget", [1.0, 0.97])
def test_against_numpy(variant, p, forget):
    C, Y, _ = flight(seed=p + 10)
    sigma = np.array([0.5, 1.0, 2.0])
    g0 = np.diag(np.linspace(1, 20, 6)) + 0.3
    x0 = np.linspace(-1, 1, 6)
    r = igea.rls_run(C, Y, x0, g0, variant=variant, p=p, forget=forget, sigma=sigma)
    xs, G, P, q = ref_rls(C, Y, x0, g0, variant, p, forget, sigma)
    np.testing.assert_allclose(r.x, xs, rtol=1e-9, atol=1e-11)
    np.testing.assert_allclose(r.gamma, G, rtol=1e-9, atol=1e-13)
    np.testing.assert_allclose(r.covariance, P, rtol=1e-9, atol=1e-13)
    assert r.q == pytest.approx(q, rel=1e-10)
    np.testing.assert_allclose(r.residual, Y - np.einsum("ekm,em->ek", C, r.x), atol=1e-12)
    assert (r.actions == 0).all() or variant is None


def test_iterated_equals_polynomial_every_p():
    C, Y, _ = flight(n=200, seed=3, smooth=True)
    for p in range(1, 11):
        a = igea.rls_run(C, Y, None, 10 * np.eye(6), variant="iterated", p=p)
        b = igea.rls_run(C, Y, None, 10 * np.eye(6), variant="polynomial", p=p)
        assert np.max(np.abs(a.x - b.x)) <= 1e-12 * np.max(np.abs(b.x))
        np.testing.assert_array_equal(a.gamma, b.gamma)


def test_batch_limit():
    """Diffuse Gamma_0, p = 1, no noise: RLS is the batch LS estimate and
    recovers X."""
    C, Y, X = flight(m=6, k=3, n=100, noise=0.0, seed=4)
    r = igea.rls_run(C, Y, None, 1e6 * np.eye(6))
    A = C.reshape(-1, 6)
    xb = np.linalg.solve(A.T @ A + np.eye(6) / 1e6, A.T @ Y.reshape(-1))
    np.testing.assert_allclose(r.x[-1], X, rtol=0, atol=1e-8)
    np.testing.assert_allclose(r.x[-1], xb, rtol=0, atol=1e-8)
    np.testing.assert_allclose(r.gamma, np.linalg.inv(A.T @ A + np.eye(6) / 1e6), rtol=1e-6)


def test_q_caution():
    """Q_p falls with p by construction while the honest covariance grows
    (METHODS 2.6): p = 1 is the optimal gain."""
    C, Y, _ = flight(m=6, k=3, n=150, noise=0.1, seed=8, smooth=True)
    qs, tr = [], []
    for p in range(1, 9):
        r = igea.rls_run(C, Y, None, 1e4 * np.eye(6), variant="polynomial", p=p)
        qs.append(r.q)
        tr.append(np.trace(r.covariance))
        if p == 1:
            np.testing.assert_array_equal(r.covariance, r.gamma)
    assert all(qs[i + 1] < qs[i] for i in range(7))
    assert all(tr[i + 1] > tr[i] for i in range(7))


# ---- anomalies ------------------------------------------------------------------

def ref_isolate(C, Y, gamma0, bad):
    """Standard RLS with the rows in bad (a set of (epoch, row)) deleted."""
    n, k, m = C.shape
    x, G = np.zeros(m), gamma0.copy()
    for e in range(n):
        keep = [j for j in range(k) if (e, j) not in bad]
        if not keep:
            continue
        c, y = C[e][keep], Y[e][keep]
        K = G @ c.T @ np.linalg.inv(np.eye(len(keep)) + c @ G @ c.T)
        x = x + K @ (y - c @ x)
        G = G - K @ c @ G
    return x, G


def test_anomaly_policies_on_outliers_and_dropouts():
    C, Y, X = flight(m=5, k=3, n=200, noise=0.01, seed=5, smooth=True)
    sig = 0.01
    Yb = Y.copy()
    Yb[50, 1] += 0.5          # outlier, 50 sigma
    Yb[120, :] = np.nan       # dropout of the whole epoch
    Yb[150, 2] = np.nan       # dropout of one row
    g0 = 1e2 * np.eye(5)
    r = igea.rls_run(C, Yb, None, g0, anomaly="isolate", sigma=sig)
    assert r.flags[50, 1] & igea.rls.FLAG_INNOVATION
    assert r.flags[120].tolist() == [igea.rls.FLAG_MISSING | igea.rls.FLAG_UNUSED] * 3
    assert r.flags[150, 2] == igea.rls.FLAG_MISSING | igea.rls.FLAG_UNUSED
    assert r.actions[50] == 4 and r.actions[120] == 3 and r.actions[150] == 4
    bad = {(50, 1), (120, 0), (120, 1), (120, 2), (150, 2)}
    flagged = {(e, j) for e, j in zip(*np.nonzero(r.flags))}
    assert bad <= flagged and len(flagged) <= len(bad) + 2
    x, G = ref_isolate(C / sig, Yb / sig, g0, flagged)
    np.testing.assert_allclose(r.x[-1], x, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(r.gamma, G, rtol=1e-8, atol=1e-15)
    assert np.max(np.abs(r.x[-1] - X)) < 5 * np.sqrt(np.max(np.diag(r.gamma)))

    s = igea.rls_run(C, Yb, None, g0, anomaly="skip", sigma=sig)
    assert s.actions[50] == 3 and s.actions[120] == 3 and s.actions[150] == 3
    np.testing.assert_array_equal(s.x[50], s.x[49])
    rp = igea.rls_run(C, Yb, None, g0, anomaly="replace", sigma=sig)
    assert rp.actions[50] == 2 and rp.actions[120] == 2
    # no policy: the outlier is flagged but used, and a NaN is an error
    with pytest.raises(igea.IgeaError) as exc:
        igea.rls_run(C, Yb, None, g0, sigma=sig)
    assert exc.value.code == -1011 and "epoch 120" in str(exc.value)
    Yo = Y.copy()
    Yo[50, 1] += 0.5
    nn = igea.rls_run(C, Yo, None, g0, sigma=sig)
    assert nn.actions[50] == 1
    assert np.max(np.abs(nn.x[-1] - X)) > np.max(np.abs(r.x[-1] - X))


def test_jump_test():
    C, Y, _ = flight(m=4, k=2, n=60, noise=0.0, seed=6, smooth=True)
    Yb = Y + 30.0
    Cb = np.concatenate([C, np.ones((60, 2, 1))], axis=2)  # bias column
    Yb[40, 0] = 0.0
    r = igea.rls_run(Cb, Yb, None, 1e4 * np.eye(5), anomaly="isolate", kappa=np.inf,
                     jump=[5.0, 5.0])
    assert r.flags[40, 0] == igea.rls.FLAG_JUMP | igea.rls.FLAG_UNUSED
    assert np.count_nonzero(r.flags) == 1


# ---- the class, handles, errors ---------------------------------------------------

def test_class_matches_run_and_frees():
    C, Y, _ = flight(seed=7)
    est = igea.RLS(None, 5 * np.eye(6), 3, variant="polynomial", p=4)
    for e in range(len(C)):
        step = est.update(C[e], Y[e])
        assert step.action == "updated" and step.flags.shape == (3,)
    r = igea.rls_run(C, Y, None, 5 * np.eye(6), variant="polynomial", p=4)
    np.testing.assert_array_equal(est.x, r.x[-1])
    np.testing.assert_array_equal(est.gamma, r.gamma)
    np.testing.assert_array_equal(est.covariance, r.covariance)
    assert est.q == r.q
    assert est.counts == {"n_epochs": 150, "updates": 150, "anomalous": 0, "rows": 450}
    np.testing.assert_allclose(est.compensate(C[0], Y[0]), Y[0] - C[0] @ est.x)
    assert isinstance(est._h.value, int)
    est.close()
    est.close()
    with pytest.raises(ValueError):
        est.x
    with igea.RLS([1.0, 2.0], np.eye(2), 1) as e2:
        e2.update([[1.0, 0.0]], [3.0])
        assert e2.x[0] == pytest.approx(1.0 + 0.5 * 2.0)


def test_covariance_off():
    C, Y, _ = flight(seed=12)
    a = igea.rls_run(C, Y, None, 5 * np.eye(6), variant="polynomial", p=3)
    b = igea.rls_run(C, Y, None, 5 * np.eye(6), variant="polynomial", p=3, covariance=False)
    np.testing.assert_array_equal(a.x, b.x)
    np.testing.assert_array_equal(a.gamma, b.gamma)
    assert b.covariance is None and a.covariance is not None
    assert "nan" in b.summary()
    est = igea.RLS(None, np.eye(6), 3, variant="polynomial", p=3, covariance=False)
    est.update(C[0], Y[0])
    with pytest.raises(igea.IgeaError) as exc:
        est.covariance
    assert exc.value.code == -1017


def test_shapes_and_errors():
    C, Y, _ = flight(n=5)
    g = np.eye(6)
    with pytest.raises(ValueError, match="C"):
        igea.rls_run(C[0], Y, None, g)
    with pytest.raises(ValueError, match="Y"):
        igea.rls_run(C, Y[:, :2], None, g)
    with pytest.raises(ValueError, match="gamma0"):
        igea.rls_run(C, Y, None, np.eye(5))
    with pytest.raises(ValueError, match="x0"):
        igea.rls_run(C, Y, np.zeros(5), g)
    with pytest.raises(ValueError, match="sigma"):
        igea.rls_run(C, Y, None, g, sigma=np.ones(4))
    with pytest.raises(ValueError, match="variant"):
        igea.rls_run(C, Y, None, g, variant="kalman")
    with pytest.raises(ValueError, match="anomaly"):
        igea.rls_run(C, Y, None, g, anomaly="drop")
    with pytest.raises(ValueError, match="c"):
        igea.RLS(None, g, 3).update(np.ones((2, 6)), np.ones(3))
    with pytest.raises(igea.IgeaError) as exc:  # not positive definite
        igea.rls_run(C, Y, None, -g)
    assert exc.value.code == -1013
    with pytest.raises(igea.IgeaError, match="p"):
        igea.rls_run(C, Y, None, g, variant="polynomial", p=0)
    with pytest.raises(igea.IgeaError, match="forget"):
        igea.rls_run(C, Y, None, g, forget=1.5)
    with pytest.raises(igea.IgeaError, match="kappa"):
        igea.rls_run(C, Y, None, g, kappa=-1)
    with pytest.raises(igea.IgeaError) as exc:
        igea.rls_run(C, Y, None, g, track_sigma=np.array([1.0, 0.0, 1.0]))
    assert exc.value.code == -1012


def test_prototypes_cover_exports():
    path = os.environ.get("IGEA_LIBRARY")
    if not path:
        pytest.skip("IGEA_LIBRARY not set")
    out = subprocess.run(["nm", "-D", "--defined-only", path], capture_output=True, text=True)
    if out.returncode != 0:
        pytest.skip("nm not available")
    syms = {line.split()[-1] for line in out.stdout.splitlines() if "igea_rls_" in line}
    assert syms and syms <= set(_lib.PROTOTYPES)


# ---- the driver ----------------------------------------------------------------------

def _driver():
    drv = os.environ.get("IGEA_DRIVER")
    if not drv or not os.path.exists(drv):
        pytest.skip("IGEA_DRIVER not set")
    return drv


def test_driver_matches_python(tmp_path):
    import json
    drv = _driver()
    C, Y, _ = flight(m=4, k=3, n=40, noise=0.01, seed=9)
    Y[25, 1] += 1.0
    data = np.hstack([Y, C.reshape(40, -1)])
    np.savetxt(tmp_path / "rec.txt", data, fmt="%.17g", header="y1 y2 y3 c...")
    np.save(tmp_path / "S.npy", C.reshape(-1, 4))
    np.savetxt(tmp_path / "dw.txt", Y.reshape(-1), fmt="%.17g")
    r = igea.rls_run(C, Y, None, 100 * np.eye(4), variant="iterated", p=3, anomaly="isolate",
                     track_sigma=0.01)
    common = ["--gamma0", "100", "--variant", "iterated", "--p", "3", "--anomaly", "isolate",
              "--sigma", "0.01"]
    out = subprocess.run([drv, "rls", "--data", str(tmp_path / "rec.txt")] + common,
                         capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    rows = np.array([[float(v) for v in line.split()] for line in out.stdout.splitlines()
                     if line and not line.startswith("#")])
    assert rows.shape == (40, 2 + 3 + 4 + 3)
    np.testing.assert_array_equal(rows[:, 1], r.actions)
    np.testing.assert_array_equal(rows[:, 2:5], r.flags)
    np.testing.assert_allclose(rows[:, 5:9], r.x, rtol=1e-14, atol=1e-15)
    np.testing.assert_allclose(rows[:, 9:], r.residual, rtol=1e-12, atol=1e-13)
    assert r.actions[25] == 4
    js = tmp_path / "o.json"
    out = subprocess.run([drv, "rls", "--S", str(tmp_path / "S.npy"), "--dw",
                          str(tmp_path / "dw.txt"), "--json", "--every", "0", "--out", str(js)]
                         + common, capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    d = json.loads(js.read_text())
    assert d["epochs"] == [] and d["n_epochs"] == 40 and d["anomalous"] >= 1
    np.testing.assert_allclose(d["x"], r.x[-1], rtol=1e-14)
    np.testing.assert_allclose(d["covariance"], r.covariance, rtol=1e-14)
    np.testing.assert_allclose(d["gamma"], r.gamma, rtol=1e-14)
    assert d["q"] == pytest.approx(r.q, rel=1e-13)


def test_driver_errors(tmp_path):
    drv = _driver()
    def run(*args):
        return subprocess.run([drv, "rls"] + list(args), capture_output=True, text=True)
    assert run("--help").returncode == 0
    assert "example" in run("--help").stdout
    assert run("--bogus").returncode == 64
    assert run("--data", "x", "--S", "y").returncode == 64
    assert run("--data", str(tmp_path / "missing.txt")).returncode == 66
    (tmp_path / "bad.txt").write_text("1 2 3 4\n1 2 x 4\n")
    o = run("--data", str(tmp_path / "bad.txt"), "--k", "1")
    assert o.returncode == 65 and "bad.txt:2:5" in o.stderr
    (tmp_path / "ok.txt").write_text("1 1 0\n2 0 1\n")
    assert run("--data", str(tmp_path / "ok.txt"), "--k", "2").returncode == 65
    assert run("--data", str(tmp_path / "ok.txt"), "--k", "1", "--p", "0").returncode == 64
    assert run("--data", str(tmp_path / "ok.txt"), "--k", "1", "--gamma0", "-1").returncode == 65
    out = tmp_path / "never.txt"
    assert run("--data", str(tmp_path / "ok.txt"), "--k", "1", "--sigma", "0",
               "--out", str(out)).returncode == 64
    assert not out.exists()


def test_diffuse_prior_keeps_p_positive_definite():
    """Gamma_0 = 1e15 I on a simulated 21-term flight: the factored Joseph
    update keeps P positive definite (the expanded sum did not)."""
    f = igea.simulate(seed=5)
    n, N = len(f.epochs), len(f.terms)
    C = (f.S * f.spec).reshape(n, 3, N)
    for g in (1e6, 1e15):
        r = igea.rls_run(C, f.dw.reshape(n, 3), None, g * np.eye(N), variant="polynomial",
                         p=5, track_sigma=f.sigma.reshape(n, 3))
        assert np.linalg.eigvalsh(r.gamma).min() > 0
        assert np.linalg.eigvalsh(r.covariance).min() > 0


def test_driver_sigma_per_row(tmp_path):
    """--S/--dw with the eqerr sigma file (one value per row of S)."""
    import json
    drv = _driver()
    C, Y, _ = flight(m=3, k=3, n=20, noise=0.05, seed=13)
    sig = np.linspace(0.05, 0.2, 60).reshape(20, 3)
    np.savetxt(tmp_path / "S.txt", C.reshape(-1, 3), fmt="%.17g")
    np.savetxt(tmp_path / "dw.txt", Y.reshape(-1), fmt="%.17g")
    np.savetxt(tmp_path / "sigma.txt", sig.reshape(-1), fmt="%.17g")
    out = subprocess.run([drv, "rls", "--S", str(tmp_path / "S.txt"), "--dw",
                          str(tmp_path / "dw.txt"), "--sigma", str(tmp_path / "sigma.txt"),
                          "--gamma0", "10", "--json"], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    d = json.loads(out.stdout)
    r = igea.rls_run(C, Y, None, 10 * np.eye(3), sigma=sig)
    np.testing.assert_allclose(d["x"], r.x[-1], rtol=1e-14)
    np.testing.assert_allclose([e["x"] for e in d["epochs"]], r.x, rtol=1e-13, atol=1e-15)
    np.savetxt(tmp_path / "sigma_bad.txt", np.ones(7))
    bad = subprocess.run([drv, "rls", "--S", str(tmp_path / "S.txt"), "--dw",
                          str(tmp_path / "dw.txt"), "--sigma", str(tmp_path / "sigma_bad.txt")],
                         capture_output=True, text=True)
    assert bad.returncode == 65 and "sigma" in bad.stderr


def test_sd_and_the_driver_spelling_of_keywords():
    """sd is the square root of the honest covariance's diagonal (numpy
    here); sigma=/jump= are the driver's --sigma/--jump; the old names
    track_sigma=/jump_max= give the same result with a DeprecationWarning,
    and both at once is an error."""
    C, Y, _ = flight(m=4, k=2, n=60, noise=0.01, seed=9)
    g0 = 1e4 * np.eye(4)
    r = igea.rls_run(C, Y, None, g0, variant="iterated", p=3, sigma=0.01, jump=50.0)
    np.testing.assert_array_equal(r.sd, np.sqrt(np.diag(r.covariance)))
    with pytest.warns(DeprecationWarning, match="track_sigma= is now sigma="):
        old = igea.rls_run(C, Y, None, g0, variant="iterated", p=3, track_sigma=0.01,
                           jump_max=[50.0, 50.0])
    np.testing.assert_array_equal(old.x, r.x)
    np.testing.assert_array_equal(old.sd, r.sd)
    with pytest.raises(TypeError, match="give sigma= only"):
        igea.rls_run(C, Y, None, g0, sigma=0.01, track_sigma=0.01)
    with igea.RLS(None, g0, 2, covariance=False, variant="iterated", p=3) as est:
        est.run(C, Y, 0.01)
        with pytest.raises(igea.IgeaError):
            est.sd
