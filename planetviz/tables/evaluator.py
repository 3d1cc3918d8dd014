"""Radiance from the tables for arbitrary rays, read exactly as the shader reads them (paper Algorithm 1).

For a camera x (moved to the top of the atmosphere when it is in space), view direction v and sun s:

* rays to space:  L = S_R(r, mu, mu_s, nu) P_R(nu) + S_M(r, mu, mu_s, nu) P_M(nu)
* rays to the ground point y at distance d (aerial perspective, Algorithm 1 line 23):
  S(x -> y) = S(x) - T(x, y) S(y), plus the ground itself:
  T(x, y) (a / pi) [T_sun(y) max(n . s, 0) + E_sky(y)]  (Lambertian, lit by the sun and the sky).

Single scattering is read from the tables except for ground rays from cameras near the ground
(tables/near_ground.py), and rays next to the horizon's direction or along which the sun is low somewhere
(tables/horizon.py, blended into the tables' reading): there it is integrated along the ray with the tables'
transmittances.

``tables`` is a 4D set (:class:`~planetviz.tables.precompute.Tables`) or a compact one
(:class:`~planetviz.tables.compact.CompactTables`: the same formulas, in-scattering read without nu).
Returns radiance (N, W) in 1/sr per unit solar irradiance and the transmittance along the view ray.
"""
from __future__ import annotations

import numpy as np

from ..model.geometry import ray_sphere
from ..model.queries import validate_queries
from .compact import CompactTables, get_compact_scattering
from .multiple import forward_factor
from .lookup import (get_irradiance, get_scattering, get_transmittance, get_transmittance_to_sun,
                     get_transmittance_to_top_atmosphere_boundary, ground_row_factor, ray_opacity)
from .horizon import read_single_scattering
from .parameterization import distance_to_bottom_atmosphere_boundary, ray_intersects_ground


def phased_scattering(tables, atm, r, mu, mu_s, nu, ground):
    """In-scattered radiance (..., W): single scattering with its phases (``horizon.read_single_scattering``:
    ground rays from cameras near the ground from near_ground.py, not the tables; the other rays next to the
    horizon's direction or with the sun low along them from horizon.py, blended into the tables' reading by its
    share), plus multiple scattering."""
    if isinstance(tables, CompactTables):
        s_r, s_m, s_ms = (get_compact_scattering(tables, table, r, mu, mu_s)
                          for table in (tables.rayleigh, tables.mie, tables.multiple))
    else:
        opacity = ray_opacity(tables, r, mu, ground)
        s_r, s_m = read_single_scattering(tables, atm, r, mu, mu_s, nu, ground, opacity)
        s_ms, s_ms_mie = (get_scattering(tables, table, r, mu, mu_s, nu, ground, opacity, top)
                          for table, top in ((tables.multiple, tables.top_multiple),
                                             (tables.multiple_mie, tables.top_multiple_mie)))
        s_ms = (s_ms + forward_factor(atm, nu) * s_ms_mie) * ground_row_factor(tables, r, mu, ground,
                                                                                tables.multiple.shape[0])
    return s_r * atm.rayleigh.phase_function(nu)[..., None] + s_m * atm.mie.phase_function(nu) + s_ms


def sky_radiance(tables, atm, camera, view_dir, sun_dir):
    """(radiance (N, W), transmittance (N, W)) for cameras (N, 3) on or above the ground and view and sun
    directions ((N, 3) or (3,), normalised here); bad input raises ValueError naming the array and row."""
    q = validate_queries(camera, view_dir, sun_dir, tables.bottom)
    c, v, s = q.camera_m, q.view_dir, q.sun_dir
    n, W = len(c), atm.n_wavelengths
    radiance = np.zeros((n, W))
    trans = np.ones((n, W))
    r = np.linalg.norm(c, axis=1)
    # Cameras in space: move to where the ray enters the atmosphere; rays that miss see nothing.
    t0, _ = ray_sphere(c, v, tables.top)
    outside = r > tables.top
    enters = ~outside | (np.isfinite(t0) & (t0 > 0))
    x = np.where((outside & enters)[:, None], c + np.nan_to_num(t0)[:, None] * v, c)
    r = np.where(outside & enters, tables.top, np.minimum(r, tables.top))
    r = np.maximum(r, tables.bottom)
    idx = np.nonzero(enters)[0]
    x, v, s, r = x[idx], v[idx], s[idx], r[idx]
    mu = np.clip(np.einsum("ij,ij->i", x, v) / r, -1, 1)
    mu_s = np.clip(np.einsum("ij,ij->i", x, s) / r, -1, 1)
    nu = np.clip(np.einsum("ij,ij->i", v, s), -1, 1)
    ground = ray_intersects_ground(r, mu, tables.bottom)
    out = phased_scattering(tables, atm, r, mu, mu_s, nu, ground)
    tr = get_transmittance_to_top_atmosphere_boundary(tables, r, mu)
    g = np.nonzero(ground)[0]
    if g.size:
        d = distance_to_bottom_atmosphere_boundary(r[g], mu[g], tables.bottom)
        r_d = np.maximum(np.sqrt(d * d + 2 * r[g] * mu[g] * d + r[g] ** 2), tables.bottom)
        mu_d = np.clip((r[g] * mu[g] + d) / r_d, -1, 1)
        mu_s_d = np.clip((r[g] * mu_s[g] + d * nu[g]) / r_d, -1, 1)
        t_xy = get_transmittance(tables, r[g], mu[g], d)
        far = phased_scattering(tables, atm, r_d, mu_d, mu_s_d, nu[g], np.ones(g.size, bool))
        albedo = np.asarray(atm.ground_albedo)
        sun_ground = get_transmittance_to_sun(tables, np.full(g.size, tables.bottom), mu_s_d) \
            * np.maximum(mu_s_d, 0.0)[:, None]
        sky_ground = get_irradiance(tables, np.full(g.size, tables.bottom), mu_s_d)
        out[g] = np.maximum(out[g] - t_xy * far, 0.0) + t_xy * albedo / np.pi * (sun_ground + sky_ground)
        tr[g] = t_xy
    radiance[idx] = out
    trans[idx] = tr
    return radiance, trans
