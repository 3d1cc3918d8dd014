"""Single scattering of ground rays from cameras near the ground, by quadrature along the ray instead of the
tables (GLSL twin: ``near_ground_single_scattering`` in shaders/atmosphere_functions.glsl).

Why. A ground ray from a camera between the single-scattering tables' rows 0 and ``NEAR_GROUND_ROWS`` is read by
interpolating in r between the rays of those rows at the same u_mu: near the horizon these are 0 (row 0's ground
rays have zero length), 58 km and 116 km long (draft; 28 and 56 km standard), where the camera's own ray is
5 km long from 2 m. With the sun low the source function changes along those rays (the sun's elevation by 0.5
deg over 58 km, and its transmittance with altitude), so the reading was off by up to 5.9% just below the
horizon from 2 m (draft; 2.4% standard) and 4.1% from 100 m (standard) where the sky next to it was within 1-2%:
a seam at the horizon (HORIZON_SEAM, docs/stability.md). :func:`lookup.ground_row_factor` had taken it from
46% down to those figures. These rays are short (at most the distance to the horizon from row 2: 116 km draft,
56 km standard) and their integrand smooth, so an 8-node Gauss-Legendre rule on [0, d] with the tables'
transmittances is exact to well under the tables' own error (0.4% from 2 m draft, 0.1% standard, against the
reference quadrature), for 8 view and 8 sun transmittance lookups per ray.

Switching at a row is continuous: there the tables hold their own quadrature of the same integral.
"""
from __future__ import annotations

import numpy as np

from .parameterization import distance_to_bottom_atmosphere_boundary
from .precompute import single_scattering_integral

#: Ground rays from cameras below this row of the single-scattering tables are integrated.
NEAR_GROUND_ROWS = 2
#: Gauss-Legendre nodes on [0, d] along the ray.
NEAR_GROUND_SAMPLES = 8


def near_ground_altitude(t) -> float:
    """Altitude [m] of the single-scattering tables' row ``NEAR_GROUND_ROWS`` (rho = row / (n_r - 1) H)."""
    h = np.sqrt(t.top * t.top - t.bottom * t.bottom)
    rho = NEAR_GROUND_ROWS * h / (t.rayleigh.shape[0] - 1)
    return rho * rho / (np.sqrt(rho * rho + t.bottom * t.bottom) + t.bottom)


def near_ground_rays(t, r, intersects_ground):
    """Boolean mask: ground rays from cameras below :func:`near_ground_altitude`."""
    return np.asarray(intersects_ground) & (np.asarray(r) - t.bottom < near_ground_altitude(t))


def near_ground_single_scattering(t, atm, r, mu, mu_s, nu):
    """(S_R,1, S_M,1) (..., W) without phase for ground rays at (r, mu, mu_s, nu): the integral of the
    precompute's single scattering (precompute.single_scattering_integral) over [0, d], d the distance to the
    ground, with ``NEAR_GROUND_SAMPLES`` Gauss-Legendre nodes; per unit solar irradiance."""
    r, mu = np.asarray(r, float), np.asarray(mu, float)
    d = distance_to_bottom_atmosphere_boundary(r, mu, t.bottom)[..., None]
    x, w = np.polynomial.legendre.leggauss(NEAR_GROUND_SAMPLES)
    return single_scattering_integral(t, atm, r, mu, mu_s, nu, 0.5 * (x + 1.0) * d, 0.5 * w * d)
