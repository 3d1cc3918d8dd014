"""Single scattering of ground rays from cameras near the ground, by quadrature along the ray instead of the
tables (GLSL twin: ``near_ground_single_scattering`` in shaders/near_ground.glsl).

Why. A ground ray from a camera between the single-scattering tables' rows 0 and ``NEAR_GROUND_ROWS`` is read by
interpolating in r between the rays of neighbouring rows at the same u_mu: near the horizon row 0's ground rays
have zero length, row 1's are 58 km long (draft; 28 km standard), where the camera's own ray is 5 km long from
2 m. With the sun low the source function changes along those rays (the sun's elevation by 0.5 deg over 58 km,
and its transmittance with altitude), so the reading is off by up to 5.9% just below the horizon from 2 m
(draft; 2.4% standard) and 4.1% from 100 m (standard) where the sky next to it is within 1-2%: a seam at the
horizon (the seam test, docs/stability.md), even with :func:`lookup.ground_row_factor` (46% without it). The
rows above the second differ too: read from the standard tables these rays are 1.7% off from 400 m, 1.1% from
800 m and 0.8% from 1.3 km, against 0.6-0.7% for the rest of the sky; from row 5 on (1.57 km standard, 6.7 km draft) they are within
0.5% (standard) and 1.4% (draft).

How. These rays are short (at most the distance to the horizon from row 5: 290 km draft, 140 km standard) and their
integrand smooth except where the ray enters the planet's shadow (the sun below the local horizon of the points
further along): there the sunlight steps to 0, which Gauss-Legendre nodes at fixed places resolve poorly (up to 48%
off in twilight from 300 m with 8 nodes over the whole ray). :func:`shadow_interval` finds that part of the ray in
closed form, and ``NEAR_GROUND_SAMPLES`` Gauss-Legendre nodes go to each lit part before and after it (where there
is none, to each side of the point where one would appear first), with the tables' transmittances: within 0.15%
of the reference quadrature in daylight (standard) and at most 5% in twilight (draft, 300 m up, the sun 0.5 deg
down; tests/test_stability.py), for 8 view and 8 sun transmittance lookups per ray, as before.

Switching at a row is continuous: there the tables hold their own quadrature of the same integral.
"""
from __future__ import annotations

import numpy as np

from .parameterization import distance_to_bottom_atmosphere_boundary, rho_from_x_r
from .single import single_scattering_integral

#: Ground rays from cameras below this row of the single-scattering tables are integrated.
NEAR_GROUND_ROWS = 5
#: Gauss-Legendre nodes on each of the two lit segments of the ray.
NEAR_GROUND_SAMPLES = 4


def near_ground_altitude(t) -> float:
    """Altitude [m] of the single-scattering tables' row ``NEAR_GROUND_ROWS`` (x_r = row / (n_r - 1))."""
    h = np.sqrt(t.top * t.top - t.bottom * t.bottom)
    rho = rho_from_x_r(NEAR_GROUND_ROWS / (t.rayleigh.shape[0] - 1), h, t.r_axis)
    return rho * rho / (np.sqrt(rho * rho + t.bottom * t.bottom) + t.bottom)


def near_ground_rays(t, r, intersects_ground):
    """Boolean mask: ground rays from cameras below :func:`near_ground_altitude`."""
    return np.asarray(intersects_ground) & (np.asarray(r) - t.bottom < near_ground_altitude(t))


def shadow_interval(r, mu, mu_s, nu, d, bottom):
    """[t_0, t_1] within [0, d]: the part of the ray (r, mu) where the planet hides the sun (mu_s, nu as for
    the camera), or t_0 = t_1 where it hides it nowhere on the ray: then the point where a shadow would appear
    first, so that the quadratures split the ray continuously as a shadow appears.

    The point x_t = x + t v is in the shadow where its ray to the sun meets the ground: p(t) = x_t . s =
    r mu_s + t nu < 0 and |x_t|^2 - p(t)^2 < R_b^2, i.e. f(t) = A t^2 + 2 B t + C < 0 with A = 1 - nu^2,
    B = r (mu - mu_s nu), C = r^2 - R_b^2 - r^2 mu_s^2. f is convex: f < 0 on [lo, hi] between its roots (taken in
    the stable form q / A, C / q; where f has none, lo = hi = -B / A, its minimum, where they appear), clipped to
    [0, d]. p is linear, so the shadow is the part of [lo, hi] where p < 0: all of it, none of it, or the part on
    one side of p's zero t_p, found between lo and hi from p(lo) and p(hi) (no division by nu, which may be
    subnormal). Where p >= 0 on all of [lo, hi] the split point is (lo p(hi) + hi p(lo)) / (p(lo) + p(hi)): lo
    where p(lo) = 0 and hi where p(hi) = 0, where a shadow appears. Splitting rays without a shadow at d / 2
    instead made the quadrature step by up to 0.8% as the shadow appeared (tables/horizon.py's rays from 30 km,
    the sun 1 deg down; docs/stability.md)."""
    r, mu, mu_s, nu, d = np.broadcast_arrays(*(np.asarray(a, float) for a in (r, mu, mu_s, nu, d)))
    a_ = np.maximum(1.0 - nu * nu, 1e-12)
    b_ = r * (mu - mu_s * nu)
    c_ = (r - bottom) * (r + bottom) - r * r * mu_s * mu_s
    disc = b_ * b_ - a_ * c_
    q = np.where(disc > 0.0, -(b_ + np.copysign(np.sqrt(np.maximum(disc, 0.0)), b_)), 1.0)   # |q| >= sqrt(disc)
    t_a, t_b = q / a_, c_ / q
    lo = np.where(disc > 0.0, np.minimum(t_a, t_b), -b_ / a_)
    hi = np.where(disc > 0.0, np.maximum(t_a, t_b), -b_ / a_)
    lo, hi = np.clip(lo, 0.0, d), np.clip(hi, 0.0, d)
    p_lo, p_hi = r * mu_s + lo * nu, r * mu_s + hi * nu
    crossing = (p_lo < 0.0) != (p_hi < 0.0)
    t_p = lo + (hi - lo) * np.where(crossing, p_lo / np.where(crossing, p_lo - p_hi, 1.0), 0.0)
    lit = (p_lo >= 0.0) & (p_hi >= 0.0)
    total = p_lo + p_hi
    split = np.where(total > 0.0, (lo * p_hi + hi * p_lo) / np.where(total > 0.0, total, 1.0), lo)
    t_0 = np.where(lit, split, np.where(p_lo < 0.0, lo, t_p))
    t_1 = np.where(lit, split, np.where(p_hi < 0.0, hi, t_p))
    return t_0, t_1


def near_ground_single_scattering(t, atm, r, mu, mu_s, nu):
    """(S_R,1, S_M,1) (..., W) without phase for ground rays at (r, mu, mu_s, nu): the integral of the
    precompute's single scattering (single.single_scattering_integral) over [0, d], d the distance to the
    ground, with ``NEAR_GROUND_SAMPLES`` Gauss-Legendre nodes on each of [0, t_0] and [t_1, d]
    (:func:`shadow_interval`); per unit solar irradiance."""
    r, mu = np.asarray(r, float), np.asarray(mu, float)
    d = distance_to_bottom_atmosphere_boundary(r, mu, t.bottom)
    t_0, t_1 = (a[..., None] for a in shadow_interval(r, mu, mu_s, nu, d, t.bottom))
    d = d[..., None]
    x, w = np.polynomial.legendre.leggauss(NEAR_GROUND_SAMPLES)
    x, w = 0.5 * (x + 1.0), 0.5 * w
    nodes = np.concatenate([x * t_0, t_1 + x * (d - t_1)], -1)
    weights = np.concatenate([w * t_0, w * (d - t_1)], -1)
    return single_scattering_integral(t, atm, r, mu, mu_s, nu, nodes, weights)
