"""Single scattering of rays next to the horizon's direction by quadrature along the ray, blended into what the
tables read (GLSL twins: ``horizon_share`` and ``horizon_single_scattering`` in shaders/horizon.glsl).

Why. Next to the horizon the single scattering changes fastest with the camera's altitude, the sun's elevation
and its azimuth (a ray grazing the ground from high up crosses the whole atmosphere, and the sun's elevation and
transmittance change along it), so interpolating the 4D tables linearly is least accurate there: the draft
tables read the rays within 1e-2 (in mu) of the horizon's direction 1.3-2.0x as far off as the rest of the sky
(2 m, 300 m, 1 km, 15-40 km; the seam test, docs/stability.md), and every table size that mends it costs over draft's
1 s of precompute. In twilight (the sun 1-5 deg down) the tables read these rays 28-960% off (draft) and 4-41%
(standard), where the twilight glow is.

How. Rays within ``HORIZON_BAND[1]`` of the horizon's direction mu_h = -sqrt(1 - (R_b / r)^2) integrate their
single scattering as the precompute does (precompute.single_scattering_integral, with the tables'
transmittances), on the two lit parts of the ray around the planet's shadow (near_ground.shadow_interval), with
``HORIZON_SAMPLES`` Gauss-Legendre nodes on each side of each part's closest approach (nodes.ray_nodes): 48
nodes at most. The result replaces the tables' reading within ``HORIZON_BAND[0]`` and blends into it by a
smoothstep up to ``HORIZON_BAND[1]`` (:func:`horizon_share`), so the radiance stays continuous where the band
ends. Against the reference quadrature (Earth, the seam test's rays from 2 m to 50 km, the sun 5-60 deg up): next
to the horizon within 0.19-0.97% (draft) and 0.05-0.25% (standard), where the rest of the sky reads 1.4-6.0% and
0.21-0.68% (tests/test_stability_horizon.py). The sunlight along these rays fades within a few nodes' spacing
where the sun sets for the points far along them: from 50 km, with 6 nodes per side they read 2-10% off, with 8
0.95%, 10 0.41%, 12 0.17% (standard tables).
Ground rays from below near_ground.NEAR_GROUND_ROWS keep near_ground.py's rule.
"""
from __future__ import annotations

import numpy as np

from .near_ground import shadow_interval
from .parameterization import distance_to_bottom_atmosphere_boundary, distance_to_top_atmosphere_boundary
from .nodes import is_optically_thick, ray_nodes
from .precompute import single_scattering_integral

#: |mu - mu_h| within which the quadrature replaces the tables, and where its share has fallen to 0.
HORIZON_BAND = (0.01, 0.03)
#: Gauss-Legendre nodes on each side of the closest approach, on each of the two lit parts of the ray.
HORIZON_SAMPLES = 12


def horizon_quadrature_applies(atm) -> bool:
    """Whether the evaluator and the shaders use this module for ``atm``: not where it is optically thick
    (nodes.is_optically_thick). There the light next to the horizon comes from the first attenuation lengths
    from the camera (hundreds of metres), between the nodes, which cluster at the closest approach: the thick test
    planet's single scattering just above the horizon read 54% off from 1 km (draft) where the tables read 7.7%."""
    return not is_optically_thick(atm)


def horizon_share(r, mu, bottom):
    """The quadrature's share w in [0, 1] of the single scattering of the ray (r, mu): 1 where |mu - mu_h| <=
    HORIZON_BAND[0], 0 from HORIZON_BAND[1] on, smoothstep x^2 (3 - 2 x) between; mu_h = -sqrt(r^2 - R_b^2) / r."""
    r, mu = np.asarray(r, float), np.asarray(mu, float)
    mu_h = -np.sqrt(np.maximum(r * r - bottom * bottom, 0.0)) / r
    inner, outer = HORIZON_BAND
    x = np.clip((outer - np.abs(mu - mu_h)) / (outer - inner), 0.0, 1.0)
    return x * x * (3.0 - 2.0 * x)


def horizon_single_scattering(t, atm, r, mu, mu_s, nu, intersects_ground):
    """(S_R,1, S_M,1) (..., W) without phase, per unit solar irradiance, of the ray (r, mu) to the ground or to
    the top: the precompute's integral over [0, t_0] and [t_1, d] ([t_0, t_1] the planet's shadow), each with
    ``ray_nodes(.., HORIZON_SAMPLES, ..)``."""
    r, mu = np.asarray(r, float), np.asarray(mu, float)
    d = np.where(intersects_ground, distance_to_bottom_atmosphere_boundary(r, mu, t.bottom),
                 distance_to_top_atmosphere_boundary(r, mu, t.top))
    t_0, t_1 = shadow_interval(r, mu, mu_s, nu, d, t.bottom)
    before, w_before = ray_nodes(r, mu, t_0, HORIZON_SAMPLES)
    after, w_after = ray_nodes(r, mu, d, HORIZON_SAMPLES, start=t_1)
    return single_scattering_integral(t, atm, r, mu, mu_s, nu, np.concatenate([before, after], -1),
                                      np.concatenate([w_before, w_after], -1))
