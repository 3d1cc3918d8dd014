"""Multiple scattering, order by order (paper Eq. 8; Bruneton and Neyret Sect. 4), in NumPy.

For order n >= 2, on the grid of the multiple-scattering table (coarser than the single-scattering one):

1. incident radiance L_{n-1}(r, mu_s; w) on a direction quadrature w per point (r, mu_s) (``QUADRATURES``; the
   quality levels' :func:`lit_band_quadrature`: Gauss-Legendre in cos(theta) on the ground's side of the
   point's horizon, on the band of lit air above it where the point lies in the planet's shadow, and on the sky
   above; midpoint rule in azimuth over [0, pi], mirrored by the symmetry about the sun's vertical plane): the
   order n-1 sky radiance from the tables (in an optically thick atmosphere, for n - 1 >= 2, J_{n-1} integrated
   along each direction as in step 4: the density iterated from itself, see ``THICK_DENSITY_ROWS``), plus for
   directions that hit the ground
   T(x, y) (a / pi) E_{n-2}(y) (E_0 = the sun's direct irradiance);
2. scattering density J_n(r, mu, mu_s, nu) = sum_w [beta_R(r) P_R(w . v) + beta_M(r) P_M(w . v)] L_{n-1}(w) dw,
   tabulated per unit density of each component (J_R / rho_R, J_M / rho_M: the densities are exponential
   in altitude and would be overestimated by linear interpolation between r texels a scale height
   apart; they are applied exactly at the integration nodes of step 4), on its own grid: S's r, mu_s and
   nu texels, mu uniform in the view zenith angle (``density_grid``; J is a property of the point and the
   direction, with no seam at the horizon, where S's distance-based mu axis squeezes every view below the
   horizon from low altitude next to the nadir texel):
   the Rayleigh-like part (a + b (w . v)^2) from the zeroth and second angular moments of L, which the
   quadrature integrates exactly; the Mie part from a kernel renormalised on each piece of the quadrature's
   cosines (the ground's side of the horizon, the lit band, the sky) to P_M's integral over it
   (``_mie_kernels``: a coarse direction set cannot resolve a forward peak: renormalising keeps energy right,
   and each piece keeps its share of a lobe that straddles the horizon); the incident light last scattered by
   particles carries their lobe toward the sun, whose aureole the directions sample as coarsely: what they miss
   of the exact integral of each phase function times that lobe (``lobe_convolutions``) is added per view, times
   that light in the sun's direction over the lobe there;
3. indirect irradiance E_{n-1}(r, mu_s) = sum_{w_z > 0} w_z L_{n-1}(w) dw (sky light only), the particles'
   part's aureole around the sun added as for J (``lobe_irradiance_excess``);
4. S_n(r, mu, mu_s, nu) = int_0^d T(x, x_t) J_n(r_t, mu_t, mu_s,t, nu) dt (J read from its table; Gauss-Legendre
   nodes clustered at the closest approach, ``nodes.LONG_RAY_NODE_FACTOR`` times as many along rays
   longer than the ground's horizontal ray to the top, as in the single-scattering stage).

S_n is radiance (phase included) and accumulates into two tables, the light last scattered by molecules
and that last scattered by particles divided by ``forward_factor`` (with the particles' part of J), so
that a sharp forward lobe leaves a slowly varying table, both divided by the ray's ``lookup.ray_opacity``
as the single-scattering tables are; E accumulates into the irradiance table, and J on its top row, views upward,
into the top tables (:func:`top_source`). With ``tolerance`` > 0 the orders stop, from order
``RRE_FIRST_ORDER`` on, where the estimated largest relative error of every order's sum by reduced rank
extrapolation is below ``tolerance`` at every wavelength (``extrapolation.OrderSum``; that sum is then the
tables'), or at ``max_orders`` (the extrapolated sum); before it, where the tail estimated from the ratio q of the
last two orders, S_n q / (1 - q), is below ``tolerance`` of the total in every channel of the scattering and the
irradiance, each of which fell (``tail_settled``; the tail is then added, ``geometric_tail``: the orders of a thin
atmosphere, which fall by its optical depth each). The
geometric tail alone does not stop later orders: it holds only once the orders' shape has settled, and where their
ratio still rises it stops them early (Mars at the standard level: 9 orders, texels 2% off the converged sum,
against 11 orders and 0.01% extrapolated). With ``tolerance`` = 0 the sum is exactly the orders up to
``max_orders``.
"""
from __future__ import annotations

from dataclasses import replace
from typing import NamedTuple

import numpy as np

from .extrapolation import OrderSum
from .horizon import read_single_scattering
from .lookup import (EMPTY_RAY_OPACITY, RayStencil, ScatteringStencil, get_irradiance, get_transmittance,
                     get_transmittance_to_sun, ground_row_factor, ray_opacity)
from .nodes import (LONG_RAY_NODE_FACTOR, ZERO_RAY_LENGTH, depth_distance, integration_grid, is_optically_thick,
                    ray_nodes, scattering_grid, split_ray_nodes)
from .parameterization import (density_uvwz_from_r_mu_mu_s_nu, distance_to_bottom_atmosphere_boundary,
                               distance_to_top_atmosphere_boundary, nu_from_x_nu, ray_intersects_ground,
                               r_mu_s_from_irradiance_uv)
from .sampling import cubic_rows
from .validated import THICK_SCATTERING_DEPTH, particle_scattering_share, scattering_depth
from ..model.optics.phase import PENNDORF_A, double_henyey_greenstein, henyey_greenstein

#: In optically thick atmospheres (vertical optical depth above 1 at some wavelength) the scattering density is
#: iterated from itself on this many times S's r rows: the incident light at its points integrated from the
#: previous order's density along each direction (``_Incident``), not read from S, whose ground half puts every
#: view from the nadir to 15 deg down from its lowest rows into one texel interval, and the density, which at a
#: vertical optical depth of 4 changes within S's first row interval (1.6 km up at standard), not interpolated
#: between S's 8 rows. The energy balance over a black ground (tests/test_stability.py, 440 nm, the 10-bar CO2
#: planet, S at 8 r rows uniform in rho): 0.851 reading S, 0.899 integrating only the directions that meet the
#: ground, 0.952 on 16 rows of its own, 0.966 on 32 at 1.6x the time. With S at 16 rows
#: (``precompute.sizes_for``) on the r axis that follows the optical depth (``parameterization.r_axis``): 0.972
#: on 32 rows of its own, 0.964 on S's 16 (``python benchmarks/energy_balance.py --balance exo-co2-thick``).
THICK_DENSITY_ROWS = 2
#: The first order after which the orders' sum may be taken by reduced rank extrapolation (``OrderSum``).
RRE_FIRST_ORDER = 4
#: Where the largest vertical optical depth exceeds ``DEEP_OPTICAL_DEPTH``, the density has ``DEEP_DENSITY_ROWS``
#: times S's rows (``density_rows``): there the light seen from the ground comes from the first unit of optical
#: depth above it, which 32 rows on the r axis that follows the optical depth cross in about five, and the
#: density changes faster than they follow. Random atmospheres' plane-parallel twins against DISORT
#: (``python benchmarks/tables_disort.py --random``; vertical optical depth 8-10 at the bluest wavelength) read
#: 2.78% -> 1.30% and 5.14% -> 3.57% RMS (100680, 100221: +6.3% / +10.6% at 440 nm from the ground with 2
#: times) and, not looked at before, 1.76% -> 1.58%, 0.99% -> 0.45%, 1.74% -> 1.74%, 1.03% -> 0.97%, 2.35% ->
#: 2.25% (100280, 100509, 100807, 100689, and random atmosphere 1 on its own planet's twin); at
#: optical depths 1.7-5.2 (100930, 100938, 100950, 100951, 100987, 100988) 4 times moved no atmosphere's RMS by
#: more than 0.15 points. The precompute takes 1.2-2.3 times as long (docs/benchmarks.md). The presets (at most
#: 4.1, the 10-bar CO2 planet) keep 2. There the density is also read on refined rows (``density_read_rows``).
DEEP_OPTICAL_DEPTH, DEEP_DENSITY_ROWS = 6.0, 4
#: How many times finer than its own rows such a density is read (``density_read_rows``).
DEEP_DENSITY_REFINEMENT = 2


def density_rows(atm) -> int:
    """How many times S's r rows the scattering density of an optically thick atmosphere has: ``DEEP_DENSITY_ROWS``
    where the largest vertical optical depth exceeds ``DEEP_OPTICAL_DEPTH``, else ``THICK_DENSITY_ROWS``."""
    deep = np.max(atm.vertical_optical_depth()) > DEEP_OPTICAL_DEPTH
    return DEEP_DENSITY_ROWS if deep else THICK_DENSITY_ROWS


def density_read_rows(atm, density_shape) -> int:
    """The r rows on which the scattering density of ``density_shape`` (n_r rows) is read: m (n_r - 1) + 1, m =
    ``DEEP_DENSITY_REFINEMENT``, where the largest vertical optical depth exceeds ``DEEP_OPTICAL_DEPTH``
    (:func:`refined_rows`), else its own.

    Read linearly between the density's own rows the error is O(h^2) in their spacing at every read, and the orders
    compound it: each order's light is read from the last order's density, and in an atmosphere of optical depth
    10 that scatters 95% of what it meets about twenty orders make the light seen from the ground. On random
    atmosphere 942's plane-parallel twin at 440 nm (optical depth 9.8, single-scattering albedo 0.95; tuning split)
    the sky seen from the ground read +1.21% off DISORT on 4 times S's rows read linearly, +0.44% on 8 times,
    -1.01% and -0.13% read geometrically between rows (both tend to about +0.2% as h^2 -> 0), +0.39% with every
    read the cubic through four rows, +0.61% on rows refined twice (m = 2), +0.45% four times (the mean over
    ground_and_top_views' 18 views from the ground). One channel's standard precompute, alternating runs: the cubic
    read took 1.45 times as long as the linear one (65 s against 45 s: it reads twice the texels), m = 2 1.01 and
    1.03 times in two A/Bs, m = 4 1.13 times (52.4 s against 46.4 s); 8 times the rows took 1.3-1.5 times on the
    three channels of random atmospheres 100221 and 100680 (docs/tables.md, "Known defects")."""
    deep = np.max(atm.vertical_optical_depth()) > DEEP_OPTICAL_DEPTH
    return DEEP_DENSITY_REFINEMENT * (density_shape[0] - 1) + 1 if deep else density_shape[0]


def refined_rows(J, n_read):
    """The scattering density J (n_r, ...) on ``n_read`` rows, n_read - 1 a multiple m of n_r - 1: J itself where
    m = 1, else J's rows at every m-th row and between them the cubic through the four rows around
    (``sampling.cubic_rows``; at the midpoint (-J_(i-1) + 9 J_i + 9 J_(i+1) - J_(i+2)) / 16, the four rows shifted
    at the axis's ends), floored at 0 where the cubic overshoots a fall to 0. J's r axis is uniform in its texel
    coordinate, so the refined rows lie on the same axis: a linear read between them is J's cubic read to within
    the linear error over 1 / m of the spacing."""
    n = J.shape[0]
    if n_read == n:
        return J
    m = (n_read - 1) // (n - 1)
    u = (np.arange(n_read) / m + 0.5) / n               # the refined rows' texture coordinates on J's axis
    cubic = sum(w.reshape((-1,) + (1,) * (J.ndim - 1)) * J[k] for k, w in cubic_rows(u, n))
    fine = np.maximum(cubic, 0.0)
    fine[0::m] = J
    return fine.astype(J.dtype, copy=False)


def direction_quadrature(n_theta: int, n_phi: int):
    """Unit directions (K, 3) over azimuths [0, pi] and weights d(cos theta) d(phi); the caller mirrors
    them (y -> -y) for the other half. Gauss-Legendre in cos(theta) on [-1, 0] and [0, 1] separately
    (the horizon is a discontinuity), midpoint rule in azimuth (exact for trigonometric polynomials)."""
    x, w = np.polynomial.legendre.leggauss(n_theta // 2)
    mu = np.concatenate([0.5 * (x - 1.0), 0.5 * (x + 1.0)])
    wm = np.concatenate([0.5 * w, 0.5 * w])
    phi = (np.arange(n_phi) + 0.5) * np.pi / n_phi
    mu_g, phi_g = np.meshgrid(mu, phi, indexing="ij")
    weight = (wm[:, None] * np.full(n_phi, np.pi / n_phi)[None, :]).ravel()
    sin = np.sqrt(np.maximum(1.0 - mu_g * mu_g, 0.0)).ravel()
    dirs = np.stack([sin * np.cos(phi_g.ravel()), sin * np.sin(phi_g.ravel()), mu_g.ravel()], -1)
    return dirs, weight


def _gauss(n, a, b):
    """Gauss-Legendre nodes and weights (..., n) on [a, b] (arrays of the same shape)."""
    x, w = np.polynomial.legendre.leggauss(n)
    a, b = np.asarray(a)[..., None], np.asarray(b)[..., None]
    return a + (b - a) * 0.5 * (x + 1.0), (b - a) * 0.5 * w


def _with_azimuths(mu, w_mu, n_phi):
    """Directions (..., K, 3) and weights (..., K), K = n_cos n_phi, of cosines mu (..., n_cos) with weights w_mu
    times n_phi azimuths on the midpoint rule over [0, pi] from the sun's (+x)."""
    phi = (np.arange(n_phi) + 0.5) * np.pi / n_phi
    mu_g = np.repeat(mu, n_phi, axis=-1)
    phi_g = np.tile(phi, mu.shape[-1])
    sin = np.sqrt(np.maximum(1.0 - mu_g * mu_g, 0.0))
    return (np.stack([sin * np.cos(phi_g), sin * np.sin(phi_g), mu_g], -1),
            np.repeat(w_mu, n_phi, axis=-1) * (np.pi / n_phi))


def _toward_horizon(n, mu_h, linear=0.0):
    """n cosines (..., n) and weights on the sky's side [mu_h, 1] (mu_h (...)), mu_h + (1 - mu_h) (l x + (1 - l)
    x^2) with l = ``linear`` and x on Gauss-Legendre nodes in [0, 1]: clustered toward the horizon (the more, the
    smaller l), and exact for polynomials in mu of degree n - 1."""
    x, w = _gauss(n, 0.0, 1.0)
    mu_h = np.asarray(mu_h)[..., None]
    return (mu_h + (1.0 - mu_h) * (linear * x + (1.0 - linear) * x * x),
            (1.0 - mu_h) * (linear + 2.0 * (1.0 - linear) * x) * w)


def horizon_quadrature(r, mu_s, bottom, top, n_theta: int, n_phi: int):
    """Per point (r (n_r,), mu_s (n_mu_s,)): unit directions (n_r, n_mu_s, K, 3), K = n_theta n_phi, over azimuths
    [0, pi] and weights (n_r, n_mu_s, K) d(cos theta) d(phi); the caller mirrors them (y -> -y). Cosines split at
    the ground's horizon seen from r, mu_h = -sqrt(1 - (R / r)^2), where the incident light jumps from the ground's to
    the sky's: n_theta / 2 Gauss-Legendre nodes on [-1, mu_h] and n_theta / 2 on [mu_h, 1] at
    mu_h + (1 - mu_h) x^2, x on Gauss-Legendre nodes in [0, 1], clustered toward the horizon, where the sky is
    brightest and, seen from the planet's shadow, the only lit air lies; midpoint rule in azimuth. The same at
    every mu_s."""
    mu_h = -np.sqrt(np.maximum(1.0 - (bottom / np.asarray(r, float)) ** 2, 0.0))
    ground_mu, ground_w = _gauss(n_theta // 2, np.full_like(mu_h, -1.0), mu_h)
    sky_mu, sky_w = _toward_horizon(n_theta - n_theta // 2, mu_h)
    dirs, weights = _with_azimuths(np.concatenate([ground_mu, sky_mu], -1), np.concatenate([ground_w, sky_w], -1),
                                   n_phi)
    ends = np.stack([-np.ones_like(mu_h), mu_h, np.ones_like(mu_h)], -1)
    n_mu_s = np.size(mu_s)
    return tuple(np.broadcast_to(x[:, None], (len(mu_h), n_mu_s) + x.shape[1:]) for x in (dirs, weights, ends))


def lit_band_top(r, mu_s, bottom, top):
    """(whether the point (r, mu_s) sees lit air only in a band above its horizon, the cosine mu_b of the band's top)
    (...): the point lies in the planet's shadow (mu_s < mu_h, the sun below its horizon) and so does the air
    straight above it up to the top of the atmosphere, and mu_b = sin e_b is the elevation toward the sun whose ray
    leaves the atmosphere at the shadow's edge. A ray at elevation e in the sun's vertical plane leaves at the central
    angle gamma(e) = pi/2 - e - asin(r cos e / r_top) from the point (decreasing in e), where the top is lit if the
    angle from the sun's direction is below pi/2 + alpha, alpha = acos(R / r_top): lit for gamma > theta_s - pi/2 -
    alpha; e_b by bisection. Rays toward other azimuths reach lit air lower, if at all."""
    r, mu_s = np.broadcast_arrays(np.asarray(r, float), np.asarray(mu_s, float))
    mu_h = -np.sqrt(np.maximum(1.0 - (bottom / r) ** 2, 0.0))
    target = np.arccos(np.clip(mu_s, -1.0, 1.0)) - 0.5 * np.pi - np.arccos(bottom / top)
    e_h = np.arcsin(mu_h)

    def gamma(e):
        return 0.5 * np.pi - e - np.arcsin(np.clip(r * np.cos(e) / top, -1.0, 1.0))
    band = (mu_s < mu_h) & (target > 0.0) & (gamma(e_h) > target)
    low, high = e_h, np.full(r.shape, 0.5 * np.pi)
    for _ in range(48):
        mid = 0.5 * (low + high)
        lit = gamma(mid) > target
        low, high = np.where(lit, mid, low), np.where(lit, high, mid)
    return band, np.where(band, np.sin(low), mu_h)


#: The share of the vertical scattering optical depth that may lie above the top of the air whose lit part
#: :func:`lit_band_quadrature` looks for (:func:`scattering_top`).
LIT_AIR_SHARE = 1e-3


def scattering_top(atm, share=LIT_AIR_SHARE):
    """The radius [m] above which ``share`` of the vertical scattering optical depth lies (at the wavelength where
    that altitude is highest): the shadow's edge above it lights next to nothing. Midpoint rule on 4096 slabs."""
    h = (np.arange(4096) + 0.5) / 4096 * atm.thickness_m
    beta = (atm.rayleigh.profile.density(h)[:, None] * np.asarray(atm.rayleigh.scattering_m)
            + atm.mie.profile.density(h)[:, None] * np.asarray(atm.mie.scattering_m))
    above = np.cumsum(beta[::-1], axis=0)[::-1] / np.maximum(beta.sum(0), 1e-300)     # share at and above each slab
    highest = max(h[np.nonzero(above[:, w] >= share)[0].max()] if np.any(above[:, w] >= share) else 0.0
                  for w in range(beta.shape[1]))
    return atm.bottom_radius_m + min(highest + 0.5 * atm.thickness_m / 4096, atm.thickness_m)


#: The linear share l of :func:`lit_band_quadrature`'s sky cosines outside the band (:func:`_toward_horizon`):
#: clustered toward the horizon for twilight, less than x^2 so that the sky near the zenith, where a forward lobe
#: gathers its light, keeps nodes. Chosen on the tuning split: the presets' 12 daylight rays at standard
#: (benchmarks/tables_vs_reference.py) read Mars 2.45% / 1.77% / 1.61% / 1.89% RMS at l = 0 / 0.5 / 0.75 / 1
#: (40 cosines: 1.31%; noise 0.35%), the 10-bar planet 1.28% / 1.27% / 1.23% / 1.16% (40 cosines 1.23%, noise
#: 0.93%: below resolution) and Earth 0.28% / 0.28% / 0.29% / 0.29% (noise 0.09%); the first two orders in deep
#: twilight (benchmarks/tables_orders.py) 59.7% / 59.7% / - / 64.2% RMS, from cameras within 100 m of the top 28.5% /
#: 35.0% / - / 38.7% (noise 9.4%; without the top tables, ``top_source``).
LIT_BAND_SKY_LINEAR = 0.5


def lit_band_quadrature(r, mu_s, bottom, top, n_theta: int, n_phi: int):
    """Per point (r (n_r,), mu_s (n_mu_s,)), ``top`` the radius of :func:`scattering_top`: directions
    (n_r, n_mu_s, K, 3) and weights (n_r, n_mu_s, K) as
    :func:`horizon_quadrature`'s, with 3/10 of the cosines (at least 1, of 3 or more) on the ground's side;
    where the point sees lit air only in a band above its horizon (:func:`lit_band_top`), 4/10 of them on the band
    [mu_h, mu_b] and the rest above it, each Gauss-Legendre; elsewhere the rest on the sky's side clustered toward
    the horizon (:func:`_toward_horizon` with l = LIT_BAND_SKY_LINEAR)."""
    if n_theta < 3:
        raise ValueError(f"directions: the lit-band quadrature needs at least 3 cosines (n_theta), got {n_theta}")
    r, mu_s = np.asarray(r, float)[:, None], np.asarray(mu_s, float)[None, :]
    n_ground = max(1, round(0.3 * n_theta))
    n_band = max(1, round(0.4 * n_theta))
    band, mu_b = lit_band_top(r, mu_s, bottom, top)
    mu_h = np.broadcast_to(-np.sqrt(np.maximum(1.0 - (bottom / r) ** 2, 0.0)), band.shape)
    ground_mu, ground_w = _gauss(n_ground, np.full(band.shape, -1.0), mu_h)
    in_band = _gauss(n_band, mu_h, mu_b)
    above = _gauss(n_theta - n_ground - n_band, mu_b, np.ones(band.shape))
    sky_mu, sky_w = _toward_horizon(n_theta - n_ground, mu_h, LIT_BAND_SKY_LINEAR)
    mu = np.where(band[..., None], np.concatenate([in_band[0], above[0]], -1), sky_mu)
    w_mu = np.where(band[..., None], np.concatenate([in_band[1], above[1]], -1), sky_w)
    ends = np.stack([-np.ones(band.shape), mu_h, np.where(band, mu_b, mu_h), np.ones(band.shape)], -1)
    return _with_azimuths(np.concatenate([ground_mu, mu], -1), np.concatenate([ground_w, w_mu], -1), n_phi) + (ends,)


#: The scattering density's direction quadratures (``multiple_scattering``): the same at every point
#: (:func:`direction_quadrature`, Gauss-Legendre on each side of the horizontal) and those per point (r, mu_s), of
#: which ``lit-band`` is the quality levels' (``TableSizes.quadrature``).
QUADRATURES = {"hemispheres": None, "horizon": horizon_quadrature, "lit-band": lit_band_quadrature}


class _Incident:
    """Geometry of the incident-radiance samples at points (r, mu_s) and directions w (K, 3), or (n_r, n_mu_s, K, 3)
    per point of r (n_r, 1) and mu_s (1, n_mu_s), fixed for all orders.

    With ``along_rays`` = (the scattering density's table shape, nodes per side), the orders >= 2 of
    the sky light come from the previous order's scattering density integrated along each direction to the
    top or the ground (:func:`_density_along_rays`), not from S: the stage then iterates the density on its
    own grid, and S is only its output. Used for optically thick atmospheres (``multiple_scattering``)."""

    def __init__(self, tables, atm, r, mu_s, dirs, ms_shape, with_ground=True, along_rays=None):
        shape = np.broadcast_shapes(np.shape(r), np.shape(mu_s)) + (dirs.shape[-2],)
        self.r = np.broadcast_to(np.asarray(r)[..., None], shape)
        self.mu_s = np.broadcast_to(np.asarray(mu_s)[..., None], shape)
        self.mu = np.broadcast_to(dirs[..., 2], shape)
        self.nu = dirs[..., 0] * np.sqrt(np.maximum(1 - self.mu_s ** 2, 0.0)) + dirs[..., 2] * self.mu_s
        self.ground = ray_intersects_ground(self.r, self.mu, tables.bottom)
        d_ground = distance_to_bottom_atmosphere_boundary(self.r, self.mu, tables.bottom)
        self.forward = None
        if along_rays is None:
            self.stencil = ScatteringStencil(tables, ms_shape, self.r, self.mu, self.mu_s, self.nu, self.ground)
            # lookup.ground_row_factor of the multiple-scattering tables at these points
            self.multiple_factor = ground_row_factor(tables, self.r, self.mu, self.ground, ms_shape[0])
            self.rays = None
        else:
            density_shape, samples = along_rays
            d = np.where(self.ground, d_ground, distance_to_top_atmosphere_boundary(self.r, self.mu, tables.top))
            # in blocks of whole points r, about RAY_BLOCK_POINTS nodes each (five segments of 2 n nodes)
            block = max(RAY_BLOCK_POINTS // (int(np.prod(shape[1:])) * 10 * samples), 1)
            self.rays = [_density_along_rays(tables, atm, density_shape, *(a[i:i + block] for a in (
                self.r, self.mu, self.mu_s, self.nu, self.ground, d)), samples, split=True, thick=True)
                for i in range(0, shape[0], block)]
        self.with_ground = with_ground and bool(np.any(self.ground))
        if self.with_ground:
            d = d_ground
            self.mu_s_g = np.clip((self.r * self.mu_s + d * self.nu) / tables.bottom, -1.0, 1.0)
            t_g = get_transmittance(tables, self.r, self.mu, d)
            self.ground_factor = np.where(self.ground[..., None], t_g * np.asarray(atm.ground_albedo) / np.pi, 0.0)

    def sky_parts(self, tables, atm, order, ms_prev, density_prev=None):
        """(light last scattered by molecules, by particles) (..., K, W): the sky radiance of that order (from
        ``density_prev``, J of that order, where the geometry integrates along the rays)."""
        if order == 1:                            # as the evaluator reads it
            s_r, s_m = read_single_scattering(tables, atm, self.r, self.mu, self.mu_s, self.nu, self.ground)
            return s_r * atm.rayleigh.phase_function(self.nu)[..., None], s_m * atm.mie.phase_function(self.nu)
        if self.forward is None:                  # the same every order: computed once
            self.forward = forward_factor(atm, self.nu)
        if self.rays is not None:
            both = np.concatenate([stencil.apply(density_prev, along=node_weight)
                                   for stencil, node_weight in self.rays])
            W = both.shape[-1] // 2
            return both[..., :W], self.forward * both[..., W:]
        both = self.stencil.apply(ms_prev)
        W = both.shape[-1] // 2
        return both[..., :W] * self.multiple_factor, self.forward * both[..., W:] * self.multiple_factor

    def radiance(self, tables, atm, order, ms_prev, irr_prev, density_prev=None):
        """(L_order, its light last scattered by particles) (..., K, W): L_order is the sky radiance of that order
        plus the ground lit by E_{order-1}."""
        molecules, particles = self.sky_parts(tables, atm, order, ms_prev, density_prev)
        sky = molecules + particles
        if not self.with_ground:
            return sky, particles
        bottom = np.full(self.mu_s_g.shape, tables.bottom)
        if order == 1:
            e = get_transmittance_to_sun(tables, bottom, self.mu_s_g) * np.maximum(self.mu_s_g, 0.0)[..., None]
        else:
            e = get_irradiance(tables, bottom, self.mu_s_g, table=irr_prev)
        return sky + self.ground_factor * e, particles


def forward_factor(atm, nu):
    """F(nu) = s DHG(nu; g1+^2, g2+^2, alpha) + (1 - s) / (4 pi), (..., W) [1/sr], g+ = max(g, 0), s the
    particles' share of the vertical scattering optical depth (``validated.particle_scattering_share``): the
    angular shape of the light the particles scatter the second time, from incident light that is their own
    forward lobe toward the sun in the share s (a Henyey-Greenstein lobe convolved with itself is the lobe of g^2)
    and the molecules' broad light in the rest, which a lobe turns into light nearly as broad.

    The particles' share of the scattering density and of the multiple-scattering table is stored divided
    by F(nu) and multiplied back on reading: with a forward lobe like Mars dust's (g = 0.88, s = 0.98-1.0) the raw
    values peak so sharply toward the sun that interpolating them between texels 20 deg apart mixes the peak into
    other directions; divided by F they vary slowly. Under a lobe that holds a small share of the scattering
    (an aerosol under Earth's air, s = 0.08-0.32) the light is broad, and divided by the lobe alone it would vary
    as 1 / F: the sky seen from the ground 10-48 deg from the sun read 2-5% high against DISORT and 2-3% low away
    from it (benchmarks/tables_disort.py). A backward lobe (g < 0) counts as isotropic: its light turns back with
    each order (twice is forward, three times backward again), so no single lobe describes it, and the lobe of g^2
    multiplied onto it made the sky 15 deg from the sun twice too bright for g = -0.99
    (benchmarks/edge_accuracy.py; tests/test_tables.py).
    """
    g1, g2, alpha = (np.maximum(np.asarray(x, dtype=float), 0.0) if k < 2 else np.asarray(x, dtype=float)
                     for k, x in enumerate((atm.mie.g1, atm.mie.g2, atm.mie.alpha)))
    share = particle_scattering_share(atm)
    lobe = double_henyey_greenstein(np.asarray(nu, dtype=float)[..., None], g1 * g1, g2 * g2, alpha)
    return share * lobe + (1.0 - share) / (4.0 * np.pi)


def thick_forward_range(atm) -> float:
    """The largest range F(1) / F(-1) of ``forward_factor`` (dimensionless, 1 for a broad F) at a wavelength where
    the whole vertical scattering optical depth exceeds ``validated.THICK_SCATTERING_DEPTH``; 1 where it is less
    everywhere. There the light is broad, and the particles' part, stored divided by F, varies across the nu axis
    about as much as F does (``precompute.sizes_for``)."""
    ratio = forward_factor(atm, 1.0) / forward_factor(atm, -1.0)
    return float(np.max(np.where(scattering_depth(atm) > THICK_SCATTERING_DEPTH, ratio, 1.0), initial=1.0))


def _view_vectors(mu, mu_s, nu):
    """View directions in the frame where z is the zenith and the sun lies in the x-z plane (x > 0)."""
    sin_s = np.sqrt(np.maximum(1.0 - mu_s * mu_s, 0.0))
    vx = np.where(sin_s > 1e-6, (nu - mu * mu_s) / np.maximum(sin_s, 1e-6), np.sqrt(np.maximum(1 - mu * mu, 0)))
    vx = np.clip(vx, -1.0, 1.0)
    vy = np.sqrt(np.maximum(1.0 - mu * mu - vx * vx, 0.0))
    return np.stack([vx, vy, mu], -1)


#: Sub-samples per side of a direction's cell in the particles' phase kernels (``_mie_kernels``): 1 samples the
#: phase function at the direction; n > 1 integrates it over the direction's cell by the midpoint rule on n^2 points.
#: 1 at every level: with 2 the light the dust's lobe sends down from the limb to a camera just under Mars's top
#: follows the view within 0-4% (the point rule's 5-46% high), but the lobe's weight then goes to the one direction
#: of its cell, where the point rule, renormalised, spreads it over the directions next to its axis, and order 2 from
#: Mars's ground 45 deg up away from the sun reads 7.9-11.4% low against its direct integration (2.0-4.2% with 1;
#: both with the ``hemispheres`` quadrature and the kernels renormalised over the whole sphere;
#: tests/test_multiple_scattering.py); the suite by day moves by less than its noise either way (docs/benchmarks.md,
#: "Orders above the first near the top").
KERNEL_CELL_SAMPLES = 1


def _cells(dirs, weights, n_phi, samples):
    """Sub-sample directions (..., K, samples^2, 3) of each direction's cell: the quadratures' directions are n_cos
    cosines (ascending) times n_phi azimuths (index k = i n_phi + j, weight w_i pi / n_phi, as ``_with_azimuths``
    and :func:`direction_quadrature` make them), so the cells [b_i, b_(i+1)] x [j, j + 1] pi / n_phi with
    b_i = -1 + sum of the cosine weights before i tile the half-sphere; the sub-samples lie at the midpoints of a
    samples x samples split of each cell. ``samples`` = 1: the directions themselves."""
    if samples == 1:
        return dirs[..., None, :]
    K = dirs.shape[-2]
    w_mu = weights[..., ::n_phi] * (n_phi / np.pi)                                   # (..., n_cos)
    b = np.concatenate([np.full(w_mu.shape[:-1] + (1,), -1.0), -1.0 + np.cumsum(w_mu, -1)], -1)
    f = (np.arange(samples) + 0.5) / samples
    mu = b[..., :-1, None] + (b[..., 1:] - b[..., :-1])[..., None] * f               # (..., n_cos, m)
    phi = (np.arange(n_phi)[:, None] + f) * (np.pi / n_phi)                          # (n_phi, m)
    mu = np.broadcast_to(mu[..., :, None, :, None], mu.shape[:-1] + (n_phi, samples, samples))
    phi = np.broadcast_to(phi[:, None, :], mu.shape)
    sin = np.sqrt(np.maximum(1.0 - mu * mu, 0.0))
    out = np.stack([sin * np.cos(phi), sin * np.sin(phi), mu], -1)                   # (..., n_cos, n_phi, m, m, 3)
    return out.reshape(out.shape[:-5] + (K, samples * samples, 3))


#: The grid of :func:`_cap_integrals`: edges x = cos(theta), theta uniform over [0, pi] (fine at the poles, where a
#: lobe seen from the zenith or the nadir changes within 1e-3 in x), and angles from the view
#: gamma = pi (u - sin(2 pi u) / (2 pi)), u on the midpoint rule, clustered at both ends for forward and backward
#: lobes: G within 2.4e-4 of a brute-force integral over the sphere for g from -0.9 to 0.95
#: (tests/test_multiple_scattering.py), in 0.04 s for 64 views and 3 phase functions.
CAP_EDGES, CAP_ANGLES = 1025, 256


def _cap_integrals(phases, mu_v):
    """The phase function's integrals over polar caps, on the edges x (CAP_EDGES,) of ``CAP_EDGES``:
    G(mu_v, x) = int_{w_z < x} P(v . w) dw, scaled so that G(mu_v, 1) = 1, (n_phase, n_v, CAP_EDGES), for views of
    zenith cosine ``mu_v`` (n_v,) and the phase functions ``phases`` (callables of the scattering angle's cosine
    [1/sr]).

    Around the view, the directions at angle gamma from it form a circle, of which the share below the cap's edge
    (w_z < x) is f = 1 - acos(t) / pi, t = (x - mu_v cos gamma) / (sin theta_v sin gamma) clipped to [-1, 1]; so
    G = 2 pi int_0^pi P(cos gamma) f sin gamma d(gamma), a one-dimensional integral (``CAP_ANGLES`` nodes)."""
    x = np.cos(np.linspace(np.pi, 0.0, CAP_EDGES))
    u = (np.arange(CAP_ANGLES) + 0.5) / CAP_ANGLES
    gamma = np.pi * (u - np.sin(2.0 * np.pi * u) / (2.0 * np.pi))
    dw = 2.0 * np.pi * np.sin(gamma) * np.pi * (1.0 - np.cos(2.0 * np.pi * u)) / CAP_ANGLES   # 2 pi sin(gamma) dgamma
    weights = np.stack([phase(np.cos(gamma)) * dw for phase in phases], -1).astype(np.float32)
    G = np.empty((len(phases), len(mu_v), CAP_EDGES))
    cos_g, sin_g = np.cos(gamma).astype(np.float32), np.sin(gamma).astype(np.float32)
    x32 = x.astype(np.float32)[:, None]
    for i, mu in enumerate(np.asarray(mu_v, float)):
        sin_v = np.float32(np.sqrt(max(1.0 - mu * mu, 0.0)))
        t = (x32 - np.float32(mu) * cos_g) / np.maximum(sin_v * sin_g, np.float32(1e-12))
        share = np.float32(1.0) - np.arccos(np.clip(t, -1.0, 1.0, out=t), out=t) * np.float32(1.0 / np.pi)
        G[:, i] = (share @ weights).T
    return x, G / G[..., -1:]


def _piece_masses(x, G, ends):
    """The phase function's weight on each piece of a quadrature's cosines, G(b) - G(a) for the pieces [a, b]
    between consecutive ``ends`` (U, n_e), (n_phase, U, n_v, n_e - 1), G of :func:`_cap_integrals` read linearly in
    the grid's angle."""
    pos = np.arccos(np.clip(-ends, -1.0, 1.0)) / np.pi * (len(x) - 1)      # the grid runs from theta = pi
    i = np.clip(pos.astype(int), 0, len(x) - 2)
    f = np.clip(pos - i, 0.0, 1.0)
    g = G[..., i] + f * (G[..., i + 1] - G[..., i])                             # (n_phase, n_v, U, n_e)
    return np.swapaxes(np.diff(g, axis=-1), 1, 2)


def _mie_kernels(atm, views, dirs, weights, ends, n_phi, n_r, samples=KERNEL_CELL_SAMPLES):
    """Per wavelength, the renormalised kernel of each direction w_k, P_M(v . w_k) + P_M(v . w_k') times its weight
    (w' the mirror image about the sun's plane), or with ``samples`` > 1 its cell's integral of the same by
    :func:`_cells`' sub-samples,
    for the views (n_mu, n_nu, n_mu_s, 3) at every point (r, mu_s) and the directions ``dirs`` (K, 3) with
    ``weights`` (K,) (the same at every point), or per point (n_r, n_mu_s, K, 3) and (n_r, n_mu_s, K). Returns
    (the kernels, one per wavelength, each (U, n_mu, n_nu, K) float32, the same array for wavelengths of the same
    phase function; the kernel of each point, (n_r, n_mu_s) indices into U).

    A forward lobe narrower than a direction's cell (g = 0.88: the half width at half maximum is 5.6 deg, the cells
    of 10 azimuths over pi are 18 deg wide) sampled at the directions misses most of its weight, which the
    renormalisation (which keeps the energy) spreads over the directions next to its axis; the cell integral
    gives each cell its share of the lobe (``KERNEL_CELL_SAMPLES`` says which the levels use and why). The
    renormalisation is per piece of the quadrature's cosines, between consecutive ``ends`` (..., n_e) (the
    ground's side of the horizon, the lit band, the sky; :func:`lit_band_quadrature`): each piece's directions
    share P_M's integral over that piece (:func:`_cap_integrals`), so that a lobe which straddles the horizon
    weighs the ground's light and the sky's as it should, whichever directions lie next to its axis. (Over the whole
    sphere at once, a horizontal view under a lobe of g = 0.94 gave its weight to the sky's nodes 1-2 deg above the
    horizon rather than the ground's 6 deg below, and the first two orders from the ground of a thin atmosphere over
    a bright ground read 10.5% low; benchmarks/tables_orders.py, random atmosphere 100004.) Points whose directions
    and views agree to 1e-6 (at a given r, every sun above the horizon) share a kernel: it is computed once per
    distinct point and kept once (on the lit-band quadrature 94-96 distinct of Mars's 768 points and random
    atmosphere 809's 1536)."""
    n_mu_s = views.shape[2]
    dirs = np.broadcast_to(dirs, (n_r, n_mu_s) + dirs.shape[-2:])
    weights = np.broadcast_to(weights, (n_r, n_mu_s) + weights.shape[-1:])
    ends = np.broadcast_to(ends, (n_r, n_mu_s) + ends.shape[-1:])
    column = np.moveaxis(views, 2, 0).reshape(n_mu_s, -1)                            # the views per mu_s
    key = np.concatenate([dirs.reshape(n_r, n_mu_s, -1), weights, ends,
                          np.broadcast_to(column, (n_r,) + column.shape)], -1).reshape(n_r * n_mu_s, -1)
    _, first, inverse = np.unique(np.round(key, 6), axis=0, return_index=True, return_inverse=True)
    r_i, s_i = np.divmod(first, n_mu_s)
    sub = _cells(dirs[r_i, s_i], weights[r_i, s_i], n_phi, samples).astype(np.float32)   # (U, K, m^2, 3)
    v = np.moveaxis(views, 2, 0)[s_i].reshape(len(first), -1, 3).astype(np.float32)      # (U, V, 3)
    n = 4096
    phase_table = atm.mie.phase_function(np.linspace(-1.0, 1.0, n + 1)).astype(np.float32)
    lobes = [(atm.mie.g1[w], atm.mie.g2[w], atm.mie.alpha[w]) for w in range(atm.n_wavelengths)]
    tabs = {lobe: phase_table[:, lobes.index(lobe)] for lobe in lobes}    # one kernel per distinct phase function
    sums = {lobe: np.zeros(v.shape[:2] + sub.shape[1:2], np.float32) for lobe in tabs}
    for mirror in (np.float32([1.0, 1.0, 1.0]), np.float32([1.0, -1.0, 1.0])):
        for q in range(sub.shape[2]):
            c = np.einsum("uvi,uki->uvk", v, sub[:, :, q] * mirror)
            x = (c + np.float32(1.0)) * np.float32(n / 2.0)
            i = np.clip(x.astype(np.int32), 0, n - 1)
            f = x - i
            for lobe, tab in tabs.items():
                lower = np.take(tab, i)
                sums[lobe] += lower + f * (np.take(tab, i + 1) - lower)
    # each piece's share of the phase function (``_piece_masses``), spread over its directions as sampled
    mu_v, view_row = np.unique(np.round(views[..., 2], 9), return_inverse=True)
    view_row = np.moveaxis(view_row.reshape(views.shape[:3]), 2, 0)[s_i].reshape(len(first), -1, 1)
    point_ends = ends[r_i, s_i]
    cosines = dirs[r_i, s_i][..., 2]                                                   # (U, K)
    piece = np.minimum((point_ends[:, None, 1:] <= cosines[..., None]).sum(-1), point_ends.shape[-1] - 2)
    x, G = _cap_integrals([lambda c, w=lobes.index(lobe): atm.mie.phase_function(c)[..., w] for lobe in tabs], mu_v)
    masses = _piece_masses(x, G, point_ends)
    in_piece = (piece[..., None] == np.arange(point_ends.shape[-1] - 1)).astype(np.float32)   # (U, K, pieces)
    out = {}
    for (lobe, k), mass in zip(sums.items(), masses):
        k *= weights[r_i, s_i][:, None, :].astype(np.float32)
        sampled = np.matmul(k, in_piece)                                               # (U, V, pieces)
        mass = np.take_along_axis(mass, view_row, axis=1).astype(np.float32)
        scale = np.where(sampled > 0.0, mass / np.where(sampled > 0.0, sampled, 1.0), 0.0)
        k *= np.take_along_axis(scale, np.broadcast_to(piece[:, None, :], k.shape), axis=-1)
        out[lobe] = k.reshape((len(first),) + views.shape[:2] + k.shape[-1:])
    return [out[lobe] for lobe in lobes], inverse.reshape(n_r, n_mu_s)


#: Rays whose optical depth exceeds ``SPLIT_OPTICAL_DEPTH`` at some wavelength before ``SPLIT_NODE_SHARE`` of their
#: quadrature nodes are integrated on segments (``nodes.split_ray_nodes``: the first up to that depth of the
#: most extinguished wavelength), in every atmosphere (in optically thick ones, every ray): a ray that leaves the
#: ground 1.7 deg up on a planet of 4e8 m crosses an optical depth of 18 at 440 nm, nearly all of it in the first
#: 0.4% of its 60,000 km, where one Gauss-Legendre rule over the whole ray puts 2 of its 16 nodes (order 2 read 7.2%
#: low there, 0.6% split in two at that depth; benchmarks/tables_orders.py, random atmosphere 100005; 6.6% low with
#: the split only where a quarter of the nodes lie before that depth). 18% of Earth's texels' rays are split (38%
#: reach that depth: splitting them all cost its standard precompute 0.3 s of 3.5).
SPLIT_OPTICAL_DEPTH, SPLIT_NODE_SHARE = 3.0, 0.5
#: The texels' rays are prepared in blocks of about this many nodes (``_ray_paths``): the geometry of every node
#: of every texel at once (several float64 arrays of 40 million nodes under the lobe texels of a thick atmosphere)
#: would take several GB.
RAY_BLOCK_POINTS = 2 ** 22


def _ray_paths(tables, atm, size, samples, thick, density_shape):
    """Integration along the texels' rays, fixed for all orders, in up to four sets: rays up to the length of the
    ground's horizontal ray to the top, and longer ones, which graze the planet from high up and get
    ``nodes.LONG_RAY_NODE_FACTOR`` times the nodes (through the limb seen from space the density peaks in
    the middle of a 1600 km ray: with 8 nodes order 2 read 11% above its value with 4x the nodes at 440 nm,
    tests/test_tables.py); each of them split in segments where its optical depth exceeds
    ``SPLIT_OPTICAL_DEPTH`` before ``SPLIT_NODE_SHARE`` of its nodes (every ray where the atmosphere is optically
    ``thick``). The rays are ``nodes.integration_grid``'s for a table of ``size``. Returns [(rays, an
    index into the (n_r, n_mu) axes; the stencil reading J, a table of ``density_shape``, at the nodes; node
    weights (rays, n_nu, n_mu_s, K, 2W), the view transmittance, each component's density and 1 / the ray's
    ``lookup.ray_opacity`` folded in, against J's 2W channels)]."""
    r, mu, mu_s, nu, ground, d = integration_grid(tables, size)
    r2, mu2, g2, d2 = r[:, :, 0, 0], mu[:, :, 0, 0], ground[:, :, 0, 0], d[:, :, 0, 0]
    opacity = ray_opacity(tables, r2, mu2, g2)
    long_ray = d2 > np.sqrt(tables.top ** 2 - tables.bottom ** 2)
    t_plain, _ = ray_nodes(r2, mu2, d2, samples)
    t_split = depth_distance(atm, r2, mu2, d2, SPLIT_OPTICAL_DEPTH)
    deep = thick | ((t_plain < t_split[..., None]).sum(-1) < SPLIT_NODE_SHARE * t_plain.shape[-1])
    paths = []
    for long, split in ((False, False), (True, False), (False, True), (True, True)):
        every = np.nonzero((long_ray == long) & (deep == split))
        n = samples * (LONG_RAY_NODE_FACTOR if long else 1)
        block = max(RAY_BLOCK_POINTS // (mu_s[0, 0].size * 2 * n), 1)
        for start in range(0, every[0].size, block):
            rays = tuple(i[start:start + block] for i in every)
            rr, mm, gg, dd = (a[rays][:, None, None] for a in (r2, mu2, g2, d2))        # (rays, 1, 1)
            stencil, node_weight = _density_along_rays(tables, atm, density_shape, rr, mm, mu_s[rays], nu[rays], gg,
                                                       dd, n, split, thick, stencil=RayStencil)
            per_opacity = np.concatenate([opacity[rays], opacity[rays]], -1)[:, None, None, None, :]
            # Where the scattering opacity is below EMPTY_RAY_OPACITY the ray holds no light a table can show
            # (S < 1e-30 J): its mean is stored as 0. Dividing there (the weights carry the densities, J the
            # coefficients) overflows float32 and gives inf x 0 = NaN for a component whose coefficient is 0.
            weight = np.divide(node_weight, per_opacity, out=np.zeros(np.broadcast_shapes(node_weight.shape,
                                                                                         per_opacity.shape)),
                               where=per_opacity > EMPTY_RAY_OPACITY)
            paths.append((rays, stencil, weight.astype(np.float32)))
    return paths


def _density_along_rays(tables, atm, shape, r, mu, mu_s, nu, ground, d, n, split, thick, stencil=ScatteringStencil):
    """The integral int_0^d T(x, x_t) J(x_t) dt along rays (r, mu, mu_s, nu) of length d to the top or the
    ground, prepared for J's table of ``shape``: (the ``stencil`` (a class of lookup.py's; :class:`RayStencil`
    where the rays' texels share their nodes' (r, mu)) reading J at the nodes, node weights (..., K, 2W)
    with the view transmittance and each component's density folded in, against J's 2W channels). r, mu,
    ``ground`` and d broadcast against mu_s and nu; n nodes per side of the closest approach
    (``nodes.ray_nodes``), on segments where ``split`` (``nodes.split_ray_nodes``, five where the atmosphere is
    optically ``thick``)."""
    t, wt = (split_ray_nodes(atm, r, mu, d, n, SPLIT_OPTICAL_DEPTH, thick=thick) if split
             else ray_nodes(r, mu, d, n))                                                    # (..., K)
    r, mu, d = r[..., None], mu[..., None], d[..., None]
    r_t = np.clip(np.sqrt(np.maximum(t * t + 2 * r * mu * t + r * r, 0.0)), tables.bottom, tables.top)
    mu_t = np.clip((r * mu + t) / r_t, -1.0, 1.0)
    mu_s_t = np.clip((r * mu_s[..., None] + t * nu[..., None]) / r_t, -1.0, 1.0)
    stencil = stencil(tables, shape, r_t, mu_t, mu_s_t, nu[..., None], ground[..., None],
                      mapping=density_uvwz_from_r_mu_mu_s_nu)
    path_weight = wt[..., None] * get_transmittance(tables, r, mu, t)
    h_t = r_t - tables.bottom
    node_weight = np.concatenate([path_weight * atm.rayleigh.profile.density(h_t)[..., None],
                                  path_weight * atm.mie.profile.density(h_t)[..., None]], -1)
    return stencil, node_weight.astype(np.float32)


def sun_centred_quadrature(mu_s, n_alpha, n_beta):
    """Directions (n, K, 3) around the sun s = (sqrt(1 - mu_s^2), 0, mu_s) for each mu_s (n,), and weights
    (n, K) of the irradiance integral sum_k c_k L(w_k) = int_{w_z > 0} L(w) w_z dw for radiance symmetric about
    the sun's vertical plane: the angle from the sun alpha = pi u^2, u on Gauss-Legendre nodes (clustered at
    the sun), the azimuth around it on the midpoint rule over [0, pi] (x2: the mirrored half),
    c_k = dw_k max(w_z, 0)."""
    u, wu = np.polynomial.legendre.leggauss(n_alpha)
    u, wu = 0.5 * (u + 1.0), 0.5 * wu
    alpha = np.pi * u * u
    beta = (np.arange(n_beta) + 0.5) * np.pi / n_beta
    a, b = (x.ravel() for x in np.meshgrid(alpha, beta, indexing="ij"))
    dw = np.repeat(2.0 * np.pi * u * wu * np.sin(alpha), n_beta) * (2.0 * np.pi / n_beta)
    mu_s = np.asarray(mu_s, dtype=float)[:, None]
    sin_s = np.sqrt(np.maximum(1.0 - mu_s * mu_s, 0.0))
    # +z turned onto the sun in the x-z plane
    x = np.sin(a) * np.cos(b) * mu_s + np.cos(a) * sin_s
    z = -np.sin(a) * np.cos(b) * sin_s + np.cos(a) * mu_s
    dirs = np.stack([x, np.broadcast_to(np.sin(a) * np.sin(b), x.shape), z], -1)
    return dirs, dw * np.maximum(z, 0.0)


def _sun_direction(mu_s):
    """The sun's direction (..., 3) in the frame where z is the zenith and the sun lies in the x-z plane (x >= 0)."""
    mu_s = np.asarray(mu_s, dtype=float)
    return np.stack([np.sqrt(np.maximum(1.0 - mu_s * mu_s, 0.0)), np.zeros_like(mu_s), mu_s], -1)


def lobe_irradiance_excess(atm, dirs, cos_weights, mu_s, fine=32):
    """(order 1, orders >= 2) (n_mu_s, W): what the irradiance's quadrature sum_k c_k lobe(w_k . s) over the upward
    directions ``dirs`` (K, 3) with weights ``cos_weights`` (K,) (mirrored azimuths included) misses of
    int_{w_z > 0} lobe(w . s) w_z dw, on a fine grid around the sun (``sun_centred_quadrature``), for suns at mu_s
    (n_mu_s,) and the particles' lobe toward the sun: P_M for order 1, F (``forward_factor``) above.

    The particles' sky light is a smooth function sigma times that lobe; its aureole, which the upward directions
    alone miss or catch on one of them, gets this times sigma in the sun's direction. Under Mars dust's g = 0.91
    lobe the 10x10 grid alone read the sky's irradiance of the ground 33% low at 440 nm with the sun 60 deg up
    (against the tables' own sky integrated over 96x192 directions); the ground seen from above and every order
    after read low with it."""
    mu_s = np.asarray(mu_s, dtype=float)
    sin_s = np.sqrt(np.maximum(1.0 - mu_s * mu_s, 0.0))[:, None]
    nu = dirs[:, 0] * sin_s + dirs[:, 2] * mu_s[:, None]
    fine_dirs, fine_weights = sun_centred_quadrature(mu_s, fine, fine)
    nu_fine = fine_dirs[..., 0] * sin_s + fine_dirs[..., 2] * mu_s[:, None]
    return [np.einsum("nk,nkw->nw", fine_weights, lobe(nu_fine)) - np.einsum("k,nkw->nw", cos_weights, lobe(nu))
            for lobe in (atm.mie.phase_function, lambda c: forward_factor(atm, c))]


def density_grid(mu_s, n_mu, n_nu):
    """(mu, nu) at the texel centres of the scattering density's table for S's mu_s (..., n_mu_s) (its r and
    mu_s texels are S's): mu uniform in the view zenith angle (``density_uvwz_from_r_mu_mu_s_nu``), nu over
    the range that (mu, mu_s) allow, each (..., n_mu, n_nu, n_mu_s)."""
    mu = np.cos(np.pi * (np.arange(n_mu) + 0.5) / n_mu)[:, None, None]
    x_nu = (np.arange(n_nu) / max(n_nu - 1, 1))[:, None]
    mu_s = np.asarray(mu_s)[..., None, None, :]
    return np.broadcast_to(mu, np.broadcast_shapes(mu.shape, mu_s.shape, x_nu.shape)), nu_from_x_nu(mu, mu_s, x_nu)


def geometric_tail(now, before, q_max=0.99):
    """q / (1 - q) per channel (the last axis), q = sum(now) / sum(before) over the other axes (at most
    ``q_max``): the sum of every order after ``now`` if each is q times the one before, as the orders become once
    their angular and vertical shape has settled. Added where the orders stop by this tail (they fall fast);
    where they fall slowly the sum is extrapolated instead (``extrapolation.OrderSum``)."""
    axes = tuple(range(now.ndim - 1))
    q = np.clip(now.sum(axes) / np.maximum(before.sum(axes), 1e-300), 0.0, q_max)
    return q / (1.0 - q)


def tail_settled(now, before, total, tolerance):
    """Whether the orders may stop at ``now`` with :func:`geometric_tail` added: in every channel (the last axis)
    the order fell from the one ``before`` (q < 1) and its tail, sum(now) q / (1 - q) over the other axes, is at
    most ``tolerance`` of the channel's ``total`` so far; a channel with nothing in it is settled. Over a bright
    ground the orders do not fall at first: the ground's light of order n lights the sky of order n + 1, and a thin
    atmosphere over a white ground has twice the sky irradiance of order 1 in order 2 and a five-hundredth of order
    2 in order 3 (random atmosphere 9, 550 nm: optical depth 0.002, ground albedo 0.94). Its tail estimated from
    orders 1 and 2, q capped at 0.99, read the sky's irradiance 99 times order 2's, 20% of the sun's."""
    axes = tuple(range(now.ndim - 1))
    s_now, s_before, s_total = now.sum(axes), before.sum(axes), total.sum(axes)
    empty = (s_now <= 0.0) & (s_before <= 0.0)
    falls = s_now < s_before
    q = np.where(falls, s_now / np.where(falls, s_before, 1.0), 0.0)
    return bool(np.all(empty | (falls & (s_now * q / (1.0 - q) <= tolerance * s_total))))


class MultipleScattering(NamedTuple):
    """The multiple-scattering stage's output (:func:`multiple_scattering`)."""

    multiple: np.ndarray        # (n_r, n_mu, n_nu, n_mu_s, W) S of the light last scattered by molecules, over opacity
    multiple_mie: np.ndarray    # the same for particles, divided by ``forward_factor``
    irradiance: np.ndarray      # (n_r, n_mu_s, W) indirect irradiance
    orders: int                 # the highest order used
    top: np.ndarray             # (n_mu / 2, n_nu, n_mu_s, W) upward views at the top (:func:`top_source`), molecules
    top_mie: np.ndarray         # and particles, divided by ``forward_factor``


def multiple_scattering(tables, atm, size, n_theta=16, n_phi=16, samples=8, tolerance=1e-3, max_orders=64,
                        progress=None, quadrature="hemispheres", extrapolate=True) -> MultipleScattering:
    """The orders >= 2 (:class:`MultipleScattering`): tables (n_r, n_mu, n_nu, n_mu_s, W) of light last scattered by
    molecules and by particles, the latter divided by ``forward_factor``; indirect irradiance; highest order used;
    the top tables of upward views (:func:`top_source`).

    Steps: the incident light's directions (the quadrature's, and the sun's for the aureole the quadrature
    misses) and the irradiance's (``_Incident``); the scattering density's grid and phase kernels
    (``_DensityKernels``); the integration paths of S's texels (``_ray_paths``); then order by order the incident
    light of the order before, the scattering density J (``_DensityKernels.density``), S integrated along the
    texels' rays, the irradiance, J on its top row for upward views, until every order's extrapolated sum
    (``extrapolation.OrderSum``) is within ``tolerance`` at every texel (from order ``RRE_FIRST_ORDER``; before
    it, until the geometric tail of the orders is below ``tolerance`` of the total, that tail added), or at
    ``max_orders`` (the extrapolated sum); the top row's J as the top tables (:func:`top_source`).

    ``quadrature``: the incident light's directions at the density's points (``QUADRATURES``), ``"hemispheres"``
    (``direction_quadrature``, the same at every point), ``"horizon"`` (``horizon_quadrature``, split at each row's
    horizon) or ``"lit-band"`` (``lit_band_quadrature``, on the band of lit air seen from the planet's shadow: the
    quality levels', which the precompute passes as ``TableSizes.quadrature``); benchmarks/tables_orders.py compares
    them. ``extrapolate``: False stops the orders by their geometric tail or ``max_orders`` alone, the tail added
    (benchmarks/orders_sum.py compares them).
    """
    if quadrature not in QUADRATURES:
        raise ValueError(f"quadrature must be one of {tuple(QUADRATURES)}, got {quadrature!r}")
    r, mu, mu_s, nu, ground = scattering_grid(tables, size)
    shape = r.shape
    W = atm.n_wavelengths
    dirs, weights = direction_quadrature(n_theta, n_phi)
    r_axis, mu_s_axis = r[:, 0, 0, 0], mu_s[0, 0, 0, :]
    # Optically thick (vertical optical depth above 1 at some wavelength): nodes within the first attenuation
    # lengths too, and the scattering density iterated on its own grid (``density_rows`` times S's r rows)
    # from itself, the incident light integrated along the rays (``_Incident``).
    thick = is_optically_thick(atm)
    density_shape = shape
    along_rays = None
    read_shape = density_shape
    if thick:
        density_shape = (density_rows(atm) * shape[0],) + shape[1:]
        read_shape = (density_read_rows(atm, density_shape),) + shape[1:]
        r_axis = scattering_grid(tables, size[:3] + (density_shape[0],))[0][:, 0, 0, 0]
        along_rays = (read_shape, samples)
    if quadrature == "hemispheres":
        point_dirs, point_weights, ends = dirs, weights, np.array([-1.0, 0.0, 1.0])
    else:
        point_dirs, point_weights, ends = QUADRATURES[quadrature](r_axis, mu_s_axis, tables.bottom, scattering_top(atm),
                                                           n_theta, n_phi)
    # the incident light on the quadrature's directions and, last, the sun's (its particles' part over their lobe
    # there is sigma_sun of ``_DensityKernels.density``)
    points = (len(r_axis), len(mu_s_axis))
    every_dir = np.concatenate([np.broadcast_to(point_dirs, points + point_dirs.shape[-2:]),
                                np.broadcast_to(_sun_direction(mu_s_axis)[None, :, None], points + (1, 3))], -2)
    incident = _Incident(tables, atm, r_axis[:, None], mu_s_axis[None, :], every_dir, shape, along_rays=along_rays)
    lobe_at_sun = (atm.mie.phase_function(1.0), forward_factor(atm, 1.0))
    n_mu_s_i, n_r_i = tables.sizes.irradiance
    u, v = np.meshgrid((np.arange(n_mu_s_i) + 0.5) / n_mu_s_i, (np.arange(n_r_i) + 0.5) / n_r_i)
    r_irr, mu_s_irr = r_mu_s_from_irradiance_uv(u, v, tables.bottom, tables.top, (n_mu_s_i, n_r_i))
    up = dirs[:, 2] > 0
    irr_dirs = np.concatenate([np.broadcast_to(dirs[up], r_irr.shape + dirs[up].shape),
                               _sun_direction(mu_s_irr)[..., None, :]], -2)
    sky_above = _Incident(tables, atm, r_irr, mu_s_irr, irr_dirs, shape, with_ground=False)
    cos_weights = 2.0 * weights[up] * dirs[up, 2]            # x2: the mirrored azimuths
    # the particles' lobe in the sky of order 1 is P_M, in the orders above F (``lobe_irradiance_excess``)
    lobe_excess = [f[None, :, :] for f in lobe_irradiance_excess(atm, dirs[up], cos_weights, mu_s_irr[0])]
    kernels = _DensityKernels(atm, size, mu_s, point_dirs, point_weights, ends, density_shape, n_phi)
    forward = forward_factor(atm, nu)                          # F(nu) at S's texels

    # Integration along each texel's ray: nodes, view transmittance and J's stencils, fixed for all orders;
    # rays longer than the ground's horizontal ray get LONG_RAY_NODE_FACTOR times the nodes.
    paths = _ray_paths(tables, atm, size, samples, thick, read_shape)

    total = np.zeros(shape + (2 * W,))
    irradiance = np.zeros(r_irr.shape + (W,))
    upward = density_shape[1] // 2                     # the density grid's views above the horizontal
    top_total = np.zeros((upward,) + density_shape[2:] + (2 * W,))
    ms_prev = irr_prev = J_prev = None
    last = None
    order = 1
    orders = OrderSum(W) if tolerance > 0 and extrapolate else None
    extrapolated = False
    for order in range(2, max_orders + 1):
        L, particles = incident.radiance(tables, atm, order - 1, ms_prev, irr_prev, J_prev)  # (n_r, n_mu_s, K + 1, W)
        sigma_sun = particles[..., -1, :] / lobe_at_sun[order > 2]
        molecules, sky_particles = sky_above.sky_parts(tables, atm, order - 1, ms_prev)
        e = np.einsum("k,abkw->abw", cos_weights, molecules[..., :-1, :] + sky_particles[..., :-1, :]) + \
            lobe_excess[order > 2] * sky_particles[..., -1, :] / lobe_at_sun[order > 2]
        J = refined_rows(kernels.density(L[..., :-1, :], sigma_sun, order - 1), read_shape[0])
        S = np.empty(shape + (2 * W,))                                            # [S_R, S_M / F(nu)]
        for rays, stencil, node_weight in paths:
            S[rays] = stencil.apply(J, along=node_weight)
        total += S
        irradiance += e
        top_total += J[-1, :upward]
        before = (ms_prev, irr_prev)
        ms_prev, irr_prev, J_prev = S, e, J
        size_now = (S[..., :W] + forward * S[..., W:]).sum()
        done = (total[..., :W] + forward * total[..., W:]).sum()
        if orders is not None:
            orders.add(S, e, J[-1, :upward])
        if last is not None and last > 0:
            if orders is not None and order >= RRE_FIRST_ORDER:
                if np.all(orders.error(below=tolerance) < tolerance):
                    extrapolated = True
                    break
            elif tail_settled(S, before[0], total, tolerance) and tail_settled(e, before[1], irradiance, tolerance):
                break
        if progress and done > 0:
            progress(f"multiple scattering, order {order}", min(1.0, 1.0 - size_now / done))
        last = size_now
    else:
        extrapolated = orders is not None and order >= RRE_FIRST_ORDER
    if extrapolated:                          # every order's sum by reduced rank extrapolation
        total, irradiance, top_total = orders.sum()
    elif tolerance > 0 and order > 2:        # the orders after the last, as a geometric series
        tail = geometric_tail(ms_prev, before[0])
        total += ms_prev * tail
        top_total += J_prev[-1, :upward] * tail
        irradiance += irr_prev * geometric_tail(irr_prev, before[1])
    if progress:
        progress(f"multiple scattering, {order} orders", 1.0)
    top, top_mie = top_source(atm, top_total)
    return MultipleScattering(total[..., :W], total[..., W:], irradiance, order, top, top_mie)


def top_source(atm, density):
    """(molecules, particles) (n_up, n_nu, n_mu_s, W): what the 4D multiple-scattering tables hold for rays of zero
    length at the top of the atmosphere looking up, by view zenith angle, from ``density`` (n_up, n_nu, n_mu_s, 2W),
    the scattering density per unit density of each component [J_R / rho_R, J_M / (rho_M F)] summed over the
    orders, on its grid's top row and its n_up views above the horizontal (u = theta / (pi / 2), texel centres at
    (i + 1/2) / n_up; the 4D tables' nu and mu_s texels).

    The 4D tables hold S over the ray's scattering opacity, int J T dt / int beta^scat T dt, which for a ray of
    zero length is J_R rho_R / beta^scat and J_M rho_M / beta^scat, beta^scat = beta_R^scat rho_R + beta_M^scat rho_M,
    each at the point; here at ``nodes.ZERO_RAY_LENGTH`` times the thickness under the top, where the tables' own
    texels of zero length are integrated, and 0 where nothing scatters there (every ray then has zero opacity).

    Why: every ray that leaves the top of the atmosphere upward from the tables' top row interval reads the top
    row at u_mu next to 1/2, where the mu axis follows the distance to the top: a ray of zero length from the top
    row, the same texel for every zenith angle. Under a forward lobe the light at the top changes fast with the
    view's zenith angle (the limb's light, seen next to the horizontal): from 33 m under Mars's top the tables'
    order 2 read 1.2-1.9 times the reference's looking at the zenith and 0.24-0.31 times at a zenith cosine of 0.1
    (``benchmarks/top_views.py``); :func:`lookup.get_scattering` reads these tables in the top row's place for
    such rays."""
    W = density.shape[-1] // 2
    h = np.array([(1.0 - ZERO_RAY_LENGTH) * atm.thickness_m])
    beta_r, beta_m = (b[0] for b in atm.scattering(h))
    beta = beta_r + beta_m
    rho_r, rho_m = atm.rayleigh.profile.density(h)[0], atm.mie.profile.density(h)[0]
    per_beta = np.where(beta > 0.0, 1.0 / np.where(beta > 0.0, beta, 1.0), 0.0)
    return density[..., :W] * rho_r * per_beta, density[..., W:] * rho_m * per_beta


def _hg_terms(atm):
    """The particles' lobes as sums of Henyey-Greenstein terms, (weights, g) each (n_terms, W): the phase function
    P_M of order 1's light (``Mie.phase_function``) and the shape F of the orders above (``forward_factor``, its
    isotropic part a term of g = 0)."""
    g1, g2, alpha = (np.asarray(x, dtype=float) for x in (atm.mie.g1, atm.mie.g2, atm.mie.alpha))
    share = particle_scattering_share(atm)
    phase = (np.stack([alpha, 1.0 - alpha]), np.stack([g1, g2]))
    shape = (np.stack([share * alpha, share * (1.0 - alpha), 1.0 - share]),
             np.stack([np.maximum(g1, 0.0) ** 2, np.maximum(g2, 0.0) ** 2, np.zeros_like(g1)]))
    return phase, shape


def lobe_convolutions(atm, nu):
    """For the particles' lobe toward the sun in the incident light of order 1 (P_M) and of the orders above (F),
    the exact integrals over the sphere int P(v . w) lobe(w . s) dw [1/sr] as functions of nu = v . s (...,):
    ((P_R * P_M, P_M * P_M), (P_R * F, P_M * F)), each (..., W).

    Both phase functions and both lobes are sums of Henyey-Greenstein terms (``_hg_terms``, P_R of Legendre
    moments 1 and f_2) and the sphere's addition theorem multiplies Legendre moments, HG(g) having g^l:
    HG(a) * HG(b) = HG(a b), and P_R * lobe = (1 + 5 f_2 h_2 P_2(nu)) / (4 pi) with h_2 the lobe's second moment,
    f_2 = 2 A / (15 + 5 A) for P_R = (1 + A nu^2) / (4 pi (1 + A / 3)) (1/10 for Rayleigh's A = 1).
    tests/test_multiple_scattering.py checks both against brute-force integrals."""
    nu = np.asarray(nu, dtype=float)[..., None, None]
    a = 1.0 if atm.rayleigh.phase == "rayleigh" else PENNDORF_A
    f_2 = 2.0 * a / (15.0 + 5.0 * a)
    p_2 = 0.5 * (3.0 * nu[..., 0, :] ** 2 - 1.0)
    lobes = _hg_terms(atm)
    c_p, g_p = lobes[0]
    out = []
    for c_l, g_l in lobes:
        h_2 = np.sum(c_l * g_l ** 2, 0)
        rayleigh = (1.0 + 5.0 * f_2 * h_2 * p_2) / (4.0 * np.pi)
        mie = np.sum((c_p[:, None] * c_l[None]).reshape(-1, c_p.shape[-1]) *
                     henyey_greenstein(nu, (g_p[:, None] * g_l[None]).reshape(-1, g_p.shape[-1])), -2)
        out.append((rayleigh, mie))
    return tuple(out)


class _DensityKernels:
    """The scattering density J on its own grid (S's mu_s texels and r rows, ``density_rows`` times as many
    rows in a thick atmosphere), per unit density of each component: the Rayleigh-like phase
    (1 + A c^2) / (4 pi (1 + A / 3)) by moments of the incident light, Mie by renormalised kernels
    (``_mie_kernels``), the particles' part divided by F(nu) (``forward_factor``).

    The light last scattered by particles is a slowly varying function sigma times their lobe toward the sun (P_M
    in order 1, F above; ``sky_parts``), which a direction quadrature samples as coarsely as the phase function:
    the aureole around the sun, of a few degrees under g = 0.9, falls between its directions or on one of them.
    What the quadrature's sum of each phase function times the lobe misses of its exact integral
    (:func:`lobe_convolutions`), per view v, is the aureole's (``lobe_excess``); J gets it back times sigma in the
    sun's direction (``density``'s ``sigma_sun``)."""

    def __init__(self, atm, size, mu_s, dirs, weights, ends, density_shape, n_phi):
        self.a_coef = 1.0 if atm.rayleigh.phase == "rayleigh" else PENNDORF_A
        mu_j, nu_j = density_grid(mu_s[:1, 0, 0, :], size[2], size[0])                 # the same at every r
        views = np.broadcast_to(_view_vectors(mu_j, mu_s[:1], nu_j), density_shape + (3,))
        full_dirs = np.concatenate([dirs, dirs * np.array([1.0, -1.0, 1.0])], axis=-2)
        outer = np.einsum("...ki,...kj->...kij", full_dirs, full_dirs)         # (..., 2K, 3, 3)
        self.outer = np.swapaxes(outer.reshape(outer.shape[:-2] + (9,)), -1, -2)   # (..., 9, 2K)
        vv = np.einsum("...i,...j->...ij", views[0], views[0])                   # (n_mu, n_nu, n_mu_s, 3, 3)
        self.vv = np.moveaxis(vv.reshape(-1, vv.shape[2], 9), 1, 0)              # (n_mu_s, n_mu n_nu, 9)
        self.beta_r = np.asarray(atm.rayleigh.scattering_m)
        self.beta_m = np.asarray(atm.mie.scattering_m)
        mie_kernels, point_kernel = _mie_kernels(atm, views[0], dirs, weights, ends, n_phi, density_shape[0])
        self.kernel_groups = [(k, [w for w, other in enumerate(mie_kernels) if other is k])
                              for k in {id(k): k for k in mie_kernels}.values()]
        self.kernel_points = [np.nonzero(point_kernel.ravel() == u)[0] for u in range(len(mie_kernels[0]))]
        self.forward_j = forward_factor(atm, nu_j)                      # (1, n_mu, n_nu, n_mu_s, W)
        self.weights = weights
        self.shape = density_shape
        self.W = atm.n_wavelengths
        mu_s_axis = mu_s[0, 0, 0, :]
        sin_s = np.sqrt(np.maximum(1.0 - mu_s_axis ** 2, 0.0))
        dirs = np.broadcast_to(dirs, (density_shape[0], len(mu_s_axis)) + dirs.shape[-2:])
        nu_k = dirs[..., 0] * sin_s[:, None] + dirs[..., 2] * mu_s_axis[:, None]          # (n_r, n_mu_s, K)
        lobes = (atm.mie.phase_function(nu_k), forward_factor(atm, nu_k))
        self.lobe_excess = [(exact[0] - self._rayleigh_like(lobe), exact[1] - self._mie(lobe))
                            for lobe, exact in zip(lobes, lobe_convolutions(atm, nu_j))]

    def _rayleigh_like(self, L):
        """sum_w P_R(w . v) L(w) dw at every view of the density grid, (density grid + (W,)), by the zeroth and
        second angular moments of L (n_r, n_mu_s, K, W), which the quadrature integrates exactly."""
        W = L.shape[-1]
        w_full = np.concatenate([self.weights, self.weights], axis=-1)
        L_full = np.concatenate([L, L], axis=2) * w_full[..., None]
        m0 = L_full.sum(2)                                                          # (n_r, n_mu_s, W)
        n_r, n_mu_s = L.shape[:2]
        m2 = np.matmul(self.outer, L_full)                                          # (n_r, n_mu_s, 9, W)
        # v^T m2 v at every view: one matrix product per mu_s, (n_mu n_nu, 9) by (9, n_r W)
        quad = np.matmul(self.vv, np.moveaxis(m2, 0, 2).reshape(n_mu_s, 9, n_r * W))
        quad = np.moveaxis(quad.reshape((n_mu_s,) + self.shape[1:3] + (n_r, W)), (0, 3), (3, 0))
        return (m0[:, None, None] + self.a_coef * quad) / (4 * np.pi * (1 + self.a_coef / 3))

    def _mie(self, L):
        """sum_w P_M(w . v) L(w) dw by the renormalised kernels at every view of the density grid, (density grid +
        (W,)), float32, for L (n_r, n_mu_s, K, W)."""
        n_r, n_mu_s, K = L.shape[:3]
        W = L.shape[-1]
        mie = np.empty((W, n_r * n_mu_s) + self.shape[1:3], np.float32)
        for kernel, ws in self.kernel_groups:
            L_ws = L[..., ws].astype(np.float32).reshape(n_r * n_mu_s, K, len(ws))
            for u, points in enumerate(self.kernel_points):
                # one matrix product per distinct kernel, for its points and the wavelengths that share it
                light = np.moveaxis(L_ws[points], 0, 1).reshape(K, -1)                   # (K, points ws)
                product = (kernel[u].reshape(-1, K) @ light).reshape(self.shape[1:3] + (len(points), len(ws)))
                for i, w in enumerate(ws):
                    mie[w, points] = np.moveaxis(product[..., i], 2, 0)
        return np.transpose(mie.reshape((W, n_r, n_mu_s) + self.shape[1:3]), (1, 3, 4, 2, 0))

    def density(self, L, sigma_sun, order):
        """J (density grid + (2W,), float32: [J_R, J_M / F]) from the incident light L of ``order`` (n_r, n_mu_s,
        K, W) on the quadrature's directions (their mirror images about the sun's plane included by symmetry), plus
        the aureole the quadrature misses, ``lobe_excess`` times ``sigma_sun`` (n_r, n_mu_s, W), the light last
        scattered by particles in the sun's direction over their lobe there.

        J per unit density of each component: its angular part varies slowly with altitude; the density,
        which does not, is applied exactly at every integration node."""
        W = self.W
        excess_r, excess_m = self.lobe_excess[order > 1]
        sigma = sigma_sun[:, None, None]                                   # on J's axes (n_r, ., ., n_mu_s, W)
        J = np.empty(self.shape + (2 * W,), np.float32)
        J[..., :W] = self.beta_r * (self._rayleigh_like(L) + excess_r * sigma)
        J[..., W:] = self.beta_m * (self._mie(L) + excess_m * sigma) / self.forward_j
        return J


def first_two_orders(tables, atm, sizes, directions=None, quadrature=None):
    """``tables`` (a :class:`~planetviz.tables.precompute.Tables`) with their multiple-scattering tables holding
    order 2 only and their sky irradiance that of order 1: the multiple-scattering stage stopped after order 2,
    with ``sizes`` (the :class:`~planetviz.tables.precompute.TableSizes` the tables were made with) and the
    scattering density's direction quadrature ``directions`` (n_theta, n_phi; default ``sizes.directions``) of the
    kind ``quadrature`` (``QUADRATURES``; default ``sizes.quadrature``). What the reference's ``max_order=2`` is
    compared with (benchmarks/tables_orders.py)."""
    out = multiple_scattering(tables, atm, sizes.multiple, *(directions or sizes.directions),
                              samples=sizes.multiple_samples, tolerance=0.0, max_orders=2,
                              quadrature=quadrature or sizes.quadrature)
    return replace(tables, multiple=out.multiple.astype(np.float32), multiple_mie=out.multiple_mie.astype(np.float32),
                   irradiance=out.irradiance.astype(np.float32), top_multiple=out.top.astype(np.float32),
                   top_multiple_mie=out.top_mie.astype(np.float32))
