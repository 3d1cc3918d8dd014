"""Single scattering by quadrature along the ray where the 4D tables read it worst, blended into their reading: next
to the horizon's direction and where the sun is low somewhere along the ray (GLSL twins of the same names in
shaders/horizon.glsl).

Why. Next to the horizon the single scattering changes fastest with the camera's altitude, the sun's elevation
and its azimuth (a ray grazing the ground from high up crosses the whole atmosphere, and the sun's elevation and
transmittance change along it), so interpolating the 4D tables linearly is least accurate there: the draft
tables read the rays within 1e-2 (in mu) of the horizon's direction 1.3-2.0x as far off as the rest of the sky
(2 m, 300 m, 1 km, 15-40 km; the seam test, docs/stability.md), and every table size that mends it costs over draft's
1 s of precompute. Where the sun sets for some point of the ray (twilight, the terminator and the night side seen
from space) the planet's shadow cuts the ray, and the light comes from the lit part's sunward end: its edge moves
along the ray as the sun moves, which texels in mu_s 0.5-3 deg apart cannot follow. There the standard tables read
the first order 3-12% RMS off of the whole radiance in twilight (the sun to 6 deg down where the ray looks; up to
57% on single rays) and up to 184 times the whole radiance on limb rays in deep twilight, on the random
atmospheres of benchmarks/tables_suite.py (--single).

How. Rays within ``HORIZON_BAND[1]`` of the horizon's direction mu_h = -sqrt(1 - (R_b / r)^2) (:func:`horizon_share`),
and rays along which the sun's elevation falls below ``TWILIGHT_BAND[1]`` (:func:`twilight_share`), integrate
their single scattering as the precompute does (single.single_scattering_integral, with the tables'
transmittances), on the two lit parts of the ray around the planet's shadow (near_ground.shadow_interval), with
``HORIZON_SAMPLES`` Gauss-Legendre nodes on each side of each part's closest approach (nodes.ray_nodes): 48
nodes at most. The larger share (:func:`quadrature_share`) replaces the tables' reading where it is 1 and blends
into it by a smoothstep, so the radiance stays continuous where the bands end. Against the reference quadrature
(Earth, the seam test's rays from 2 m to 50 km, the sun 5-60 deg up): next to the horizon within 0.19-0.97%
(draft) and 0.05-0.25% (standard), where the rest of the sky reads 1.4-6.0% and 0.21-0.68%
(tests/test_stability_horizon.py). The sunlight along these rays fades within a few nodes' spacing where the sun
sets for the points far along them: from 50 km, with 6 nodes per side they read 2-10% off, with 8 0.95%, 10 0.41%,
12 0.17% (standard tables). In optically thick atmospheres the light of a ray next to the horizon comes from its
first attenuation lengths, between the nodes where they cluster far away at the closest approach; even so the
quadrature reads those rays nearer the reference than the tables do (docs/tables.md).
Ground rays from below near_ground.NEAR_GROUND_ROWS keep near_ground.py's rule.
"""
from __future__ import annotations

import numpy as np

from .lookup import get_scattering, ray_opacity
from .near_ground import near_ground_rays, near_ground_single_scattering, shadow_interval
from .parameterization import distance_to_bottom_atmosphere_boundary, distance_to_top_atmosphere_boundary
from .nodes import ray_nodes
from .single import single_scattering_integral

#: |mu - mu_h| within which the quadrature replaces the tables, and where its share has fallen to 0.
HORIZON_BAND = (0.01, 0.03)
#: The sine of the lowest sun elevation along the ray at and below which the quadrature replaces the tables
#: (0 deg: the sun sets for some point of the ray), and from which on its share is 0 (2 deg).
TWILIGHT_BAND = (0.0, float(np.sin(np.radians(2.0))))
#: Gauss-Legendre nodes on each side of the closest approach, on each of the two lit parts of the ray.
HORIZON_SAMPLES = 12


def horizon_share(r, mu, bottom):
    """The quadrature's share w in [0, 1] of the single scattering of the ray (r, mu): 1 where |mu - mu_h| <=
    HORIZON_BAND[0], 0 from HORIZON_BAND[1] on, smoothstep x^2 (3 - 2 x) between; mu_h = -sqrt(r^2 - R_b^2) / r."""
    r, mu = np.asarray(r, float), np.asarray(mu, float)
    mu_h = -np.sqrt(np.maximum(r * r - bottom * bottom, 0.0)) / r
    inner, outer = HORIZON_BAND
    x = np.clip((outer - np.abs(mu - mu_h)) / (outer - inner), 0.0, 1.0)
    return x * x * (3.0 - 2.0 * x)


def lowest_mu_s(r, mu, mu_s, nu, d):
    """The least cos(sun zenith) at the points x_t = x + t v, t in [0, d], of the ray (r, mu) (mu_s, nu at x).

    The direction of x_t turns by theta_d = atan2(d sqrt(1 - mu^2), r + d mu) (< pi) in the plane of x and v, and
    mu_s(theta) = a cos(theta) + b sin(theta) with a = mu_s and b = (nu - mu mu_s) / sqrt(1 - mu^2), the sun's
    component along the plane's second axis (|b| <= sqrt(1 - mu_s^2), clamped against rounding). Its least value on
    [0, theta_d] is at an end, or -sqrt(a^2 + b^2) at theta = atan2(b, a) + pi when that lies between."""
    r, mu, mu_s, nu, d = np.broadcast_arrays(*(np.asarray(x, float) for x in (r, mu, mu_s, nu, d)))
    sin_v = np.sqrt(np.maximum(1.0 - mu * mu, 0.0))
    theta_d = np.arctan2(d * sin_v, r + d * mu)
    b_max = np.sqrt(np.maximum(1.0 - mu_s * mu_s, 0.0))
    b = np.clip(np.where(sin_v > 0.0, (nu - mu * mu_s) / np.where(sin_v > 0.0, sin_v, 1.0), 0.0), -b_max, b_max)
    low = np.minimum(mu_s, mu_s * np.cos(theta_d) + b * np.sin(theta_d))
    between = np.mod(np.arctan2(b, mu_s) + np.pi, 2.0 * np.pi) <= theta_d
    return np.where(between, np.minimum(low, -np.sqrt(mu_s * mu_s + b * b)), low)


def twilight_share(r, mu, mu_s, nu, intersects_ground, bottom, top):
    """The quadrature's share w in [0, 1] of the single scattering of the ray (r, mu) to the ground or the top from
    the sun's elevation along it: 1 where the lowest mu_s (:func:`lowest_mu_s`) is at most TWILIGHT_BAND[0], 0 from
    TWILIGHT_BAND[1] on, smoothstep x^2 (3 - 2 x) between."""
    r, mu = np.asarray(r, float), np.asarray(mu, float)
    d = np.where(intersects_ground, distance_to_bottom_atmosphere_boundary(r, mu, bottom),
                 distance_to_top_atmosphere_boundary(r, mu, top))
    inner, outer = TWILIGHT_BAND
    x = np.clip((outer - lowest_mu_s(r, mu, mu_s, nu, d)) / (outer - inner), 0.0, 1.0)
    return x * x * (3.0 - 2.0 * x)


def quadrature_share(r, mu, mu_s, nu, intersects_ground, bottom, top):
    """The quadrature's share of the single scattering of the ray: the larger of :func:`horizon_share` and
    :func:`twilight_share`."""
    return np.maximum(horizon_share(r, mu, bottom), twilight_share(r, mu, mu_s, nu, intersects_ground, bottom, top))


def horizon_single_scattering(t, atm, r, mu, mu_s, nu, intersects_ground):
    """(S_R,1, S_M,1) (..., W) without phase, per unit solar irradiance, of the ray (r, mu) to the ground or to
    the top: the precompute's integral over [0, t_0] and [t_1, d] ([t_0, t_1] the planet's shadow), each with
    ``ray_nodes(.., HORIZON_SAMPLES, ..)``. A part of zero length adds nothing and is not evaluated (a ray
    wholly in the shadow, or lit on one side of it only: most of the precompute's incident rays in the shadow)."""
    r, mu, mu_s, nu, intersects_ground = np.broadcast_arrays(
        *(np.asarray(a, float) for a in (r, mu, mu_s, nu)), np.asarray(intersects_ground, bool))
    d = np.where(intersects_ground, distance_to_bottom_atmosphere_boundary(r, mu, t.bottom),
                 distance_to_top_atmosphere_boundary(r, mu, t.top))
    t_0, t_1 = shadow_interval(r, mu, mu_s, nu, d, t.bottom)
    out = np.zeros((2,) + r.shape + (atm.n_wavelengths,))
    for start, end in ((np.zeros_like(d), t_0), (t_1, d)):
        part = end > start
        if np.any(part):
            nodes, weights = ray_nodes(r[part], mu[part], end[part], HORIZON_SAMPLES, start=start[part])
            out[:, part] += single_scattering_integral(t, atm, r[part], mu[part], mu_s[part], nu[part], nodes,
                                                       weights)
    return out[0], out[1]


def read_single_scattering(t, atm, r, mu, mu_s, nu, intersects_ground, opacity=None):
    """(S_R,1, S_M,1) (..., W) without phase of the rays (r, mu) with the sun at (mu_s, nu), as the evaluator and
    the shaders read single scattering: the 4D tables (``opacity``: the rays' ``lookup.ray_opacity``, computed
    here if None), near_ground.py's quadrature for ground rays from cameras near the ground, and for the other
    rays :func:`horizon_single_scattering` blended into the tables' reading by :func:`quadrature_share` (the
    tables are read only where that share is below 1). The precompute's orders above the first read the sky of
    order 1 so too (tables/multiple.py)."""
    r, mu, mu_s, nu, ground = np.broadcast_arrays(
        *(np.asarray(a, float) for a in (r, mu, mu_s, nu)), np.asarray(intersects_ground, bool))
    near = near_ground_rays(t, r, ground)
    share = np.where(near, 0.0, quadrature_share(r, mu, mu_s, nu, ground, t.bottom, t.top))
    W = atm.n_wavelengths
    s = np.zeros((2,) + r.shape + (W,))                               # (S_R,1, S_M,1)
    read = ~near & (share < 1.0)                                       # the rays whose tables' reading counts
    if np.any(read):
        opacity = (ray_opacity(t, r[read], mu[read], ground[read]) if opacity is None
                   else np.broadcast_to(opacity, r.shape + (W,))[read])
        both = get_scattering(t, np.concatenate([t.rayleigh, t.mie], -1), r[read], mu[read], mu_s[read], nu[read],
                              ground[read], np.concatenate([opacity] * 2, -1))   # both tables read at once
        s[0][read], s[1][read] = both[..., :W], both[..., W:]
    if np.any(near):
        s[0][near], s[1][near] = near_ground_single_scattering(t, atm, r[near], mu[near], mu_s[near], nu[near])
    band = share > 0.0
    if np.any(band):
        q = np.stack(horizon_single_scattering(t, atm, r[band], mu[band], mu_s[band], nu[band], ground[band]))
        s[:, band] += share[band][..., None] * (q - s[:, band])
    return s[0], s[1]
