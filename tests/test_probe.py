"""The radiance probe's numbers (planetviz/app/probe.py) and the windows' parameter rows
(planetviz/app/parameters.py)."""
import numpy as np
import pytest

from planetviz.app.parameters import GEOMETRY, STANDARD, apply_parameter
from planetviz.app.probe import angles_seen_from, probe_directions, readings, sun_vertical
from planetviz.model.geometry import EYE_HEIGHT_M, local_frame, site_direction
from planetviz.model.limits import LIMITS, AtmosphereError
from planetviz.model.optics.light import star_irradiance
from planetviz.model.presets import load_atmosphere
from planetviz.tables import QUALITY, TableCache, precompute


@pytest.fixture(scope="module")
def earth():
    atm = load_atmosphere("earth")
    return atm, precompute(atm, QUALITY["draft"], cache=TableCache())


def test_a_reading_in_every_unit(earth):
    atm, _ = earth
    rng = np.random.default_rng(3)
    radiance = rng.uniform(0.0, 0.2, (5, atm.n_wavelengths))
    camera = (atm.bottom_radius_m + 10.0) * local_frame(20.0, 30.0)[0]
    dirs = np.array([site_direction(e, a, 20.0, 30.0) for e, a in zip([5, 20, 45, 70, 89], [0, 90, 180, 270, 359])])
    for i, r in enumerate(readings(radiance, atm, camera, dirs, "test")):
        assert np.allclose(r.spectral_radiance, radiance[i] * star_irradiance(atm.star, atm.wavelengths_nm))
        # sRGB's luminance row (IEC 61966-2-1: 0.2126, 0.7152, 0.0722, given to 4 digits) against CIE Y.
        assert np.dot([0.2126, 0.7152, 0.0722], r.linear_srgb) == pytest.approx(r.luminance, rel=1e-3)
        assert (r.elevation_deg, r.azimuth_deg) == pytest.approx(([5, 20, 45, 70, 89][i], [0, 90, 180, 270, 359][i]),
                                                                 abs=1e-9)


def test_angles_of_a_direction_seen_from_a_site():
    camera = 6.4e6 * local_frame(-33.0, 151.0)[0]
    assert angles_seen_from(camera, site_direction(12.0, 300.0, -33.0, 151.0)) == pytest.approx((12.0, 300.0))


def test_the_sun_vertical_reads_the_tables_along_the_vertical_through_the_sun(earth):
    atm, tables = earth
    site = (45.0, 10.0)
    up = local_frame(*site)[0]
    sun = site_direction(25.0, 135.0, *site)
    angle, luminance, at = sun_vertical(tables, atm, 4.0 * atm.bottom_radius_m * up, sun, points=7)
    # From space the vertical is seen from eye height below the camera.
    assert np.allclose(at, (atm.bottom_radius_m + EYE_HEIGHT_M) * up)
    assert np.allclose(angle, [0, 30, 60, 90, 120, 150, 180])
    want = [site_direction(min(a, 180 - a), 135.0 if a <= 90 else 315.0, *site) for a in angle]
    direct = [r.luminance for r in probe_directions(tables, atm, at, np.array(want), sun)]
    assert np.allclose(luminance[1:-1], direct[1:-1], rtol=1e-9)
    # Exactly horizontal, the two ways of writing the direction differ in the last bit, and the tables' reading
    # there is not continuous to that bit (0.1% seen): 1% checks the end points are the horizons.
    assert np.allclose(luminance[[0, -1]], np.array(direct)[[0, -1]], rtol=0.01)


def test_parameter_rows_refuse_values_naming_the_row_or_the_field_and_the_range():
    atm = load_atmosphere("earth")
    d = atm.to_dict()
    g1 = next(r for r in STANDARD if r.label.startswith("Mie g1"))
    with pytest.raises(AtmosphereError, match=r"Mie g1.*\[-0.999, 0.999\]"):
        apply_parameter(g1, d, d, 1.2)
    radius = next(r for r in GEOMETRY if r.label.startswith("planet radius"))
    with pytest.raises(AtmosphereError, match=r"top_radius_m.*allowed range"):
        apply_parameter(radius, d, d, 40.0)          # 40 km of planet under 60 km of atmosphere
    scale = next(r for r in STANDARD if r.label.startswith("Rayleigh x"))
    lo, hi = scale.allowed_range(d)
    assert lo == 0 and hi * max(d["rayleigh"]["scattering_m"]) == pytest.approx(LIMITS["coefficient_m"][1])
    new, source = apply_parameter(scale, d, d, 2.0)
    assert np.allclose(new.rayleigh.scattering_m, 2.0 * np.asarray(atm.rayleigh.scattering_m))
    assert d == atm.to_dict()                        # the caller's form untouched
