"""Inputs of igea.eqerr as analysts hold them: a data frame for S (its
columns name the terms), and S transposed refused as such, in Python and
in the driver.

pandas is not installed here: the frame is a stand-in with the two members
eqerr uses (.columns and .to_numpy()), as a pandas DataFrame has them."""
import os
import subprocess

import numpy as np
import pytest

import igea

DRIVER = os.environ.get("IGEA_DRIVER")


class Frame:
    """The two members of pandas.DataFrame that igea.eqerr reads."""

    def __init__(self, data, columns):
        self._data, self.columns = np.array(data, dtype=float), list(columns)

    def to_numpy(self):
        return self._data.copy()


@pytest.fixture(scope="module")
def fl():
    return igea.simulate(seed=5)


def test_frame_columns_are_the_names(fl):
    names = ["t%02d" % j for j in range(fl.S.shape[1])]
    a = igea.eqerr(Frame(fl.S, names), fl.dw, fl.sigma, fl.spec)
    # the stand-in hands out a C-order copy, which eqerr reads row by row (a
    # summation order of its own): the same layout on both sides
    b = igea.eqerr(np.ascontiguousarray(fl.S), fl.dw, fl.sigma, fl.spec, names=names)
    assert a.to_dict() == b.to_dict()
    terms = {t[0] for c in a.components for t in c["terms"]}
    assert terms and terms <= set(names)
    assert getattr(a, "_names") == names


def test_frame_names_given_win(fl):
    N = fl.S.shape[1]
    mine = ["k%d" % j for j in range(N)]
    r = igea.eqerr(Frame(fl.S, range(N)), fl.dw, fl.sigma, fl.spec, names=mine)
    assert getattr(r, "_names") == mine
    r = igea.eqerr(Frame(fl.S, range(N)), fl.dw, fl.sigma, fl.spec)
    assert getattr(r, "_names") == [str(j) for j in range(N)]    # non-string columns
    with pytest.raises(ValueError, match="names: 2 names"):
        igea.eqerr(Frame(fl.S, ["a", "b"]), fl.dw, fl.sigma, fl.spec)


def test_transposed_S_is_named(fl):
    m, N = fl.S.shape
    msg = r"S has %d rows and %d columns; dw has %d values: pass S\.T\?" % (N, m, m)
    with pytest.raises(ValueError, match=msg):
        igea.eqerr(fl.S.T, fl.dw, fl.sigma, fl.spec)
    with pytest.raises(ValueError, match=msg):                 # a frame the wrong way round
        igea.eqerr(Frame(fl.S.T, range(m)), fl.dw, fl.sigma)
    with pytest.raises(ValueError, match=r"pass S\.T\?"):      # the noise-model route too
        igea.eqerr(fl.S.T, fl.dw, fl.sigma, robust=True)
    # a dw that is merely short is not called a transposition
    with pytest.raises(ValueError) as e:
        igea.eqerr(fl.S, fl.dw[:-3], fl.sigma)
    assert "S.T" not in str(e.value)


@pytest.mark.skipif(not DRIVER or not os.path.exists(DRIVER), reason="IGEA_DRIVER not built")
@pytest.mark.parametrize("fmt", ["txt", "npy"])
def test_driver_names_a_transposed_S(tmp_path, fl, fmt):
    m, N = fl.S.shape
    if fmt == "npy":
        np.save(tmp_path / "ST.npy", fl.S.T)
        np.save(tmp_path / "S.npy", fl.S)
    else:
        np.savetxt(tmp_path / "ST.txt", fl.S.T, fmt="%.17g")
        np.savetxt(tmp_path / "S.txt", fl.S, fmt="%.17g")
    np.savetxt(tmp_path / "dw.txt", fl.dw, fmt="%.17g")
    np.savetxt(tmp_path / "short.txt", fl.dw[:-3], fmt="%.17g")

    def run(S, dw):
        return subprocess.run([DRIVER, "eqerr", "--S", "%s.%s" % (S, fmt), "--dw", dw,
                               "--sigma", "0.01"], capture_output=True, text=True, cwd=tmp_path)
    r = run("ST", "dw.txt")
    assert r.returncode == 65
    assert ("ST.%s has %d rows and %d columns; dw.txt has %d values: transposed?"
            % (fmt, N, m, m)) in r.stderr, r.stderr
    r = run("S", "short.txt")        # the short dw keeps its own message
    assert r.returncode == 65 and "short.txt ends early" in r.stderr
    assert "transposed" not in r.stderr
