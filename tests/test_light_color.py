"""The light source and the colour pipeline."""
import numpy as np
import pytest

from planetviz import load_atmosphere
from planetviz.model.atmosphere import Star
from planetviz.model.color import radiance_to_xyz, xyz_matrix
from planetviz.model.optics.light import SOLAR_CONSTANT, solar_spectrum, star_irradiance


def test_blackbody_star_delivers_the_solar_constant():
    # int pi B_lambda(T) scale d lambda over 10 nm - 1 mm must be the solar constant (the Planck tail
    # beyond 1 mm and below 10 nm holds < 1e-6 of it at 3200 K).
    wl = np.geomspace(10.0, 1e6, 400001)
    e = star_irradiance(Star("blackbody", 3200.0), wl)
    assert np.trapezoid(e, wl) == pytest.approx(SOLAR_CONSTANT, rel=1e-4)


def test_shipped_solar_spectrum_is_astm_g173():
    # The shipped table equals colour-science's ASTM G-173 ETR at every wavelength (5 significant
    # digits), and that dataset integrates over 280-4000 nm to NREL's published total of the G-173
    # extraterrestrial column, 1348.0 W/m^2 (0.5%; 1366.1 would be ASTM E-490's, a different table).
    from colour.plotting.datasets import SD_ASTMG173_ETR as ref
    wl, e = solar_spectrum()
    assert np.allclose(e, np.interp(wl, ref.wavelengths, ref.values), rtol=1e-4)
    assert np.trapezoid(ref.values, ref.wavelengths) == pytest.approx(1348.0, rel=0.005)


def test_flat_spectrum_is_white_and_an_m_dwarf_reddens_the_same_sky():
    import colour
    atm = load_atmosphere("earth")
    flat = np.ones(3) @ xyz_matrix(atm.wavelengths_nm)
    # A flat spectrum between the samples has the chromaticity of illuminant E (1/3, 1/3).
    assert np.allclose(flat[:2] / flat.sum(), [1 / 3, 1 / 3], atol=2e-3)
    radiance = np.array([0.004, 0.009, 0.022])     # a blue zenith, per unit irradiance
    sun_xy = colour.XYZ_to_xy(radiance_to_xyz(radiance, atm))
    mdwarf = load_atmosphere("exo-mdwarf").replace(wavelengths_nm=atm.wavelengths_nm)
    red_xy = colour.XYZ_to_xy(radiance_to_xyz(radiance, mdwarf))
    assert red_xy[0] > sun_xy[0] + 0.05            # much redder (larger x) under a 3200 K star
