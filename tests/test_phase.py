"""Phase functions integrate to 1 over the sphere, and the samplers draw from them."""
import numpy as np
import pytest

from planetviz import PRESETS, load_atmosphere
from planetviz.model.optics.phase import (PENNDORF_A, double_henyey_greenstein, henyey_greenstein,
                                    penndorf_phase, rayleigh_phase, sample_henyey_greenstein,
                                    sample_rayleigh_like)


def sphere_integral(f, panels=4000):
    """2 pi int_{-1}^{1} f(mu) dmu by composite 8-point Gauss-Legendre, panels denser near mu = +-1."""
    x, w = np.polynomial.legendre.leggauss(8)
    s = np.linspace(-1.0, 1.0, panels + 1)
    edges = np.sin(0.5 * np.pi * s)            # clusters panels at the poles, where HG(g -> 1) peaks
    a, b = edges[:-1, None], edges[1:, None]
    mu = 0.5 * (a + b) + 0.5 * (b - a) * x
    return 2.0 * np.pi * np.sum(0.5 * (b - a) * w * f(mu))


# Tolerance 1e-9: the quadrature is exact for the polynomial phases and converged to ~1e-12 for HG
# with |g| <= 0.99 (peak width (1 - g) = 0.01 spans ~40 panels); an unnormalised lobe such as the
# printed Eq. 16 ((1 + g^2) numerators) would be off by a factor (1 + g^2) / (1 - g^2).
def test_rayleigh_and_penndorf_integrate_to_one():
    assert sphere_integral(rayleigh_phase) == pytest.approx(1.0, abs=1e-9)
    assert sphere_integral(penndorf_phase) == pytest.approx(1.0, abs=1e-9)


@pytest.mark.parametrize("g", [-0.99, -0.5, 0.0, 0.3, 0.8, 0.99])
def test_henyey_greenstein_integrates_to_one(g):
    assert sphere_integral(lambda mu: henyey_greenstein(mu, g)) == pytest.approx(1.0, abs=1e-9)


@pytest.mark.parametrize("preset", sorted(PRESETS))
def test_every_preset_mie_phase_integrates_to_one_per_wavelength(preset):
    atm = load_atmosphere(preset)
    for i in range(atm.n_wavelengths):
        value = sphere_integral(lambda mu: atm.mie.phase_function(mu)[..., i])
        assert value == pytest.approx(1.0, abs=1e-9), atm.wavelengths_nm[i]
    assert sphere_integral(atm.rayleigh.phase_function) == pytest.approx(1.0, abs=1e-9)


def test_double_henyey_greenstein_second_lobe_uses_g2():
    # alpha = 0 leaves only the second lobe: it must equal HG(g2), whatever g1 is.
    mu = np.linspace(-1, 1, 11)
    assert np.allclose(double_henyey_greenstein(mu, 0.9, -0.3, 0.0), henyey_greenstein(mu, -0.3))


def test_penndorf_constant_matches_eq10_to_print_precision():
    # Eq. 10 prints 0.7629; the exact normaliser 1 / (1 + 0.932 / 3) rounds to it.
    assert 4 * np.pi * penndorf_phase(0.0) == pytest.approx(0.7629, abs=1e-4)


def test_samplers_reproduce_analytic_moments():
    # E[mu] = g for HG; E[mu^2] = (1/3 + a/5) / (1 + a/3) for (1 + a mu^2). 4e5 samples give a
    # standard error below 2e-3, so 1e-2 is a 5-sigma bound.
    rng = np.random.default_rng(1)
    u = rng.random(400_000)
    for g in (-0.7, 0.0, 0.5, 0.95):
        assert sample_henyey_greenstein(u, g).mean() == pytest.approx(g, abs=1e-2)
    for a in (1.0, PENNDORF_A):
        mu = sample_rayleigh_like(u, a)
        assert (mu * mu).mean() == pytest.approx((1 / 3 + a / 5) / (1 + a / 3), abs=1e-2)
        assert abs(mu.mean()) < 1e-2
