"""Phase functions P(nu) [1/sr] and their exact samplers.

``nu`` is the cosine between the incoming and the outgoing propagation directions
(nu = 1: forward scattering). For a camera looking along ``v`` at light from the
sun direction ``s``, nu = dot(v, s). Every function integrates to 1 over the sphere.
The GLSL shaders carry the same names.
"""
from __future__ import annotations

import numpy as np

#: Penndorf's anisotropy coefficient in P(nu) ~ 1 + 0.932 nu^2 (paper Eq. 10).
PENNDORF_A = 0.932
#: Exact normaliser 1 / (1 + a / 3) = 0.76298...; Eq. 10 prints it rounded as 0.7629.
PENNDORF_K = 1.0 / (1.0 + PENNDORF_A / 3.0)


def rayleigh_phase(nu):
    """P_R(nu) = 3 / (16 pi) (1 + nu^2)  (paper Eq. 9)."""
    nu = np.asarray(nu, dtype=float)
    return 3.0 / (16.0 * np.pi) * (1.0 + nu * nu)


def penndorf_phase(nu):
    """P_R(nu) = 0.76298 (1 + 0.932 nu^2) / (4 pi)  (paper Eq. 10, normaliser kept exact)."""
    nu = np.asarray(nu, dtype=float)
    return PENNDORF_K * (1.0 + PENNDORF_A * nu * nu) / (4.0 * np.pi)


def henyey_greenstein(nu, g):
    """HG(nu, g) = (1 - g^2) / (4 pi (1 + g^2 - 2 g nu)^(3/2)), |g| < 1."""
    nu = np.asarray(nu, dtype=float)
    g = np.asarray(g, dtype=float)
    return (1.0 - g * g) / (4.0 * np.pi * (1.0 + g * g - 2.0 * g * nu) ** 1.5)


def double_henyey_greenstein(nu, g1, g2, alpha):
    """P_M = alpha HG(nu, g1) + (1 - alpha) HG(nu, g2)  (paper Eq. 16, corrected).

    The printed Eq. 16 has (1 + g1^2) in both numerators; the normalised lobes have
    (1 - g^2), and the second lobe uses g2 (see docs/physics.md).
    """
    return alpha * henyey_greenstein(nu, g1) + (1.0 - alpha) * henyey_greenstein(nu, g2)


def sample_rayleigh_like(u, a):
    """Invert the CDF of (1 + a nu^2) on [-1, 1] for uniform ``u`` in [0, 1).

    F(nu) = (nu + a nu^3 / 3 + 1 + a / 3) / (2 + 2 a / 3); F(nu) = u is the depressed cubic
    nu^3 + p nu + q = 0 with p = 3 / a, q = 3 (1 + a / 3 - u (2 + 2 a / 3)) / a, which has one
    real root (p > 0), given by Cardano's formula.
    """
    u = np.asarray(u, dtype=float)
    c = u * (2.0 + 2.0 * a / 3.0) - 1.0 - a / 3.0
    p = 3.0 / a
    q = -3.0 * c / a
    disc = np.sqrt(q * q / 4.0 + p ** 3 / 27.0)
    return np.clip(np.cbrt(-q / 2.0 + disc) + np.cbrt(-q / 2.0 - disc), -1.0, 1.0)


def sample_henyey_greenstein(u, g):
    """Invert the CDF of HG(nu, g) for uniform ``u`` in [0, 1) (isotropic where g = 0)."""
    u = np.asarray(u, dtype=float)
    g = np.asarray(g, dtype=float) * np.ones_like(u)
    out = 2.0 * u - 1.0
    m = np.abs(g) > 1e-6
    gm = g[m]
    s = (1.0 - gm * gm) / (1.0 - gm + 2.0 * gm * u[m])
    out[m] = (1.0 + gm * gm - s * s) / (2.0 * gm)
    return np.clip(out, -1.0, 1.0)
