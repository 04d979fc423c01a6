"""Residual whiteness per axis (Ljung-Box, runs test) against numpy
formulas written here; the streamed driver against the in-memory Python
result."""
import json
import os
import subprocess

import numpy as np
import pytest
from scipy import stats

import igea
from test_eqerr import flight


def ljung_box(x, lags):
    """Ljung & Box (1978): Q = n (n + 2) sum r_k^2 / (n - k), chi2(lags)."""
    d = x - x.mean()
    n = len(d)
    r = np.array([np.dot(d[:-k], d[k:]) for k in range(1, lags + 1)]) / np.dot(d, d)
    q = n * (n + 2) * np.sum(r ** 2 / (n - np.arange(1, lags + 1)))
    return q, stats.chi2.sf(q, lags)


def runs_test(x):
    """Wald & Wolfowitz (1940) on the signs about the mean, normal approximation."""
    s = np.sign(x - x.mean())
    s = s[s != 0]
    n1, n2 = np.sum(s > 0), np.sum(s < 0)
    runs = 1 + np.count_nonzero(s[1:] != s[:-1])
    n = n1 + n2
    mu = 2 * n1 * n2 / n + 1
    var = 2 * n1 * n2 * (2 * n1 * n2 - n) / (n * n * (n - 1))
    z = (runs - mu) / np.sqrt(var)
    return runs, n1, n2, z, 2 * stats.norm.sf(abs(z))


@pytest.mark.parametrize("ar, lags", [(0.0, 20), (0.8, 10), (0.0, 1)])
def test_whiteness_against_numpy(ar, lags):
    S, dw, sigma, spec, _ = flight(7, m=900, ar=ar)
    r = igea.eqerr(S, dw, sigma, spec, lags=lags)
    for a in range(3):
        x = r.residual[a::3]
        w = r.whiteness[a]
        q, p = ljung_box(x, lags)
        runs, n1, n2, z, pr = runs_test(x)
        assert w["axis"] == a and w["n"] == len(x) and w["lags"] == lags
        assert w["ljung_box"] == pytest.approx(q, rel=1e-10)
        assert w["ljung_box_p"] == pytest.approx(p, rel=1e-8, abs=1e-300)
        assert (w["runs"], w["n_above"], w["n_below"]) == (runs, n1, n2)
        assert w["runs_z"] == pytest.approx(z, rel=1e-10)
        assert w["runs_p"] == pytest.approx(pr, rel=1e-8)
    if ar:
        # AR(0.8) noise: far too few runs and a huge Q on every axis
        assert all(w["ljung_box_p"] < 1e-6 and w["runs_z"] < -4 for w in r.whiteness)
    assert "Ljung-Box" in r.summary()


def test_whiteness_not_computed_on_short_axes():
    S, dw, sigma, spec, _ = flight(3, m=60)
    r = igea.eqerr(S, dw, sigma, spec, lags=19)  # 20 values per axis < 19 + 2
    assert r.whiteness == [None, None, None]
    assert "not computed" in r.summary()
    with pytest.raises(igea.IgeaError):
        igea.eqerr(S, dw, sigma, spec, lags=0)


# 70,001 rows of 14 terms are read in three blocks of about 4 MB (rows
# 32,769 per block): the streamed states cross block boundaries mid-epoch.
@pytest.mark.parametrize("m", [1200, 70001])
def test_driver_streams_the_same_diagnostics(tmp_path, m):
    S, dw, sigma, spec, _ = flight(9, m=m, ar=0.3)
    for k, v in dict(S=S, dw=dw, sigma=sigma, spec=spec).items():
        np.save(tmp_path / (k + ".npy"), v)
    c = subprocess.run([os.environ["IGEA_DRIVER"], "eqerr", "--S", "S.npy", "--dw", "dw.npy",
                        "--sigma", "sigma.npy", "--spec", "spec.npy", "--lags", "12", "--json"],
                       cwd=tmp_path, capture_output=True, text=True)
    assert c.returncode in (0, 1), c.stderr
    j = json.loads(c.stdout)
    r = igea.eqerr(S, dw, sigma, spec, lags=12)
    for a in range(3):
        for k, v in r.whiteness[a].items():
            assert j["whiteness"][a][k] == pytest.approx(v, rel=1e-9), (a, k)
    c = subprocess.run([os.environ["IGEA_DRIVER"], "eqerr", "--S", "S.npy", "--dw", "dw.npy",
                        "--sigma", "sigma.npy", "--lags", "101"], cwd=tmp_path,
                       capture_output=True, text=True)
    assert c.returncode == 64 and "--lags" in c.stderr
