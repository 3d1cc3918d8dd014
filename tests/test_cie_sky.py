"""The CIE standard general sky against its published check value and its defining properties."""
import numpy as np

from planetviz.validation.cie_sky import cie_relative_luminance, gradation


def test_published_check_value():
    # CIE S 011 check value quoted in the issue: Z = 45 deg, alpha = 180 deg, Z_s = 30 deg, alpha_s = 0,
    # type 12 -> 0.4544524 (7 digits).
    got = cie_relative_luminance(np.radians(45), np.radians(180), np.radians(30), 0.0, 12)
    assert abs(got - 0.4544524) < 5e-8


def test_defining_properties():
    z_s = np.radians([10.0, 35.0, 70.0])
    for t in (12, 13):
        # L / L_z = 1 at the zenith, whatever the sun; phi = 1 at the horizon.
        assert np.allclose(cie_relative_luminance(0.0, 1.234, z_s, 0.0, t), 1.0)
        assert np.isclose(gradation(np.pi / 2, -1.0, -0.32), 1.0)
        # Symmetric about the solar meridian.
        z = np.radians(50.0)
        assert np.allclose(cie_relative_luminance(z, 0.7, z_s, 0.0, t), cie_relative_luminance(z, -0.7, z_s, 0.0, t))
    # The clear sky is brightest toward the sun and darkest about 90 deg from it, on the meridian.
    z = np.radians(np.arange(0, 90, 1.0))
    toward = cie_relative_luminance(z, 0.0, np.radians(40), 0.0, 12)
    away = cie_relative_luminance(z, np.pi, np.radians(40), 0.0, 12)
    assert np.argmax(toward) == 40 and away.min() < toward.min()
