"""Reading the tables: transmittance, irradiance and scattering lookups (GLSL functions of the same names).

``t`` is a :class:`~planetviz.tables.precompute.Tables`; every lookup returns (..., W).
"""
from __future__ import annotations

import numpy as np

from .parameterization import (density_uvwz_from_r_mu_mu_s_nu, distance_coordinate, distance_from_coordinate,
                               distance_to_bottom_atmosphere_boundary, distance_to_top_atmosphere_boundary,
                               distance_warp, irradiance_uv_from_r_mu_s,
                               ray_intersects_ground, rho_from_x_r, safe_sqrt, scattering_uvwz_from_r_mu_mu_s_nu,
                               texcoord_from_unit_range, transmittance_uv_from_r_mu, VIEW_ANGLE_OFFSET,
                               x_mu_s_from_mu_s, x_r_from_rho)
from .sampling import texel_axis
from .sampling import texture2d

#: The least a zero texel counts for in :func:`geometric_blend`, relative to its lit neighbour.
ZERO_FLOOR = 1e-3
#: Values are raised to this before their logarithm (the smallest normal float32 is 1.2e-38).
SMALLEST = 1e-37
#: A ray whose scattering opacity (``ray_opacity``) is below this is empty: the multiple-scattering tables'
#: mean is 0 there.
EMPTY_RAY_OPACITY = 1e-30


def get_optical_depth_to_top_atmosphere_boundary(t, r, mu):
    """tau between (r, mu) and the top of the atmosphere (the ray must not hit the ground): the table's mean
    extinction along the ray, tau / d, times the ray's length d.

    Why the mean: next to the top of the atmosphere tau goes to 0 with d, like the column of air above the
    camera, a convex function of the altitude that linear interpolation between the table's rows (1.9 km
    apart under the Earth's top at standard) overestimates: a table of tau itself read 10-11% high from 1-100 m
    under the top looking up (64 deg above the horizontal), the mean within 0.08% (benchmarks/top_rows.py,
    against the reference quadrature); tau / d is smooth there and tends to the extinction at the top."""
    n_r, n_mu = t.optical_depth.shape[:2]
    u, v = transmittance_uv_from_r_mu(r, mu, t.bottom, t.top, (n_mu, n_r))
    d = distance_to_top_atmosphere_boundary(np.asarray(r, float), np.asarray(mu, float), t.top)
    return texture2d(t.optical_depth, u, v) * d[..., None]


def get_transmittance_to_top_atmosphere_boundary(t, r, mu):
    """T between (r, mu) and the top of the atmosphere (the ray must not hit the ground)."""
    return np.exp(-get_optical_depth_to_top_atmosphere_boundary(t, r, mu))


def get_optical_depth(t, r, mu, d):
    """tau between (r, mu) and the point at distance d along the ray (Bruneton's ratio of two transmittances,
    taken in the log so that it survives thick atmospheres), from lookups of rays that point up only (below).

    The ray descends to its lowest point at d_l = -r mu (mu < 0) and climbs after it. On the descending part the
    reversed ray is read: tau(r_d, -mu_d) - tau(r, -mu) (this holds every ray toward the ground). Past the lowest
    point, at r_l = r sqrt(1 - mu^2): tau(r_l, 0) - tau(r, -mu) to it, plus tau(r_l, 0) - tau(r_d, mu_d) from it.
    Rays up (mu >= 0): tau(r, mu) - tau(r_d, mu_d).

    Why up only: each term then follows one ray up (or the reversed ray), whose readings move smoothly across
    the table's upward half, and the difference of two readings of one ray only takes in more of it as d grows.
    Bruneton's form for rays that pass their lowest point, tau(r, mu) - tau(r_d, mu_d) with mu < 0, reads
    downward rays next to the horizon, where the table changes fastest, and T rose along such rays by up to 0.4%
    (draft tables; 0.15% standard). With this form: no rise over 3000 rays x 200 points (Earth, draft and
    standard), nor in Mars or the edge atmospheres of tests/test_stability.py, except 10 m scale heights, where
    interpolating across rows 240 m apart reads up to 1.5e-3 of optical depth that is not there (Bruneton's
    form alike; docs/stability.md), and rays a fraction of a degree below the horizon from within a metre of the
    ground, whose last step to the ground can rise by a few 1e-5 (the two readings are of grazing rays with
    optical depths of 10-40 that differ by the segment's few 1e-3), within the tables' own error there. The GLSL
    twin carries the descending branch only: every segment the shaders read ends on the ground.
    """
    r, mu, d = np.broadcast_arrays(np.asarray(r, float), np.asarray(mu, float), np.asarray(d, float))
    r_d = np.sqrt(np.maximum(d * d + 2.0 * r * mu * d + r * r, 0.0))
    r_d = np.clip(r_d, t.bottom, t.top)
    mu_d = np.clip((r * mu + d) / r_d, -1.0, 1.0)
    descending = (mu < 0.0) & (d <= -r * mu)
    past = (mu < 0.0) & ~descending
    r_l = np.clip(r * np.sqrt(np.maximum(1.0 - mu * mu, 0.0)), t.bottom, t.top)
    top = get_optical_depth_to_top_atmosphere_boundary
    tau_near = top(t, np.where(descending, r_d, np.where(past, r_l, r)), np.where(descending, -mu_d,
                                                                             np.where(past, 0.0, mu)))
    tau_far = top(t, np.where(descending, r, r_d), np.where(descending, -mu, np.maximum(mu_d, 0.0)))
    tau = np.maximum(tau_near - tau_far, 0.0)
    if np.any(past):
        to_lowest = tau_near[past] - top(t, r[past], -mu[past])      # tau_near holds tau(r_l, 0) there
        tau[past] += np.maximum(to_lowest, 0.0)
    return tau


def get_transmittance(t, r, mu, d):
    """T between (r, mu) and the point at distance d along the ray: exp(-:func:`get_optical_depth`)."""
    return np.exp(-get_optical_depth(t, r, mu, d))


def one_minus_exp(x):
    """1 - exp(-x) for x >= 0, without cancellation for small x (the GLSL twin: its Taylor series below 1e-2)."""
    return -np.expm1(-x)


def ray_opacity(t, r, mu, intersects_ground):
    """The scattering opacity (..., W) of rays (r, mu) that leave through the top of the atmosphere,
    int_0^d beta^scat T dt = s (1 - T) with T their transmittance to the top and s the share of 1 - T that
    scatters (``Tables.scattering_share``, ``precompute.scattering_share_to_top``: on the optical-depth table's grid,
    read at the same texture coordinates); 1 for rays that hit the ground: what the 4D scattering tables are
    divided by at their texels and multiplied by again on every read (:func:`get_scattering`,
    :class:`ScatteringStencil`; the GLSL twin of the same name). Dimensionless.

    In-scattered light along a ray is S = int J T dt = int (J / beta^scat) beta^scat T dt, so the sky half of the
    tables holds <J / beta^scat>, the source function per unit scattering coefficient (the phase-weighted
    radiance arriving at the scattering points) averaged along the ray with the weights beta^scat T dt, which
    changes slowly with the ray, while S itself follows the ray's length and optical depth. Next to the top of
    the atmosphere S goes to 0 with the column of air above the camera, a convex fall that linear interpolation
    between r rows 3.8 km apart (the Earth's single scattering at standard; 17 km for its multiple scattering)
    read 26-29% high from 1-100 m under the top looking up, and 19-24% high looking horizontally, where the
    texels at the same u_mu of the two rows hold rays of other lengths (``benchmarks/top_rows.py``, single
    scattering against the reference quadrature): within 0.2% with the mean. The weights are the scattering's,
    not the extinction's (1 - T = int beta T dt): inside an absorbing layer the mean over the extinction is the
    single-scattering albedo times the light, above it the light, and rows on either side of the layer's edge
    (the Earth's ozone at 24 and 37 km, the standard multiple-scattering rows) held values that differ by the
    albedo, which linear interpolation between them read up to 22% off from 30-40 km; the mean over the
    scattering is the light on both sides (docs/tables.md).

    Ground rays keep S (and :func:`ground_row_factor` for cameras below the first row): their 1 - T for short
    rays from near the ground is the difference of two readings of long upward rays at rows of very different
    altitude spacing (the rows are dense near the ground), off by several times its value 0.2 m up."""
    r, mu, ground = np.broadcast_arrays(np.asarray(r, float), np.asarray(mu, float), np.asarray(intersects_ground))
    mu_sky = np.where(ground, 0.0, mu)
    n_r, n_mu = t.optical_depth.shape[:2]
    u, v = transmittance_uv_from_r_mu(r, mu_sky, t.bottom, t.top, (n_mu, n_r))
    tau = texture2d(t.optical_depth, u, v) * distance_to_top_atmosphere_boundary(r, mu_sky, t.top)[..., None]
    return np.where(ground[..., None], 1.0, texture2d(t.scattering_share, u, v) * one_minus_exp(tau))


def first_row_rho(t, n_r):
    """rho [m] of the first row above the ground of a 4D table of ``n_r`` rows (the shaders' multiple_row_1_rho)."""
    return float(rho_from_x_r(1.0 / (n_r - 1), np.sqrt(t.top * t.top - t.bottom * t.bottom), t.r_axis))


def ground_row_factor(t, r, mu, intersects_ground, n_r):
    """(..., W) factor on what :func:`get_scattering` reads from a 4D table of ``n_r`` rows at (r, mu) (every
    reader of the multiple-scattering tables applies it: the evaluator, the shaders' get_phased_scattering, the
    precompute's reads of each order, the compact tables; the last also to the single-scattering tables, which
    the others replace there by near_ground.py's quadrature): for ground rays from
    below the table's first row above the ground, the correction of the linear interpolation between the ground
    row and that row; 1 for every other ray ((..., 1) where no ray needs it).

    The ground row's ground rays have zero length and hold 0, so interpolating in u_r reads f S_1, f the
    camera's fraction of the way to row 1 and S_1 the in-scattering of row 1's ray at the same u_mu: as if
    in-scattering grew in proportion to the ray's length f. It saturates instead, S = (J / beta) (1 - T) for a
    source function J / beta that is about the same along both rays (both lie within one row spacing of the
    ground). With k = d / d_1 the ratio of the two rays' lengths and tau_1 row 1's optical depth (the same mean
    extinction along both rays): S = S_1 (1 - exp(-k tau_1)) / (1 - exp(-tau_1)), so the factor on f S_1 is
    (1 - exp(-k tau_1)) / (f (1 - exp(-tau_1))), k / f where tau_1 = 0 (which also makes straight-down rays,
    whose length goes as f^2, right). Without it a camera 2 m up read single scattering just below the horizon
    25% off with standard tables (46% draft); with it 2.4% (5.9%), and 0.1% (0.4%) by near_ground.py's
    quadrature (the seam test, docs/stability.md).
    """
    r, mu = np.broadcast_arrays(np.asarray(r, float), np.asarray(mu, float))
    h = np.sqrt(t.top * t.top - t.bottom * t.bottom)
    rho = np.sqrt(np.maximum(r * r - t.bottom * t.bottom, 0.0))
    f = x_r_from_rho(rho, h, t.r_axis) * (n_r - 1)
    sel = np.asarray(intersects_ground) & (f > 0.0) & (f < 1.0)
    if not np.any(sel):
        return np.ones(r.shape + (1,))
    factor = np.ones(r.shape + (t.optical_depth.shape[-1],))
    r, mu, rho, f = r[sel], mu[sel], rho[sel], f[sel]
    a = r - t.bottom
    d = distance_to_bottom_atmosphere_boundary(r, mu, t.bottom)
    x = distance_coordinate(d, a, rho, distance_warp(r, t.bottom, t.top, True), VIEW_ANGLE_OFFSET)
    rho_1 = first_row_rho(t, n_r)
    r_1 = np.sqrt(rho_1 * rho_1 + t.bottom * t.bottom)
    a_1 = rho_1 * rho_1 / (r_1 + t.bottom)
    d_1 = distance_from_coordinate(x, a_1, rho_1, distance_warp(r_1, t.bottom, t.top, True), VIEW_ANGLE_OFFSET)
    mu_1 = np.clip(-(rho_1 * rho_1 + d_1 * d_1) / (2.0 * r_1 * d_1), -1.0, 1.0)
    tau_1 = get_optical_depth(t, np.full_like(r, r_1), mu_1, d_1)
    k = (d / d_1)[:, None]
    den = one_minus_exp(tau_1)
    ratio = np.where(tau_1 > 0.0, one_minus_exp(k * tau_1) / np.where(tau_1 > 0.0, den, 1.0), k)
    factor[sel] = ratio / f[:, None]
    return factor


def get_transmittance_to_sun(t, r, mu_s):
    """T toward a point sun: 0 when the planet hides it.

    Where r broadcasts against many more suns than the table is wide (the precompute's single scattering: one
    radius per quadrature node, every (mu_s, nu) of the 4D grid), the table is interpolated along r once per
    radius and then along mu per sun: the same bilinear lookup, in float32 as the table is."""
    r, mu_s = np.asarray(r, float), np.asarray(mu_s, float)
    shape = np.broadcast_shapes(r.shape, mu_s.shape)
    n_r, n_mu = t.optical_depth.shape[:2]
    if 4 * r.size >= np.prod(shape, dtype=np.int64):
        return np.where(ray_intersects_ground(r, mu_s, t.bottom)[..., None], 0.0,
                        get_transmittance_to_top_atmosphere_boundary(t, r, mu_s))
    # per radius: the table's row at r (linear in r, as the texture reads it) and the terms of the mu mapping
    bottom2, top2 = t.bottom * t.bottom, t.top * t.top
    h = np.sqrt(top2 - bottom2)
    rho = safe_sqrt(r * r - bottom2)
    v0, v1, fv = texel_axis(texcoord_from_unit_range(rho / h, n_r), n_r)
    fv = fv.astype(np.float32)[..., None, None]
    rows = t.optical_depth[v0] * (1 - fv) + t.optical_depth[v1] * fv         # r.shape + (n_mu, W)
    rows = np.ascontiguousarray(np.moveaxis(rows.reshape(-1, rows.shape[-1]), -1, 0))   # (W, r.size n_mu)
    d_min, d_max = t.top - r, rho + h
    scale = np.where(d_max > d_min, (n_mu - 1) / np.where(d_max > d_min, d_max - d_min, 1.0), 0.0)
    top_r, bottom_r = top2 - r * r, bottom2 - r * r
    # per sun: the distance d to the top, the texel coordinate u n - 1/2 = x_mu (n - 1), the planet's shadow
    r_mu = r * mu_s
    r_mu2 = r_mu * r_mu
    d = np.maximum(safe_sqrt(r_mu2 + top_r) - r_mu, 0.0)
    shadow = (mu_s < 0.0) & (r_mu2 + bottom_r >= 0.0)
    x = np.maximum((d - d_min) * scale, 0.0)
    u0 = np.minimum(x.astype(np.int64), n_mu - 1)
    fu = (x - u0).astype(np.float32)
    i0 = u0 + np.arange(r.size).reshape(r.shape) * n_mu
    i1 = i0 + (u0 < n_mu - 1)
    minus_d = -d.astype(np.float32)
    lit = ~shadow
    out = np.empty((len(rows),) + shape, np.float32)                # wavelength-major in memory
    for w, tau in zip(rows, out):
        np.take(w, i0, out=tau)
        step = np.take(w, i1)
        step -= tau
        step *= fu
        tau += step
        tau *= minus_d
        np.exp(tau, out=tau)
        tau *= lit
    return np.moveaxis(out, 0, -1)


def get_irradiance(t, r, mu_s, table=None):
    """Indirect (sky) irradiance E(r, mu_s) per unit solar irradiance (``table``: default t.irradiance): linear in r;
    along mu_s linear between two texels where the upper one has the sun above the horizon, geometric
    (:func:`geometric_blend`) where it has not.

    Why geometric below the horizon: there E falls by about e per degree of the sun's depression, a convex fall that
    linear interpolation between texels 0.9 deg apart (standard) read up to 16% high between them on the Earth
    preset (5.9% RMS to 6 deg below the horizon, 10% to 18 deg, against a table of 1024 texels); geometric, 1.2% and
    2.8% RMS (tests/test_tables.py). Above the horizon E is concave in mu_s and the linear reading is the closer
    (0.16% RMS). The two blends agree at texel centres, so E stays continuous."""
    table = t.irradiance if table is None else table
    n_r, n_mu_s = table.shape[:2]
    u, v = irradiance_uv_from_r_mu_s(r, mu_s, t.bottom, t.top, (n_mu_s, n_r))
    u0, u1, fu = texel_axis(u, n_mu_s)
    v0, v1, fv = texel_axis(v, n_r)
    fu, fv = fu[..., None], fv[..., None]
    low = table[v0, u0] * (1 - fv) + table[v1, u0] * fv
    high = table[v0, u1] * (1 - fv) + table[v1, u1] * fv
    below = (2.0 * u1 / (n_mu_s - 1) - 1.0 <= 0.0)[..., None]
    return np.where(below, geometric_blend(low, high, fu), low + (high - low) * fu)


def mu_s_pairs(table):
    """(n_r, n_mu, n_nu, n_mu_s + 1, 2C): the table (n_r, n_mu, n_nu, n_mu_s, C) as pairs of neighbouring mu_s
    texels, pair i holding texels i - 1 and i side by side, clamped at the edges (pair 0 holds texel 0 twice, pair
    n_mu_s the last texel twice): what a lookup between texels i - 1 and i (``sampling.texel_axis``) reads along
    mu_s, in one place."""
    padded = np.concatenate([table[..., :1, :], table, table[..., -1:, :]], axis=3)
    return np.concatenate([padded[..., :-1, :], padded[..., 1:, :]], axis=-1)


class ScatteringStencil:
    """A 4D lookup in tables of ``shape`` (n_r, n_mu, n_nu, n_mu_s) prepared once for many tables read at the
    same points (the precompute reads every order's table at fixed points). ``mapping`` gives the texture
    coordinates (u_nu, u_mu_s, u_mu, u_r) (S's by default; the scattering density has its own).

    For each point, the eight (r, mu, nu) neighbours, weighted to sum to 1, are kept as sparse matrices over
    the table's pairs of neighbouring mu_s texels (:func:`mu_s_pairs`), one per chunk of about ``STENCIL_CHUNK``
    points (whole rows of the last axis); :meth:`apply` reads both texels of the point's pair and blends them along
    mu_s as :func:`get_scattering` does (geometrically), so the precompute reads its own tables as the renderer
    reads the final ones. Chunk by chunk, the reads and the blend stay in the caches: the standard precompute of
    the 10-bar preset took 2.2 times as long with all the points read at once."""

    def __init__(self, t, shape, r, mu, mu_s, nu, intersects_ground, mapping=scattering_uvwz_from_r_mu_mu_s_nu):
        from scipy.sparse import csr_matrix
        n_r, n_mu, n_nu, n_mu_s = shape
        u_nu, u_mu_s, u_mu, u_r = mapping(r, mu, mu_s, nu, intersects_ground, t.bottom, t.top,
                                          (n_nu, n_mu_s, n_mu, n_r), t.r_axis)
        coord = u_nu * (n_nu - 1)
        tex_nu = np.clip(np.floor(coord), 0, max(n_nu - 2, 0))
        lerp = coord - tex_nu
        fs = texel_axis(u_mu_s, n_mu_s)[2]
        pair = np.clip(np.floor(np.asarray(u_mu_s, float) * n_mu_s - 0.5) + 1, 0, n_mu_s).astype(np.int64)
        (j0, j1, fy), (k0, k1, fz) = texel_axis(u_mu, n_mu), texel_axis(u_r, n_r)
        n_x = n_nu * (n_mu_s + 1)
        self.shape = np.shape(fs)
        n_points, n_texels = int(np.prod(self.shape)), n_r * n_mu * n_x
        per_point = 8 if n_nu > 1 else 4
        index = np.int32 if max(n_points * per_point, n_texels) < 2 ** 31 else np.int64
        columns = np.empty(self.shape + (per_point,), index)
        weights = np.empty(self.shape + (per_point,), np.float32)
        c = 0
        for dn, wn in ((0, 1.0 - lerp), (1, lerp))[:per_point // 4]:
            slot = (tex_nu + dn).astype(np.int64) * (n_mu_s + 1) + pair
            for kk, wz in ((k0, 1 - fz), (k1, fz)):
                for jj, wy in ((j0, 1 - fy), (j1, fy)):
                    columns[..., c] = (kk * n_mu + jj) * n_x + slot
                    weights[..., c] = wn * wz * wy
                    c += 1
        matrix = csr_matrix((weights.reshape(-1), columns.reshape(-1),
                             np.arange(n_points + 1, dtype=index) * per_point), shape=(n_points, n_texels))
        # in chunks of whole rows of the last axis (a ray's nodes when :meth:`apply` sums along it), about
        # STENCIL_CHUNK points each, so that a chunk's reads and blend stay in the caches
        step = max(STENCIL_CHUNK // self.shape[-1], 1) * self.shape[-1] if self.shape else 1
        self.chunks = [(slice(start, min(start + step, n_points)), matrix[start:start + step])
                       for start in range(0, n_points, step)]
        self.f = fs.reshape(-1, 1).astype(np.float32)
        self.opacity = None
        if mapping is scattering_uvwz_from_r_mu_mu_s_nu:
            opacity = ray_opacity(t, r, mu, intersects_ground)
            self.opacity = np.broadcast_to(opacity, self.shape + opacity.shape[-1:]).reshape(n_points, -1)
            self.opacity = self.opacity.astype(np.float32)

    def apply(self, table, along=None):
        """The table (n_r, n_mu, n_nu, n_mu_s, C) at the stencil's points: (..., C); where the table holds
        channels for several components of the same wavelengths (C a multiple of the opacity's), the opacity
        multiplies each. With ``along`` (the stencil's points + (C,), weights): the weighted sum over the points'
        last axis instead (an integral along rays whose nodes are that axis), (...[:-1], C)."""
        channels = table.shape[-1]
        pairs = mu_s_pairs(table).reshape(-1, 2 * channels)
        opacity = None if self.opacity is None else np.tile(self.opacity, (1, channels // self.opacity.shape[-1]))
        if along is not None:
            along = np.broadcast_to(along, self.shape + (channels,))
        out = []
        for points, matrix in self.chunks:
            both = matrix @ pairs
            value = geometric_blend(*(np.ascontiguousarray(both[:, k:k + channels]) for k in (0, channels)),
                                    self.f[points])
            if opacity is not None:
                value *= opacity[points]
            out.append(value if along is None else sum_along_rays(value, points, self.shape, along))
        return stencil_output(out, self.shape, along)


#: Points per chunk of :meth:`ScatteringStencil.apply` and :meth:`RayStencil.apply`.
STENCIL_CHUNK = 32768


class RayStencil:
    """:class:`ScatteringStencil`'s lookup, stored per (r, mu) and not per point, for points whose (r, mu, ground)
    take fewer values than their (mu_s, nu): the nodes along the multiple-scattering tables' rays, where the
    n_nu n_mu_s texels of a ray (r, mu) share its nodes (r_t, mu_t) and differ only in (mu_s_t, nu). It reads a
    table that is not divided by the rays' opacity (the scattering density J, whose ``mapping`` is the default).
    ``mapping``'s u_r and u_mu must follow (r, mu, ground) alone, as both mappings' do.

    :meth:`apply` takes the same steps as :class:`ScatteringStencil`'s in another order:

    1. per (r, mu) value, the four (r, mu) neighbours' rows of the table's mu_s pairs (:func:`mu_s_pairs`),
       weighted to sum to 1: n_nu (n_mu_s + 1) pairs each;
    2. per point, that blend's two entries at its nu texels, weighted linearly in u_nu;
    3. the pair's two mu_s texels blended geometrically (:func:`geometric_blend`).

    It stores 12 bytes per point (where the sparse matrix stores 68: eight column indices and weights) and reads
    the same values within float32 rounding. The (r, mu) values follow the points' leading axis (repeated along it
    where r, mu and ground do not vary there); the points go in chunks of whole leading indices (whole rays where
    :meth:`apply` sums along the last axis), about ``STENCIL_CHUNK`` points each (at least one leading index)."""

    def __init__(self, t, shape, r, mu, mu_s, nu, intersects_ground, mapping=density_uvwz_from_r_mu_mu_s_nu):
        from scipy.sparse import csr_matrix
        n_r, n_mu, n_nu, n_mu_s = shape
        self.shape = np.broadcast_shapes(*(np.shape(a) for a in (r, mu, mu_s, nu, intersects_ground)))
        rows_shape = np.broadcast_shapes(*(np.shape(a) for a in (r, mu, intersects_ground)))
        rows_shape = self.shape[:1] + ((1,) * (len(self.shape) - len(rows_shape)) + rows_shape)[1:]
        u_nu, u_mu_s, u_mu, u_r = mapping(r, mu, mu_s, nu, intersects_ground, t.bottom, t.top,
                                          (n_nu, n_mu_s, n_mu, n_r), t.r_axis)
        (j0, j1, fy), (k0, k1, fz) = (texel_axis(np.broadcast_to(u, rows_shape), n)
                                      for u, n in ((u_mu, n_mu), (u_r, n_r)))
        columns = np.stack([k * n_mu + j for k in (k0, k1) for j in (j0, j1)], -1).reshape(-1)
        weights = np.stack([wz * wy for wz in (1 - fz, fz) for wy in (1 - fy, fy)], -1).reshape(-1)
        n_rows = columns.size // 4
        self.rows = csr_matrix((weights.astype(np.float32), columns.astype(np.int32),
                                np.arange(n_rows + 1, dtype=np.int32) * 4), shape=(n_rows, n_r * n_mu))
        # per point: its (r, mu) value's index times the pairs per row, plus its lower nu texel's pair
        self.n_x, self.nu_step = n_nu * (n_mu_s + 1), (n_mu_s + 1) if n_nu > 1 else 0
        coord = u_nu * (n_nu - 1)
        tex_nu = np.clip(np.floor(coord), 0, max(n_nu - 2, 0))
        pair = np.clip(np.floor(np.asarray(u_mu_s, float) * n_mu_s - 0.5) + 1, 0, n_mu_s)
        row = np.arange(n_rows).reshape(rows_shape)
        index = np.int32 if n_rows * self.n_x < 2 ** 31 else np.int64
        self.entry = np.broadcast_to(row * self.n_x + tex_nu * (n_mu_s + 1) + pair, self.shape).astype(index).ravel()
        self.lerp = np.broadcast_to(coord - tex_nu, self.shape).astype(np.float32).reshape(-1, 1)
        self.f = np.broadcast_to(texel_axis(u_mu_s, n_mu_s)[2], self.shape).astype(np.float32).reshape(-1, 1)
        lead, per_lead = self.shape[0], int(np.prod(self.shape[1:], dtype=np.int64))
        step, rows_per_lead = max(STENCIL_CHUNK // max(per_lead, 1), 1), n_rows // lead
        self.chunks = [(slice(a * per_lead, min(a + step, lead) * per_lead),
                        slice(a * rows_per_lead, min(a + step, lead) * rows_per_lead)) for a in range(0, lead, step)]

    def apply(self, table, along=None):
        """As :meth:`ScatteringStencil.apply`: the table at the stencil's points, or with ``along`` their weighted sum
        along the last axis."""
        channels = table.shape[-1]
        pairs = mu_s_pairs(table).reshape(-1, self.n_x * 2 * channels)
        if along is not None:
            along = np.broadcast_to(along, self.shape + (channels,))
        out = []
        for points, rows in self.chunks:
            blend = (self.rows[rows] @ pairs).reshape(-1, 2 * channels)                # step 1
            entry = self.entry[points] - rows.start * self.n_x
            both = np.take(blend, entry, axis=0)                                         # step 2
            if self.nu_step:
                upper = np.take(blend, entry + self.nu_step, axis=0)
                upper -= both
                upper *= self.lerp[points]
                both += upper
            value = geometric_blend(np.ascontiguousarray(both[:, :channels]),          # step 3
                                    np.ascontiguousarray(both[:, channels:]), self.f[points])
            out.append(value if along is None else sum_along_rays(value, points, self.shape, along))
        return stencil_output(out, self.shape, along)


def sum_along_rays(value, points, shape, along):
    """A chunk of a stencil's values (the flat ``points``, whole rows of the last axis of ``shape``; C) summed along
    that axis with the weights ``along`` (``shape`` + (C,)): the chunk's rays, (rays, C)."""
    rays = np.unravel_index(np.arange(points.start, points.stop, shape[-1]) // shape[-1], shape[:-1])
    return np.einsum("rkc,rkc->rc", value.reshape(-1, shape[-1], value.shape[-1]), along[rays])


def stencil_output(chunks, shape, along):
    """A stencil's chunks of values joined: ``shape`` + (C,), or ``shape[:-1]`` + (C,) summed ``along`` rays."""
    value = np.concatenate(chunks)
    return value.reshape((shape if along is None else shape[:-1]) + value.shape[-1:])


def get_scattering(t, table, r, mu, mu_s, nu, intersects_ground, opacity=None, top=None):
    """A 4D table (n_r, n_mu, n_nu, n_mu_s, W) read as the shader reads its 3D texture (n_r, n_mu, n_nu * n_mu_s),
    times :func:`ray_opacity` (``opacity``, computed here when not given): the tables hold S over it.

    ``top`` (n_up, n_nu, n_mu_s, W), the multiple-scattering tables' top tables (``multiple.top_source``): rays
    upward (mu >= 0) read them in place of the top row, at u = theta / (pi / 2) (theta the view zenith angle) and
    the same nu and mu_s texels: the top row holds rays of zero length there, one texel for every zenith angle.

    Along mu_s and nu the two neighbouring texels are fetched separately (each at its exact texel centre, so
    the hardware interpolates only r and mu: four texture() calls in the shader) and blended geometrically,
    a^(1 - f) b^f, or linearly where one of them is 0: in twilight the in-scattered light falls by a factor
    of about 4 per degree of sun elevation, which a linear blend over texels a degree apart overestimates
    several times, while the geometric blend is exact for an exponential.
    """
    n_r, n_mu, n_nu, n_mu_s = table.shape[:4]
    u_nu, _, u_mu, u_r = scattering_uvwz_from_r_mu_mu_s_nu(r, mu, mu_s, nu, intersects_ground,
                                                                t.bottom, t.top, (n_nu, n_mu_s, n_mu, n_r), t.r_axis)
    coord = u_nu * (n_nu - 1)
    tex_nu = np.clip(np.floor(coord), 0, max(n_nu - 2, 0))
    lerp = (coord - tex_nu)[..., None]
    # Along mu_s the blend may extrapolate below the first texel (the sun more than 18 deg below the
    # horizon): geometrically, the twilight decay continues to 0 instead of freezing at its last value.
    coord_s = texcoord_from_unit_range(x_mu_s_from_mu_s(mu_s, t.bottom, t.top, clamp=False), n_mu_s) * n_mu_s - 0.5
    s0 = np.clip(np.floor(coord_s), 0, n_mu_s - 2).astype(np.int64)
    s1 = s0 + 1
    fs = np.minimum(coord_s - s0, 1.0)[..., None]
    flat = table.reshape(n_r * n_mu, n_nu * n_mu_s, table.shape[-1])
    (k0, k1, fz), (j0, j1, fy) = texel_axis(u_r, n_r), texel_axis(u_mu, n_mu)
    fz, fy = fz[..., None], fy[..., None]

    if top is None:
        def row_pair(kk, col):
            return flat[kk * n_mu + j0, col] * (1 - fy) + flat[kk * n_mu + j1, col] * fy
    else:
        n_up = top.shape[0]
        top_flat = top.reshape(n_up, n_nu * n_mu_s, top.shape[-1])
        t0, t1, ft = texel_axis(np.arccos(np.clip(mu, 0.0, 1.0)) / (0.5 * np.pi), n_up)
        ft = ft[..., None]
        upward = (~np.asarray(intersects_ground) & (np.asarray(mu) >= 0.0))[..., None]

        def row_pair(kk, col):
            sky = flat[kk * n_mu + j0, col] * (1 - fy) + flat[kk * n_mu + j1, col] * fy
            at_top = top_flat[t0, col] * (1 - ft) + top_flat[t1, col] * ft
            return np.where(upward & (kk == n_r - 1)[..., None], at_top, sky)

    def bilinear(col):
        return row_pair(k0, col) * (1 - fz) + row_pair(k1, col) * fz

    slices = []
    for dn in (0, 1) if n_nu > 1 else (0,):
        base = (tex_nu + dn).astype(np.int64) * n_mu_s
        slices.append(geometric_blend(bilinear(base + s0), bilinear(base + s1), fs))
    read = slices[0] if n_nu == 1 else geometric_blend(slices[0], slices[1], lerp)
    return read * (ray_opacity(t, r, mu, intersects_ground) if opacity is None else opacity)


def geometric_blend(a, b, f):
    """a^(1 - f) b^f, with a zero neighbour raised to ZERO_FLOOR times the other (0 where both are 0).

    A texel can hold an exact 0 where the tables end in the planet's shadow (the sun 18 deg below the horizon,
    rays along the horizon): blending linearly toward it made the last degree before -18 deg glow up to 100
    times too bright near the horizon (tests/test_render.py, the twilight sweep); the floor keeps the
    blend geometric, a decay to ZERO_FLOOR of the lit value over one texel. f < 0 extrapolates beyond a,
    never above a (it only continues a decay). Computed in the precision of a and b (float32 for the tables'
    reads, as the shaders do: within 5e-7 of float64, in half the time). Where every a is at least SMALLEST and
    every b / a within [ZERO_FLOOR, 1 / ZERO_FLOOR] (most reads) the floors change nothing and are skipped."""
    f = np.asarray(f, np.result_type(a, b))
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = b / a
    plain = a.min(initial=np.inf) >= SMALLEST and ratio.min(initial=1.0) >= ZERO_FLOOR \
        and ratio.max(initial=1.0) <= 1.0 / ZERO_FLOOR
    if plain:
        a_f = a
    else:
        lit = (a > 0) | (b > 0)
        a_f = np.maximum(a, ZERO_FLOOR * b)
        np.maximum(a_f, SMALLEST, out=a_f)
        ratio = np.maximum(b, ZERO_FLOOR * a)
        np.maximum(ratio, SMALLEST, out=ratio)
        ratio /= a_f                                    # within [ZERO_FLOOR, 1 / ZERO_FLOOR]
    if np.any(f < 0):
        ratio = np.where(f < 0, np.maximum(ratio, 1.0), ratio)   # f < 0: the decay continues, never a rise
    out = np.log(ratio, out=ratio) * f
    np.exp(out, out=out)
    out *= a_f
    if not plain:
        out *= lit
    return out
