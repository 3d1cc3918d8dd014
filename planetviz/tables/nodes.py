"""Where the precompute evaluates: texel centres, the 4D scattering grid and the quadrature nodes along rays.

Shared by the single-scattering stage (tables/precompute.py), the multiple-scattering stage
(tables/multiple.py) and the evaluator's quadratures near the ground and the horizon (tables/near_ground.py,
tables/horizon.py). Distances in metres; directions as (r, mu) with mu the cosine of the view zenith angle.
"""
from __future__ import annotations

import functools

import numpy as np

from .parameterization import (distance_to_bottom_atmosphere_boundary, distance_to_top_atmosphere_boundary,
                               r_mu_mu_s_nu_from_scattering_uvwz, texcoord_from_unit_range, x_r_from_rho)

#: How many times the nodes rays longer than the ground's horizontal ray get (``single_scattering`` and the
#: multiple-scattering stage, ``multiple._ray_paths``).
LONG_RAY_NODE_FACTOR = 2


def is_optically_thick(atm) -> bool:
    """Whether the vertical optical depth exceeds 1 at some wavelength: the light then comes from the first
    attenuation lengths of a ray, and the radiance changes with altitude within a few of the tables' rows."""
    return bool(np.max(atm.vertical_optical_depth()) > 1.0)


def texel_centres(n):
    """Texel centres (i + 1/2) / n of n texels on [0, 1]."""
    return (np.arange(n) + 0.5) / n


@functools.lru_cache(maxsize=None)
def gauss_legendre_unit(n):
    """Gauss-Legendre nodes and weights of order n on [0, 1]."""
    x, w = np.polynomial.legendre.leggauss(n)
    return 0.5 * (x + 1.0), 0.5 * w


def ray_nodes(r, mu, d, n, start=0.0, ascending=False):
    """Quadrature nodes t (..., 2n) and weights on [start, d] along (r, mu), clustered at the closest approach.

    Gauss-Legendre with t = t_c -+ span u^2 on each side of the closest approach t_c (clamped to the segment);
    where t_c is an end of the segment (rays going up, or reaching the ground before their closest approach)
    all 2n nodes go to the one side there is. ``ascending``: the nodes in the order of t along every ray (the
    same nodes and weights; by default each side runs outward from t_c).
    """
    u, wu = gauss_legendre_unit(n)
    u2, wu2 = gauss_legendre_unit(2 * n)
    s = np.asarray(start, dtype=float)
    dd = np.asarray(d, dtype=float)[..., None]
    tc = np.clip(-r * mu, s, d)[..., None]
    s = s[..., None]
    before = tc - (tc - s) * u * u                # t from t_c down to start
    after = tc + (dd - tc) * u * u                # t from t_c up to d
    wb = 2.0 * (tc - s) * u * wu
    wa = 2.0 * (dd - tc) * u * wu
    span = dd - s
    up, w_up = s + span * u2 * u2, 2.0 * span * u2 * wu2          # all at one side: from start up
    down, w_down = dd - span * u2 * u2, w_up                       # or from d down
    if ascending:
        before, wb, down, w_down = before[..., ::-1], wb[..., ::-1], down[..., ::-1], w_up[..., ::-1]
    t, wt = np.concatenate([before, after], -1), np.concatenate([wb, wa], -1)
    t = np.where(tc <= s, up, np.where(tc >= dd, down, t))
    wt = np.where(tc <= s, w_up, np.where(tc >= dd, w_down, wt))
    return t, wt


def split_ray_nodes(atm, r, mu, d, n, depth=3.0, fine=64, thick=False):
    """:func:`ray_nodes` on three segments of the ray (:func:`split_distances`), five where ``thick``: (..., 4n) or
    (..., 6n) nodes and weights, n per side on the first segment and n // 2 (at least 1) on each other.

    For optically thick atmospheres, where the in-scattered light comes from the first attenuation lengths
    (a few hundred metres at tau = 4) while the more transparent wavelengths see tens of kilometres: one
    Gauss-Legendre rule over the whole ray puts its first nodes kilometres apart. The first segment ends where the
    most extinguished wavelength's optical depth reaches ``depth`` (t_a). A segment then holds the least
    extinguished wavelength's next attenuation lengths (to t_b), so that they do not lie on one that runs to the
    end of a long ray: without it random atmosphere 4's sky at 550 nm computed with its 680 and 440 nm channels
    read 1.0% below the same sky computed alone (tests/test_tables_disort.py). Where ``thick`` (every ray then
    split, its first segment a few hundred metres long) two more end at t_m and t_c: the most extinguished
    wavelength's next attenuation lengths (its light beyond t_a: e^-3, 5%) and the least extinguished one's after
    t_b. On random atmosphere 100807's plane-parallel twin with 4 nodes per side, the light each ray takes out of
    the beam (int beta T dt = 1 - T(d), tests/test_multiple_scattering.py) reads 1.5% / 0.52% / 1.0% RMS off at
    680 / 550 / 440 nm on three segments, 0.19% / 0.10% / 0.11% on five; in the Earth's atmosphere the two change no
    texel's error against 16 nodes per side (0.23% RMS either way; benchmarks/extinguished_light.py --tables
    earth), so the split rays of thin atmospheres keep three segments.
    """
    r, mu, d = np.broadcast_arrays(np.asarray(r, float), np.asarray(mu, float), np.asarray(d, float))
    t_a, t_m, t_b, t_c = split_distances(atm, r, mu, d, depth, fine)
    inner = (t_a,) + tuple(np.sort([t_m, t_b, t_c], axis=0)) if thick else (t_a, t_b)
    ends = (np.zeros_like(d),) + inner + (d,)
    t, w = [], []
    for k in range(len(ends) - 1):
        start, length = ends[k], ends[k + 1] - ends[k]
        r_s = np.sqrt(np.maximum(start * start + 2.0 * r * mu * start + r * r, 0.0))
        mu_s = np.clip((r * mu + start) / np.maximum(r_s, 1e-300), -1.0, 1.0)
        t_k, w_k = ray_nodes(r_s, mu_s, length, n if k == 0 else max(n // 2, 1))
        t.append(start[..., None] + t_k)
        w.append(w_k)
    return np.concatenate(t, -1), np.concatenate(w, -1)


def split_distances(atm, r, mu, d, depth=3.0, fine=64):
    """(t_a, t_m, t_b, t_c) [m] along the rays (r, mu) of length d: t_a and t_m where the optical depth of the most
    extinguished wavelength reaches ``depth`` and twice ``depth``; t_b and t_c where that of the least
    extinguished one (the smallest over the ray) has grown past its value at t_a by ``depth`` and twice
    ``depth`` or, if sooner, by a half and three quarters of what is left of it up to d (d where nothing is
    reached); the nodes of :func:`ray_nodes` (``fine`` per side) where the sums over the nodes first reach them.
    From t_a on, t_m bounds the most extinguished wavelength's next attenuation lengths and t_b, t_c the least
    extinguished one's, or its light beyond t_a where it crosses less than twice ``depth`` there."""
    r, mu, d = np.broadcast_arrays(np.asarray(r, float), np.asarray(mu, float), np.asarray(d, float))
    out = np.empty((4,) + d.shape)
    flat = out.reshape(4, -1)
    rays = [a.ravel() for a in (r, mu, d)]
    # in chunks of SPLIT_CHUNK rays: the fine nodes' optical depths, (rays, 2 fine, W), stay a few megabytes
    for start in range(0, d.size, SPLIT_CHUNK):
        part = slice(start, start + SPLIT_CHUNK)
        flat[:, part] = _split_distances(atm, *(a[part] for a in rays), depth, fine)
    return tuple(out)


#: Rays per chunk of :func:`split_distances`.
SPLIT_CHUNK = 4096


def _split_distances(atm, r, mu, d, depth, fine):
    """:func:`split_distances` of the rays (n,): (4, n)."""
    tf, wf = ray_nodes(r, mu, d, fine)
    order = np.argsort(tf, -1)
    tf, wf = np.take_along_axis(tf, order, -1), np.take_along_axis(wf, order, -1)
    beta = atm.extinction(altitude(r[..., None], mu[..., None], tf, atm.bottom_radius_m))      # (..., K, W)
    tau = np.cumsum(beta * wf[..., None], -2)
    last = tf.shape[-1] - 1
    most = tau.max(-1)
    a, m = (np.where(most[..., -1] >= x, np.argmax(most >= x, -1), last) for x in (depth, 2.0 * depth))
    least = np.take_along_axis(tau, np.argmin(tau[..., -1, :], -1)[..., None, None], -1)[..., 0]     # (..., K)
    at_a = np.take_along_axis(least, a[..., None], -1)[..., 0]
    b, c = (np.maximum(np.argmax(least >= (at_a + np.minimum(x * depth, share * (least[..., -1] - at_a)))[..., None],
                                 -1), a) for x, share in ((1.0, 0.5), (2.0, 0.75)))
    at = lambda i: np.where(i < last, np.take_along_axis(tf, i[..., None], -1)[..., 0], d)
    return np.stack([at(a), at(m), at(b), at(c)])


def depth_distance(atm, r, mu, d, depth=3.0, fine=64):
    """The distance [m] along the rays (r, mu) of length d at which the optical depth of the most extinguished
    wavelength reaches ``depth`` (d where it does not): :func:`split_distances`' first."""
    return split_distances(atm, r, mu, d, depth, fine)[0]


def altitude(r, mu, t, bottom):
    """Altitude [m] of the point at distance t [m] along the ray (r, mu) above a ground of radius ``bottom``."""
    return np.sqrt(np.maximum(t * t + 2.0 * r * mu * t + r * r, 0.0)) - bottom


def scattering_share(atm, r, mu, d, n, wavelengths=None):
    """(N, W') the share of the opacity of each ray (r, mu) of length d [m] that scatters light back into it:
    sum_k omega(t_k) [T(0, t_k^-) - T(0, t_k^+)] / (1 - T(0, d)), over the cells of the quadrature nodes t_k
    (:func:`ray_nodes`, n per side of the closest approach, in the order of t), omega = beta^scat / beta^ext at the
    node, T from the optical depth summed over the cells before. The single scattering of a uniform, isotropic source
    along the ray, integral of beta^scat T dt, is this share times the opacity 1 - T, exactly so where omega is the
    same over each cell whatever their optical depths (1 where nothing absorbs); an absorbing layer (ozone) lowers
    it for the rays through it and leaves the rays in front of it alone. ``wavelengths``: a slice of the
    atmosphere's wavelengths (W' of them; default all)."""
    wavelengths = slice(None) if wavelengths is None else wavelengths
    t, w = ray_nodes(r, mu, d, n, ascending=True)
    h = altitude(np.asarray(r, float)[..., None], np.asarray(mu, float)[..., None], t, atm.bottom_radius_m)
    components = atm.components()
    density = np.stack([profile.density(h) for _, _, profile in components], axis=-1)       # (N, K, C)
    extinction = density @ np.stack([beta_ext[wavelengths] for _, beta_ext, _ in components])  # (N, K, W')
    scattering = density @ np.stack([beta_scat[wavelengths] for beta_scat, _, _ in components])
    tau = np.cumsum(w[..., None] * extinction, axis=-2)                     # through each cell
    transmittance = np.exp(-tau)
    before = np.concatenate([np.ones_like(transmittance[..., :1, :]), transmittance[..., :-1, :]], axis=-2)
    albedo = scattering / np.maximum(extinction, 1e-300)
    opacity = 1.0 - transmittance[..., -1, :]
    # Below an opacity of 1e-4 the cells' transmittance steps lose digits; there the share is the albedo weighted
    # by optical depth, its limit, to O(opacity).
    thin = np.einsum("...k,...kw->...w", w, scattering) / np.maximum(tau[..., -1, :], 1e-300)
    thick = np.einsum("...kw,...kw->...w", albedo, before - transmittance) / np.maximum(opacity, 1e-300)
    return np.where(opacity > 1e-4, thick, np.where(tau[..., -1, :] > 0.0, thin, albedo[..., 0, :]))


def scattering_grid(tables, size=None):
    """(r, mu, mu_s, nu, intersects_ground) at the texel centres, each (n_r, n_mu, n_nu, n_mu_s), of a table
    of ``size`` (default ``tables.sizes.scattering``) between ``tables.bottom`` and ``tables.top``."""
    size = tables.sizes.scattering if size is None else size
    n_nu, n_mu_s, n_mu, n_r = size
    u_r = texel_centres(n_r)[:, None, None, None]
    u_mu = texel_centres(n_mu)[None, :, None, None]
    u_nu = (np.arange(n_nu) / max(n_nu - 1, 1))[None, None, :, None]
    u_mu_s = texel_centres(n_mu_s)[None, None, None, :]
    shape = (n_r, n_mu, n_nu, n_mu_s)
    out = r_mu_mu_s_nu_from_scattering_uvwz(u_nu, u_mu_s, u_mu, u_r, tables.bottom, tables.top, size, tables.r_axis)
    return tuple(np.ascontiguousarray(np.broadcast_to(a, shape)) for a in out)     # r and mu per (r, mu) only


#: The length of the rays that stand in for the tables' rays of zero length, as a fraction of the atmosphere's
#: thickness (``integration_grid``; ``precompute.optical_depth_to_top``).
ZERO_RAY_LENGTH = 1e-4


def integration_grid(tables, size=None):
    """(r, mu, mu_s, nu, intersects_ground, d) of the rays the stages integrate for a 4D table of ``size``: the
    texel centres of :func:`scattering_grid` and each ray's length d to the ground or the top, except the top
    row's sky texels whose ray has zero length (next to the zenith), which are integrated from the same texture
    coordinates (u_nu, u_mu_s, u_mu) of a row ``ZERO_RAY_LENGTH`` times the thickness under the top: the sky
    half of the tables holds S over the ray's scattering opacity (``lookup.ray_opacity``), which for those texels
    is the limit 0 / 0, the source function at the top, and those rays give it. (The ground row's ground rays, of
    zero length too, hold S = 0: the ground half is not divided.)"""
    size = tables.sizes.scattering if size is None else size
    n_nu, n_mu_s, n_mu, n_r = size
    r, mu, mu_s, nu, ground = (np.array(a) for a in scattering_grid(tables, size))
    d = _length(r, mu, ground, tables.bottom, tables.top)
    h = np.sqrt(tables.top ** 2 - tables.bottom ** 2)
    radius = tables.top - ZERO_RAY_LENGTH * (tables.top - tables.bottom)
    row = n_r - 1
    zero = (d[row] == 0.0) & ~ground[row]
    if np.any(zero):
        u_r = texcoord_from_unit_range(x_r_from_rho(np.sqrt(radius ** 2 - tables.bottom ** 2), h, tables.r_axis), n_r)
        u_mu = np.broadcast_to(texel_centres(n_mu)[:, None, None], zero.shape)[zero]
        u_nu = np.broadcast_to((np.arange(n_nu) / max(n_nu - 1, 1))[None, :, None], zero.shape)[zero]
        u_mu_s = np.broadcast_to(texel_centres(n_mu_s)[None, None, :], zero.shape)[zero]
        sub = r_mu_mu_s_nu_from_scattering_uvwz(u_nu, u_mu_s, u_mu, u_r, tables.bottom, tables.top, size,
                                                tables.r_axis)
        for array, value in zip((r, mu, mu_s, nu, ground), sub):
            array[row][zero] = value
        d[row][zero] = _length(sub[0], sub[1], sub[4], tables.bottom, tables.top)
    return r, mu, mu_s, nu, ground, d


def _length(r, mu, ground, bottom, top):
    """The distance along (r, mu) to the ground (``ground``) or the top."""
    return np.where(ground, distance_to_bottom_atmosphere_boundary(r, mu, bottom),
                    distance_to_top_atmosphere_boundary(r, mu, top))
