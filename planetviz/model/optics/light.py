"""The light source: the Sun's measured spectrum or a blackbody star.

Radiance from :mod:`planetviz.reference` and the tables is per unit irradiance at the top of
the atmosphere; multiplying by the star's spectral irradiance E(lambda) [W m^-2 nm^-1] gives
spectral radiance [W m^-2 sr^-1 nm^-1] for the colour pipeline.
"""
from __future__ import annotations

from functools import lru_cache

import numpy as np

from ...resources import read_data_csv

PLANCK = 6.62607015e-34
LIGHT_SPEED = 299792458.0
BOLTZMANN = 1.380649e-23
SOLAR_CONSTANT = 1361.0  # W/m^2 at 1 AU (total solar irradiance)


@lru_cache(maxsize=None)
def solar_spectrum():
    """(wavelength [nm], E [W m^-2 nm^-1]): ASTM G-173 extraterrestrial, 280-2500 nm."""
    t = read_data_csv("solar_astm_g173_etr.csv")
    return t["wavelength_nm"], t["irradiance_w_m2_nm"]


def planck_radiance(wavelength_nm, temperature_k):
    """B_lambda(T) [W m^-2 sr^-1 nm^-1], Planck's law."""
    lam = np.asarray(wavelength_nm, dtype=float) * 1e-9
    x = PLANCK * LIGHT_SPEED / (lam * BOLTZMANN * temperature_k)
    return 2.0 * PLANCK * LIGHT_SPEED ** 2 / lam ** 5 / np.expm1(x) * 1e-9


def star_irradiance(star, wavelength_nm, bolometric_irradiance=SOLAR_CONSTANT):
    """E(lambda) [W m^-2 nm^-1] at the top of the atmosphere.

    ``sun``: the ASTM G-173 extraterrestrial spectrum. ``blackbody``: pi B_lambda(T) scaled so
    that its integral over all wavelengths is ``bolometric_irradiance`` (default: the solar
    constant, i.e. the planet receives as much energy as Earth does), so only the colour changes.
    """
    wl = np.asarray(wavelength_nm, dtype=float)
    if star.type == "sun":
        w, e = solar_spectrum()
        return np.interp(wl, w, e)
    sigma = 5.670374419e-8
    scale = bolometric_irradiance / (sigma * star.temperature_k ** 4)
    return np.pi * planck_radiance(wl, star.temperature_k) * scale
