"""Scattering and extinction by large particles (paper Sect. 4.3, Eqs. 17-20)."""
from __future__ import annotations

import numpy as np


def turbidity_concentration(turbidity):
    """C(T) = (0.65 T - 0.65) 1e-16, the concentration factor of Eq. 17 (Morales et al.)."""
    return (0.65 * np.asarray(turbidity, dtype=float) - 0.65) * 1e-16


def mie_scattering_turbidity(wavelength_m, turbidity, junge_exponent, k):
    """beta_M^scat at the ground [1/m] = 0.434 C(T) pi (2 pi / lambda)^(v - 2) K  (Eq. 17)."""
    lam = np.asarray(wavelength_m, dtype=float)
    return 0.434 * turbidity_concentration(turbidity) * np.pi * (2.0 * np.pi / lam) ** (junge_exponent - 2.0) \
        * np.asarray(k, dtype=float)


#: Eq. 17 for the standard mode's turbidity control: Junge exponent 4 and K = 0.0092 (Table 1's Earth value at
#: 550 nm).
TURBIDITY_JUNGE, TURBIDITY_K = 4.0, 0.0092


def turbidity_from_scattering(wavelength_m, scattering_m, junge_exponent=TURBIDITY_JUNGE, k=TURBIDITY_K):
    """The turbidity T whose Eq. 17 beta_M^scat at the first wavelength is ``scattering_m[0]`` [1/m].

    C(T) is linear in T - 1 (Eq. 16), so T = 1 + beta / beta(T = 2).
    """
    at_two = mie_scattering_turbidity(np.asarray(wavelength_m, dtype=float)[:1], 2.0, junge_exponent, k)[0]
    return 1.0 + float(np.asarray(scattering_m, dtype=float)[0]) / at_two


def _rho_beta(wavelength_m, radius_m, m, k):
    rho = 4.0 * np.pi / np.asarray(wavelength_m, dtype=float) * radius_m * (np.asarray(m, float) - 1.0)
    beta = np.arctan2(np.asarray(k, float), np.asarray(m, float) - 1.0)
    return rho, beta


def extinction_efficiency(wavelength_m, radius_m, m, k):
    """Q_ext of an absorbing sphere by anomalous diffraction (van de Hulst; paper Eq. 19).

    Q = 2 - 4 e^{-rho tan b} (cos b / rho) sin(rho - b) - 4 e^{-rho tan b} (cos b / rho)^2 cos(rho - 2b)
        + 4 (cos b / rho)^2 cos 2b,   rho = 4 pi r (m - 1) / lambda,  tan b = k / (m - 1).
    """
    rho, b = _rho_beta(wavelength_m, radius_m, m, k)
    c = np.cos(b) / rho
    e = np.exp(-rho * np.tan(b))
    return 2.0 - 4.0 * e * c * np.sin(rho - b) - 4.0 * e * c * c * np.cos(rho - 2.0 * b) \
        + 4.0 * c * c * np.cos(2.0 * b)


def absorption_efficiency(wavelength_m, radius_m, k):
    """Q_abs = 1 + 2 e^{-w} / w + 2 (e^{-w} - 1) / w^2, w = 4 x k, x = 2 pi r / lambda.

    The anomalous-diffraction absorption efficiency of the same sphere (van de Hulst 1957,
    Sect. 11.22); not in the paper, used to split Eq. 20's extinction into scattering and
    absorption consistently (single-scattering albedo 1 - Q_abs / Q_ext).
    """
    x = 2.0 * np.pi * radius_m / np.asarray(wavelength_m, dtype=float)
    w = 4.0 * x * np.asarray(k, dtype=float)
    small = w < 1e-4
    ws = np.where(small, 1.0, w)
    full = 1.0 + 2.0 * np.exp(-ws) / ws + 2.0 * np.expm1(-ws) / ws ** 2
    return np.where(small, 2.0 * w / 3.0, full)


def mie_extinction_particles(wavelength_m, radius_m, m, k, number_density):
    """beta_M^ext at the ground [1/m] = pi r^2 Q_ext N_r (Eq. 20, one mean radius)."""
    return np.pi * radius_m ** 2 * extinction_efficiency(wavelength_m, radius_m, m, k) * number_density


def mie_absorption_particles(wavelength_m, radius_m, k, number_density):
    """beta_M^abs at the ground [1/m] = pi r^2 Q_abs N_r."""
    return np.pi * radius_m ** 2 * absorption_efficiency(wavelength_m, radius_m, k) * number_density
