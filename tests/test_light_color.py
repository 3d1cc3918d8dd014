"""The light source and the colour pipeline."""
import numpy as np
import pytest

from planetviz import load_atmosphere
from planetviz.model.atmosphere import Star
from planetviz.model.color import radiance_to_xyz, xyz_matrix
from planetviz.model.atmosphere import AtmosphereError, from_dict
from planetviz.model.optics.light import SOLAR_CONSTANT, solar_spectrum, star_irradiance


def test_blackbody_star_delivers_the_solar_constant():
    # int pi B_lambda(T) scale d lambda over 10 nm - 1 mm must be the solar constant (the Planck tail
    # beyond 1 mm and below 10 nm holds < 1e-6 of it at 3200 K).
    wl = np.geomspace(10.0, 1e6, 400001)
    e = star_irradiance(Star("blackbody", 3200.0), wl)
    assert np.trapezoid(e, wl) == pytest.approx(SOLAR_CONSTANT, rel=1e-4)


def test_a_star_scales_its_spectrum_to_its_irradiance():
    # The Sun at Mars (586.2 W/m^2) is the same spectrum times 586.2 / 1361; a blackbody integrates to its own
    # irradiance (the Planck tails as in the test above, < 1e-6).
    wl = np.geomspace(10.0, 1e6, 400001)
    assert np.trapezoid(star_irradiance(Star("blackbody", 5000.0, 500.0), wl), wl) == pytest.approx(500.0, rel=1e-4)
    sun, mars = star_irradiance(Star(), [440.0, 550.0]), star_irradiance(Star(irradiance_w_m2=586.2), [440.0, 550.0])
    assert np.allclose(mars / sun, 586.2 / SOLAR_CONSTANT, rtol=1e-12)


def test_the_star_disc_follows_from_the_star_and_its_irradiance():
    # The Sun from Earth: the IAU nominal radius over 1 AU, 959.2 arcsec (the apparent mean semi-diameter the
    # almanacs give, 959.63", to 0.05%). A blackbody at the Sun's effective temperature (5772 K, IAU 2015)
    # giving the solar constant must look as large as the Sun (E = sigma T^4 (R/d)^2 holds for the nominal
    # values to 0.02%). The Sun from Mars (1.5237 AU) is smaller by that distance (its sine is; the angle to
    # theta^2 / 6 = 4e-6); a 3200 K star giving Earth's irradiance is larger, by (5772 / 3200)^2 = sqrt(sigma
    # 5772^4 / sigma 3200^4) (its sine; the angle to 1e-4 at 0.87 deg).
    earth = Star().angular_radius_deg()
    assert earth * 3600 == pytest.approx(959.63, rel=5e-4)
    assert Star("blackbody", 5772.0).angular_radius_deg() == pytest.approx(earth, rel=2e-4)
    assert Star(irradiance_w_m2=SOLAR_CONSTANT / 1.5237 ** 2).angular_radius_deg() == pytest.approx(earth / 1.5237,
                                                                                                   rel=1e-5)
    assert load_atmosphere("exo-mdwarf").star.angular_radius_deg() == pytest.approx(earth * (5772 / 3200) ** 2,
                                                                                    rel=5e-4)


def test_a_star_too_bright_for_its_disc_is_refused_naming_the_field():
    d = load_atmosphere("earth").to_dict()
    d["star"] = {"type": "blackbody", "temperature_k": 1000.0, "irradiance_w_m2": 1e5}   # sigma T^4 = 5.7e4
    with pytest.raises(AtmosphereError) as info:
        from_dict(d)
    assert info.value.field == "star.irradiance_w_m2" and "at most" in str(info.value)
    d["star"] = {"type": "sun", "irradiance_w_m2": 586.2}
    assert from_dict(d).star.irradiance_w_m2 == 586.2 and from_dict(d).to_dict()["star"] == d["star"]


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


def test_display_colour_is_colour_sciences_srgb_encoding_of_the_tone_mapped_value():
    # display_colour (float32, the shader's twin) against colour-science's sRGB transfer function and the tone
    # curves written out in float64: float32 arithmetic (the exposed value, up to 4 here, rounded to 6e-8 relative,
    # then exp and the 1 / 2.4 power) differs by about 1e-6; bound 1e-5, far below an 8-bit step (3.9e-3).
    import colour
    from planetviz.model.color import display_colour
    rgb = np.random.default_rng(4).uniform(0.0, 4e4, (5000, 3))
    for name, curve in (("exponential", lambda x: 1 - np.exp(-x)), ("clamp", lambda x: np.clip(x, 0, 1)),
                        ("filmic", lambda x: np.clip(x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14), 0, 1))):
        want = colour.cctf_encoding(np.clip(curve(rgb * 1e-4), 0, 1), function="sRGB")
        got = display_colour(rgb, 1e-4, name)
        assert got.dtype == np.float32 and np.abs(got - want).max() < 1e-5, name
