"""The light source: the Sun's measured spectrum or a blackbody star, its irradiance and its disc.

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
STEFAN_BOLTZMANN = 5.670374419e-8   # W m^-2 K^-4
SOLAR_CONSTANT = 1361.0             # W/m^2 at 1 AU (total solar irradiance)
SUN_RADIUS_M = 6.957e8              # IAU 2015 nominal solar radius
ASTRONOMICAL_UNIT_M = 1.495978707e11


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


def star_irradiance(star, wavelength_nm):
    """E(lambda) [W m^-2 nm^-1] at the top of the atmosphere, with the star's bolometric irradiance
    ``star.irradiance_w_m2`` (E_bol).

    ``sun``: the ASTM G-173 extraterrestrial spectrum times E_bol / SOLAR_CONSTANT (the Sun from farther or
    nearer than 1 AU). ``blackbody``: pi B_lambda(T) scaled so that its integral over all wavelengths is E_bol.
    """
    wl = np.asarray(wavelength_nm, dtype=float)
    if star.type == "sun":
        w, e = solar_spectrum()
        return np.interp(wl, w, e) * (star.irradiance_w_m2 / SOLAR_CONSTANT)
    scale = star.irradiance_w_m2 / (STEFAN_BOLTZMANN * star.temperature_k ** 4)
    return np.pi * planck_radiance(wl, star.temperature_k) * scale


def star_angular_radius(star_type, temperature_k, irradiance_w_m2) -> float:
    """Angular radius [rad] of the star's disc seen from the planet, from its bolometric irradiance E_bol.

    ``sun``: asin(R_sun / d), d = 1 AU sqrt(SOLAR_CONSTANT / E_bol) the distance at which the Sun gives E_bol
    (0.2665 deg at 1 AU). ``blackbody`` of temperature T: E_bol = sigma T^4 sin^2(theta) (a uniform disc of
    radiance sigma T^4 / pi), so sin(theta) = sqrt(E_bol / (sigma T^4)); NaN where E_bol > sigma T^4.
    """
    if star_type == "sun":
        sin = SUN_RADIUS_M / ASTRONOMICAL_UNIT_M * np.sqrt(irradiance_w_m2 / SOLAR_CONSTANT)
    else:
        sin = np.sqrt(irradiance_w_m2 / (STEFAN_BOLTZMANN * temperature_k ** 4))
    return float(np.arcsin(sin)) if sin <= 1.0 else float("nan")


def star_irradiance_at_radius(star_type, temperature_k, angular_radius_rad) -> float:
    """The bolometric irradiance [W/m^2] at which the star's disc has ``angular_radius_rad``: the inverse of
    :func:`star_angular_radius`."""
    sin2 = np.sin(angular_radius_rad) ** 2
    if star_type == "sun":
        return float(SOLAR_CONSTANT * sin2 / (SUN_RADIUS_M / ASTRONOMICAL_UNIT_M) ** 2)
    return float(STEFAN_BOLTZMANN * temperature_k ** 4 * sin2)
