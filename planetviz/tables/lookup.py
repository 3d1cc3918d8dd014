"""Reading the tables: transmittance, irradiance and scattering lookups (GLSL functions of the same names).

``t`` is a :class:`~planetviz.tables.precompute.Tables`; every lookup returns (..., W).
"""
from __future__ import annotations

import numpy as np

from .parameterization import (distance_to_bottom_atmosphere_boundary, irradiance_uv_from_r_mu_s,
                               ray_intersects_ground, scattering_uvwz_from_r_mu_mu_s_nu,
                               transmittance_uv_from_r_mu)
from .sampling import texture2d, texture3d


def get_transmittance_to_top_atmosphere_boundary(t, r, mu):
    """T between (r, mu) and the top of the atmosphere (the ray must not hit the ground)."""
    n_r, n_mu = t.transmittance.shape[:2]
    u, v = transmittance_uv_from_r_mu(r, mu, t.bottom, t.top, (n_mu, n_r))
    return texture2d(t.transmittance, u, v)


def get_transmittance(t, r, mu, d, intersects_ground):
    """T between (r, mu) and the point at distance d along the ray (Bruneton's ratio of two lookups)."""
    r_d = np.sqrt(np.maximum(d * d + 2.0 * r * mu * d + r * r, 0.0))
    r_d = np.clip(r_d, t.bottom, t.top)
    mu_d = np.clip((r * mu + d) / r_d, -1.0, 1.0)
    g = np.asarray(intersects_ground)[..., None]
    down = (get_transmittance_to_top_atmosphere_boundary(t, r_d, -mu_d)
            / np.maximum(get_transmittance_to_top_atmosphere_boundary(t, r, -mu), 1e-30))
    up = (get_transmittance_to_top_atmosphere_boundary(t, r, mu)
          / np.maximum(get_transmittance_to_top_atmosphere_boundary(t, r_d, mu_d), 1e-30))
    return np.minimum(np.where(g, down, up), 1.0)


def get_transmittance_to_sun(t, r, mu_s):
    """T toward a point sun: 0 when the planet hides it."""
    shadow = ray_intersects_ground(r, mu_s, t.bottom)
    return np.where(shadow[..., None], 0.0, get_transmittance_to_top_atmosphere_boundary(t, r, mu_s))


def get_irradiance(t, r, mu_s):
    """Indirect (sky) irradiance E(r, mu_s) per unit solar irradiance."""
    n_r, n_mu_s = t.irradiance.shape[:2]
    u, v = irradiance_uv_from_r_mu_s(r, mu_s, t.bottom, t.top, (n_mu_s, n_r))
    return texture2d(t.irradiance, u, v)


def get_scattering(t, table, r, mu, mu_s, nu, intersects_ground):
    """A 4D table read as the shader does: two trilinear fetches blended along nu."""
    n_r, n_mu, n_x = table.shape[:3]
    n_nu = t.sizes.scattering[0]
    n_mu_s = n_x // n_nu
    u_nu, u_mu_s, u_mu, u_r = scattering_uvwz_from_r_mu_mu_s_nu(r, mu, mu_s, nu, intersects_ground,
                                                                t.bottom, t.top, (n_nu, n_mu_s, n_mu, n_r))
    coord = u_nu * (n_nu - 1)
    tex_nu = np.clip(np.floor(coord), 0, n_nu - 2 if n_nu > 1 else 0)
    lerp = (coord - tex_nu)[..., None]
    a = texture3d(table, (tex_nu + u_mu_s) / n_nu, u_mu, u_r)
    if n_nu == 1:
        return a
    b = texture3d(table, (tex_nu + 1 + u_mu_s) / n_nu, u_mu, u_r)
    return a * (1.0 - lerp) + b * lerp


def distance_to_ground(t, r, mu):
    return distance_to_bottom_atmosphere_boundary(r, mu, t.bottom)
