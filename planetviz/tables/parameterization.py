"""Mappings between the physical coordinates and texture coordinates of the tables.

After Bruneton (2017, "precomputed_atmospheric_scattering", functions of the same names). Notation:
r = distance to the planet centre, mu = cos(view zenith), mu_s = cos(sun zenith), nu = cos(view-sun);
R_b, R_t the bottom and top radii, H = sqrt(R_t^2 - R_b^2) the distance to the top along the horizon
from the ground, rho = sqrt(r^2 - R_b^2) the same from radius r.

* Transmittance T(r, mu): x_r = rho / H; x_mu = (d - d_min) / (d_max - d_min) with d the distance to the
  top, d_min = R_t - r, d_max = rho + H. Dense near the horizon, where T varies fastest.
* Irradiance E(r, mu_s): x_r = (r - R_b) / (R_t - R_b), x_mu_s = (mu_s + 1) / 2.
* Scattering S(r, mu, mu_s, nu): u_r = x_r(rho / H), rho / H stretched by the optical depth (``r_axis``);
  u_mu in [0, 1/2) for rays that hit the ground (distance to the ground, mapped so both halves meet at the
  horizon), [1/2, 1] for the others (distance to the top), on planets much larger than their atmosphere is
  thick through a warp of the distance (``distance_warp``); the sky half refined for the rays that dip below
  the horizontal (``refine_dipping_rays``);
  u_mu_s from the distance to the top along mu_s seen from the ground, concentrated above mu_s_min;
  u_nu linear in nu over the range that (mu, mu_s) allow (``x_nu_from_nu``); mu_s_min = cos(108 deg) keeps
  twilight down to 18 deg below the horizon.
* Scattering density J(r, mu, mu_s, nu) (internal to the multiple-scattering stage): as S, but u_mu =
  theta / pi (``density_uvwz_from_r_mu_mu_s_nu``).

Texture coordinates put texel centres at (i + 1/2) / n (``texcoord_from_unit_range``), as OpenGL does.
"""
from __future__ import annotations

import numpy as np

#: Sun zenith angle covered by the tables: 108 deg (the sun 18 deg below the horizon).
MU_S_MIN = float(np.cos(np.radians(108.0)))


def safe_sqrt(a):
    return np.sqrt(np.maximum(a, 0.0))


def clamp_cosine(mu):
    return np.clip(mu, -1.0, 1.0)


def distance_to_top_atmosphere_boundary(r, mu, top):
    """d >= 0 along (r, mu) to the sphere of radius ``top``, for r <= top."""
    disc = r * r * (mu * mu - 1.0) + top * top
    return np.maximum(-r * mu + safe_sqrt(disc), 0.0)


def distance_to_bottom_atmosphere_boundary(r, mu, bottom):
    disc = r * r * (mu * mu - 1.0) + bottom * bottom
    return np.maximum(-r * mu - safe_sqrt(disc), 0.0)


def ray_intersects_ground(r, mu, bottom):
    return (mu < 0.0) & (r * r * (mu * mu - 1.0) + bottom * bottom >= 0.0)


def texcoord_from_unit_range(x, n):
    return 0.5 / n + x * (1.0 - 1.0 / n)


def unit_range_from_texcoord(u, n):
    return (u - 0.5 / n) / (1.0 - 1.0 / n)


# ------------------------------------------------------------------ transmittance
def transmittance_uv_from_r_mu(r, mu, bottom, top, size):
    """(u, v) texture coordinates of T(r, mu); ``size`` = (width along mu, height along r)."""
    h = np.sqrt(top * top - bottom * bottom)
    rho = safe_sqrt(r * r - bottom * bottom)
    d = distance_to_top_atmosphere_boundary(r, mu, top)
    d_min = top - r
    d_max = rho + h
    x_mu = np.where(d_max > d_min, (d - d_min) / np.where(d_max > d_min, d_max - d_min, 1.0), 0.0)
    x_r = rho / h
    return texcoord_from_unit_range(x_mu, size[0]), texcoord_from_unit_range(x_r, size[1])


def r_mu_from_transmittance_uv(u, v, bottom, top, size):
    x_mu = unit_range_from_texcoord(u, size[0])
    x_r = unit_range_from_texcoord(v, size[1])
    h = np.sqrt(top * top - bottom * bottom)
    rho = h * x_r
    r = np.sqrt(rho * rho + bottom * bottom)
    d_min = top - r
    d_max = rho + h
    d = d_min + x_mu * (d_max - d_min)
    mu = np.where(d == 0.0, 1.0, (h * h - rho * rho - d * d) / np.where(d == 0.0, 1.0, 2.0 * r * d))
    return r, clamp_cosine(mu)


# ------------------------------------------------------------------- irradiance
def irradiance_uv_from_r_mu_s(r, mu_s, bottom, top, size):
    x_r = (r - bottom) / (top - bottom)
    x_mu_s = mu_s * 0.5 + 0.5
    return texcoord_from_unit_range(x_mu_s, size[0]), texcoord_from_unit_range(x_r, size[1])


def r_mu_s_from_irradiance_uv(u, v, bottom, top, size):
    x_mu_s = unit_range_from_texcoord(u, size[0])
    x_r = unit_range_from_texcoord(v, size[1])
    return bottom + x_r * (top - bottom), clamp_cosine(2.0 * x_mu_s - 1.0)


# ------------------------------------------------------------------- scattering
def scattering_uvwz_from_r_mu_mu_s_nu(r, mu, mu_s, nu, intersects_ground, bottom, top, size, axis=None):
    """(u_nu, u_mu_s, u_mu, u_r) of S; ``size`` = (n_nu, n_mu_s, n_mu, n_r); ``axis`` the r axis (:func:`r_axis`,
    the tables' ``r_axis``; None: uniform in rho)."""
    n_nu, n_mu_s, n_mu, n_r = size
    h = np.sqrt(top * top - bottom * bottom)
    rho = safe_sqrt(r * r - bottom * bottom)
    u_r, u_mu_s = _u_r_u_mu_s(r, mu_s, bottom, top, n_r, n_mu_s, axis)
    r_mu = r * mu
    disc = r_mu * r_mu - r * r + bottom * bottom
    # Ground rays: distance to the ground, from r - R_b (looking down) to rho (the horizon).
    d_g = -r_mu - safe_sqrt(disc)
    x_g = distance_coordinate(d_g, r - bottom, rho, distance_warp(r, bottom, top, True), VIEW_ANGLE_OFFSET)
    u_mu_g = 0.5 - 0.5 * texcoord_from_unit_range(x_g, n_mu // 2)
    # Sky rays: distance to the top, from R_t - r (looking up) to rho + H (the horizon).
    d_s = -r_mu + safe_sqrt(disc + h * h)
    x_s = refine_dipping_rays(distance_coordinate(d_s, top - r, rho + h, distance_warp(r, bottom, top, False),
                                                  sky_angle_offset(r, bottom, top)), r, bottom, top)
    u_mu_s_half = 0.5 + 0.5 * texcoord_from_unit_range(x_s, n_mu // 2)
    u_mu = np.where(intersects_ground, u_mu_g, u_mu_s_half)
    return x_nu_from_nu(mu, mu_s, nu), u_mu_s, u_mu, u_r


#: The 4D tables' r axis (``r_axis``) is tabulated at this many values of rho / H, uniformly spaced on [0, 1], and
#: read linearly between them (shaders/table_lookup.glsl declares the same number).
R_AXIS_KNOTS = 65

#: Gauss-Legendre nodes per interval between knots integrating the vertical optical depth (``r_axis``).
R_AXIS_SAMPLES = 8


def r_axis(bottom, top, extinction):
    """x_r, the 4D tables' r coordinate in [0, 1], at the ``R_AXIS_KNOTS`` values q_k = k / (R_AXIS_KNOTS - 1) of
    q = rho / H (linear in q between them):

        x_r(q) = (q + kappa s(q)) / (1 + kappa),    kappa = max(0, c(1) - 1),
        s(q) = 1/2 + (ln(1 + c(q)) - ln(1 + c(1) - c(q))) / (2 ln(1 + c(1))),

    c(q) the largest over the wavelengths of the vertical optical depth [dimensionless] from the ground up to the
    altitude of q, a(q) = sqrt(q^2 H^2 + R_b^2) - R_b. ``extinction``: the extinction coefficient [1/m] as a
    function of altitude [m], shape ``a.shape + (W,)``.

    Bruneton's x_r = q puts the rows densely near the ground, where the horizon's geometry changes fastest, but
    wherever the atmosphere puts its air. In an optically thick atmosphere the light's logarithm changes by about
    1 / (1 + tau) per unit of optical depth at an optical depth tau from the nearer boundary: by a factor e per
    unit in the first unit under the top, where the sunlight enters and the views from space look, and more slowly
    deeper down, where the diffuse light varies linearly with the optical depth left to the other boundary. s(q)
    spaces the rows uniformly in that change: a unit of optical depth at tau from the nearer boundary gets a share
    of about 1 / ((1 + tau) 2 ln(1 + c(1))) of the optical term (a unit at each boundary 7.6% at c(1) = 100, where
    rows uniform in c gave the top unit 1% and put the last unit, above 37 km on a 60 km atmosphere, between two
    rows). The optical term takes the share kappa / (1 + kappa) = 1 - 1 / c(1) of the rows, the optical depth
    beyond the first unit (86% at c(1) = 7.1); an atmosphere whose vertical optical depth is at most 1 (the Earth
    0.25, Mars 0.38) keeps Bruneton's rows: its light changes little with the optical depth, and where its rows
    fall matters through other structure (rows that follow the optical depth on every atmosphere move the rows of
    thin ones across their absorbing layers: docs/tables.md)."""
    h = np.sqrt(top * top - bottom * bottom)
    q = np.linspace(0.0, 1.0, R_AXIS_KNOTS)
    a = safe_sqrt(q * q * h * h + bottom * bottom) - bottom
    nodes, weights = np.polynomial.legendre.leggauss(R_AXIS_SAMPLES)
    half = 0.5 * np.diff(a)[:, None]
    heights = 0.5 * (a[1:] + a[:-1])[:, None] + half * nodes                          # (K - 1, N)
    steps = np.einsum("kn,knw->kw", half * weights, extinction(heights))             # (K - 1, W)
    c = np.concatenate([np.zeros((1, steps.shape[1])), np.cumsum(steps, axis=0)]).max(axis=1)
    if c[-1] <= 1.0:
        return q
    kappa = c[-1] - 1.0
    s = 0.5 + (np.log1p(c) - np.log1p(np.maximum(c[-1] - c, 0.0))) / (2.0 * np.log1p(c[-1]))
    return (q + kappa * s) / (1.0 + kappa)


def x_r_from_rho(rho, h, axis=None):
    """The r coordinate x_r in [0, 1] of rho [m] (H = ``h``): ``axis`` (:func:`r_axis`) read linearly at
    q = rho / H, or q itself where ``axis`` is None (Bruneton's mapping)."""
    q = rho / h
    return q if axis is None else np.interp(q, np.linspace(0.0, 1.0, len(axis)), axis)


def rho_from_x_r(x, h, axis=None):
    """Inverse of :func:`x_r_from_rho` (exact: x_r is linear in q between knots)."""
    return h * (x if axis is None else np.interp(x, axis, np.linspace(0.0, 1.0, len(axis))))


def _u_r_u_mu_s(r, mu_s, bottom, top, n_r, n_mu_s, axis):
    """(u_r, u_mu_s), the same for S and the scattering density J."""
    h = np.sqrt(top * top - bottom * bottom)
    u_r = texcoord_from_unit_range(x_r_from_rho(safe_sqrt(r * r - bottom * bottom), h, axis), n_r)
    return u_r, texcoord_from_unit_range(x_mu_s_from_mu_s(mu_s, bottom, top), n_mu_s)


def density_uvwz_from_r_mu_mu_s_nu(r, mu, mu_s, nu, intersects_ground, bottom, top, size, axis=None):
    """(u_nu, u_mu_s, u_mu, u_r) of the scattering density J (internal to the multiple-scattering stage):
    u_r, u_mu_s and u_nu as for S; u_mu = theta / pi with theta the view zenith angle, texel centres at
    (i + 1/2) / n. J(x, v) is a property of the point and the direction, continuous across the horizon: the
    ground and sky halves of S, which follow the distance along the ray, would put every view below the
    horizon from the lowest row onto one texel (the nadir: rays to the ground of zero length), and views
    15 deg below the horizontal from 1 km next to it. ``intersects_ground`` is not used (the same signature
    as :func:`scattering_uvwz_from_r_mu_mu_s_nu`)."""
    n_nu, n_mu_s, n_mu, n_r = size
    u_r, u_mu_s = _u_r_u_mu_s(r, mu_s, bottom, top, n_r, n_mu_s, axis)
    return x_nu_from_nu(mu, mu_s, nu), u_mu_s, np.arccos(clamp_cosine(mu)) / np.pi, u_r


def nu_from_x_nu(mu, mu_s, x):
    """Inverse of :func:`x_nu_from_nu` (exact where nu's range is at least ``NU_RANGE_FLOOR`` wide)."""
    return clamp_cosine(mu * mu_s + (2.0 * x - 1.0) * safe_sqrt((1.0 - mu * mu) * (1.0 - mu_s * mu_s)))


#: Below this half-width sqrt((1 - mu^2)(1 - mu_s^2)) of nu's range (the view or the sun within 0.57 deg of
#: the zenith or the nadir) the range counts as this wide, so that x_nu goes to 1/2 there, continuously. The
#: sun-view azimuth is undefined at the poles and float32 cannot resolve it near them: for the sun at the
#: nadir a float32 mu_s of -1 + 6e-8 leaves a half-width of 3.5e-4 and an arbitrary azimuth, read past the
#: tables' last mu_s texel at another nu than the float64 evaluator's (0.55% apart with a floor of 1e-6,
#: tests/test_stability_shader.py). Within the floor the query's own range of nu is < 0.02 wide; for the view
#: or the sun near the zenith the neighbouring texels, which have a wider range, weigh < 1e-4 (the mu and mu_s
#: coordinates are quadratic in the angle there); for the sun near the nadir, past the tables' last mu_s
#: texel, the extrapolated night sky is read at the azimuth 90 deg (x_nu = 1/2).
NU_RANGE_FLOOR = 1e-2


def x_nu_from_nu(mu, mu_s, nu):
    """The view-sun coordinate in [0, 1]: linear in nu over the range that (mu, mu_s) allow,
    nu = mu mu_s + (2 x - 1) sqrt((1 - mu^2)(1 - mu_s^2)), i.e. (1 + cos(phi)) / 2 with phi the sun-view
    azimuth (0: the sun's vertical plane on the sun's side).

    Bruneton's (nu + 1) / 2 spans [-1, 1] whatever (mu, mu_s) allow; the texels outside the allowed range
    hold the clamped geometry of another nu. For a horizontal view with the sun 60 deg up only nu in
    [-0.5, 0.5] exists: two of the multiple-scattering tables' four nu texels, and the top mu_s texel (the
    sun at the zenith, nu = mu for every nu) held one geometry for all of them. Reading the Mars dust's
    forward-scattered light between such texels put the sky 10 km up +33% off the reference on that view
    (docs/tables.md, Mars); over the allowed range every texel is a real geometry, at least as densely
    spaced in nu as Bruneton's.
    """
    root = np.maximum(safe_sqrt((1.0 - mu * mu) * (1.0 - mu_s * mu_s)), NU_RANGE_FLOOR)
    return np.clip(0.5 + 0.5 * (nu - mu * mu_s) / root, 0.0, 1.0)


#: The sky half's refinement of the rays that dip below the horizontal (``refine_dipping_rays``): the
#: pivot's smoothing length at the top as a fraction of H; the altitude over which the refinement sets in as
#: a fraction of the atmosphere's thickness; the share of sqrt(t) in G(t); the lowest points' altitude below
#: which G's square root turns linear, as a fraction of the atmosphere's thickness.
PIVOT_SMOOTHING = 0.03
REFINEMENT_ALTITUDE = 0.1
SQRT_SHARE = 5.0 / 6.0
LINEAR_ALTITUDE = 0.005


def dipping_pivot_and_weight(r, bottom, top):
    """(x_p, w) of :func:`refine_dipping_rays` for cameras at radius r.

    x_p is the horizontal ray's x, :func:`distance_coordinate` of its length sqrt(s), s = R_t^2 - r^2, where sqrt(s) is
    replaced by s / sqrt(s + c^2), c = PIVOT_SMOOTHING H: sqrt(s) goes as sqrt(R_t - r) at the top, and the
    mapping of every sky ray would change there faster than the camera moves (the reading jumped by more than
    0.1% between cameras 1 m apart across the top); s / sqrt(s + c^2) is smooth there and within c^2 / (2 sqrt(s))
    of sqrt(s) below (390 m on the ground, 960 m from 50 km up: a few rays just above the horizontal are refined
    too). w = 1 - exp(-(r - R_b) / (REFINEMENT_ALTITUDE (R_t - R_b))): 0 (Bruneton's mapping) on the ground,
    where the dipping rays' lowest points all lie within metres of the camera and the density along them is
    near linear in x (the refinement everywhere read 3.3% next to the horizon from 100 m, against 0.9%), 1 from
    some 20 km up (Earth)."""
    h = np.sqrt(top * top - bottom * bottom)
    rho = safe_sqrt(r * r - bottom * bottom)
    c = PIVOT_SMOOTHING * h
    d_min, d_max = top - r, rho + h
    s = np.maximum((top - r) * (top + r), 0.0)
    x_p = np.clip(distance_coordinate(s / np.sqrt(s + c * c), d_min, d_max, distance_warp(r, bottom, top, False),
                                      sky_angle_offset(r, bottom, top)), 0.0, 1.0)
    w = 1.0 - np.exp(-np.maximum(r - bottom, 0.0) / (REFINEMENT_ALTITUDE * (top - bottom)))
    return x_p, w


def _softened_sqrt(t, e):
    """(sqrt(t + e) - sqrt(e)) / (sqrt(1 + e) - sqrt(e)), in a form without cancellation: 0 at t = 0, 1 at
    t = 1; sqrt(t) for e = 0, linear in t where t << e."""
    return t * (np.sqrt(1.0 + e) + np.sqrt(e)) / np.maximum(np.sqrt(t + e) + np.sqrt(e), 1e-300)


def _linear_share(r, bottom, top):
    """e of :func:`_softened_sqrt`: LINEAR_ALTITUDE (R_t - R_b) over the camera's altitude (t is near the
    horizon the lowest point's altitude over the camera's)."""
    return LINEAR_ALTITUDE * (top - bottom) / np.maximum(r - bottom, 1e-9)


def refine_dipping_rays(x, r, bottom, top):
    """The sky half's coordinate (Bruneton's x, linear in the distance to the top) with the rays past the pivot
    x_p (those that dip below the horizontal) refined: x_p + (1 - x_p)(1 - G(t)), t = (1 - x) / (1 - x_p),
    G(t) = (1 - w) t + w (a S_e(t) + (1 - a) t^2), a = SQRT_SHARE, S_e(t) = (sqrt(t + e) - sqrt(e)) /
    (sqrt(1 + e) - sqrt(e)) with e = LINEAR_ALTITUDE (R_t - R_b) / (r - R_b); x_p and w:
    :func:`dipping_pivot_and_weight`.

    Next to the horizon 1 - x goes as the square of the lowest point's rho, so Bruneton's texels there are
    linear in the lowest point's altitude: from 30 km up some 1.6 km apart, across which the aerosol density at
    the lowest point changes by e^1.3, and the rays just above the horizon read 8.7% off against 1.4% for the
    rest of the sky (standard tables; the seam test, docs/stability.md). The square root makes x linear in the
    lowest point's rho there, as the r axis is in rho; the t^2 term gives back the texels next to the horizontal:
    G'(1) = a / 2 + 2 (1 - a) = 3/4 (1/2 with sqrt(t) alone, which read the view 3 deg from the setting sun
    from 30 km 4.5% off, against 1.1% with Bruneton's x and 1.6% with this G). The square root is softened
    (S_e) for lowest points below LINEAR_ALTITUDE (R_t - R_b) (300 m for the Earth): a pure sqrt(t) put the
    first texel next to the horizon 250 m of lowest-point altitude away from 1.5-3 km up, across which the
    radiance is linear in that altitude, not in its square root, and read those rays 1.4% off against 0.7% for
    the rest of the sky (the dense seam check, docs/benchmarks.md)."""
    x_p, w = dipping_pivot_and_weight(r, bottom, top)
    t = np.clip((1.0 - x) / np.maximum(1.0 - x_p, 1e-300), 0.0, 1.0)
    g = _dipping_g(t, w, _linear_share(r, bottom, top))
    return np.where(x > x_p, x_p + (1.0 - x_p) * (1.0 - g), x)


def _dipping_g(t, w, e):
    return (1.0 - w) * t + w * (SQRT_SHARE * _softened_sqrt(t, e) + (1.0 - SQRT_SHARE) * t * t)


def unrefine_dipping_rays(x, r, bottom, top):
    """Inverse of :func:`refine_dipping_rays`: G(t) = g solved for t by bisection (G is increasing from
    G(0) = 0 to G(1) = 1; 64 halvings reach float64's resolution)."""
    x_p, w = dipping_pivot_and_weight(r, bottom, top)
    g = np.clip((1.0 - x) / np.maximum(1.0 - x_p, 1e-300), 0.0, 1.0)
    e = _linear_share(r, bottom, top)
    lo, hi = np.zeros_like(g * w), np.ones_like(g * w)
    for _ in range(64):
        mid = 0.5 * (lo + hi)
        below = _dipping_g(mid, w, e) < g
        lo, hi = np.where(below, mid, lo), np.where(below, hi, mid)
    return np.where(x > x_p, x_p + (1.0 - x_p) * (1.0 - 0.5 * (lo + hi)), x)


#: The largest H / (R_t - R_b), H = sqrt(R_t^2 - R_b^2), of the geometry on which the tables place the texels of
#: the sun-zenith axis (:func:`x_mu_s_from_mu_s`) and space those of the view-zenith axis (:func:`distance_warp`)
#: (the Earth's is 14.6, Mars's 8.3).
RATIO_LIMIT = 16.0


def limited_geometry(bottom, top):
    """(R_b', R_t'): the planet's own radii, or where its H / (R_t - R_b) exceeds RATIO_LIMIT = K, a smaller planet
    under the same thickness t whose ratio is K: R_b' = t (K^2 - 1) / 2."""
    thickness = top - bottom
    small = min(bottom, thickness * (RATIO_LIMIT ** 2 - 1.0) / 2.0)
    return small, small + thickness


def distance_warp(r, bottom, top, intersects_ground):
    """k [1/m] >= 0 of the view-zenith axis's distance coordinate (:func:`distance_coordinate`) for cameras at
    radius r, in the ground half (``intersects_ground``) or the sky half: k = 1 / d_max' - 1 / d_max, d_max the
    longest ray of that half (to the horizon: rho, or rho + H to the top) and d_max' the same on the planet of
    :func:`limited_geometry` at the same altitude; 0 where the two planets are one.

    Bruneton's coordinate is linear in the ray's length d from d_min (straight up, or down) to d_max. On a planet
    much larger than its atmosphere is thick d_max is many times every ray's length but those next to the horizon:
    under 60 km of air on a planet of 1e9 m the sky seen from the ground from the zenith to 78 deg from it took 2.1%
    of the sky half (rays 60 to 290 km long of 11,000), under one texel of the multiple-scattering tables' 32, and
    it read 2.8% RMS off DISORT's, 4.5% looking down from the top (benchmarks/tables_disort.py). The coordinate is
    taken on d / (1 + k d) instead, which is d for rays much shorter than 1 / k and makes the longest one d_max':
    the axis is spread as on the smaller planet, whose horizon is as far in units of the thickness as the Earth's."""
    r = np.asarray(r, dtype=float)
    small, small_top = limited_geometry(bottom, top)
    if small >= bottom:
        return np.zeros(np.broadcast(r, intersects_ground).shape)
    a = np.maximum(r - bottom, 0.0)
    rho, rho_small = safe_sqrt(r * r - bottom * bottom), np.sqrt(a * (2.0 * small + a))
    h, h_small = np.sqrt(top * top - bottom * bottom), np.sqrt(small_top * small_top - small * small)
    ground = np.asarray(intersects_ground)
    d_max, d_max_small = np.where(ground, rho, rho + h), np.where(ground, rho_small, rho_small + h_small)
    with np.errstate(divide="ignore", invalid="ignore"):         # the ground half at the ground: no rays
        return np.where(d_max_small > 0.0, np.maximum(1.0 / d_max_small - 1.0 / d_max, 0.0), 0.0)


def _warped(d, k):
    return d / (1.0 + k * d)


#: The share of the angle in the view-zenith coordinate: (1 - c) y + c s(y), y linear in the ray's length
#: (:func:`distance_coordinate`), s(y) a square root (``VIEW_ANGLE_OFFSET``). The length, H / cos(theta) next to the
#: zenith and the nadir, is flat there: with c = 0 the sky's first texels seen from the ground lie at 0 and 48.9 deg
#: from the zenith, with c = 1/2 at 0, 19.2, 34.6 deg (random atmosphere 4's plane-parallel twin, 64 mu texels;
#: :func:`sky_angle_offset`).
#: Under a forward lobe in an optically thick atmosphere (that twin) the sky within 35 deg of the zenith read up to
#: +14% / -16% off DISORT with c = 0 (benchmarks/lobe_sky_axes.py).
VIEW_ANGLE_SHARE = 0.5


#: The offset e of the angle-like part of the view-zenith coordinate, s(y) = (sqrt(y + e) - sqrt(e)) / (sqrt(1 + e)
#: - sqrt(e)), in the ground half and, for a camera at the top, in the sky half (:func:`sky_angle_offset`): sqrt(y)
#: alone is linear in the angle next to the zenith and the nadir but its slope there is infinite, and a camera that
#: enters at the top moves its rays' coordinates by 0.013 texel over 1 m (tests/test_tables.py bounds 1e-3), and
#: short ground rays lose their proportion to the length; e = 1.5e-3 keeps both within their tests.
VIEW_ANGLE_OFFSET = 1.5e-3


def sky_angle_offset(r, bottom, top):
    """e of the sky half's :func:`distance_coordinate` for cameras at radius r: VIEW_ANGLE_OFFSET times the
    camera's altitude over the thickness. On the ground e = 0 and s(y) = sqrt(y): the sky's first texels seen from
    there lie at 0, 19.2, 34.6 deg from the zenith (random atmosphere 4's plane-parallel twin, 64 mu texels; with
    e = VIEW_ANGLE_OFFSET at 0, 26.4, 40.3 deg, and under its forward lobe the views 10 deg from the zenith read
    +3.8% / -3.7% off DISORT toward / away from the sun; benchmarks/lobe_sky_axes.py). At the top e =
    VIEW_ANGLE_OFFSET, whose finite slope a camera entering the atmosphere needs."""
    return VIEW_ANGLE_OFFSET * np.clip((np.asarray(r, dtype=float) - bottom) / (top - bottom), 0.0, 1.0)


def distance_coordinate(d, d_min, d_max, k, e):
    """x in [0, 1] of a ray of length d in a half of the view-zenith axis from d_min to d_max:
    (1 - c) y + c (sqrt(y + e) - sqrt(e)) / (sqrt(1 + e) - sqrt(e)), c = ``VIEW_ANGLE_SHARE``, e the half's
    offset (the ground half's ``VIEW_ANGLE_OFFSET``, the sky half's :func:`sky_angle_offset`), y linear
    in d / (1 + k d), k of :func:`distance_warp` (Bruneton's (d - d_min) / (d_max - d_min) for k = 0); 0 where the
    half is a single ray (d_max = d_min)."""
    low = _warped(d_min, k)
    span = _warped(d_max, k) - low
    y = np.clip(np.where(span > 0.0, (_warped(d, k) - low) / np.where(span > 0.0, span, 1.0), 0.0), 0.0, 1.0)
    return (1.0 - VIEW_ANGLE_SHARE) * y + VIEW_ANGLE_SHARE * _softened_sqrt(y, e)


def distance_from_coordinate(x, d_min, d_max, k, e):
    """Inverse of :func:`distance_coordinate` (the same ``e``): the length d of the ray at x; with s = sqrt(y + e),
    the quadratic
    (1 - c) s^2 + (c / D) s - ((1 - c) e + c sqrt(e) / D + x) = 0, D = sqrt(1 + e) - sqrt(e)."""
    c = VIEW_ANGLE_SHARE
    x = np.clip(x, 0.0, 1.0)
    D = np.sqrt(1.0 + e) - np.sqrt(e)
    a, b, q = 1.0 - c, c / D, (1.0 - c) * e + c * np.sqrt(e) / D + x
    s = 2.0 * q / (b + np.sqrt(b * b + 4.0 * a * q))                       # the positive root, no cancellation
    y = np.clip(s * s - e, 0.0, 1.0)
    low = _warped(d_min, k)
    w = low + y * (_warped(d_max, k) - low)
    return w / (1.0 - k * w)


#: The share of the sun's zenith angle in the sun-zenith coordinate (:func:`x_mu_s_from_mu_s`): Bruneton's mapping
#: alone puts the multiple-scattering tables' 32 texels at 0, 45.4, 57.9 ... deg of sun zenith, and a sun 30 deg
#: from the zenith was blended between the zenith and 45 deg (random atmosphere 4's plane-parallel twin, views 55-78
#: deg from the zenith toward the sun +9% to +14% off DISORT; benchmarks/lobe_sky_axes.py); with 0.2, at 0, 16.0,
#: 30.7 ... deg. 0.4 took texels from twilight (the Earth's interpolation error there 1.3% -> 1.9% RMS).
SUN_ANGLE_SHARE = 0.2
#: The sun's largest zenith angle the tables cover [rad].
THETA_S_MAX = float(np.arccos(MU_S_MIN))


def _bruneton_x_mu_s(mu_s, bottom, top):
    """Bruneton's non-linear sun-zenith coordinate (1 at the zenith, 0 at mu_s_min, below 0 past it), on the
    geometry of :func:`limited_geometry`."""
    bottom, top = limited_geometry(bottom, top)
    h = np.sqrt(top * top - bottom * bottom)
    d = distance_to_top_atmosphere_boundary(bottom, mu_s, top)
    d_min, d_max = top - bottom, h
    a = (d - d_min) / (d_max - d_min)
    big_d = distance_to_top_atmosphere_boundary(bottom, MU_S_MIN, top)
    big_a = (big_d - d_min) / (d_max - d_min)
    return (1.0 - a / big_a) / (1.0 + a)


def sun_zenith_angle(mu_s):
    """The sun's zenith angle theta_s = acos(mu_s) [rad] down to mu_s_min, continued below it along its tangent,
    THETA_S_MAX + (MU_S_MIN - mu_s) / sin(THETA_S_MAX), linear in mu_s.

    Only the twilight extrapolation reads it below mu_s_min, and it is exponential in the coordinate: acos's slope
    is infinite at mu_s = -1, where float32's resolution of mu_s (6e-8) is 3.5e-4 rad of sun angle, and the night
    sky of a sun near the nadir read 0.6% apart in the shaders and here; the tangent keeps the slope that of
    mu_s_min (both continuous there)."""
    mu_s = np.clip(mu_s, -1.0, 1.0)
    tangent = THETA_S_MAX + (MU_S_MIN - mu_s) / np.sqrt(1.0 - MU_S_MIN * MU_S_MIN)
    return np.where(mu_s >= MU_S_MIN, np.arccos(mu_s), tangent)


def x_mu_s_from_mu_s(mu_s, bottom, top, clamp=True):
    """The sun-zenith coordinate in [0, 1] (0 at mu_s_min, 1 at the zenith): (1 - c) x_B + c (theta_max - theta_s) /
    theta_max, c = ``SUN_ANGLE_SHARE``, x_B Bruneton's non-linear coordinate on the geometry of
    :func:`limited_geometry`, theta_max = ``THETA_S_MAX``.

    Bruneton's mapping depends on the planet only through H / (R_t - R_b), which grows as sqrt(R_b / (R_t - R_b)):
    the larger it is, the more of the axis goes to the sun near and below the horizon. Under 60 km of air on a
    planet of 1e9 m (ratio 183) the sun from the zenith to 80 deg took 2.6% of the axis (28% on the Earth), under
    one texel of the multiple-scattering tables' 32, and the sky seen from the ground read 6.2% RMS off DISORT's
    (benchmarks/tables_disort.py); the limit keeps at least the share a ratio of 16 gives.

    ``clamp=False`` lets it go negative below mu_s_min, for ``lookup.get_scattering``'s extrapolation (a
    texture coordinate below the first texel centre would read the neighbouring nu slice); there theta_s is
    :func:`sun_zenith_angle`'s, continued along its tangent."""
    x = (1.0 - SUN_ANGLE_SHARE) * _bruneton_x_mu_s(mu_s, bottom, top) + \
        SUN_ANGLE_SHARE * (THETA_S_MAX - sun_zenith_angle(mu_s)) / THETA_S_MAX
    return np.maximum(x, 0.0) if clamp else x


def mu_s_from_x_mu_s(x, bottom, top):
    """Inverse of :func:`x_mu_s_from_mu_s` (rising in mu_s: 64 halvings of [-1, 1] reach float64's resolution)."""
    x = np.asarray(x, dtype=float)
    lo, hi = np.full(x.shape, -1.0), np.full(x.shape, 1.0)
    for _ in range(64):
        mid = 0.5 * (lo + hi)
        below = x_mu_s_from_mu_s(mid, bottom, top, clamp=False) < x
        lo, hi = np.where(below, mid, lo), np.where(below, hi, mid)
    return clamp_cosine(0.5 * (lo + hi))


def r_mu_mu_s_nu_from_scattering_uvwz(u_nu, u_mu_s, u_mu, u_r, bottom, top, size, axis=None):
    """Inverse of :func:`scattering_uvwz_from_r_mu_mu_s_nu`; also returns ``intersects_ground``.

    Exact where nu's range is at least ``NU_RANGE_FLOOR`` wide each side; nearer the poles the slices'
    geometries lie within that range (< 0.02 of nu apart, the same light) and are read back near x_nu = 1/2.
    """
    n_nu, n_mu_s, n_mu, n_r = size
    h = np.sqrt(top * top - bottom * bottom)
    rho = rho_from_x_r(unit_range_from_texcoord(u_r, n_r), h, axis)
    r = np.sqrt(rho * rho + bottom * bottom)
    ground = u_mu < 0.5
    # ground half
    d_g = distance_from_coordinate(unit_range_from_texcoord(1.0 - 2.0 * u_mu, n_mu // 2), r - bottom, rho,
                                   distance_warp(r, bottom, top, True), VIEW_ANGLE_OFFSET)
    mu_g = np.where(d_g == 0.0, -1.0, -(rho * rho + d_g * d_g) / np.where(d_g == 0.0, 1.0, 2.0 * r * d_g))
    # sky half
    x_s = unrefine_dipping_rays(unit_range_from_texcoord(2.0 * u_mu - 1.0, n_mu // 2), r, bottom, top)
    d_s = distance_from_coordinate(x_s, top - r, rho + h, distance_warp(r, bottom, top, False),
                                   sky_angle_offset(r, bottom, top))
    mu_sky = np.where(d_s == 0.0, 1.0, (h * h - rho * rho - d_s * d_s) / np.where(d_s == 0.0, 1.0, 2.0 * r * d_s))
    mu = clamp_cosine(np.where(ground, mu_g, mu_sky))
    mu_s = mu_s_from_x_mu_s(unit_range_from_texcoord(u_mu_s, n_mu_s), bottom, top)
    return r, mu, mu_s, nu_from_x_nu(mu, mu_s, u_nu), ground
