"""igea eqerr --cov reads each epoch's lower triangle by rows (xx yx yy zx
zy zz). A file whose header names its columns as covariance entries in
another order (igea dw --cov-out writes xx xy xz yy yz zz) would swap
c_xz and c_yy if read by position: it is refused, naming the file and the
file to use; files in the right order, or without covariance names, pass."""
import os
import subprocess

import numpy as np
import pytest

DRIVER = os.environ.get("IGEA_DRIVER", "build/bin/igea")


@pytest.fixture
def flight(tmp_path):
    rng = np.random.default_rng(1)
    M = 20
    np.savetxt(tmp_path / "S.txt", rng.standard_normal((3 * M, 3)))
    np.savetxt(tmp_path / "dw.txt", rng.standard_normal(3 * M) * 0.01)
    c = np.tile([1e-4, 2e-5, 1e-4, 1e-5, 3e-5, 1e-4], (M, 1))
    return tmp_path, c


def run(d, cov):
    return subprocess.run([DRIVER, "eqerr", "--S", "S.txt", "--dw", "dw.txt", "--cov", cov],
                          cwd=d, capture_output=True, text=True)


@pytest.mark.parametrize("header", ["names c_xx c_yx c_yy c_zx c_zy c_zz",
                                    "names c_xx c_xy c_yy c_xz c_yz c_zz",  # symmetric names
                                    "xx yx yy zx zy zz", "names a b c d e f", None])
def test_right_order_or_no_covariance_names(flight, header):
    d, c = flight
    if header:  # igea's header: names, then more comment lines
        header += "\nunits m^2/s^2\none row per epoch, launch-inertial axes"
    np.savetxt(d / "k.txt", c, **({"header": header} if header else {}))
    r = run(d, "k.txt")
    assert r.returncode == 0, r.stderr


@pytest.mark.parametrize("header,hint", [("names c_xx c_xy c_xz c_yy c_yz c_zz", True),
                                         ("c_zz c_yx c_yy c_zx c_zy c_xx", False)])
def test_another_order_refused(flight, header, hint):
    d, c = flight
    np.savetxt(d / "c.txt", c, header=header + "\nunits m^2/s^2")
    r = run(d, "c.txt")
    assert r.returncode == 65 and r.stdout == ""
    assert "c.txt: its columns are named in another order" in r.stderr
    assert ("igea dw --k-out" in r.stderr) == hint
