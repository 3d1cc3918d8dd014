"""Unbiased Monte Carlo solution of the full radiative transfer problem (paper Eqs. 6-8).

Problem: spherical shell between ``bottom_radius_m`` and ``top_radius_m``; all orders of
scattering by the Rayleigh and Mie components; absorption by every component; a Lambertian
ground of albedo ``ground_albedo`` lit by the attenuated sun and by the sky; the sun a
directional light of irradiance 1 at the top of the atmosphere. The sun disc itself (the
unscattered direct beam, L_0) is excluded. Result: radiance in 1/sr per unit solar irradiance.

Method (per wavelength, vectorised over paths): paths start at the camera (moved to the
entry point when it is in space) and are traced backward.

* Free flights by forced collisions: along each straight segment (to the ground or to space)
  the optical depth tau(t) is tabulated at 65 nodes clustered at the point of closest approach,
  each interval integrated by 4-point Gauss-Legendre (relative error < 5e-5 where the ozone
  tent's kinks cross a segment, 1e-9 elsewhere; tested against :func:`optical_depth`), linear in t within an interval. A collision is forced inside the
  segment with probability 1 when the segment leaves to space (weight 1 - T_segment) and
  max(1 - T, 1/2) when it ends on the ground (weights (1 - T) / p and T / (1 - p)), and its
  distance is drawn from the tabulated tau, so thin atmospheres are sampled as well as thick
  ones.
* At a real collision the path weight is multiplied by the single-scattering albedo
  beta_scat / beta_ext (absorption as weighting, not termination); the next-event estimate
  adds weight * P(nu) * T_sun, with P the mixture of the Rayleigh and Mie phase functions
  weighted by their local scattering coefficients; the new direction is sampled exactly from
  that mixture (so the weight needs no phase correction).
* At the ground the next-event estimate adds weight * (a / pi) max(0, n . s) T_sun; the path
  continues with a cosine-weighted direction and weight * a.
* T_sun by deterministic quadrature (:func:`optical_depth`, converged to ~1e-9), 0 in the
  planet's shadow.
* Russian roulette after the third event keeps the estimator unbiased and finite.

``max_order`` keeps only light scattered or reflected at most that many times (1: single
scattering plus the directly lit ground).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..geometry import distance_to_ground, distance_to_top_exit
from ..optics.phase import (PENNDORF_A, sample_henyey_greenstein, sample_rayleigh_like)
from .optical_depth import shell_segment, sun_transmittance, view_transmittance


@dataclass
class ReferenceResult:
    """Radiance (N, W) [1/sr per unit solar irradiance], its standard error, the view transmittance."""

    radiance: np.ndarray
    stderr: np.ndarray
    transmittance: np.ndarray
    samples: int


def solve(atm, camera, view_dir, sun_dir, samples: int = 1024, seed: int = 0,
          max_order: int | None = None, batch_paths: int = 262144) -> ReferenceResult:
    """Monte Carlo radiance for N rays (camera (N, 3) [m], view_dir (N, 3), sun_dir (N, 3) or (3,)).

    Example
    -------
    >>> import numpy as np
    >>> from planetviz import load_atmosphere
    >>> from planetviz.reference import solve
    >>> atm = load_atmosphere("earth")
    >>> res = solve(atm, [[0, 0, 6360001.0]], [[0, 0, 1.0]], [0, 0.5, 0.866], samples=256)
    >>> res.radiance.shape
    (1, 3)
    """
    camera = np.atleast_2d(np.asarray(camera, dtype=float))
    view = np.atleast_2d(np.asarray(view_dir, dtype=float))
    view = view / np.linalg.norm(view, axis=-1, keepdims=True)
    sun = np.broadcast_to(np.asarray(sun_dir, dtype=float), camera.shape)
    sun = sun / np.linalg.norm(sun, axis=-1, keepdims=True)
    n = len(camera)
    rng = np.random.default_rng(seed)
    mean = np.zeros((n, atm.n_wavelengths))
    err = np.zeros_like(mean)
    per_batch = max(1, batch_paths // samples)
    for w in range(atm.n_wavelengths):
        for lo in range(0, n, per_batch):
            q = np.arange(lo, min(n, lo + per_batch))
            rep = np.repeat(q, samples)
            contrib = _trace(atm, w, camera[rep], view[rep], sun[rep], rng, max_order)
            contrib = contrib.reshape(len(q), samples)
            mean[q, w] = contrib.mean(axis=1)
            err[q, w] = contrib.std(axis=1, ddof=1) / np.sqrt(samples) if samples > 1 else np.inf
    transmittance, _ = view_transmittance(atm, camera, view)
    return ReferenceResult(mean, err, transmittance, samples)


def _onb_rotate(d, cos_theta, phi):
    """Directions at polar angle acos(cos_theta), azimuth phi around the unit vectors d."""
    x, y, z = d[:, 0], d[:, 1], d[:, 2]
    sign = np.where(z >= 0.0, 1.0, -1.0)
    a = -1.0 / (sign + z)
    b = x * y * a
    t1 = np.stack([1.0 + sign * x * x * a, sign * b, -sign * x], axis=1)
    t2 = np.stack([b, sign + y * y * a, -y], axis=1)
    sin_theta = np.sqrt(np.maximum(0.0, 1.0 - cos_theta * cos_theta))
    out = (sin_theta * np.cos(phi))[:, None] * t1 + (sin_theta * np.sin(phi))[:, None] * t2 \
        + cos_theta[:, None] * d
    return out / np.linalg.norm(out, axis=1, keepdims=True)


def _sample_phase(atm, w, b_r, b_m, rng):
    """cos(theta) between the old and new tracing directions, drawn from the local phase mixture."""
    m = len(b_r)
    u = rng.random(m)
    use_mie = rng.random(m) * (b_r + b_m) < b_m
    cos = np.empty(m)
    a = 1.0 if atm.rayleigh.phase == "rayleigh" else PENNDORF_A
    cos[~use_mie] = sample_rayleigh_like(u[~use_mie], a)
    k = int(use_mie.sum())
    if k:
        lobe1 = rng.random(k) < atm.mie.alpha[w]
        g = np.where(lobe1, atm.mie.g1[w], atm.mie.g2[w])
        cos[use_mie] = sample_henyey_greenstein(u[use_mie], g)
    return cos


_GL4_X, _GL4_W = np.polynomial.legendre.leggauss(4)
_SEGMENT_INTERVALS = 64


def segment_optical_depth(atm, w, p, d, length):
    """(node distances (P, K+1), cumulative tau at the nodes (P, K+1)) along p + t d, t in [0, length].

    Nodes are uniform in s = sign(t - t_c) sqrt|t - t_c| (t_c: the point of closest approach, where
    grazing rays meet the densest air; 0 for rays going up); each interval by 4-point Gauss-Legendre.
    """
    tc = np.clip(-np.einsum("ij,ij->i", p, d), 0.0, length)[:, None]
    s = np.linspace(0.0, 1.0, _SEGMENT_INTERVALS + 1)
    s = -np.sqrt(tc) + (np.sqrt(tc) + np.sqrt(length[:, None] - tc)) * s
    t = tc + np.sign(s) * s * s                                       # (P, K+1), dense at t_c
    a, b = t[:, :-1], t[:, 1:]
    mid, rad = 0.5 * (a + b), 0.5 * (b - a)
    tq = mid[..., None] + rad[..., None] * _GL4_X                   # (P, K, 4)
    pts = p[:, None, None, :] + tq[..., None] * d[:, None, None, :]
    h = np.linalg.norm(pts, axis=-1) - atm.bottom_radius_m
    sig = atm.extinction(h, w)[..., 0]
    dtau = rad * (sig * _GL4_W).sum(-1)
    tau = np.concatenate([np.zeros((len(p), 1)), np.cumsum(dtau, axis=1)], axis=1)
    return t, tau


def _sample_in_segment(t, tau, target):
    """Distance where the piecewise-linear tau(t) reaches ``target`` (< tau[-1]), and sigma there."""
    k = np.array([np.searchsorted(row, x, side="right") - 1 for row, x in zip(tau, target)])
    k = np.clip(k, 0, t.shape[1] - 2)
    rows = np.arange(len(t))
    dt = t[rows, k + 1] - t[rows, k]
    dtau = tau[rows, k + 1] - tau[rows, k]
    sigma = np.where(dt > 0, dtau / np.where(dt > 0, dt, 1.0), 0.0)
    frac = np.where(dtau > 0, (target - tau[rows, k]) / np.where(dtau > 0, dtau, 1.0), 0.0)
    return t[rows, k] + frac * dt, sigma


def _trace(atm, w, origin, direction, sun, rng, max_order):
    """Contribution of one backward path per row, for wavelength index ``w``."""
    p_count = len(origin)
    radiance = np.zeros(p_count)
    start, end = shell_segment(origin, direction, atm.top_radius_m)
    pos = origin + start[:, None] * direction
    d = direction.copy()
    weight = np.ones(p_count)
    order = np.zeros(p_count, dtype=np.int64)
    idx = np.nonzero(end > start)[0]
    albedo = float(atm.ground_albedo[w])
    r_bottom, r_top = atm.bottom_radius_m, atm.top_radius_m
    limit = np.iinfo(np.int64).max if max_order is None else max_order
    while idx.size:
        p, dd = pos[idx], d[idx]
        t_ground = distance_to_ground(p, dd, r_bottom)
        t_top = distance_to_top_exit(p, dd, r_top)
        ground = np.isfinite(t_ground) & (t_ground <= t_top)
        length = np.where(ground, t_ground, t_top)
        nodes, tau = segment_optical_depth(atm, w, p, dd, length)
        trans = np.exp(-tau[:, -1])
        absorbed = 1.0 - trans
        p_collide = np.where(ground, np.maximum(absorbed, 0.5), 1.0)
        p_collide = np.where(absorbed > 0.0, p_collide, 0.0)
        collide = rng.random(idx.size) < p_collide
        alive = np.ones(idx.size, dtype=bool)

        # ---- forced collision inside the segment
        if np.any(collide):
            ci = np.nonzero(collide)[0]
            g = idx[ci]
            target = -np.log1p(-rng.random(ci.size) * absorbed[ci])
            t, sig_tilde = _sample_in_segment(nodes[ci], tau[ci], target)
            x = p[ci] + t[:, None] * dd[ci]
            pos[g] = x
            h = np.linalg.norm(x, axis=1) - r_bottom
            sig_t = atm.extinction(h, w)[:, 0]
            b_r, b_m = atm.scattering(h)
            b_r, b_m = b_r[:, w], b_m[:, w]
            b_s = b_r + b_m
            ratio = np.where(sig_tilde > 0, sig_t / np.where(sig_tilde > 0, sig_tilde, 1.0), 0.0)
            weight[g] *= absorbed[ci] / p_collide[ci] * ratio * np.where(sig_t > 0, b_s / np.where(sig_t > 0, sig_t, 1.0), 0.0)
            order[g] += 1
            scat = b_s > 0.0
            contrib = scat & (order[g] <= limit)
            if np.any(contrib):
                gc = g[contrib]
                nu = np.einsum("ij,ij->i", d[gc], sun[gc])
                phase = (b_r[contrib] * atm.rayleigh.phase_function(nu)
                         + b_m[contrib] * atm.mie.phase_function(nu)[:, w]) / b_s[contrib]
                t_sun = sun_transmittance(atm, pos[gc], sun[gc], index=w)[:, 0]
                radiance[gc] += weight[gc] * phase * t_sun
            weight[g[~scat]] = 0.0
            if np.any(scat):
                gs = g[scat]
                cos = _sample_phase(atm, w, b_r[scat], b_m[scat], rng)
                d[gs] = _onb_rotate(d[gs], cos, 2.0 * np.pi * rng.random(gs.size))

        # ---- no collision: the ground reflects, the top lets the path escape
        bi = np.nonzero(~collide)[0]
        if bi.size:
            alive[bi[~ground[bi]]] = False
            gi = bi[ground[bi]]
            if gi.size:
                g = idx[gi]
                x = p[gi] + t_ground[gi, None] * dd[gi]
                normal = x / np.linalg.norm(x, axis=1, keepdims=True)
                pos[g] = normal * r_bottom
                weight[g] *= trans[gi] / (1.0 - p_collide[gi])
                order[g] += 1
                cos_s = np.maximum(np.einsum("ij,ij->i", normal, sun[g]), 0.0)
                contrib = (order[g] <= limit) & (cos_s > 0.0) & (albedo > 0.0)
                if np.any(contrib):
                    gc = g[contrib]
                    t_sun = sun_transmittance(atm, pos[gc], sun[gc], index=w)[:, 0]
                    radiance[gc] += weight[gc] * albedo / np.pi * cos_s[contrib] * t_sun
                weight[g] *= albedo
                u = rng.random(g.size)
                d[g] = _onb_rotate(normal, np.sqrt(u), 2.0 * np.pi * rng.random(g.size))

        # ---- termination: order limit, zero weight, Russian roulette past the third event
        gidx = idx
        alive &= (order[gidx] < limit) & (weight[gidx] > 0.0)
        rr = alive & (order[gidx] >= 3)
        if np.any(rr):
            q = np.clip(weight[gidx[rr]], 0.05, 1.0)
            survive = rng.random(q.size) < q
            weight[gidx[rr]] /= q
            alive[np.nonzero(rr)[0][~survive]] = False
        idx = idx[alive]
    return radiance
