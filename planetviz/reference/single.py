"""Deterministic single scattering, the analytic check of the Monte Carlo solver.

L_1(x, v) = int_0^t_end T(x, x_t) [beta_R^scat(h_t) P_R(nu) + beta_M^scat(h_t) P_M(nu)] T_sun(x_t) dt
          + T(x, x_g) (a / pi) max(0, n . s) T_sun(x_g)      (where the ray hits the ground x_g)

in 1/sr per unit solar irradiance (paper Eq. 7 with only the first scattering or reflection
event; nu = v . s). Both transmittances come from :func:`optical_depth`.
"""
from __future__ import annotations

import numpy as np

from ..geometry import distance_to_ground
from .optical_depth import _nodes, optical_depth, shell_segment, sun_transmittance


def single_scattering(atm, camera, view_dir, sun_dir, panels: int = 24):
    """(in-scattered radiance, directly lit ground radiance), each (N, W). The directions are normalised here
    exactly as :func:`~planetviz.reference.montecarlo.solve` normalises them, so that both classify a ray
    tangent to the ground alike (bit for bit: a tangent ray's ground hit turns on the last bit of its direction)."""
    c = np.atleast_2d(np.asarray(camera, dtype=float))
    v = np.atleast_2d(np.asarray(view_dir, dtype=float))
    v = v / np.linalg.norm(v, axis=-1, keepdims=True)
    s = np.broadcast_to(np.asarray(sun_dir, dtype=float), c.shape)
    s = s / np.linalg.norm(s, axis=-1, keepdims=True)
    start, end = shell_segment(c, v, atm.top_radius_m)
    t_ground = distance_to_ground(c, v, atm.bottom_radius_m)
    end = np.minimum(end, t_ground)
    length = np.maximum(end - start, 0.0)
    o = c + start[:, None] * v
    tc = np.clip(-np.einsum("ni,ni->n", o, v), 0.0, length)
    u, w = _nodes(panels)
    nu = np.einsum("ni,ni->n", v, s)
    p_r = atm.rayleigh.phase_function(nu)[:, None]
    p_m = atm.mie.phase_function(nu)
    scatter = np.zeros((len(c), atm.n_wavelengths))
    for sign, span in ((-1.0, tc), (1.0, length - tc)):
        t = tc[:, None] + sign * span[:, None] * u * u
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
