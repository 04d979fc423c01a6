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
