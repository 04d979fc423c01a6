"""Virtual IMUs (igea.redund_group) against numpy written here: the group
frames by Gram-Schmidt of each triad's calibrated axes, the unification
into group 0's frame, the fused output and its covariance L diag(s^2) L^T
for the average, per-axis weighted and GLS rules (the GLS by numpy's
weighted normal equations); seed 002's grouping (Ax1..Ax4 with the shared
Ay, Az): the shared sensors double the variance of the fused y and z
channels against what independent groups would state (two distinct Ay
sensors, not four), while the four distinct X accelerometers halve the x
sigma (fusing 4: sd / 2, the seed's 1530 -> 790 m is a ratio of 1.94)."""
import numpy as np
import pytest

import igea


def rot(v):
    """exp([v x]) by Rodrigues."""
    a = np.linalg.norm(v)
    k = np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]]) / a
    return np.eye(3) + np.sin(a) * k + (1 - np.cos(a)) * k @ k


def seed002_sensors(rng):
    """8 accelerometers Ax1..Ax4, Ay1, Ay2, Az1, Az2: nominal axes x x x x y
    y z z of the IMU, each misaligned by ~1 mrad and scaled by 1 +- 1e-4,
    the IMU turned by a rotation Q in the reference frame R."""
    Q = rot(np.array([0.3, -0.5, 1.1]))
    nominal = np.array([[1, 0, 0]] * 4 + [[0, 1, 0]] * 2 + [[0, 0, 1]] * 2, dtype=float)
    axes = np.array([(1 + 1e-4 * rng.standard_normal()) * (rot(1e-3 * rng.standard_normal(3)) @ n)
                     for n in nominal])
    return axes @ Q.T


def frame(A):
    x = A[0] / np.linalg.norm(A[0])
    y = A[1] - (A[1] @ x) * x
    y /= np.linalg.norm(y)
    return np.array([x, y, np.cross(x, y)])


def numpy_reference(axes, sigma, y, groups, fusion):
    F0 = frame(axes[list(groups[0])])
    n = len(sigma)
    Gs, Cs = [], []
    for g in groups:
        A = axes[list(g)]
        G = np.zeros((3, n))
        G[:, list(g)] = F0 @ np.linalg.inv(A)
        Gs.append(G)
        Cs.append(F0 @ frame(A).T)
    S = np.diag(sigma ** 2)
    covs = [G @ S @ G.T for G in Gs]
    if fusion == "gls":
        used = sorted({s for g in groups for s in g})
        B = axes[used] @ F0.T                       # body-frame axes
        Wi = np.diag(1 / sigma[used] ** 2)
        N = B.T @ Wi @ B
        L = np.zeros((3, n))
        L[:, used] = np.linalg.solve(N, B.T @ Wi)
        ci = np.linalg.inv(N)
    else:
        if fusion == "average":
            W = np.ones((len(groups), 3))
        else:
            W = np.array([1 / np.diag(c) for c in covs])
        W /= W.sum(axis=0)
        L = sum(np.diag(W[k]) @ Gs[k] for k in range(len(groups)))
        ci = sum(np.diag(W[k]) @ covs[k] @ np.diag(W[k]) for k in range(len(groups)))
    return np.array(Cs), np.array([G @ y for G in Gs]), L @ y, L @ S @ L.T, ci


@pytest.mark.parametrize("fusion", ["average", "weighted", "gls"])
def test_against_numpy(fusion):
    rng = np.random.default_rng(2)
    axes = seed002_sensors(rng)
    sigma = np.array([1e-4, 1.2e-4, 0.8e-4, 1.1e-4, 2e-4, 1.5e-4, 2e-4, 2.5e-4])
    f = np.array([0.3, 9.8, -0.2])
    y = axes @ f + sigma * rng.standard_normal(8)
    r = igea.redund_group(axes, sigma, y, fusion=fusion)
    C, u, fu, cov, ci = numpy_reference(axes, sigma, y,
                                        ((0, 4, 6), (1, 5, 7), (2, 4, 6), (3, 5, 7)), fusion)
    np.testing.assert_allclose(r.frames, C, rtol=0, atol=1e-13)
    np.testing.assert_allclose(r.group_out, u, rtol=1e-12)
    np.testing.assert_allclose(r.fused, fu, rtol=1e-12)
    np.testing.assert_allclose(r.cov, cov, rtol=1e-10, atol=1e-24)
    np.testing.assert_allclose(r.cov_indep, ci, rtol=1e-10, atol=1e-24)
    for Cg in r.frames:
        np.testing.assert_allclose(Cg @ Cg.T, np.eye(3), atol=1e-13)


def test_shared_sensors_and_the_x_ratio():
    """Equal sigmas, the average rule: the fused x variance is s^2 / 4
    (four distinct Ax), y and z s^2 / 2 (two distinct Ay, Az each shared by
    two groups) where independent groups would state s^2 / 4: to 1e-3
    relative (the 1e-4 scale factors enter the variances at first order)."""
    rng = np.random.default_rng(5)
    axes = seed002_sensors(rng)
    s = 1e-4
    sigma = np.full(8, s)
    r = igea.redund_group(axes, sigma, axes @ np.array([0.0, 9.8, 0.0]), fusion="average")
    np.testing.assert_allclose(np.diag(r.cov), [s**2 / 4, s**2 / 2, s**2 / 2], rtol=1e-3)
    np.testing.assert_allclose(np.diag(r.cov_indep), [s**2 / 4] * 3, rtol=1e-3)
    one = igea.redund_group(axes, sigma, axes @ np.array([0.0, 9.8, 0.0]),
                            groups=[(0, 4, 6)], fusion="average")
    assert np.sqrt(one.cov[0, 0] / r.cov[0, 0]) == pytest.approx(2.0, rel=1e-3)


def test_refusals():
    rng = np.random.default_rng(1)
    axes = seed002_sensors(rng)
    sigma, y = np.full(8, 1e-4), np.zeros(8)
    with pytest.raises(igea.IgeaError):                       # a sensor twice in a group
        igea.redund_group(axes, sigma, y, groups=[(0, 0, 6)])
    with pytest.raises(igea.IgeaError):                       # index out of range
        igea.redund_group(axes, sigma, y, groups=[(0, 4, 8)])
    bad = axes.copy()
    bad[6] = bad[0] + bad[4]                                  # dependent triad
    with pytest.raises(igea.IgeaError, match="singular"):
        igea.redund_group(bad, sigma, y)
    with pytest.raises(igea.IgeaError):
        igea.redund_group(axes, np.r_[sigma[:7], 0.0], y)
    with pytest.raises(ValueError, match="fusion"):
        igea.redund_group(axes, sigma, y, fusion="median")


def test_driver(tmp_path):
    """igea redund group: the JSON equals igea.redund_group of the same
    inputs (axes as rows of a text file); bad groups are refused naming
    --groups."""
    import json
    import os
    import subprocess
    rng = np.random.default_rng(7)
    axes = seed002_sensors(rng)
    y = axes @ np.array([0.2, 9.8, -0.1]) + 1e-4 * rng.standard_normal(8)
    np.savetxt(tmp_path / "axes.txt", axes, fmt="%.17g")
    np.savetxt(tmp_path / "y.txt", y, fmt="%.17g")
    drv = os.environ["IGEA_DRIVER"]
    base = [drv, "redund", "group", "--axes", str(tmp_path / "axes.txt"), "--y",
            str(tmp_path / "y.txt"), "--sigma", "1e-4"]
    for extra, fusion in (([], "weighted"), (["--gls"], "gls"), (["--average"], "average")):
        js = json.loads(subprocess.run(base + extra + ["--json"], capture_output=True, text=True,
                                       check=True).stdout)
        r = igea.redund_group(axes, np.full(8, 1e-4), y, fusion=fusion)
        assert js["fusion"] == fusion
        for key in ("frames", "group_out", "fused", "cov", "cov_indep"):
            np.testing.assert_allclose(np.array(js[key]), getattr(r, key), rtol=1e-12, atol=1e-300)
    bad = subprocess.run(base + ["--groups", "0,4,6;1,5"], capture_output=True, text=True)
    assert bad.returncode == 64 and "--groups" in bad.stderr
    bad = subprocess.run(base + ["--groups", "0,4,8"], capture_output=True, text=True)
    assert bad.returncode == 64 and "--groups" in bad.stderr
