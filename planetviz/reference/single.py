"""Deterministic single scattering: the first order of the reference solution, by quadrature.

L_1(x, v) = int_0^t_end T(x, x_t) [beta_R^scat(h_t) P_R(nu) + beta_M^scat(h_t) P_M(nu)] T_sun(x_t) dt
          + T(x, x_g) (a / pi) max(0, n . s) T_sun(x_g)      (where the ray hits the ground x_g)

in 1/sr per unit solar irradiance (paper Eq. 7 with only the first scattering or reflection event;
nu = v . s). Both transmittances come from :func:`optical_depth`.

The ray is cut at the point of closest approach t_c (the densest air) and at the ends of the planet's
shadow on it (where T_sun jumps); each of the four parts is integrated by composite Gauss-Legendre
quadrature mapped by t = end + span u^2 from its end nearest t_c, so no node straddles the shadow's edge.
Relative error against 4x the panels: 1e-11 for exponential profiles, up to 7.5e-6 where a ray crosses the
kinks of an ozone-like tent layer (Earth preset; tests/test_reference.py bounds it by 1e-4).
"""
from __future__ import annotations

import numpy as np

from ..model.geometry import distance_to_ground
from .optical_depth import gauss_legendre_panels, optical_depth, shell_segment, sun_transmittance
from .shadow import shadow_interval


def single_scattering(atm, camera, view_dir, sun_dir, panels: int = 12):
    """(in-scattered radiance, directly lit ground radiance), each (N, W) [1/sr per unit irradiance].

    ``panels`` Gauss-Legendre panels of 16 points on each of the ray's four parts. The directions are
    normalised here exactly as :func:`~planetviz.reference.montecarlo.solve` normalises them, so that both
    classify a ray tangent to the ground alike (a tangent ray's ground hit turns on the last bit of its
    direction).
    """
    c = np.atleast_2d(np.asarray(camera, dtype=float))
    v = np.atleast_2d(np.asarray(view_dir, dtype=float))
    v = v / np.linalg.norm(v, axis=-1, keepdims=True)
    s = np.broadcast_to(np.asarray(sun_dir, dtype=float), c.shape)
    s = s / np.linalg.norm(s, axis=-1, keepdims=True)
    parts = [_single_scattering(atm, c[i:i + _CHUNK], v[i:i + _CHUNK], s[i:i + _CHUNK], panels)
             for i in range(0, len(c), _CHUNK)]
    if not parts:
        empty = np.zeros((0, atm.n_wavelengths))
        return empty, empty.copy()
    return np.concatenate([p[0] for p in parts]), np.concatenate([p[1] for p in parts])


#: Rays per block (each holds rays x 768 nodes x 256 sun-path nodes of work arrays).
_CHUNK = 32


def _single_scattering(atm, c, v, s, panels):
    """:func:`single_scattering` for one block of rays with unit directions."""
    start, end = shell_segment(c, v, atm.top_radius_m)
    t_ground = distance_to_ground(c, v, atm.bottom_radius_m)
    end = np.minimum(end, t_ground)
    length = np.maximum(end - start, 0.0)
    o = c + start[:, None] * v
    tc = np.clip(-np.einsum("ni,ni->n", o, v), 0.0, length)
    a, b = shadow_interval(o, v, s, atm.bottom_radius_m)
    a, b = np.clip(a, 0.0, length), np.clip(b, 0.0, length)
    cuts = np.sort(np.stack([np.zeros_like(length), tc, np.where(a < b, a, tc), np.where(a < b, b, tc),
                             length], axis=1), axis=1)
    u, w = gauss_legendre_panels(panels)
    nu = np.einsum("ni,ni->n", v, s)
    p_r = atm.rayleigh.phase_function(nu)[:, None]
    p_m = atm.mie.phase_function(nu)
    scatter = np.zeros((len(c), atm.n_wavelengths))
    for lo, hi in zip(cuts.T[:-1], cuts.T[1:]):
        span = hi - lo
        near_lo = lo >= tc                              # the part lies beyond t_c: cluster at its start
        t = np.where(near_lo[:, None], lo[:, None] + span[:, None] * u * u, hi[:, None] - span[:, None] * u * u)
        jac = 2.0 * span[:, None] * u * w
        pts = o[:, None, :] + t[..., None] * v[:, None, :]
        h = np.linalg.norm(pts, axis=-1) - atm.bottom_radius_m
        b_r, b_m = atm.scattering(h)
        t_view = np.exp(-optical_depth(atm, np.repeat(o[:, None, :], t.shape[1], 1),
                                       np.repeat(v[:, None, :], t.shape[1], 1), t))
        t_sun = sun_transmittance(atm, pts, s[:, None, :])
        integrand = t_view * (b_r * p_r[:, None, :] + b_m * p_m[:, None, :]) * t_sun
        scatter += np.einsum("nk,nkw->nw", jac, integrand)
    ground = np.zeros_like(scatter)
    hit = np.isfinite(t_ground)
    if np.any(hit):
        xg = c[hit] + t_ground[hit, None] * v[hit]
        n = xg / np.linalg.norm(xg, axis=-1, keepdims=True)
        cos_s = np.maximum(np.einsum("ni,ni->n", n, s[hit]), 0.0)
        t_view = np.exp(-optical_depth(atm, c[hit], v[hit], t_ground[hit]))
        ground[hit] = (t_view * np.asarray(atm.ground_albedo) / np.pi * cos_s[:, None]
                       * sun_transmittance(atm, xg, s[hit]))
    return scatter, ground
