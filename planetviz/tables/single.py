"""The single-scattering stage of the precompute (stage 2 of tables/precompute.py) and its integrand, which the
quadratures along rays at render time share (tables/near_ground.py, tables/horizon.py):

    S_i,1(r, mu, mu_s, nu) = int_0^d beta_i^scat(h_t) T(x, x_t) T_sun(x_t) dt        (i = R, M; per unit solar
                                                                                    irradiance, without phase)

with x_t = x + t v at radius r_t = sqrt(t^2 + 2 r mu t + r^2) and mu_s,t = (r mu_s + t nu) / r_t. The view
transmittance and the densities depend on (r, mu, t) only; only T_sun is evaluated for every sun.
"""
from __future__ import annotations

import numpy as np

from .lookup import SMALLEST, get_transmittance, get_transmittance_to_sun, ray_opacity
from .nodes import LONG_RAY_NODE_FACTOR, integration_grid, ray_nodes


def single_scattering_integral(tables, atm, r, mu, mu_s, nu, t, w):
    """(S_R,1, S_M,1) (..., W) without phase at (r, mu, mu_s, nu) from quadrature nodes t and weights w (..., K)
    along the ray: sum_k w_k beta_i^scat rho_i(h_k) T(x, x_k) T_sun(x_k) (stage 2 of the module docstring),
    mu_s,k = (r mu_s + t_k nu) / r_k. r, mu, mu_s, nu broadcast against each other and against t's leading axes
    (the view transmittance and the densities are computed once for what r, mu and t share)."""
    r, mu = (np.asarray(a, float)[..., None] for a in (r, mu))
    r_t, weights = _node_weights(tables, atm, r, mu, t, w)
    return _sun_sum(tables, r, r_t, t, weights, mu_s, nu)


def _node_weights(tables, atm, r, mu, t, w):
    """(r_t, the node weights (..., K, W, 2)) of the rays (r, mu) (..., 1) at their nodes t with weights w
    (..., K): r_t the nodes' radii [m], the weights w_k beta_i^scat rho_i(h_k) T(x, x_k) [1/m x m] of molecules
    and particles, what the single-scattering integral shares over every sun."""
    r_t = np.sqrt(np.maximum(t * t + 2.0 * r * mu * t + r * r, 0.0))
    h = r_t - tables.bottom
    view = get_transmittance(tables, r, mu, t)
    return r_t, np.stack([(w * species.profile.density(h))[..., None] * view * np.asarray(species.scattering_m)
                          for species in (atm.rayleigh, atm.mie)], -1)


def _sun_sum(tables, r, r_t, t, weights, mu_s, nu):
    """(S_R,1, S_M,1) (..., W): the node weights of :func:`_node_weights` times T_sun(r_t, mu_s,t) summed over
    the nodes, for suns (mu_s, nu) broadcasting against the rays' leading axes."""
    mu_s, nu = (np.asarray(a, float)[..., None] for a in (mu_s, nu))
    mu_s_t = np.clip((r * mu_s + t * nu) / r_t, -1.0, 1.0)
    s = _sum_over_nodes(weights, get_transmittance_to_sun(tables, r_t, mu_s_t))
    return s[..., 0], s[..., 1]


def _sum_over_nodes(a, sun):
    """sum_k a[..., k, w, c] sun[..., k, w]: (..., W, C), for ``a`` (..., K, W, C) broadcasting against ``sun``
    (..., K, W). Where ``a`` is constant along sun's trailing axes (the single-scattering stage: one set of node
    weights per ray, many suns) this is one matrix product per wavelength, in float32 as the tables are."""
    full, k, n_w = sun.shape[:-2], sun.shape[-2], sun.shape[-1]
    lead = (1,) * (len(full) - (a.ndim - 3)) + a.shape[:-3]
    j = len(full)
    while j > 0 and lead[j - 1] == 1:
        j -= 1
    if j == len(full):
        return np.einsum("...kw,...kwc->...wc", sun, a)
    p, q = int(np.prod(full[:j], dtype=np.int64)), int(np.prod(full[j:], dtype=np.int64))
    sun_w = np.moveaxis(sun, -1, 0).reshape(n_w, p, q, k)
    a_w = np.moveaxis(np.broadcast_to(a.reshape(lead + a.shape[-3:]), full[:j] + (1,) * (len(full) - j)
                                      + a.shape[-3:]).reshape(p, k, n_w, -1), 2, 0).astype(np.float32)
    return np.moveaxis(np.matmul(sun_w, a_w), 0, -2).reshape(full + (n_w, a.shape[-1]))


#: Quadrature nodes times (mu_s, nu) texels the single-scattering stage evaluates at once.
SINGLE_SCATTERING_BLOCK = 2 ** 16


def single_scattering(tables, atm, progress=None):
    """(S_R,1, S_M,1), each (n_r, n_mu, n_nu, n_mu_s, W): in-scattered radiance without phase, divided by the
    ray's opacity 1 - T (``lookup.ray_opacity``), on ``nodes.integration_grid``'s rays.

    Rays longer than the horizontal ray from the ground to the top (those that graze the planet from high up)
    get LONG_RAY_NODE_FACTOR times the nodes: with a low sun behind the camera the sunlight along them ends
    where they enter the planet's shadow, far away, a step that nodes at fixed places resolve poorly (from 50 km
    such a ray reads 3.0% off with 8 nodes per side, 0.8% with 16; the seam test, docs/stability.md)."""
    r, mu, mu_s, nu, ground, d = integration_grid(tables)
    n_r = r.shape[0]
    out_r = np.empty(r.shape + (atm.n_wavelengths,))
    out_m = np.empty_like(out_r)
    r_2, mu_2, ground_2, d = (a[:, :, :1, :1] for a in (r, mu, ground, d))            # (n_r, n_mu, 1, 1)
    opacity = ray_opacity(tables, r_2, mu_2, ground_2)
    long_ray = d[:, :, 0, 0] > np.sqrt(tables.top ** 2 - tables.bottom ** 2)
    for i in range(n_r):
        if progress:
            progress("single scattering", i / n_r)
        for long in (False, True):
            samples = (LONG_RAY_NODE_FACTOR if long else 1) * tables.sizes.scattering_samples
            block = max(1, SINGLE_SCATTERING_BLOCK // (r[0, 0].size * 2 * samples))
            rows = np.flatnonzero(long_ray[i] == long)
            if rows.size == 0:
                continue
            ri, mui = r[i, rows][:, :1, :1, None], mu[i, rows][:, :1, :1, None]   # per mu, (rows, 1, 1, 1)
            t, w = ray_nodes(ri[..., 0], mui[..., 0], d[i, rows], samples)         # (rows, 1, 1, K)
            r_t, weights = _node_weights(tables, atm, ri, mui, t, w)
            for j in range(0, rows.size, block):
                rays, part = (i, rows[j:j + block]), slice(j, j + block)
                out_r[rays], out_m[rays] = _sun_sum(tables, ri[part], r_t[part], t[part], weights[part],
                                                    mu_s[rays], nu[rays])
    opacity = np.maximum(opacity, SMALLEST)                 # 0 where the air is too thin to represent (S is 0)
    return out_r / opacity, out_m / opacity
