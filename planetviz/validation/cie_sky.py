"""The CIE standard general sky (CIE S 011 / ISO 15469): relative sky luminance, for validation.

colour-science 0.4.7 does not ship it. For a sky element at zenith angle Z and azimuth alpha, the sun at
Z_s and alpha_s:

    L / L_z = f(chi) phi(Z) / (f(Z_s) phi(0))
    phi(Z) = 1 + a exp(b / cos Z)             (gradation; phi = 1 at the horizon)
    f(chi) = 1 + c (exp(d chi) - exp(d pi / 2)) + e cos^2 chi    (indicatrix)
    cos chi = cos Z_s cos Z + sin Z_s sin Z cos(alpha - alpha_s)

with chi the angle between the sky element and the sun. Types 12 (CIE standard clear sky, low
luminance turbidity) and 13 (clear sky, polluted atmosphere) are tabulated in ``CIE_SKY_TYPES``.
"""
from __future__ import annotations

import numpy as np

#: (a, b, c, d, e) of the CIE standard general sky types used by the paper's Fig. 7.
CIE_SKY_TYPES = {
    12: (-1.0, -0.32, 10.0, -3.0, 0.45),
    13: (-1.0, -0.32, 16.0, -3.0, 0.30),
}


def gradation(z, a, b):
    """phi(Z) = 1 + a exp(b / cos Z), with phi = 1 at and below the horizon (cos Z <= 0)."""
    cos_z = np.cos(z)
    safe = np.where(cos_z > 0, cos_z, 1.0)
    return np.where(cos_z > 0, 1.0 + a * np.exp(b / safe), 1.0)


def indicatrix(chi, c, d, e):
    """f(chi) = 1 + c (exp(d chi) - exp(d pi / 2)) + e cos^2 chi."""
    return 1.0 + c * (np.exp(d * chi) - np.exp(d * np.pi / 2)) + e * np.cos(chi) ** 2


def cie_relative_luminance(zenith, azimuth, sun_zenith, sun_azimuth, sky_type=12):
    """L / L_z of the CIE standard general sky (angles in radians).

    Example
    -------
    >>> round(float(cie_relative_luminance(np.radians(45), np.radians(180), np.radians(30), 0.0, 12)), 7)
    0.4544524
    """
    a, b, c, d, e = CIE_SKY_TYPES[sky_type]
    cos_chi = (np.cos(sun_zenith) * np.cos(zenith)
               + np.sin(sun_zenith) * np.sin(zenith) * np.cos(azimuth - sun_azimuth))
    chi = np.arccos(np.clip(cos_chi, -1.0, 1.0))
    return (indicatrix(chi, c, d, e) * gradation(zenith, a, b)
            / (indicatrix(sun_zenith, c, d, e) * gradation(0.0, a, b)))
