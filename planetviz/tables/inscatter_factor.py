"""The small tables that the per-vertex renderer's inscatter factor reads per pixel (shaders/inscatter_factor.glsl,
the GLSL twins of :func:`path_opacity_u` and :func:`phase_factor_u`): the opacity and the scattering opacity of
every view ray from the frame's ray altitude, the phase functions, and the sky's irradiance on the ground.

**Path opacity.** The opacity 1 - T of every view ray from one altitude, and the share of it that scatters light
(``nodes.scattering_share``): their product, the integral of beta_scat T along the ray, is what the inscatter grows
with along the limb's halo and toward the horizon, where an absorbing layer (ozone) raises the opacity and not the
inscatter.

All the rays of a frame start at the same altitude a (the camera's, or the top of the atmosphere for a camera in
space, where the rays enter), so their opacity to where they leave the atmosphere or meet the ground is a function
of mu alone. Read from the 2D optical-depth table it costs a pixel two lookups of it (the ground ray's is the
difference of two), and on a software renderer, which runs both sides of a branch, three; from this table, one.

The table has two halves, like the mu axis of the 4D tables (Bruneton 2017): u in [0, 1/2] for the rays that meet
the ground, x = (d - a) / (rho - a) of their length d to the ground; u in [1/2, 1] for the others,
x = (d - d_min) / (d_max - d_min) of their length to the top, d_min = R_t - r (straight up), d_max = rho + H (to
the horizon and on to the top), rho = sqrt(r^2 - R_b^2), H = sqrt(R_t^2 - R_b^2); each half's texels are centred
on its own range (``texcoord_from_unit_range``), so filtering never mixes the two sides of the horizon. Uniform in
the ray's length, the table follows the limb's halo as finely as the optical depth changes there: from the top of
the Earth's atmosphere a texel is 0.2 km of tangent altitude (34 texels per 8 km scale height).

**Phases.** The phase functions of the inscatter's four parts (the molecules', the particles' double
Henyey-Greenstein phase, 1 for the molecules' orders above the first, ``forward_factor`` for the particles')
as functions of u = s / sqrt(2) toward the sun (nu >= 0) and 1 - c / sqrt(2) away from it, s = sin(theta / 2) =
sqrt((1 - nu) / 2), c = cos(theta / 2) = sqrt((1 + nu) / 2), theta the view-sun angle: a lobe of asymmetry |g| is
(1 - |g|) / (2 sqrt(|g|)) wide in s (forward) or c (backward), 19 texels for |g| = 0.95, where linear
interpolation's error is below 2e-3.

**Sky irradiance.** The sky's irradiance on the ground E(0, mu_s) as the tables read it (``get_irradiance``),
on rows of mu_s from the irradiance table's last texel below MU_S_MIN to 1: the table's own texels where the
texel above has the sun up (there the table is read linearly, so linear filtering between these rows is that
reading exactly), and IRRADIANCE_SUBROWS rows per texel below (there the table is read geometrically, an
exponential between texels, which linear filtering between rows 1/IRRADIANCE_SUBROWS of a texel apart follows
within about (ln q / IRRADIANCE_SUBROWS)^2 / 8 for a change by q over the texel: 0.34% for the Earth's steepest,
e^1.3 over a standard texel of 0.9 deg). The renderer stores the phases times this irradiance, an outer product,
as one 2D texture: bilinear filtering of a product f(x) g(y) of two tables is the product of their linear
interpolations, so one fetch reads both factors. At standard quality the texture takes 3.8 MB per group of four
wavelengths (1024 x 232 texels).
"""
from __future__ import annotations

import numpy as np

from .lookup import get_irradiance, get_optical_depth, get_optical_depth_to_top_atmosphere_boundary, one_minus_exp
from .multiple import forward_factor
from .nodes import scattering_share
from .parameterization import (MU_S_MIN, distance_to_bottom_atmosphere_boundary,
                               distance_to_top_atmosphere_boundary, safe_sqrt, texcoord_from_unit_range,
                               unit_range_from_texcoord)

#: Texels of each half of the path-opacity table (the rays to the ground, the others).
PATH_OPACITY_TEXELS = 1024
#: Texels of the phase table along u (module docstring), 0 .. 1.
PHASE_FACTOR_TEXELS = 1024
#: Gauss-Legendre nodes per side of a ray's closest approach for ``nodes.scattering_share``.
SCATTERING_SHARE_NODES = 48
#: Texels of the path-opacity table between those whose scattering share is computed.
SCATTERING_SHARE_STRIDE = 8
#: The change of the rays' altitude, as a fraction of the atmosphere's thickness, within which a
#: :func:`path_scattering_share` stands (:func:`share_holds`).
SHARE_ALTITUDE_STEP = 1e-5
#: Rows of the sky irradiance per texel of the irradiance table where the sun is below the horizon.
IRRADIANCE_SUBROWS = 8


def path_opacity_altitude(camera_altitude, bottom, top):
    """The altitude a [m] the frame's rays start at: the camera's, or the top's for a camera above it."""
    return float(np.clip(camera_altitude, 0.0, top - bottom))


def path_opacity_u(a, mu, intersects_ground, bottom, top, n=PATH_OPACITY_TEXELS):
    """The table's coordinate u in [0, 1] of the rays (a, mu) from altitude a [m] (module docstring)."""
    a, mu = np.broadcast_arrays(np.asarray(a, float), np.asarray(mu, float))
    r = bottom + a
    rho = safe_sqrt(a * (a + 2.0 * bottom))
    h = np.sqrt(top * top - bottom * bottom)
    d_ground = distance_to_bottom_atmosphere_boundary(r, mu, bottom)
    x_ground = np.where(rho > a, (d_ground - a) / np.where(rho > a, rho - a, 1.0), 0.0)
    d_top = distance_to_top_atmosphere_boundary(r, mu, top)
    d_min, d_max = (top - bottom) - a, rho + h
    x_sky = (d_top - d_min) / (d_max - d_min)
    x = np.clip(np.where(intersects_ground, x_ground, x_sky), 0.0, 1.0)
    return np.where(intersects_ground, 0.5 - 0.5 * texcoord_from_unit_range(x, n),
                    0.5 + 0.5 * texcoord_from_unit_range(x, n))


def path_opacity_rays(a, bottom, top, n=PATH_OPACITY_TEXELS):
    """(mu, d, intersects_ground) of the table's 2n texel centres from altitude a, in the order of u."""
    r = bottom + a
    rho = np.sqrt(a * (a + 2.0 * bottom))
    h = np.sqrt(top * top - bottom * bottom)
    x = unit_range_from_texcoord((np.arange(n) + 0.5) / n, n)            # 0 .. 1 over each half's centres
    ground_x = x[::-1]                                                    # u = 0.5 - 0.5 u_x: x falls along u
    d_ground = np.maximum(a + ground_x * (rho - a), 1e-9)
    d_sky = np.maximum((top - bottom) - a + x * (rho + h - (top - bottom) + a), 1e-9)
    # mu from the ray's length: R^2 = r^2 + d^2 + 2 r mu d (to the ground), R_t^2 likewise (to the top).
    mu_ground = -(a * (a + 2.0 * bottom) + d_ground ** 2) / (2.0 * r * d_ground)
    mu_sky = ((top - bottom - a) * (top + r) - d_sky ** 2) / (2.0 * r * d_sky)
    mu = np.clip(np.concatenate([mu_ground, mu_sky]), -1.0, 1.0)
    d = np.concatenate([d_ground, d_sky])
    return mu, d, np.arange(2 * n) < n


def path_opacity_table(tables, a, n=PATH_OPACITY_TEXELS):
    """(2n, W) the opacity 1 - T of the rays at the texel centres from altitude a [m] (clipped to the
    atmosphere): to the ground for the first half (tables' get_optical_depth), to the top for the second."""
    a = path_opacity_altitude(a, tables.bottom, tables.top)
    mu, d, ground = path_opacity_rays(a, tables.bottom, tables.top, n)
    r = np.full(mu.shape, tables.bottom + a)
    tau = np.empty(mu.shape + (tables.optical_depth.shape[-1],))
    tau[ground] = get_optical_depth(tables, r[ground], mu[ground], d[ground])
    tau[~ground] = get_optical_depth_to_top_atmosphere_boundary(tables, r[~ground], mu[~ground])
    return one_minus_exp(tau)


def path_scattering_share(tables, atm, a, n=PATH_OPACITY_TEXELS, wavelengths=None):
    """(2n, W') the ``nodes.scattering_share`` of the rays of :func:`path_opacity_table` from altitude a [m]; times
    their opacity, the factor of the per-vertex inscatter (an absorbing layer raises a ray's opacity, not its
    inscatter). The share changes over the absorbing layers' scale rather than the optical depth's: it is computed
    on every SCATTERING_SHARE_STRIDE-th texel of each half and read linearly between them. ``wavelengths``: a
    slice of the atmosphere's wavelengths (W' of them; default all)."""
    a = path_opacity_altitude(a, tables.bottom, tables.top)
    mu, d, _ = path_opacity_rays(a, tables.bottom, tables.top, n)
    coarse = np.concatenate([np.arange(0, n, SCATTERING_SHARE_STRIDE), [n - 1]])
    rays = np.concatenate([coarse, n + coarse])
    coarse_share = scattering_share(atm, np.full(rays.shape, tables.bottom + a), mu[rays], d[rays],
                                    SCATTERING_SHARE_NODES, wavelengths)
    share = np.empty((2 * n, coarse_share.shape[-1]))
    for half, values in ((slice(0, n), coarse_share[:len(coarse)]), (slice(n, 2 * n), coarse_share[len(coarse):])):
        for w in range(share.shape[-1]):
            share[half, w] = np.interp(np.arange(n), coarse, values[:, w])
    return share


def share_holds(share_altitude, a, atm):
    """Whether the :func:`path_scattering_share` made at altitude ``share_altitude`` [m] stands for altitude a [m]:
    within SHARE_ALTITUDE_STEP of the atmosphere's thickness (0.6 m on Earth), over which the share of a texel
    changed by at most 0.05% on the presets and 2% on 16 random atmospheres (a texel's ray moves with the altitude,
    most near the top of a thin atmosphere). A camera turning about a point moves by millimetres; one flying
    recomputes it."""
    return abs(a - share_altitude) <= SHARE_ALTITUDE_STEP * atm.thickness_m


def phase_factor_u(nu, n=PHASE_FACTOR_TEXELS):
    """The phase table's texture coordinate of the view-sun cosine nu (module docstring)."""
    nu = np.asarray(nu, float)
    t = np.sqrt(np.clip(0.5 - 0.5 * np.abs(nu), 0.0, 0.5)) / np.sqrt(2.0)
    return texcoord_from_unit_range(np.where(nu >= 0.0, t, 1.0 - t), n)


def phase_factor_table(atm, n=PHASE_FACTOR_TEXELS):
    """(n, W, 4) the phases of the inscatter's parts [1/sr] at the texel centres, per wavelength of ``atm``: the
    molecules' P_R(nu), the particles' P_M(nu), 1, and ``forward_factor`` F(nu)."""
    u = unit_range_from_texcoord((np.arange(n) + 0.5) / n, n)
    nu = np.where(u <= 0.5, 1.0 - 4.0 * u * u, 4.0 * (1.0 - u) ** 2 - 1.0)
    mie = atm.mie.phase_function(nu)
    return np.stack([np.broadcast_to(atm.rayleigh.phase_function(nu)[:, None], mie.shape), mie, np.ones_like(mie),
                     forward_factor(atm, nu)], axis=-1)


def irradiance_rows(n_mu_s):
    """(mu_s of the first row, of the knee, the rows' step below the knee, above it) for an irradiance table of
    ``n_mu_s`` texels (module docstring; texel i at mu_s = -1 + 2 i / (n_mu_s - 1)): the knee the first texel with
    the sun up, rows IRRADIANCE_SUBROWS to a texel below it from the last texel below MU_S_MIN on, one per texel
    above it."""
    step = 2.0 / (n_mu_s - 1)
    first = float(np.floor((MU_S_MIN + 1.0) / step))
    knee = float(np.floor(1.0 / step)) + 1.0
    return -1.0 + first * step, -1.0 + knee * step, step / IRRADIANCE_SUBROWS, step


def irradiance_row_index(mu_s, rows):
    """The row (a fractional index, 0 at the first row's centre) of the sun's cosine mu_s on ``rows``
    (:func:`irradiance_rows`)."""
    first, knee, below, above = rows
    mu_s = np.asarray(mu_s, float)
    return (np.minimum(mu_s, knee) - first) / below + np.maximum(mu_s - knee, 0.0) / above


def sky_irradiance_rows(tables):
    """(rows, W) the sky's irradiance on the ground E(0, mu_s) (``get_irradiance``) on the rows of
    :func:`irradiance_rows` for the tables' irradiance table."""
    first, knee, below, above = irradiance_rows(tables.irradiance.shape[1])
    n_below = int(round((knee - first) / below))
    n_above = int(round((1.0 - knee) / above)) + 1
    mu_s = np.concatenate([first + below * np.arange(n_below), knee + above * np.arange(n_above)])
    return get_irradiance(tables, np.full(mu_s.shape, tables.bottom), np.clip(mu_s, -1.0, 1.0))
