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
