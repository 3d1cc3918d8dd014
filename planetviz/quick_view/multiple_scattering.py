"""The quick view's estimate of the orders of scattering above the first, with no 4D tables: the mean radiance
Psi(h, mu_s) of the light that has scattered at least once, for isotropic phase functions, a 2D table solved in
NumPy in a few hundred milliseconds, and the sky's irradiance on the ground.

At a point x at altitude h with the sun at mu_s (cosine of its zenith angle), for unit solar irradiance at the top
of the atmosphere, with isotropic phase functions (1 / (4 pi)), the radiance toward x along -omega of the light
scattered at least once, its mean over the directions and the sky's irradiance on the ground are

    L(x, omega) = int_0^D T(x, y) beta_s(y) [T_sun(y) / (4 pi) + Psi(y)] dt                                    (1)
                  + T(x, g) (albedo / pi) [max(n . s, 0) T_sun(g) + E(g)]    (g: the ground, if the ray meets it)
    Psi(x)      = (1 / (4 pi)) int L(x, omega) d omega                                                           (2)
    E(mu_s)     = int over the sky's half of L(ground, omega) cos(theta) d omega                                  (3)

[1/sr per unit solar irradiance; E per unit solar irradiance]. Psi appears on both sides: (1)-(3) are a linear
integral equation for Psi and E, spherically symmetric about the axis through the planet's centre and the sun, so
that Psi depends on (h, mu_s) only and E on mu_s. Hillaire ("A Scalable and Production Ready Sky and Atmosphere
Rendering Technique", EGSR 2020, Sect. 5.5) approximates its solution by one point's second order times the
geometric series 1 / (1 - f_ms) of that point's own transfer; that misses the light diffusing down through an
optically thick atmosphere (the 10-bar planet's sky from the ground read 30% off the tables). Here it is solved:
the unknowns are Psi at the table's nodes (altitudes H (i / (n_h - 1))^2, H the thickness; mu_s on
:func:`cosine_grid`) and E at its cosines; the quadrature of (1)-(3), with Psi, E and T_sun read bilinearly between
the nodes, is a matrix K (:func:`transfer_matrix`), and

    (I - K) z = s                                                                                                 (4)

with z = (Psi, E) and s the light scattered once (T_sun / (4 pi) in (1), T_sun read at each step from a finer
transmittance table: on the nodes, the sunset and the twilight of the 10-bar planet read 1.7 and 1.5 times as far
from the tables) and the sunlit ground, is solved directly for each wavelength (:func:`multiple_scattering_table`):
every order, in spherical geometry, so the twilight sky and the night side next to the terminator are lit (T_sun is
zero where the planet hides the sun; nothing else is shadowed). The directions of (2) are Gauss-Legendre cosines on
each hemisphere times azimuths over half the circle (:func:`direction_set`; the sun in the x-z plane makes L
symmetric about it); along each ray the steps are at (k / n)^2 of its length from x, dense where the ray starts,
each integrated exactly for coefficients constant over the step (:func:`step_weights`). The table is computed for
the atmosphere with its particles' scattering scaled by the similarity principle to an isotropic phase function
(:func:`transport_scaled`: beta_M^s (1 - g), beta_M^ext - g beta_M^s, g the phase function's mean cosine): a forward
lobe sends most of the light on along the sun's direction, which isotropic phase functions would spread over the
sphere.

Along a view ray the quick view then adds, at each of its points p_i,

    Delta_i beta_s(h_i) Psi(h_i, mu_s,i) exp(-tau(x, p_i))

(planetviz/quick_view/single_scattering.py). Psi and the sky's irradiance on the ground for the view
(:func:`ground_sky_irradiance`: single scattering with the atmosphere's own phase functions plus Psi) are read
geometrically between the nodes (:func:`read_table` with ``geometric=True``: bilinear in their logarithms, stored so
in the textures): in twilight they fall by about three times per degree of the sun's depression, and reading them
linearly between two columns a degree apart lit the Earth's ground 10-15% too bright.
"""
from __future__ import annotations

import numpy as np

from ..model.atmosphere import Mie
from ..tables.parameterization import (distance_to_bottom_atmosphere_boundary, distance_to_top_atmosphere_boundary,
                                       ray_intersects_ground)
from .single_scattering import coefficients, sample_fractions

#: What the quick view adds up: every order ("all": single scattering and this table for the orders above, with
#: the sky's light on the ground) or Keller and Bohn's single scattering alone ("single").
ORDERS = ("all", "single")
#: Psi table size (altitudes, sun zenith cosines). 64 cosines or 24 altitudes change the pictures against the tables
#: by at most 0.01 of RMS (docs/benchmarks.md) and cost 2-4 times as much.
MS_SIZE = (16, 32)
#: Directions of the mean (2): Gauss-Legendre zenith cosines per hemisphere, azimuths over half the circle.
MS_DIRECTIONS = (8, 4)
#: Steps along each ray and the exponent of their edges (k / n)^e from the ray's start: with equal steps the first
#: one, opaque near the ground of an optically thick atmosphere, read Psi at its middle, where it is larger than
#: where that step's light comes from (the 10-bar planet's ground read 1.6-1.9 times the tables' mean radiance).
MS_STEPS = 24
MS_STEP_EXPONENT = 2.0
#: The least value stored where a table is read geometrically (its logarithm is interpolated).
LOG_FLOOR = 1e-30
#: Directions of the sky's irradiance on the ground: its single scattering has the particles' forward lobe, which
#: 32 directions over the sky's half alias (Mars' sky irradiance jumps by 60% from one sun elevation to the next).
GROUND_SKY_DIRECTIONS = 256
#: Columns of the sky's irradiance on the ground (mu_s on cosine_grid), 0.5 deg of the sun's elevation apart near
#: -4 deg, where it falls about 7 times per 2 deg: with 32 columns read linearly the Earth preset's ground was lit 1.4
#: times the tables' irradiance at -4 deg and 2.1 times at -6 deg.
GROUND_SKY_COLUMNS = 128
#: Transmittance table size (altitudes, view zenith cosines) and midpoints (power law 2) along each ray.
TRANSMITTANCE_SIZE = (32, 64)
TRANSMITTANCE_STEPS = 40


def transport_scaled(atm):
    """``atm`` with its particles' coefficients scaled to an isotropic phase function by the similarity principle:
    scattering beta_M^s (1 - g) and extinction beta_M^ext - g beta_M^s, g = alpha g1 + (1 - alpha) g2 the double
    Henyey-Greenstein phase function's mean cosine per wavelength (0 for a backward lobe, whose scaling would
    raise the coefficients)."""
    m = atm.mie
    g = np.maximum(np.asarray(m.alpha) * np.asarray(m.g1) + (1.0 - np.asarray(m.alpha)) * np.asarray(m.g2), 0.0)
    scattering, extinction = np.asarray(m.scattering_m), np.asarray(m.extinction_m)
    return atm.replace(mie=Mie(tuple(scattering * (1.0 - g)), tuple(extinction - g * scattering), m.profile,
                               m.g1, m.g2, m.alpha))


def quick_view_tables(atm):
    """(Psi (n_h, n_mu_s, W), E_sky (n_mu_s, W)) of ``atm`` for the quick view."""
    psi = multiple_scattering_table(atm)
    return psi, ground_sky_irradiance(atm, psi, transmittance_table(atm))


def altitude_grid(atm, n):
    """Altitudes [m] of a table's rows: H (i / (n - 1))^2, denser near the ground."""
    return atm.thickness_m * (np.arange(n) / (n - 1)) ** 2


def cosine_grid(n):
    """Cosines of a table's columns: sign(x) x^2 for x uniform in [-1, 1], dense near 0 (the horizon, where the
    sun sets and the planet's shadow begins)."""
    x = np.linspace(-1.0, 1.0, n)
    return np.sign(x) * x * x


def cosine_coordinate(mu):
    """x in [-1, 1] of the cosine ``mu`` on :func:`cosine_grid` (its inverse)."""
    mu = np.clip(mu, -1.0, 1.0)
    return np.sign(mu) * np.sqrt(np.abs(mu))


def fibonacci_sphere(n):
    """``n`` unit vectors (n, 3) spread evenly over the sphere (the golden-angle spiral), z from 1 - 1/n to -1 + 1/n."""
    k = np.arange(n) + 0.5
    z = 1.0 - 2.0 * k / n
    phi = np.pi * (1.0 + 5.0 ** 0.5) * k
    s = np.sqrt(1.0 - z * z)
    return np.stack([s * np.cos(phi), s * np.sin(phi), z], axis=-1)


def ray_length(atm, r, mu):
    """(distance along (r, mu) to the ground or the top, whether it is the ground) [m]."""
    ground = ray_intersects_ground(r, mu, atm.bottom_radius_m)
    return np.where(ground, distance_to_bottom_atmosphere_boundary(r, mu, atm.bottom_radius_m),
                    distance_to_top_atmosphere_boundary(r, mu, atm.top_radius_m)), ground


def _extinction(extinction, h):
    """beta_ext at altitudes h (...) -> (..., W)."""
    return sum(profile.density(h)[..., None] * np.asarray(ext) for ext, profile in extinction)


def _scattering(atm, b_r, b_m, h):
    """beta_s = beta_R^s rho_R(h) + beta_M^s rho_M(h): (..., W)."""
    return atm.rayleigh.profile.density(h)[..., None] * b_r + atm.mie.profile.density(h)[..., None] * b_m


def step_weights(beta_s, dt, step_tau):
    """The integral over each step (axis -2) of beta_s T(x, y) dt, with beta_s and beta_ext constant on the step
    and T from the start of the ray: T(x, start of the step) beta_s dt (1 - exp(-step_tau)) / step_tau. Exact
    for any optical thickness of a step, where the midpoint rule fails once a step is opaque."""
    before = np.cumsum(step_tau, axis=-2) - step_tau
    thin = step_tau < 1e-6
    factor = np.where(thin, 1.0 - 0.5 * step_tau, -np.expm1(-step_tau) / np.where(thin, 1.0, step_tau))
    return np.exp(-before) * beta_s * dt[..., None] * factor


def transmittance_table(atm, size=TRANSMITTANCE_SIZE, steps=TRANSMITTANCE_STEPS):
    """T to the top of the atmosphere (n_h, n_mu, W) at the altitudes of :func:`altitude_grid` and the cosines of
    :func:`cosine_grid`; 0 where the ray meets the ground (the planet's shadow). Midpoint rule at (j / m)^2 from
    the start."""
    _, _, extinction = coefficients(atm, "physical")
    n_h, n_mu = size
    r = atm.bottom_radius_m + altitude_grid(atm, n_h)[:, None]
    mu = cosine_grid(n_mu)[None, :]
    ground = ray_intersects_ground(r, mu, atm.bottom_radius_m)
    to_top = distance_to_top_atmosphere_boundary(r, mu, atm.top_radius_m)
    mid, width = sample_fractions(steps, 2.0)
    t = to_top[..., None] * mid
    h = np.sqrt(t * t + 2.0 * r[..., None] * mu[..., None] * t + r[..., None] ** 2) - atm.bottom_radius_m
    tau = np.einsum("hmsw,s->hmw", _extinction(extinction, np.maximum(h, 0.0)), width)
    return np.where(ground[..., None], 0.0, np.exp(-tau * to_top[..., None]))


def table_coordinates(atm, n_h, n_mu, h, mu):
    """(row i, column j, fractions fx, fy) of (h, mu) on a table's grid (:func:`altitude_grid` by
    :func:`cosine_grid`), clamped to its edges, each (...): the lower node and the position between it and the
    next, as a GPU's linear filtering reads between texel centres."""
    x = np.sqrt(np.clip(np.asarray(h) / atm.thickness_m, 0.0, 1.0)) * (n_h - 1)
    y = (cosine_coordinate(mu) + 1.0) / 2.0 * (n_mu - 1)
    i, j = np.minimum(x.astype(np.intp), n_h - 2), np.minimum(y.astype(np.intp), n_mu - 2)
    return i, j, x - i, y - j


def read_table(table, atm, h, mu, geometric=False):
    """Bilinear read of a table (n_h, n_mu, W) over altitudes :func:`altitude_grid` and cosines :func:`cosine_grid`
    at (h, mu) (...), clamped to its edges: (..., W). The same as a GPU's linear filtering at texel centres;
    ``geometric``: bilinear in the logarithm of the table (values below :data:`LOG_FLOOR` read as it), as the quick
    view's shader reads its textures of Psi and E_sky."""
    table = np.log(np.maximum(table, LOG_FLOOR)) if geometric else np.asarray(table)
    n_h, n_mu = table.shape[:2]
    i, j, fx, fy = table_coordinates(atm, n_h, n_mu, h, mu)
    fx, fy = fx.reshape(-1, 1), fy.reshape(-1, 1)
    flat = table.reshape(n_h * n_mu, -1)
    k = (i * n_mu + j).ravel()
    low = flat.take(k, axis=0)
    low += fy * (flat.take(k + 1, axis=0) - low)
    high = flat.take(k + n_mu, axis=0)
    high += fy * (flat.take(k + n_mu + 1, axis=0) - high)
    low += fx * (high - low)
    out = low.reshape(np.shape(i) + table.shape[2:])
    return np.exp(out) if geometric else out


def direction_set(n_zenith=MS_DIRECTIONS[0], n_azimuth=MS_DIRECTIONS[1]):
    """(directions (D, 3), weights (D,)) for the mean over the sphere of a function symmetric about the x-z plane:
    ``n_zenith`` Gauss-Legendre cosines on each hemisphere (dense toward the horizon, where the rays are long, and
    the zenith) times ``n_azimuth`` azimuths at the midpoints of [0, pi]; the weights sum to 1.

    >>> d, w = direction_set()
    >>> d.shape, round(w.sum(), 12)
    ((64, 3), 1.0)
    """
    x, w = np.polynomial.legendre.leggauss(n_zenith)
    mu = np.concatenate([(x - 1.0) / 2.0, (x + 1.0) / 2.0])
    w_mu = np.concatenate([w, w]) / 4.0                                 # the mean over mu in [-1, 1]
    phi = (np.arange(n_azimuth) + 0.5) * np.pi / n_azimuth
    m, p = np.meshgrid(mu, phi, indexing="ij")
    s = np.sqrt(1.0 - m * m)
    directions = np.stack([s * np.cos(p), s * np.sin(p), m], axis=-1).reshape(-1, 3)
    return directions, np.repeat(w_mu / n_azimuth, n_azimuth)


def transfer_matrix(atm, size=MS_SIZE, directions=MS_DIRECTIONS, steps=MS_STEPS):
    """(K (W, N, N), s (N, W)) of Eq. (4) in the module's docstring for ``atm`` (already scaled), N = n_h n_mu_s +
    n_mu_s: z = (Psi at node (i, j) as row i n_mu_s + j, then E at each cosine j), K z the quadrature of (1)-(3)
    for that z with the sun's terms left out, s the sun's terms: the light scattered once and the sunlit ground.

    Rows of Psi: for each node's directions omega (weights w_d, :func:`direction_set`) and steps along them, the
    step's weight w_d int beta_s T dt (:func:`step_weights`) spread over the four nodes around the step's midpoint
    (h, mu_s) by their bilinear weights; where the ray meets the ground, w_d T(x, g) albedo / pi on the two cosines
    of E around the ground point's mu_s. Rows of E: the ground node's upward directions with w_d 4 pi cos(theta)
    in place of w_d (Eq. 3)."""
    b_r, b_m, extinction = coefficients(atm, "physical")
    n_h, n_mu = size
    n_psi = n_h * n_mu
    n = n_psi + n_mu
    R = atm.bottom_radius_m
    r = R + altitude_grid(atm, n_h)[:, None]                            # (n_h, 1)
    omega, w_dir = direction_set(*directions)                           # (D, 3), (D,)
    mu = omega[None, :, 2]
    length, ground = ray_length(atm, r, mu)                             # (n_h, D)
    mid, width = sample_fractions(steps, MS_STEP_EXPONENT)
    t, dt = length[..., None] * mid, length[..., None] * width          # (n_h, D, S)
    rr = r[..., None]
    r_t = np.sqrt(t * t + 2.0 * rr * mu[..., None] * t + rr * rr)
    h_t = np.maximum(r_t - R, 0.0)
    step_tau = _extinction(extinction, h_t) * dt[..., None]
    weight = step_weights(_scattering(atm, b_r, b_m, h_t), dt, step_tau) * w_dir[:, None, None]   # (n_h, D, S, W)
    t_ray = np.exp(-step_tau.sum(axis=2)) * w_dir[:, None]             # (n_h, D, W)
    mu_s = cosine_grid(n_mu)
    sun = np.stack([np.sqrt(1.0 - mu_s ** 2), np.zeros(n_mu), mu_s], axis=-1)     # (M, 3)
    nu = sun @ omega.T                                                  # (M, D)
    # The sun's zenith cosine at each step's midpoint, (r mu_s + t nu) / r_t, and its four nodes.
    mu_s_t = np.clip((rr[:, None] * mu_s[None, :, None, None] + t[:, None] * nu[None, :, :, None]) / r_t[:, None],
                     -1.0, 1.0)                                         # (n_h, M, D, S)
    i, j, fx, fy = table_coordinates(atm, n_h, n_mu, np.broadcast_to(h_t[:, None], mu_s_t.shape), mu_s_t)
    node = i * n_mu + j
    corners = [(node, (1 - fx) * (1 - fy)), (node + 1, (1 - fx) * fy), (node + n_mu, fx * (1 - fy)),
               (node + n_mu + 1, fx * fy)]
    row = (np.arange(n_h)[:, None] * n_mu + np.arange(n_mu))[:, :, None, None]
    up = np.maximum(omega[:, 2], 0.0) * 4.0 * np.pi                     # Eq. (3)'s factor per direction
    e_row = n_psi + np.arange(n_mu)[:, None, None]
    # The ground where a direction meets it: E at the ground point's mu_s, linear between two cosines.
    mu_s_g = np.clip((r[:, None, :] * mu_s[None, :, None] + length[:, None, :] * nu[None]) / R, -1.0, 1.0)
    _, j_g, _, f_g = table_coordinates(atm, 2, n_mu, np.zeros_like(mu_s_g), mu_s_g)   # columns only (a 1-row E)
    g_row = np.broadcast_to(row[..., 0], mu_s_g.shape)
    seen = ground[:, None, :, None] * t_ray[:, None] * (np.asarray(atm.ground_albedo) / np.pi)   # (n_h, M, D, W)
    index = np.concatenate([(row * n + c).ravel() for c, _ in corners]
                           + [(e_row * n + c[0]).ravel() for c, _ in corners]
                           + [(g_row * n + n_psi + j_g).ravel(), (g_row * n + n_psi + j_g + 1).ravel()])
    t_sun_table = transmittance_table(atm)
    t_sun = read_table(t_sun_table, atm, np.broadcast_to(h_t[:, None], mu_s_t.shape), mu_s_t)
    once = np.einsum("hmdsw,hdsw->hmdw", t_sun, weight) / (4.0 * np.pi)      # (n_h, M, D, W)
    W = weight.shape[-1]
    K = np.empty((W, n, n))
    for w in range(W):
        values = np.concatenate([(weight[:, None, :, :, w] * f).ravel() for _, f in corners]
                                + [(weight[0, None, :, :, w] * up[:, None] * f[0]).ravel() for _, f in corners]
                                + [(seen[..., w] * (1 - f_g)).ravel(), (seen[..., w] * f_g).ravel()])
        K[w] = np.bincount(index, values, n * n).reshape(n, n)
    sunlit = seen * (np.maximum(mu_s_g, 0.0)[..., None] * read_table(t_sun_table, atm, np.zeros_like(mu_s_g), mu_s_g))
    s_psi = (once + sunlit).sum(axis=2).reshape(n_psi, W)
    s_e = np.einsum("mdw,d->mw", once[0], up)
    return K, np.concatenate([s_psi, s_e])


def multiple_scattering_table(atm, size=MS_SIZE, directions=MS_DIRECTIONS, steps=MS_STEPS):
    """Psi (n_h, n_mu_s, W) [1/sr per unit solar irradiance] of ``atm``'s :func:`transport_scaled` atmosphere:
    Eq. (4) of the module's docstring solved for each wavelength.

    Example
    -------
    >>> from planetviz import load_atmosphere
    >>> psi = multiple_scattering_table(load_atmosphere("earth"))
    >>> psi.shape
    (16, 32, 3)
    """
    K, s = transfer_matrix(transport_scaled(atm), size, directions, steps)
    n = K.shape[1]
    z = np.stack([np.linalg.solve(np.eye(n) - K[w], s[:, w]) for w in range(K.shape[0])], axis=-1)
    return np.maximum(z[:size[0] * size[1]], 0.0).reshape(*size, -1)


def ground_sky_irradiance(atm, psi, transmittance, columns=GROUND_SKY_COLUMNS, directions=GROUND_SKY_DIRECTIONS,
                          steps=MS_STEPS):
    """E_sky (columns, W): the irradiance of the sky on the ground per unit solar irradiance, at the mu_s of
    :func:`cosine_grid` (``columns``): the sum over the upward directions omega of the :func:`fibonacci_sphere` of
    L(omega) cos(theta) 4 pi / D, with L(omega) the single scattering (the atmosphere's phase functions) and
    the orders above it (``psi``, read geometrically) along omega, as the quick view computes them on a view ray,
    with the steps of :data:`MS_STEPS`."""
    b_r, b_m, extinction = coefficients(atm, "physical")
    n_mu_s = columns
    R = atm.bottom_radius_m
    omega = fibonacci_sphere(directions)
    omega = omega[omega[:, 2] > 0.0]                                   # (U, 3) the sky's half
    mu = omega[:, 2]
    length, _ = ray_length(atm, np.full(mu.shape, R), mu)             # (U,)
    mid, width = sample_fractions(steps, MS_STEP_EXPONENT)
    t, dt = length[:, None] * mid, length[:, None] * width            # (U, S)
    r_t = np.sqrt(t * t + 2.0 * R * mu[:, None] * t + R * R)
    h_t = np.maximum(r_t - R, 0.0)
    rho_r, rho_m = atm.rayleigh.profile.density(h_t), atm.mie.profile.density(h_t)
    step_tau = _extinction(extinction, h_t) * dt[..., None]
    mu_s = cosine_grid(n_mu_s)
    sun = np.stack([np.sqrt(1.0 - mu_s ** 2), np.zeros(n_mu_s), mu_s], axis=-1)
    nu = sun @ omega.T                                                 # (M, U)
    mu_s_t = (R * mu_s[:, None, None] + t[None] * nu[..., None]) / r_t[None]      # (M, U, S)
    h_b = np.broadcast_to(h_t, mu_s_t.shape)
    t_sun = read_table(transmittance, atm, h_b, mu_s_t)
    p_r = atm.rayleigh.phase_function(nu)[..., None]                  # (M, U, 1)
    p_m = atm.mie.phase_function(nu)                                   # (M, U, W)
    beta_s = rho_r[..., None] * b_r + rho_m[..., None] * b_m                       # (U, S, W)
    weight = step_weights(beta_s, dt, step_tau)
    # The phase functions weight each component's share of beta_s: J / beta_s = (beta_R P_R + beta_M P_M) / beta_s.
    share_r = np.divide(rho_r[..., None] * b_r, beta_s, out=np.zeros_like(beta_s), where=beta_s > 0)
    phase = share_r[None] * p_r[:, :, None] + (1.0 - share_r[None]) * p_m[:, :, None]
    radiance = np.einsum("musw,usw->muw", phase * t_sun + read_table(psi, atm, h_b, mu_s_t, geometric=True), weight)
    return np.einsum("muw,u->mw", radiance, mu) * 4.0 * np.pi / directions
