"""Quick view: the single-scattering integrator of Keller and Bohn ("A GPU-based real time method for simulating
atmospheric light scattering"), with no precomputed tables.

The NumPy twin of the quick-view shader: the same sampling and the same names. For a view ray from x (moved to
where it enters the atmosphere when x is in space) along v, with D the length of its part in the atmosphere
(up to the ground where it hits it) and the sun in direction s:

    L = sum_i  Delta_i  [beta_R^s(h_i) P_R(nu) + beta_M^s(h_i) P_M(nu)]  exp(-tau(x, p_i) - tau(p_i, sun))  V_i
      + T(x, y) (albedo / pi) T_sun(y) max(n . s, 0)                    (rays that hit the ground at y)

with the paper's midpoint rule on non-equidistant points (Sect. 6): a_i = (i / n)^3, b_i = ((i + 1) / n)^3,
p_i = x + D (a_i + b_i) / 2 v, Delta_i = D (b_i - a_i); V_i = 0 where the planet hides the sun from p_i. On a ray
that reaches the ground half the points follow that law from x and half mirror it from the ground
(:func:`ground_sample_edges`): from space, x is the top of the atmosphere. The sun's
optical depth tau(p_i, sun) is the same midpoint rule with (j / m)^2 along its own path, starting where the density
is highest: at the path's lower end (for the ground's paths from space, their far end). The paper computes
tau(x, p_i) with samples of its own as well; here it is summed over the view path's own intervals
(:func:`view_optical_depth`, 2-point Gauss-Legendre each): two evaluations per interval instead of m per point, so
that n = 20 points on the view path cost about what 8 and 8 cost, and a ray from space into an optically thick
atmosphere, whose last interval spans most of its optical depth, gets 20 of them (docs/benchmarks.md).
``sampling="equidistant"`` uses exponents 1 and 1 instead, for the comparison in docs/benchmarks.md.

``terms="physical"`` (default) uses the atmosphere file's coefficients and phase functions, radiance in 1/sr
per unit solar irradiance as everywhere else. ``terms="artistic"`` uses the paper's Table 1 simplifications:
molecular coefficients scaled from the longest wavelength's by (lambda_red / lambda)^4, particle coefficients
by (lambda_red / lambda)^2, phases 1 + 0.5 cos^2 and the Henyey-Greenstein lobe without its 1 / (4 pi): not
normalised, so that radiance is in arbitrary units (the paper's artistic control, never the physical model).

With ``multiple`` and ``ground_sky`` (planetviz/quick_view/multiple_scattering.py), the orders above the first
and the sky's light on the ground are added from a 2D table; without them, single scattering alone (no
sky light on the ground). docs/benchmarks.md measures both against the tables.
"""
from __future__ import annotations

import numpy as np

from ..model.geometry import distance_to_ground, distance_to_top_exit
from ..model.queries import validate_queries
from ..reference.optical_depth import shell_segment

#: Exponents of the sample positions (i / n)^e: the scattering integral, the optical depths.
SAMPLING = {"power": (3.0, 2.0), "equidistant": (1.0, 1.0)}
TERMS = ("physical", "artistic")
#: The most points on a path (view or optical depth).
MAX_SAMPLES = 256
#: Points n on each view path by default: with 8, the power law's last interval of a ray from space to the ground of
#: an optically thick atmosphere spans most of its optical depth, and the 10-bar planet's disc from orbit read 3
#: times the error it reads with 20 (docs/benchmarks.md). Points m on each of the sun's optical-depth paths: with 6,
#: Earth's terminator from orbit read 0.156 at the 99th percentile (target 0.15), 0.144 with 8.
DEFAULT_SAMPLES = 20
DEFAULT_DENSITY_SAMPLES = 8


def check_settings(samples, density_samples=None, sampling="power", terms="physical"):
    """(n, m) for valid settings; a ValueError naming the setting and its allowed values otherwise."""
    if sampling not in SAMPLING:
        raise ValueError(f"sampling: one of {', '.join(SAMPLING)}, got {sampling!r}")
    if terms not in TERMS:
        raise ValueError(f"terms: one of {', '.join(TERMS)}, got {terms!r}")
    for name, value in (("samples", samples), ("density_samples", density_samples)):
        if value is not None and not (isinstance(value, (int, np.integer)) and 1 <= value <= MAX_SAMPLES):
            raise ValueError(f"{name}: an integer in [1, {MAX_SAMPLES}], got {value!r}")
    return int(samples), int(density_samples or DEFAULT_DENSITY_SAMPLES)


def sample_edges(n, exponent):
    """(n + 1,) the edges (i / n)^exponent, i = 0 .. n, of a path's intervals as fractions of its length: dense at
    its start (the view path's camera end, an optical-depth path's lower end)."""
    return (np.arange(n + 1) / n) ** exponent


def ground_sample_edges(n, exponent):
    """(n + 1,) the edges of a view path that reaches the ground, as fractions of its length: the first n // 2
    intervals at 0.5 (i / k)^exponent (k = n // 2, dense at the camera's end) and the others mirrored,
    1 - 0.5 ((n - i) / (n - k))^exponent, dense at the ground, where the density is highest. From space the
    camera's end is the top of the atmosphere: with every interval dense there (:func:`sample_edges`) the last one
    of a ray into an optically thick atmosphere spans most of its optical depth, and the 10-bar planet's disc read
    6-14% above the single-scattering integral at 20 points, 1.3-2% with these edges (tests/test_quick_view_physics.py).
    The camera's end keeps half the points for rays from within the atmosphere, where the air is densest near the
    camera too."""
    k = n // 2
    i = np.arange(n + 1)
    return np.where(i <= k, 0.5 * (i / max(k, 1)) ** exponent, 1.0 - 0.5 * ((n - i) / (n - k)) ** exponent)


def sample_fractions(n, exponent):
    """Midpoints (a_i + b_i) / 2 and widths b_i - a_i of the intervals [(i / n)^e, ((i + 1) / n)^e], i < n."""
    edges = sample_edges(n, exponent)
    return 0.5 * (edges[:-1] + edges[1:]), np.diff(edges)


def coefficients(atm, terms):
    """(beta_R^s [W], beta_M^s [W], [(extinction [W], profile)...]) under the chosen terms."""
    b_r, b_m = np.asarray(atm.rayleigh.scattering_m), np.asarray(atm.mie.scattering_m)
    comps = atm.components()
    if terms == "physical":
        return b_r, b_m, [(ext, prof) for _, ext, prof in comps]
    wl = np.asarray(atm.wavelengths_nm, dtype=float)
    red = int(np.argmax(wl))
    b_r = b_r[red] * (wl[red] / wl) ** 4
    b_m = b_m[red] * (wl[red] / wl) ** 2
    m_ext = np.asarray(atm.mie.extinction_m)[red] * (wl[red] / wl) ** 2
    return b_r, b_m, [(b_r, atm.rayleigh.profile), (m_ext, atm.mie.profile)] + \
        [(ext, prof) for _, ext, prof in comps[2:]]


def _phases(atm, nu, terms):
    """(P_R (N, 1), P_M (N, W)) at nu."""
    if terms == "physical":
        return atm.rayleigh.phase_function(nu)[:, None], atm.mie.phase_function(nu)
    g = np.asarray(atm.mie.g1, dtype=float)[None, :]
    p_m = (1 - g * g) / (1 - 2 * g * nu[:, None] + g * g) ** 1.5
    return (1 + 0.5 * nu * nu)[:, None], p_m


def path_optical_depth(extinction, bottom, start, direction, length, m, exponent):
    """tau along start + t direction, 0 <= t <= length, by the midpoint rule at (j / m)^exponent from the path's
    lower end (where the density is highest: the start, or the end where it is nearer the planet's centre): (..., W).
    """
    mid, width = sample_fractions(m, exponent)
    end = start + length[..., None] * direction
    from_end = (np.linalg.norm(end, axis=-1) < np.linalg.norm(start, axis=-1))[..., None]
    t = length[..., None] * np.where(from_end, 1.0 - mid, mid)
    pts = start[..., None, :] + t[..., None] * direction[..., None, :]
    h = np.maximum(np.linalg.norm(pts, axis=-1) - bottom, 0.0)   # < 0 only on sun paths through the planet
    tau = 0.0
    for ext, profile in extinction:
        tau = tau + np.einsum("...k,k,w->...w", profile.density(h), width, ext)
    return tau * length[..., None]


#: The offset of the 2-point Gauss-Legendre nodes from an interval's middle, in units of its width.
GAUSS_OFFSET = 0.5 / np.sqrt(3.0)


def extinction_at(extinction, bottom, points):
    """beta_ext (..., W) at ``points`` (..., 3) [1/m]."""
    h = np.maximum(np.linalg.norm(points, axis=-1) - bottom, 0.0)
    return sum(profile.density(h)[..., None] * np.asarray(ext) for ext, profile in extinction)


def view_optical_depth(extinction, bottom, x, v, length, edges):
    """tau (N, n, W) from x to each midpoint p_i of the view path x + t v, 0 <= t <= length, of intervals
    [a_i, b_i] at the fractions ``edges`` (N, n + 1) of its length: each interval's optical depth by the 2-point
    Gauss-Legendre rule, summed from x, and over [a_i, p_i] half the interval's width times the extinction at its
    first node. Two evaluations per interval, where an optical depth of its own from x to each p_i takes m."""
    a = length[:, None] * edges[:, :-1]                              # (N, n)
    w = length[:, None] * np.diff(edges, axis=1)
    start, toward = x[:, None, :], v[:, None, :]
    first = extinction_at(extinction, bottom, start + (a + (0.5 - GAUSS_OFFSET) * w)[..., None] * toward)
    second = extinction_at(extinction, bottom, start + (a + (0.5 + GAUSS_OFFSET) * w)[..., None] * toward)
    step = 0.5 * w[..., None] * (first + second)
    before = np.cumsum(step, axis=1) - step
    return before + 0.5 * w[..., None] * first


def quick_view_radiance(atm, camera, view_dir, sun_dir, samples=DEFAULT_SAMPLES, density_samples=None,
                        sampling="power",
                        terms="physical", multiple=None, ground_sky=None):
    """(radiance (N, W), transmittance (N, W)) of single scattering along each ray (and the sunlit ground).

    ``samples``: points n on the view path; ``density_samples``: points m of each optical depth (default
    :data:`DEFAULT_DENSITY_SAMPLES`);
    ``multiple``: a Psi table (planetviz/quick_view/multiple_scattering.py) whose orders above the first are
    added at the same points (beta_s Psi exp(-tau), read geometrically), or None for single scattering alone; ``ground_sky``: the sky's
    irradiance on the ground (n_mu_s, W) over mu_s in [-1, 1] (``ground_sky_irradiance`` there), added to the
    sun's on the ground, or None.

    Example
    -------
    >>> from planetviz import load_atmosphere
    >>> atm = load_atmosphere("earth")
    >>> L, T = quick_view_radiance(atm, [[0, 0, atm.bottom_radius_m + 2]], [[0, 0, 1]], [0, 0.5, 0.866])
    >>> L.shape
    (1, 3)
    """
    n, m = check_settings(samples, density_samples, sampling, terms)
    e_view, e_depth = SAMPLING[sampling]
    q = validate_queries(camera, view_dir, sun_dir, atm.bottom_radius_m)
    c, v, s = q.camera_m, q.view_dir, q.sun_dir
    R, top = atm.bottom_radius_m, atm.top_radius_m
    b_r, b_m, extinction = coefficients(atm, terms)

    start_t, end_t = shell_segment(c, v, top)
    t_ground = distance_to_ground(c, v, R)
    hits = np.isfinite(t_ground) & (t_ground <= end_t)
    end_t = np.where(hits, t_ground, end_t)
    length = np.maximum(end_t - start_t, 0.0)
    x = c + start_t[:, None] * v
    nu = np.clip(np.einsum("ni,ni->n", v, s), -1.0, 1.0)
    p_r, p_m = _phases(atm, nu, terms)

    edges = np.where(hits[:, None], ground_sample_edges(n, e_view), sample_edges(n, e_view))   # (N, n + 1)
    mid, width = 0.5 * (edges[:, :-1] + edges[:, 1:]), np.diff(edges, axis=1)
    t_i = length[:, None] * mid                                           # (N, n)
    p = x[:, None, :] + t_i[..., None] * v[:, None, :]
    h = np.linalg.norm(p, axis=-1) - R
    s_i = np.broadcast_to(s[:, None, :], p.shape)
    lit = ~np.isfinite(distance_to_ground(p, s_i, R))
    tau_view = view_optical_depth(extinction, R, x, v, length, edges)
    tau_sun = path_optical_depth(extinction, R, p, s_i, distance_to_top_exit(p, s_i, top), m, e_depth)
    j = (b_r * atm.rayleigh.profile.density(h)[..., None] * p_r[:, None, :]
         + b_m * atm.mie.profile.density(h)[..., None] * p_m[:, None, :])
    weight = (length[:, None] * width) * lit
    radiance = np.einsum("nk,nkw->nw", weight, j * np.exp(-tau_view - tau_sun))
    if multiple is not None:
        from .multiple_scattering import read_table
        mu_s = np.einsum("nki,nki->nk", p, s_i) / (h + R)
        beta_s = b_r * atm.rayleigh.profile.density(h)[..., None] + b_m * atm.mie.profile.density(h)[..., None]
        radiance += np.einsum("nk,nkw->nw", length[:, None] * width,
                              beta_s * read_table(multiple, atm, h, mu_s, geometric=True) * np.exp(-tau_view))

    transmittance = np.exp(-path_optical_depth(extinction, R, x, v, length, m, e_depth))
    if np.any(hits):
        y = x[hits] + length[hits, None] * v[hits]
        normal = y / np.linalg.norm(y, axis=-1, keepdims=True)
        cos_s = np.maximum(np.einsum("ni,ni->n", normal, s[hits]), 0.0)
        t_sun = np.exp(-path_optical_depth(extinction, R, y, s[hits], distance_to_top_exit(y, s[hits], top),
                                           m, e_depth))
        irradiance = cos_s[:, None] * t_sun
        if ground_sky is not None:
            from .multiple_scattering import read_table
            mu_s = np.einsum("ni,ni->n", normal, s[hits])
            irradiance = irradiance + read_table(ground_sky[None], atm, np.zeros_like(mu_s), mu_s, geometric=True)
        radiance[hits] += transmittance[hits] * np.asarray(atm.ground_albedo) / np.pi * irradiance
    return radiance, transmittance
