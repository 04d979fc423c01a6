"""igea.nav_* against closed forms written here with numpy/scipy: the
meridian ellipse (WGS-84, NIMA TR8350.2), a point fixed on the Earth seen
from the launch-inertial frame, J2 gravitation at the equator and pole,
and a ballistic flight against scipy's solve_ivp."""
import numpy as np
import pytest
from scipy.integrate import solve_ivp

import igea

A, F, GM, WE, J2 = 6378137.0, 1 / 298.257223563, 3.986004418e14, 7.292115e-5, 1.082629821313e-3
B = 6356752.3142  # TR8350.2 table 3.3


@pytest.mark.parametrize("lat,lon,h", [(0, 0, 0), (45, 10, 0), (-33.3, 151.2, 3000),
                                       (89.99, -60, 1e5), (28.5, -80.6, 1.5e6)])
def test_geodetic_ecef(lat, lon, h):
    phi, lam = np.radians(lat), np.radians(lon)
    beta = np.arctan((1 - F) * np.tan(phi))  # reduced latitude
    p = A * np.cos(beta) + h * np.cos(phi)
    want = np.array([p * np.cos(lam), p * np.sin(lam), A * (1 - F) * np.sin(beta) + h * np.sin(phi)])
    r = igea.nav_geodetic_to_ecef(phi, lam, h)
    np.testing.assert_allclose(r, want, atol=1e-7)
    back = igea.nav_ecef_to_geodetic(want)
    np.testing.assert_allclose(back, (phi, lam, h), atol=1e-7)


def test_pole():
    r = igea.nav_geodetic_to_ecef(np.pi / 2, 0.0, 0.0)
    assert abs(r[2] - B) < 1e-4


def test_earth_fixed_point_in_li():
    site = igea.nav_site(np.radians(40.0), np.radians(100.0), 500.0, np.radians(60.0))
    C = site[7:16].reshape(3, 3)
    r0 = site[4:7]
    axis, centre = C[:, 2], -C @ r0
    rle = np.array([3000.0, 100.0, -2000.0])
    for t in (0.0, 60.0, 2 * np.pi / WE):
        r, v = igea.nav_transform(site, rle, np.zeros(3), t, frm="le", to="li")
        np.testing.assert_allclose(v, np.cross(WE * axis, r - centre), atol=1e-9)
        np.testing.assert_allclose(np.linalg.norm(r - centre), np.linalg.norm(rle - centre),
                                   rtol=1e-14)
    np.testing.assert_allclose(r, rle, atol=1e-6)  # after one sidereal turn


def test_gravity():
    g, G = igea.nav_gravity([A, 0, 0])
    assert g[0] == pytest.approx(-GM / A**2 * (1 + 1.5 * J2), rel=1e-14)
    g, G = igea.nav_gravity([0, 0, B])
    assert g[2] == pytest.approx(-GM / B**2 * (1 - 3 * J2 * (A / B) ** 2), rel=1e-14)
    g, G = igea.nav_gravity([1e6, 2e6, 6e6], model="point_mass")
    r = np.array([1e6, 2e6, 6e6])
    n = np.linalg.norm(r)
    np.testing.assert_allclose(G, -GM / n**3 * (np.eye(3) - 3 * np.outer(r, r) / n**2), rtol=1e-13)


def test_ballistic_platform():
    """No specific force, 1.5 km/s up: navigation (100 Hz, trapezoid) against
    solve_ivp of the point-mass motion in the inertial frame."""
    site = igea.nav_site(np.radians(20.0), np.radians(30.0), 0.0, 0.0)
    C, r0 = site[7:16].reshape(3, 3), site[4:7]
    _, vpad = igea.nav_transform(site, np.zeros(3), np.zeros(3), 0.0, frm="le", to="li")
    v0 = vpad + np.array([0, 1500.0, 0])
    tel = np.zeros((10001, 4))
    tel[:, 0] = np.arange(10001) / 100.0
    res = igea.nav_navigate(site, tel, system="platform", gravity="point_mass", v0=v0)
    sol = solve_ivp(lambda t, x: np.concatenate([x[3:], -GM * x[:3] / np.linalg.norm(x[:3])**3]),
                    (0, 100.0), np.concatenate([r0, C.T @ v0]), method="DOP853", rtol=1e-13,
                    atol=1e-8)
    rI, vI = sol.y[:3, -1], sol.y[3:, -1]
    np.testing.assert_allclose(res.r[-1], C @ (rI - r0), atol=2e-3)
    np.testing.assert_allclose(res.v[-1], C @ vI, atol=1e-5)
    assert np.all(res.w == 0)


def test_bad_arguments():
    with pytest.raises(igea.IgeaError, match="lat"):
        igea.nav_geodetic_to_ecef(2.0, 0.0, 0.0)
    with pytest.raises(ValueError, match="frm"):
        igea.nav_transform(np.zeros(16), np.zeros(3), np.zeros(3), 0.0, frm="eci")
