"""Errors of the Python package: data errors are ValueErrors and say where.

A data status the library returns without naming an argument (NaN or Inf,
a sigma <= 0 or below IGEA_SIGMA_MIN) is reported with the first offending
element of the inputs; an invalid argument -i names the parameter; out of
memory, non-convergence and LAPACK failures are not ValueErrors.
"""
import os
import subprocess
import sys

import numpy as np
import pytest

import igea
from igea import _capi, _lib

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))

# 8 rows, 2 terms: a small, well-posed flight (rows x, y, z epoch-major)
S = np.array([[1.0, 0.5], [0.2, 1.0], [0.3, 0.1], [1.0, 1.0], [0.0, 2.0], [1.0, 0.0],
              [0.5, 0.5], [2.0, 0.1]])
DW = np.array([0.1, -0.05, 0.02, 0.2, 0.1, 0.0, 0.03, -0.1])


def test_nonfinite_names_the_element():
    dw = DW.copy()
    dw[5] = np.nan
    with pytest.raises(ValueError) as e:
        igea.eqerr(S, dw, 0.1)
    assert isinstance(e.value, igea.DataError) and isinstance(e.value, igea.IgeaError)
    assert e.value.code == _capi.ENONFINITE and e.value.detail == "dw[5] = nan"
    assert "dw[5] = nan" in str(e.value)
    s = S.copy()
    s[6, 1] = np.inf  # a matrix element: (row, column)
    with pytest.raises(igea.DataError) as e:
        igea.eqerr(s, DW, 0.1)
    assert e.value.detail == "S[6, 1] = inf"


def test_nonpositive_sigma_names_the_element():
    sigma = np.full(8, 0.1)
    sigma[3] = 0.0
    with pytest.raises(ValueError) as e:
        igea.eqerr(S, DW, sigma)
    assert e.value.code == _capi.ENONPOSITIVE
    assert e.value.detail == "track_sigma[3] = 0.0"
    assert str(e.value).startswith("igea.eqerr: track_sigma[3] = 0.0: ")
    sigma[3] = 1e-200  # positive, below IGEA_SIGMA_MIN = 2^-511
    with pytest.raises(ValueError) as e:
        igea.eqerr(S, DW, sigma)
    assert e.value.code == _capi.ERANGE and e.value.detail == "track_sigma[3] = 1e-200"


def test_invalid_argument_is_a_value_error():
    with pytest.raises(ValueError) as e:
        igea.reliability_kofn([0.9, 0.9], 3)
    assert e.value.argument == "k" and "(k)" in str(e.value)
    with pytest.raises(ValueError, match="alpha"):
        igea.eqerr(S, DW, 0.1, alpha=1.5)


@pytest.mark.parametrize("code, data", [
    (_capi.ENOMEM, False), (_capi.ENOCONV, False), (_capi.ELAPACK, False),
    (_capi.ENONFINITE, True), (_capi.ESINGULAR, True), (_capi.ERANK, True),
    (_capi.ENOTESTABLE, True), (-3, True)])
def test_which_statuses_are_data_errors(code, data):
    e = _lib.error(code, "text")
    assert isinstance(e, igea.IgeaError)
    assert isinstance(e, ValueError) == data


def test_library_directory_accepted():
    """IGEA_LIBRARY may name the directory that holds libigea.so.1."""
    lib = os.environ.get("IGEA_LIBRARY") or os.path.join(REPO, "build", "lib", "libigea.so.1")
    d = lib if os.path.isdir(lib) else os.path.dirname(lib)
    env = dict(os.environ, IGEA_LIBRARY=d, PYTHONPATH=os.path.join(REPO, "python"))
    r = subprocess.run([sys.executable, "-c", "import igea._lib as L; print(L.lib._name)"],
                       env=env, capture_output=True, text=True, cwd="/")
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip() == os.path.join(d, "libigea.so.1")


def test_status_class_is_one_fact_for_the_driver_and_python(tmp_path):
    """igea_status_class decides both: a DATA status is a DataError in Python
    and exit 65 in the driver; a FAILURE or RESOURCE status is neither."""
    lib = igea._lib.lib
    data = [_capi.ENONFINITE, _capi.ENONPOSITIVE, _capi.ESINGULAR, _capi.ERANK, _capi.EDOMAIN,
            _capi.ENOTESTABLE, _capi.EDEPENDENT, _capi.EEMPTY, _capi.ERANGE, _capi.EOVERFLOW,
            _capi.EFORMAT]
    for code in data:
        assert lib.igea_status_class(code) == _capi.STATUS_DATA, code
        assert isinstance(igea._lib.error(code, "x"), ValueError)
    for code, cls in ((_capi.ENOMEM, _capi.STATUS_RESOURCE), (_capi.ENOCONV, _capi.STATUS_FAILURE),
                      (_capi.ELAPACK, _capi.STATUS_FAILURE), (_capi.EREAD, _capi.STATUS_INPUT),
                      (-1, _capi.STATUS_ARGUMENT), (0, _capi.STATUS_OK), (-5000, _capi.STATUS_FAILURE)):
        assert lib.igea_status_class(code) == cls, code
        assert isinstance(igea._lib.error(code, "x"), ValueError) == (cls == _capi.STATUS_ARGUMENT)
