"""Pickering's air mass (paper Sect. 4.4, Eq. 21), an approximation of refraction near the horizon.

AM = 1 / sin(h + 244 / (165 + 47 h^1.1)), h the apparent altitude in degrees. The printed
Eq. 21 applies the exponent 1.1 to the whole denominator; it belongs to h alone.
It multiplies the zenith optical depth of a ground observer: T = exp(-tau_zenith AM).
Straight-line (geometric) paths in a spherical shell remain the model everywhere else.
"""
from __future__ import annotations

import numpy as np


def pickering_air_mass(apparent_altitude_deg):
    """AM(h) for h in degrees (h >= -1 keeps the formula meaningful; at the horizon AM ~ 38)."""
    h = np.asarray(apparent_altitude_deg, dtype=float)
    hp = np.maximum(h, 0.0)
    return 1.0 / np.sin(np.radians(h + 244.0 / (165.0 + 47.0 * hp ** 1.1)))


def pickering_transmittance(zenith_optical_depth, apparent_altitude_deg):
    """T = exp(-tau_zenith * AM(h)) per wavelength, for an observer on the ground."""
    am = pickering_air_mass(apparent_altitude_deg)
    return np.exp(-np.asarray(zenith_optical_depth, dtype=float) * np.asarray(am)[..., None])
