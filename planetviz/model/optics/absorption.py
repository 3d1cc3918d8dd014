"""Absorption by molecules and small particles (paper Sect. 4.2, Eqs. 12-15)."""
from __future__ import annotations

from functools import lru_cache

import numpy as np

from ...resources import read_data_csv

DOBSON_UNIT = 2.6867e20  # molecules/m^2


def small_particle_absorption(wavelength_m, radius_m, m, k, number_density):
    """beta_R^abs at the ground [1/m] = 8 pi^2 r^3 N / lambda * Im((n^2 - 1) / (n^2 + 2))  (Eq. 12).

    ``n = m + i k`` is the complex refractive index of the particles of radius r.
    """
    n = np.asarray(m, dtype=float) + 1j * np.asarray(k, dtype=float)
    lorentz = (n * n - 1.0) / (n * n + 2.0)
    return 8.0 * np.pi ** 2 * radius_m ** 3 * number_density / np.asarray(wavelength_m, float) * lorentz.imag


def oxygen_absorption(cross_section_m2, volume_fraction, number_density):
    """beta_O2^abs at the ground [1/m] = sigma_O2 * O2% * N_0  (Eqs. 13-14; profile exp(-h / H_O2))."""
    return np.asarray(cross_section_m2, dtype=float) * volume_fraction * number_density


def oxygen_cia_absorption(cia_m5, volume_fraction, number_density):
    """beta_O2^abs at the ground [1/m] from O2-O2 collision-induced absorption = k (O2% N_0)^2.

    This is Eq. 13 with the per-molecule cross-section sigma_O2 = k rho_O2 [m^2]: in the visible, O2 absorbs
    through collisions of two O2 molecules, so the coefficient scales with rho_O2^2 and its height profile is
    exp(-2 h / H_O2) (Eq. 14 squared).
    """
    n_o2 = volume_fraction * number_density
    return np.asarray(cia_m5, dtype=float) * n_o2 * n_o2


@lru_cache(maxsize=None)
def ozone_cross_section_table():
    """(bin-centre wavelengths [nm], sigma_O3 [m^2]) from assets/data/ozone_cross_section.csv."""
    t = read_data_csv("ozone_cross_section.csv")
    return t["wavelength_nm"], t["cross_section_m2"]


def ozone_cross_section(wavelength_nm):
    """sigma_O3(lambda) [m^2], linear between the 10 nm bins, 0 outside 365-835 nm."""
    wl, sigma = ozone_cross_section_table()
    return np.interp(np.asarray(wavelength_nm, dtype=float), wl, sigma, left=0.0, right=0.0)


@lru_cache(maxsize=None)
def oxygen_cia_table():
    """(wavelengths [nm], O2-O2 CIA coefficient k [m^5]) from assets/data/o2_o2_cia.csv (HITRAN 2016)."""
    t = read_data_csv("o2_o2_cia.csv")
    return t["wavelength_nm"], t["cia_m5"]


def oxygen_cia(wavelength_nm):
    """k_O2-O2(lambda) [m^5], linear between the table's samples; ValueError outside the tabulated range."""
    wl, k = oxygen_cia_table()
    lam = np.asarray(wavelength_nm, dtype=float)
    outside = (lam < wl[0]) | (lam > wl[-1])
    if np.any(outside):
        raise ValueError(f"O2-O2 absorption is tabulated for {wl[0]:.1f}-{wl[-1]:.1f} nm only; got "
                         f"{lam[outside][0]:g} nm (give cross_section_m2 explicitly outside that range)")
    return np.interp(lam, wl, k)


@lru_cache(maxsize=None)
def ozone_profile_table():
    """(altitude [m], O3 number density [1/m^3]) of the US Standard Atmosphere (AFGL 1986, table 1f)."""
    t = read_data_csv("ozone_us_standard_1976.csv")
    return t["altitude_m"], t["o3_number_density_m3"]


def ozone_column_du(altitude_m=None, density_m3=None) -> float:
    """Total column [Dobson units] of a profile (trapezoid rule on the table's nodes)."""
    if altitude_m is None:
        altitude_m, density_m3 = ozone_profile_table()
    return float(np.trapezoid(density_m3, altitude_m) / DOBSON_UNIT)
