"""Rayleigh scattering by molecules (paper Sect. 4.1, Eq. 11) and the hydrostatic scale height."""
from __future__ import annotations

import numpy as np

BOLTZMANN = 1.380649e-23          # J/K
AVOGADRO = 6.02214076e23          # 1/mol
GAS_CONSTANT = BOLTZMANN * AVOGADRO  # J/(mol K)


def king_factor(depolarization):
    """f(delta) = (6 + 3 delta) / (6 - 7 delta), the King correction for anisotropic molecules (Eq. 11)."""
    d = np.asarray(depolarization, dtype=float)
    return (6.0 + 3.0 * d) / (6.0 - 7.0 * d)


def rayleigh_scattering(wavelength_m, refractive_index, number_density, depolarization,
                        refractive_index_number_density=None):
    """beta_R^scat at the ground [1/m] (paper Eq. 11).

    beta = 8 pi^3 (n^2 - 1)^2 / (3 N lambda^4) f(delta), with n the refractive index of the gas
    at number density N [1/m^3]. When n was measured at another density N_ref, (n^2 - 1) is
    scaled by N / N_ref first (Lorentz-Lorenz for n close to 1), which gives
    beta = 8 pi^3 (n_ref^2 - 1)^2 N / (3 N_ref^2 lambda^4) f(delta).
    """
    lam = np.asarray(wavelength_m, dtype=float)
    n = np.asarray(refractive_index, dtype=float)
    n_ref = number_density if refractive_index_number_density is None else refractive_index_number_density
    polar = (n * n - 1.0) * (number_density / n_ref)
    return 8.0 * np.pi ** 3 * polar ** 2 / (3.0 * number_density * lam ** 4) * king_factor(depolarization)


def scale_height(molar_mass_kg_mol, temperature_k, gravity_m_s2):
    """H = R T / (M g) [m], the isothermal hydrostatic scale height (Sect. 4.1)."""
    return GAS_CONSTANT * temperature_k / (molar_mass_kg_mol * gravity_m_s2)


def number_density(pressure_pa, temperature_k):
    """N = p / (k T) [1/m^3], ideal gas."""
    return pressure_pa / (BOLTZMANN * temperature_k)
