"""The quick view's estimate of the orders of scattering above the first, with no 4D tables: Hillaire's
multiple-scattering table ("A Scalable and Production Ready Sky and Atmosphere Rendering Technique", EGSR 2020,
Sect. 5.5), a 2D table Psi_ms(h, mu_s) computed in NumPy in tens of milliseconds.

At a point at altitude h with the sun at mu_s (cosine of its zenith angle), for unit solar irradiance at the top
of the atmosphere, with p_u = 1 / (4 pi) the isotropic phase function:

    L'(omega)  = int_0^D T(x, y) beta_s(y) p_u T_sun(y) dt  +  T(x, g) (albedo / pi) max(n . s, 0) T_sun(g)
                 (light scattered once toward x along -omega, isotropically; g: the ground if the ray meets it)
    f(omega)   = int_0^D T(x, y) beta_s(y) dt
                 (the share of an isotropic radiance at x scattered back toward x along omega)
    L_2        = mean over omega of L'(omega),        f_ms = mean over omega of f(omega)   (Eqs. 5, 7, 8)
    Psi_ms     = L_2 / (1 - f_ms)                                                            (Eqs. 9, 10)

the second order with isotropic phase functions, times the geometric series of the orders above it with the same
transfer f_ms at every order. The table is computed for the atmosphere with its particles' scattering scaled by
the similarity principle to an isotropic phase function (:func:`transport_scaled`: beta_M^s (1 - g), beta_M^ext
- g beta_M^s, g the phase function's mean cosine): a forward lobe sends most of the light on along the sun's
direction, which the isotropic phase functions above would spread over the sphere (on the dusty Mars preset,
unscaled, the quick view reads 40% RMS from the tables by day, 57% at 440 nm where g = 0.9; scaled, 19%:
docs/benchmarks.md). Along a view ray the quick view then adds, at each of its points p_i,

    Delta_i beta_s(h_i) Psi_ms(h_i, mu_s,i) exp(-tau(x, p_i))                                  (Eq. 11)

with no shadow test (the light of the orders above the first reaches into the planet's shadow). Psi_ms [1/sr
per unit solar irradiance, like radiance] is tabulated at altitudes h = H (i / (n_h - 1))^2 (H the thickness)
and mu_s on :func:`cosine_grid` (dense near the horizon), and read bilinearly at texel centres as the GPU reads it
(:func:`read_table`). T_sun comes from a transmittance table of the same kind (:func:`transmittance_table`).
:func:`quick_view_tables` makes Psi_ms and the sky's irradiance on the ground (:func:`ground_sky_irradiance`).
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
#: Psi_ms table size (altitudes, sun zenith cosines), directions averaged, midpoints along each direction.
MS_SIZE = (16, 32)
MS_DIRECTIONS = 64
MS_STEPS = 16
#: Directions of the sky's irradiance on the ground: its single scattering has the particles' forward lobe, which
#: 32 directions over the sky's half alias (Mars' sky irradiance jumps by 60% from one sun elevation to the next).
GROUND_SKY_DIRECTIONS = 256
#: Columns of the sky's irradiance on the ground (mu_s on cosine_grid): in twilight it falls by about 7 times per
#: column of Psi_ms's 32 (2 deg of sun elevation near -4 deg), and linear filtering between such columns read the
#: Earth preset's 1.4 times the tables' irradiance at -4 deg and 2.1 times at -6 deg; 128 columns are 0.5 deg apart
#: there.
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
    """(Psi_ms (n_h, n_mu_s, W), E_sky (n_mu_s, W)) of ``atm`` for the quick view."""
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


def read_table(table, atm, h, mu):
    """Bilinear read of a table (n_h, n_mu, W) over altitudes :func:`altitude_grid` and cosines :func:`cosine_grid`
    at (h, mu) (...), clamped to its edges: (..., W). The same as a GPU's linear filtering at texel centres."""
    n_h, n_mu = table.shape[:2]
    x = np.sqrt(np.clip(np.asarray(h) / atm.thickness_m, 0.0, 1.0)) * (n_h - 1)
    y = (cosine_coordinate(mu) + 1.0) / 2.0 * (n_mu - 1)
    i, j = np.minimum(x.astype(np.intp), n_h - 2), np.minimum(y.astype(np.intp), n_mu - 2)
    fx, fy = (x - i).reshape(-1, 1), (y - j).reshape(-1, 1)
    flat = np.asarray(table).reshape(n_h * n_mu, -1)
    k = (i * n_mu + j).ravel()
    low = flat.take(k, axis=0)
    low += fy * (flat.take(k + 1, axis=0) - low)
    high = flat.take(k + n_mu, axis=0)
    high += fy * (flat.take(k + n_mu + 1, axis=0) - high)
    low += fx * (high - low)
    return low.reshape(np.shape(x) + table.shape[2:])


def multiple_scattering_table(atm, size=MS_SIZE, directions=MS_DIRECTIONS, steps=MS_STEPS):
    """Psi_ms (n_h, n_mu_s, W) [1/sr per unit solar irradiance] of ``atm``'s :func:`transport_scaled` atmosphere
    (the module's docstring gives the equations).

    Example
    -------
    >>> from planetviz import load_atmosphere
    >>> psi = multiple_scattering_table(load_atmosphere("earth"))
    >>> psi.shape
    (16, 32, 3)
    """
    atm = transport_scaled(atm)
    b_r, b_m, extinction = coefficients(atm, "physical")
    t_sun_table = transmittance_table(atm)
    n_h, n_mu_s = size
    R = atm.bottom_radius_m
    r = R + altitude_grid(atm, n_h)[:, None]                         # (n_h, 1)
    omega = fibonacci_sphere(directions)                               # (D, 3), z: the local vertical
    mu = omega[None, :, 2]                                             # (1, D)
    length, ground = ray_length(atm, r, mu)                            # (n_h, D)
    mid, width = sample_fractions(steps, 1.0)
    t = length[..., None] * mid                                        # (n_h, D, S)
    dt = length[..., None] * width
    rr = r[..., None]
    r_t = np.sqrt(t * t + 2.0 * rr * mu[..., None] * t + rr * rr)
    h_t = np.maximum(r_t - R, 0.0)
    beta_s = _scattering(atm, b_r, b_m, h_t)                          # (n_h, D, S, W)
    step_tau = _extinction(extinction, h_t) * dt[..., None]
    weight = step_weights(beta_s, dt, step_tau)                        # int over the step of beta_s T(x, y) dt
    f = weight.sum(axis=2)
    mu_s = cosine_grid(n_mu_s)
    sun = np.stack([np.sqrt(1.0 - mu_s ** 2), np.zeros(n_mu_s), mu_s], axis=-1)     # (M, 3)
    nu = sun @ omega.T                                                 # (M, D)
    # The sun's zenith cosine at each point: (r mu_s + t nu) / r_t.
    mu_s_t = (rr[:, None] * mu_s[None, :, None, None] + t[:, None] * nu[None, :, :, None]) / r_t[:, None]
    t_sun = read_table(t_sun_table, atm, np.broadcast_to(h_t[:, None], mu_s_t.shape), mu_s_t)   # (h, M, D, S, W)
    lit = np.einsum("hmdsw,hdsw->hmdw", t_sun, weight) / (4.0 * np.pi)
    # The ground where the direction meets it: sunlit Lambertian, seen through the whole ray.
    mu_s_g = (r[:, None, :] * mu_s[None, :, None] + length[:, None, :] * nu[None]) / R          # (h, M, D)
    t_sun_g = read_table(t_sun_table, atm, np.zeros_like(mu_s_g), mu_s_g)
    ground_light = (ground[:, None, :, None] * np.asarray(atm.ground_albedo) / np.pi
                    * np.maximum(mu_s_g, 0.0)[..., None] * t_sun_g
                    * np.exp(-step_tau.sum(axis=2))[:, None])
    second = (lit + ground_light).mean(axis=2)                         # L_2 (n_h, M, W)
    f_ms = f.mean(axis=1)                                              # (n_h, W)
    return second / (1.0 - np.minimum(f_ms, 0.999))[:, None, :]


def ground_sky_irradiance(atm, psi, transmittance, columns=GROUND_SKY_COLUMNS, directions=GROUND_SKY_DIRECTIONS,
                          steps=MS_STEPS):
    """E_sky (columns, W): the irradiance of the sky on the ground per unit solar irradiance, at the mu_s of
    :func:`cosine_grid` (``columns``): the sum over the upward directions omega of the :func:`fibonacci_sphere` of
    L(omega) cos(theta) 4 pi / D, with L(omega) the single scattering (the atmosphere's phase functions) and
    the orders above it (``psi``) along omega, as the quick view computes them on a view ray."""
    b_r, b_m, extinction = coefficients(atm, "physical")
    n_mu_s = columns
    R = atm.bottom_radius_m
    omega = fibonacci_sphere(directions)
    omega = omega[omega[:, 2] > 0.0]                                   # (U, 3) the sky's half
    mu = omega[:, 2]
    length, _ = ray_length(atm, np.full(mu.shape, R), mu)             # (U,)
    mid, width = sample_fractions(steps, 1.0)
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
    radiance = np.einsum("musw,usw->muw", phase * t_sun + read_table(psi, atm, h_b, mu_s_t), weight)
    return np.einsum("muw,u->mw", radiance, mu) * 4.0 * np.pi / directions
