"""igea.ls: library standard deviations, rank threshold and refinement,
against numpy formulas written here."""
import numpy as np

import igea


def _design(seed=3, m=30, N=4):
    rng = np.random.default_rng(seed)
    A = rng.standard_normal((m, N)) * np.array([1.0, 1e3, 1e-2, 5.0])
    y = A @ np.array([1.0, -2e-3, 40.0, 0.5]) + 0.1 * rng.standard_normal(m)
    return A, y


def test_ls_sd_and_rank_tol():
    A, y = _design()
    m, N = A.shape
    r = igea.ls(A, y)
    xs, *_ = np.linalg.lstsq(A, y, rcond=None)
    res = y - A @ xs
    s2 = res @ res / (m - N)
    sd = np.sqrt(np.diag(s2 * np.linalg.inv(A.T @ A)))
    np.testing.assert_allclose(r.x, xs, rtol=1e-12)
    np.testing.assert_allclose(r.sd, sd, rtol=1e-10)
    np.testing.assert_allclose(r.sd, np.sqrt(np.diag(r.cov)), rtol=1e-15)
    # the cut: max(m, N) eps times the largest singular value of the
    # design with unit-norm columns
    s1 = np.linalg.svd(A / np.linalg.norm(A, axis=0), compute_uv=False)[0]
    assert r.rank_tol == __import__("pytest").approx(max(m, N) * np.finfo(float).eps * s1,
                                                     rel=1e-12)
    assert r.rank == N and r.refine_steps >= 1


def test_ls_wampler1_exact():
    """NIST StRD Wampler1: y = 1 + x + ... + x^5 exactly, x = 0..20."""
    x = np.arange(21.0)
    A = np.vander(x, 6, increasing=True)
    y = A @ np.ones(6)
    r = igea.ls(A, y)
    np.testing.assert_array_equal(r.x, np.ones(6))
    np.testing.assert_array_equal(r.residual, np.zeros(21))


def test_ridge_pce_scale_and_rank():
    """Columns 1e-15 apart: scaled internally, rank kept, exact fit recovered
    (k = 0 and all components are least squares)."""
    t = np.linspace(0, 1, 12)
    A = np.column_stack([np.ones(12), t, 1e-15 * t * t])
    y = 1.5 - 0.75 * t + 2.0 * t * t
    xt = np.array([1.5, -0.75, 2e15])
    r = igea.ridge(A, y, k=0.0)
    assert r.scaled and r.rank == 3
    np.testing.assert_allclose(r.x, xt, rtol=1e-12)
    p = igea.pce(A, y, eig_min=1e-6)
    assert p.scaled and p.rank == 3 and p.ncomp == 3
    np.testing.assert_allclose(p.x, xt, rtol=1e-12)
    # a well-scaled design: not scaled; the cut is max(m, N) eps s_1
    A2 = np.column_stack([np.ones(12), t, t * t])
    r2 = igea.ridge(A2, y, k=0.0)
    s1 = np.linalg.svd(A2, compute_uv=False)[0]
    assert not r2.scaled and r2.rank == 3
    assert abs(r2.rank_tol / (12 * np.finfo(float).eps * s1) - 1) < 1e-12


def test_ebr_rank_tol():
    """EBR's rank and the cut it applied: max(m, N) eps s_1 of diag(1/sigma) A D."""
    rng = np.random.default_rng(5)
    A = rng.standard_normal((20, 6))
    A[:, 5] = A[:, 4] + A[:, 3]  # exactly dependent: rank 5
    y = A @ rng.standard_normal(6) + 0.1 * rng.standard_normal(20)
    spec = np.array([1, 2, 3, 1, 1, 1.0])
    r = igea.ebr(A, y, 0.5, spec=spec)
    s = np.linalg.svd(A * spec / 0.5, compute_uv=False)
    assert r.rank == 5
    assert abs(r.rank_tol / (20 * np.finfo(float).eps * s[0]) - 1) < 1e-12
    assert s[4] > r.rank_tol > s[5]


def test_tall_designs_through_the_qr_factor():
    """m >= 2N rows go through the QR factor of the weighted design (no U,
    docs/regress.md "Tall designs"): x, sd, residuals and the leverages
    against numpy's QR of the whole weighted design, written here, for a
    well-conditioned design (leverages from the factor, to 1e-12) and one
    with s_1/s_r ~ 1e8 (leverages from U of the full SVD); the residual sum
    of squares rho^2 + sum z_i^2 beyond the rank against numpy's."""
    rng = np.random.default_rng(11)
    m, N = 3000, 12
    for scales in (np.ones(N), np.logspace(0, -7, N)):
        Q0, _ = np.linalg.qr(rng.standard_normal((m, N)))
        V0, _ = np.linalg.qr(rng.standard_normal((N, N)))
        A = (Q0 * np.logspace(0, -1, N)) @ (V0 * scales).T * 50.0
        sg = 0.5 + rng.random(m)
        y = A @ rng.standard_normal(N) + sg * rng.standard_normal(m)
        r = igea.ls(A, y, sg)
        Aw, yw = A / sg[:, None], y / sg
        Q, R = np.linalg.qr(Aw)
        x = np.linalg.solve(R, Q.T @ yw)
        e = y - A @ x
        s2 = np.sum((e / sg) ** 2) / (m - N)
        Ri = np.linalg.inv(R)
        # numpy's own error grows with the conditioning: eps cond
        tol = 1e-14 + 4 * np.finfo(float).eps * np.linalg.cond(Aw)
        np.testing.assert_allclose(r.x, x, rtol=tol)
        np.testing.assert_allclose(r.sigma2, s2, rtol=1e-12)
        np.testing.assert_allclose(r.residual, e, rtol=0, atol=tol * np.abs(y).max())
        np.testing.assert_allclose(r.sd, np.sqrt(s2 * np.sum(Ri ** 2, axis=1)), rtol=10 * tol)
        # the leverages of an ill-conditioned design move by eps cond with the
        # rounding of its columns' scaling (numpy's of the equilibrated
        # design differ from its own as much)
        np.testing.assert_allclose(r.leverage, np.sum(Q ** 2, axis=1), rtol=1e-12 + 10 * tol)
        assert r.rank == N and r.refine_steps >= 1
    # rank-deficient (two equal columns): minimum-norm solution, RSS from
    # the components of Q^T y beyond the rank
    A = np.column_stack([A[:, :N - 1], A[:, 0]])
    r = igea.ls(A, y)
    xs = np.linalg.pinv(A) @ y
    np.testing.assert_allclose(r.x, xs, rtol=1e-8)
    assert r.rank == N - 1
    np.testing.assert_allclose(r.sigma2, np.sum((y - A @ xs) ** 2) / (m - N + 1), rtol=1e-10)
