"""Rayleigh scattering of a gas mixture from per-gas refractive indices and King factors.

Each gas carries a dispersion formula for (n - 1) at a stated reference temperature and
pressure, its King factor F_K, and its molar mass. The per-molecule cross-section is

    sigma_i(lambda) = 24 pi^3 / lambda^4 * ((n_i^2 - 1) / ((n_i^2 + 2) N_ref,i))^2 * F_K,i   [m^2]

(Lorentz-Lorenz: (n^2 - 1) / ((n^2 + 2) N) does not depend on density), and a mixture of
mole fractions x_i at total number density N scatters incoherently:
beta = N sum_i x_i sigma_i. Wavelengths in micrometres in the formulas below; sigma = 1 / lambda.
Sources (formulas as published, conditions as stated):

* N2: Peck and Khanna (1966), 0 degC, 101325 Pa; F_K = 1.034 + 3.17e-4 / lambda^2 (Bates 1984).
* O2: Zhang, Lu and Zhu (2008), 20 degC, 101325 Pa; F_K = 1.096 + 1.385e-3 / lambda^2 + 1.448e-4 / lambda^4 (Bates 1984).
* Ar: Peck and Fisher (1964), 15 degC, 101325 Pa; F_K = 1 (an atom).
* CO2: Bideau-Mehu et al. (1973), 0 degC, 101325 Pa (the paper's reference [3]; it reproduces
  Table 1's n_CO2 to 1e-8); F_K = 1.1364 + 25.3e-12 nu^2, nu in 1/cm (Sneep and Ubachs 2005).
* H2: Peck and Huang (1977), 0 degC, 101325 Pa; F_K taken as 1 (assumed: its depolarisation is small).
* He: Mansfield and Peck (1969), 0 degC, 101325 Pa; F_K = 1 (an atom).
* H2O: Ciddor (1996) water vapour, 20 degC, 1333 Pa; F_K = 1.0518 (depolarisation 0.03, assumed).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from .rayleigh import BOLTZMANN


@dataclass(frozen=True)
class Gas:
    name: str
    molar_mass_kg_mol: float
    refractivity: Callable        # (n - 1) at the reference conditions, lambda in micrometres
    reference_temperature_k: float
    reference_pressure_pa: float
    king: Callable                # F_K(lambda in micrometres)
    source: str

    @property
    def reference_number_density(self) -> float:
        return self.reference_pressure_pa / (BOLTZMANN * self.reference_temperature_k)

    def cross_section(self, wavelength_m):
        """sigma(lambda) [m^2 per molecule], the Rayleigh scattering cross-section."""
        lam_m = np.asarray(wavelength_m, dtype=float)
        lam_um = lam_m * 1e6
        n = 1.0 + self.refractivity(lam_um)
        lorentz = (n * n - 1.0) / ((n * n + 2.0) * self.reference_number_density)
        return 24.0 * np.pi ** 3 / lam_m ** 4 * lorentz ** 2 * self.king(lam_um)


def _s2(lam_um):
    return 1.0 / (np.asarray(lam_um, dtype=float) ** 2)


GASES = {
    "N2": Gas("N2", 28.0134e-3, lambda l: 6.8552e-5 + 3.243157e-2 / (144.0 - _s2(l)), 273.15, 101325.0,
              lambda l: 1.034 + 3.17e-4 * _s2(l), "Peck & Khanna 1966; King: Bates 1984"),
    "O2": Gas("O2", 31.9988e-3, lambda l: 1.181494e-4 + 9.708931e-3 / (75.4 - _s2(l)), 293.15, 101325.0,
              lambda l: 1.096 + 1.385e-3 * _s2(l) + 1.448e-4 * _s2(l) ** 2, "Zhang et al. 2008; King: Bates 1984"),
    "Ar": Gas("Ar", 39.948e-3, lambda l: 6.432135e-5 + 2.8606021e-2 / (144.0 - _s2(l)), 288.15, 101325.0,
              lambda l: np.ones_like(np.asarray(l, dtype=float)), "Peck & Fisher 1964"),
    "CO2": Gas("CO2", 44.0095e-3,
               lambda l: (6.99100e-2 / (166.175 - _s2(l)) + 1.44720e-3 / (79.609 - _s2(l))
                          + 6.42941e-5 / (56.3064 - _s2(l)) + 5.21306e-5 / (46.0196 - _s2(l))
                          + 1.46847e-6 / (0.0584738 - _s2(l))), 273.15, 101325.0,
               lambda l: 1.1364 + 25.3e-12 * (1e4 / np.asarray(l, dtype=float)) ** 2,
               "Bideau-Mehu et al. 1973; King: Sneep & Ubachs 2005"),
    "H2": Gas("H2", 2.01588e-3, lambda l: 0.0148956 / (180.7 - _s2(l)) + 0.0049037 / (92.0 - _s2(l)),
              273.15, 101325.0, lambda l: np.ones_like(np.asarray(l, dtype=float)), "Peck & Huang 1977"),
    "He": Gas("He", 4.002602e-3, lambda l: 0.01470091 / (423.98 - _s2(l)), 273.15, 101325.0,
              lambda l: np.ones_like(np.asarray(l, dtype=float)), "Mansfield & Peck 1969"),
    "H2O": Gas("H2O", 18.01528e-3,
               lambda l: 1.022e-8 * (295.235 + 2.6422 * _s2(l) - 0.032380 * _s2(l) ** 2
                                     + 0.004028 * _s2(l) ** 3), 293.15, 1333.0,
               lambda l: np.full_like(np.asarray(l, dtype=float), 1.0518), "Ciddor 1996"),
}


def mixture_cross_section(fractions: dict, wavelength_m):
    """sum_i x_i sigma_i(lambda) [m^2] for mole fractions ``fractions`` (normalised to sum 1)."""
    total = sum(fractions.values())
    return sum(x / total * GASES[name].cross_section(wavelength_m) for name, x in fractions.items())


def mean_molar_mass(fractions: dict) -> float:
    """M = sum_i x_i M_i [kg/mol]."""
    total = sum(fractions.values())
    return sum(x / total * GASES[name].molar_mass_kg_mol for name, x in fractions.items())
