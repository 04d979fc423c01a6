"""Named components: the tested eigen-components as patterns of the error
terms (shares p_ij^2, loadings spec_j p_ij, candidates), against numpy on
the result's own eigenvectors and the spec; the driver's names from
--names and from the '# names' header igea writes; a term set far out of
spec is named among the candidates of the component that rejects it."""
import json
import os
import subprocess

import numpy as np
import pytest

import igea
from test_eqerr import flight


def driver(*args, cwd=None):
    return subprocess.run([os.environ["IGEA_DRIVER"], *map(str, args)], capture_output=True,
                          text=True, cwd=cwd)


def test_components_against_numpy():
    S, dw, sigma, spec, _ = flight(4)
    names = ["t%02d" % j for j in range(S.shape[1])]
    r = igea.eqerr(S, dw, sigma, spec, names=names)
    assert len(r.components) == r.n_test > 0
    # independent eigenvectors of the spec-scaled weighted normal matrix
    St = S * spec / sigma[:, None]
    w, V = np.linalg.eigh(St.T @ St)
    V = V[:, ::-1]
    for c in r.components:
        i = c["index"]
        p = V[:, i] * np.sign(V[:, i] @ r.eigenvectors[:, i])
        share = dict(c["terms"])
        np.testing.assert_allclose([share[n] for n in names], p ** 2, atol=1e-9)
        assert sum(share.values()) == pytest.approx(1.0, abs=1e-12)
        got = [s for _, s in c["terms"]]
        assert got == sorted(got, reverse=True)
        np.testing.assert_allclose(c["loading"], spec * p, rtol=1e-7, atol=1e-12 * spec.max())
        assert c["candidates"] == [n for n, s in c["terms"] if s >= 0.10]
        assert c["lambda"] == r.eigenvalues[i] and c["z"] == r.z[i]
        assert c["reject"] == bool(r.reject[i])
    assert "named components" in r.summary()
    default = igea.eqerr(S, dw, sigma, spec)
    assert default.components[0]["terms"][0][0].startswith("column_")
    with pytest.raises(ValueError, match="names"):
        igea.eqerr(S, dw, sigma, spec, names=names[:-1])


def test_driver_names_from_header_and_option(tmp_path):
    f = igea.simulate(x={"gyro_bias_y": 8.0}, seed=2)
    hdr = " ".join(f.terms)
    np.savetxt(tmp_path / "S.txt", f.S, header=hdr)     # '# name name ...'
    for k in ("dw", "sigma", "spec"):
        np.savetxt(tmp_path / (k + ".txt"), getattr(f, k))
    base = ["eqerr", "--S", "S.txt", "--dw", "dw.txt", "--sigma", "sigma.txt", "--spec",
            "spec.txt"]
    c = driver(*base, "--json", cwd=tmp_path)
    j = json.loads(c.stdout)
    r = igea.eqerr(f.S, f.dw, f.sigma, f.spec, names=list(f.terms))
    assert len(j["components"]) == r.n_test
    for cj, cp in zip(j["components"], r.components):
        assert [t[0] for t in cj["terms"]] == [t[0] for t in cp["terms"]]
        np.testing.assert_allclose([t[1] for t in cj["terms"]], [t[1] for t in cp["terms"]],
                                   atol=1e-12)
        # eigenvector entries hold their digits relative to the vector, not each
        # (the driver streams and runs BLAS on one thread; Python loads)
        big = np.max(np.abs(cp["loading"]))
        np.testing.assert_allclose(cj["loading"], cp["loading"], rtol=1e-9, atol=1e-12 * big)
        assert cj["candidates"] == cp["candidates"] and cj["reject"] == cp["reject"]
    # gyro_bias_y at 8 x spec: a rejected component names it
    rejected = [c for c in r.components if c["reject"]]
    assert rejected and any("gyro_bias_y" in c["candidates"] for c in rejected)
    text = driver(*base, cwd=tmp_path).stdout
    assert "REJECT candidates:" in text and "gyro_bias_y" in text
    # --names overrides, and must name every column
    names = ",".join("n%d" % k for k in range(len(f.terms)))
    j2 = json.loads(driver(*base, "--names", names, "--json", cwd=tmp_path).stdout)
    assert j2["components"][0]["terms"][0][0].startswith("n")
    c = driver(*base, "--names", "a,b", cwd=tmp_path)
    assert c.returncode == 64 and "--names" in c.stderr
    # no header: column_j
    np.savetxt(tmp_path / "S.txt", f.S)
    j3 = json.loads(driver(*base, "--json", cwd=tmp_path).stdout)
    assert j3["components"][0]["terms"][0][0].startswith("column_")
