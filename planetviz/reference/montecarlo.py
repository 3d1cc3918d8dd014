"""The reference solution of the full radiative transfer problem (paper Eqs. 6-8), and its standard error.

Problem: spherical shell between ``bottom_radius_m`` and ``top_radius_m``; all orders of scattering by the
Rayleigh and Mie components; absorption by every component; a Lambertian ground of albedo
``ground_albedo`` lit by the attenuated sun and by the sky; the sun a directional light of irradiance 1 at
the top of the atmosphere. The sun disc itself (the unscattered direct beam, L_0) is excluded. Result:
radiance in 1/sr per unit solar irradiance.

Method. L = L_1 + L_{>=2}:

* L_1 (single scattering and the directly lit ground seen along the view ray) by deterministic quadrature
  (:func:`~planetviz.reference.single.single_scattering`, relative error < 1e-5).
* L_{>=2} by backward Monte Carlo path tracing, one wavelength per path, vectorised over paths:

  - **Free flights**: along each straight segment (to the ground or to space) the optical depth is
    tabulated at 65 nodes (:func:`segment_optical_depth`) and a collision drawn from the piecewise-linear
    tau~ through them (forced: with probability 1 when the segment leaves to space, max(1 - T, 1/2) when it
    ends on the ground). The weight is the integrand over the density actually sampled,
    beta_scat(t) exp(-tau(t)) / (sigma~(t) exp(-tau~(t))), with tau(t) integrated exactly to the
    sampled point (Gauss-Legendre from the node before it), so the estimator is unbiased for any
    tabulation; only the optical depth's quadrature error (< 5e-5 relative) remains. With
    ``collisions="scattering"`` the collision follows the scattering part of that density instead,
    beta_scat exp(-tau~), per interval between the nodes (:func:`_scattering_collision`), its weight divided
    by the ratio of the two pdfs: the same pdf where the single-scattering albedo is the same along the
    segment, the scattering air instead of an absorbing layer where one holds most of the extinction.
  - **Next-event estimation along the next segment**: at a path vertex x with new direction d, the light
    the next vertex scatters toward x straight from the sun is estimated before that vertex is sampled:
    one collision drawn only from the sun-lit part of the segment (the planet's shadow is an interval of
    the line, :mod:`planetviz.reference.shadow`), plus the directly lit ground at the segment's end,
    exactly. The collision is drawn from strata of equal length of the lit part, each weighted by
    its collision mass times a bound on the single-scattering albedo times T_sun in it (:func:`_strata`),
    so that neither an absorbing layer nor T_sun's climb out of the shadow gives a rare draw a large
    weight. Light from vertices in the shadow, which is zero, is never sampled.
  - **Directions**: drawn from the local Rayleigh/Mie phase mixture around the previous direction (the
    cosine law at the ground) with probability 1 - EPSILON, and with probability EPSILON from a guide pdf
    around the sun (a Henyey-Greenstein lobe of g = GUIDE_SUN_G, half and half with the Mie phase function
    where that has a forward lobe), weighted by phase / mixture pdf. The next event's P_M(d . s) over the
    mixture pdf is then at most 2 / EPSILON, so a strong forward lobe (g up to 0.999) cannot give a rare
    path a huge weight: the estimator has no heavy tail there.
  - Absorption enters as a weight (the single-scattering albedo); Russian roulette after the third event,
    against the path's weight after its first, survival at least ROULETTE_MIN.

  - **Randomised quasi-Monte Carlo**: every draw of a path is one coordinate of a point (:class:`_Uniforms`),
    the draws of its first SOBOL_EVENTS events from scrambled Sobol' sets, so that the paths of a ray cover
    the first vertex's position, the new direction and the next event's collision evenly rather than at
    random (by day order 2 is most of the variance); REPLICAS independently scrambled sets per ray and
    wavelength, digitally shifted per ray, whose means are independent unbiased estimates.

Contributions of order ``max_order`` and below only; ``single="paths"`` estimates L_1 with the same paths
too (the check of the path tracer against the quadrature). ``samples`` paths per ray and wavelength; the
standard error is that of the mean of the REPLICAS replicas' means (of independent paths with
``sampler="random"``).
"""
from __future__ import annotations

import multiprocessing
import os
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass

import numpy as np

from ..model.geometry import distance_to_ground, distance_to_top_exit
from ..model.optics.phase import PENNDORF_A, henyey_greenstein, sample_henyey_greenstein, sample_rayleigh_like
from .optical_depth import chunks, shell_segment, sun_transmittance, view_transmittance
from .shadow import shadow_interval
from .single import single_scattering

#: Version of the estimator; stored with every reference result under benchmarks/data/.
SOLVER_VERSION = "5"
#: Paths per ray and wavelength at each quality of ``planetviz radiance --method reference`` and
#: ``planetviz sky`` (median relative standard errors in docs/benchmarks.md).
QUALITY_SAMPLES = {"draft": 512, "standard": 4096, "high": 32768}
#: Probability of drawing a new direction from the guide pdf around the sun; the guide's own lobe; the g
#: above which a Mie lobe (of any weight) joins the guide; the events of a path (from its first) whose new
#: direction may come from the guide (:func:`solve`'s ``guide_events``).
EPSILON = 0.25
GUIDE_SUN_G = 0.7
GUIDE_MIN_G = 0.3
GUIDE_EVENTS = 3
#: Russian roulette starts after this many events; a path survives with probability weight / (its weight
#: after the first event), at least ROULETTE_MIN (so a survivor's weight grows at most 1 / ROULETTE_MIN-fold).
ROULETTE_ORDER = 3
ROULETTE_MIN = 0.2
#: The uniform draws of a path's event, each its own coordinate (:class:`_Uniforms`): the next event's
#: collision, whether the path collides in the air, where, whether the new direction is guided, its
#: cosine, its azimuth, the phase function's component (or the guide's part), the Mie lobe, Russian roulette.
(_NEXT_EVENT, _COLLIDE, _FLIGHT, _GUIDED, _COS, _PHI, _KIND, _LOBE, _ROULETTE) = range(9)
DRAWS = 9
#: Samplers of the paths' draws; the events whose draws come from randomised Sobol' sets under "sobol", and
#: the independent replicas (point sets) per ray and wavelength whose spread gives the standard error.
SAMPLERS = ("sobol", "random")
SOBOL_EVENTS = 3
REPLICAS = 32
SOBOL_BITS = 30
#: Strata of the next event's lit part, and the share of their mass-weighted mean bound on the albedo times T_sun
#: every stratum keeps (:func:`_strata`).
STRATA = 16
DEFENSIVE = 0.1
#: The factor within which T_sun may vary along a segment for :func:`_strata` to take it as constant.
SUN_FLAT = 2.0
#: How a path's collision along a segment is drawn (:func:`_collide`; :func:`solve`'s ``collisions``):
#: "scattering", in proportion to the scattering part of the collision mass, beta_scat exp(-tau), tabulated per
#: interval between the segment's nodes (:func:`_scattering_collision`), so that where an absorbing layer holds
#: most of a long ray's extinction the scattering air is not left to rare draws of large weight; "extinction", in
#: proportion to the whole collision mass beta_ext exp(-tau) (the piecewise-linear tau~ through the nodes).
COLLISIONS = ("scattering", "extinction")
#: How :func:`solve` draws collisions unless told.
DEFAULT_COLLISIONS = COLLISIONS[0]
#: Paths whose work along their segments' nodes is done together (``optical_depth.chunks``).
CHUNK_PATHS = 4096


@dataclass
class ReferenceResult:
    """Radiance (N, W) [1/sr per unit solar irradiance], its standard error, the view transmittance."""

    radiance: np.ndarray
    stderr: np.ndarray
    transmittance: np.ndarray
    samples: int


def solve(atm, camera, view_dir, sun_dir, samples: int = 1024, seed: int = 0, max_order: int | None = None,
          single: str = "quadrature", workers: int | None = None, batch_paths: int = 65536,
          sampler: str = "sobol", guide_events: int | None = GUIDE_EVENTS,
          collisions: str = DEFAULT_COLLISIONS) -> ReferenceResult:
    """Reference radiance for N rays (camera (N, 3) [m], view_dir (N, 3), sun_dir (N, 3) or (3,)).

    ``samples`` paths per ray and wavelength; ``seed`` fixes the result whatever ``workers`` is (default:
    every core for runs of more than 2e4 paths, else 1). ``single``: ``"quadrature"`` (L_1 exact) or
    ``"paths"`` (L_1 by the paths too, for checks). ``sampler``: ``"sobol"`` (randomised quasi-Monte Carlo for
    the paths' first SOBOL_EVENTS events, :class:`_Uniforms`) or ``"random"`` (independent paths).
    ``guide_events``: the events of a path (1 its first scattering or ground bounce) whose new direction may be
    drawn from the guide around the sun, the first ``guide_events`` (None: every event). Past them the direction
    follows the phase function (the cosine law at the ground) alone, with weight 1: over the tens of events of
    light diffusing through an optically thick atmosphere the guide's weights, phase / mixture pdf up to
    1 / (1 - EPSILON) each, would multiply into a heavy tail (docs/benchmarks.md, "Reference solver").
    ``collisions``: how a collision along a segment is drawn (:data:`COLLISIONS`).

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
    if single not in ("quadrature", "paths"):
        raise ValueError(f"single: must be 'quadrature' or 'paths', got {single!r}")
    if sampler not in SAMPLERS:
        raise ValueError(f"sampler: must be one of {SAMPLERS}, got {sampler!r}")
    if guide_events is not None and (not isinstance(guide_events, (int, np.integer)) or guide_events < 0):
        raise ValueError(f"guide_events: must be None or an integer >= 0, got {guide_events!r}")
    if collisions not in COLLISIONS:
        raise ValueError(f"collisions: must be one of {COLLISIONS}, got {collisions!r}")
    camera = np.atleast_2d(np.asarray(camera, dtype=float))
    view = np.atleast_2d(np.asarray(view_dir, dtype=float))
    view = view / np.linalg.norm(view, axis=-1, keepdims=True)
    sun = np.broadcast_to(np.asarray(sun_dir, dtype=float), camera.shape)
    sun = sun / np.linalg.norm(sun, axis=-1, keepdims=True)
    n = len(camera)
    mean = np.zeros((n, atm.n_wavelengths))
    err = np.zeros_like(mean)
    first = 1
    if single == "quadrature":
        scatter, ground = single_scattering(atm, camera, view, sun)
        mean += scatter + ground
        first = 2
    limit = np.iinfo(np.int64).max if max_order is None else max_order
    if first <= limit and samples > 0:
        # Tasks: blocks of rays x chunks of at most batch_paths paths, per wavelength, each with its own seed.
        chunk = min(samples, batch_paths)
        per_block = max(1, batch_paths // chunk)
        tasks = [(w, lo, min(n, lo + per_block), c, min(chunk, samples - c * chunk))
                 for w in range(atm.n_wavelengths) for lo in range(0, n, per_block)
                 for c in range(-(-samples // chunk))]
        args = [(atm, w, camera[lo:hi], view[lo:hi], sun[lo:hi], paths, (seed, w, lo) + ((c,) if c else ()),
                 first, limit, sampler, guide_events, collisions) for w, lo, hi, c, paths in tasks]
        if workers is None:
            workers = (os.cpu_count() or 1) if n * samples * atm.n_wavelengths > 20_000 else 1
        if workers > 1 and len(tasks) > 1:
            with ProcessPoolExecutor(min(workers, len(tasks)), mp_context=multiprocessing.get_context("fork")) as ex:
                results = list(ex.map(_task, args))
        else:
            results = [_task(a) for a in args]
        # Chunks combined: the mean weighted by their paths, the squared standard errors by its square.
        count, m_ms, var = (np.zeros((n, atm.n_wavelengths)) for _ in range(3))
        for (w, lo, hi, _, paths), (m, v) in zip(tasks, results):
            count[lo:hi, w] += paths
            m_ms[lo:hi, w] += paths * m
            var[lo:hi, w] += paths * paths * v
        mean += m_ms / count
        err = np.sqrt(var) / count if samples > 1 else np.full_like(mean, np.inf)
    transmittance, _ = view_transmittance(atm, camera, view)
    return ReferenceResult(mean, err, transmittance, samples)


def path_contributions(atm, w, camera, view_dir, sun_dir, samples: int, seed: int = 0,
                       guide_events: int | None = GUIDE_EVENTS, collisions: str = DEFAULT_COLLISIONS) -> np.ndarray:
    """The orders >= 2 of ``samples`` independent paths (``sampler="random"``) of one ray (camera (3,) [m],
    view_dir, sun_dir) at wavelength index w, each path's own contribution [1/sr] (samples,): their mean is
    :func:`solve`'s estimate of those orders; how few of them carry the sum shows a heavy tail that a standard
    error need not (benchmarks/reference_tail.py).

    Example
    -------
    >>> from planetviz import load_atmosphere
    >>> atm = load_atmosphere("earth")
    >>> path_contributions(atm, 2, [0, 0, 6360002.0], [0, 0, 1.0], [0, 0.5, 0.866], 64).shape
    (64,)
    """
    rows = np.zeros(samples, dtype=int)
    camera, view, sun = (np.atleast_2d(np.asarray(a, dtype=float))[rows] for a in (camera, view_dir, sun_dir))
    view = view / np.linalg.norm(view, axis=-1, keepdims=True)
    sun = sun / np.linalg.norm(sun, axis=-1, keepdims=True)
    uniforms = _Uniforms.make("random", 1, samples, np.random.default_rng(seed))
    return _trace(atm, w, camera, view, sun, uniforms, 2, np.iinfo(np.int64).max, guide_events, collisions)


def _task(args):
    """(mean, squared standard error of the mean) per ray, of one block of rays and paths at one wavelength."""
    atm, w, camera, view, sun, samples, key, first, limit, sampler, guide_events, collisions = args
    rng = np.random.default_rng(np.random.SeedSequence(list(key)))
    n = len(camera)
    rep = np.repeat(np.arange(n), samples)
    uniforms = _Uniforms.make(sampler, n, samples, rng)
    contrib = _trace(atm, w, camera[rep], view[rep], sun[rep], uniforms, first, limit, guide_events,
                     collisions).reshape(n, samples)
    return uniforms.mean_and_variance(contrib)


class _Uniforms:
    """The uniform numbers of the paths of one task, one coordinate per draw: coordinate k of a path is its
    draw k % DRAWS (:data:`DRAWS`) at event k // DRAWS.

    ``"random"``: independent pseudo-random numbers; the standard error is that of the mean of independent
    paths. ``"sobol"``: the first SOBOL_EVENTS events' coordinates from REPLICAS randomised Sobol' point sets per
    ray, each of samples / REPLICAS paths (pseudo-random past them): REPLICAS scrambled sets, each shifted for
    every ray by its own random digital shift (a bitwise exclusive or of every coordinate's SOBOL_BITS bits,
    which keeps a set's structure and leaves each point uniform), so that every replica's mean is an unbiased
    estimate, the standard error is that of the mean of the REPLICAS independent replicas, and the errors of
    different rays are independent (the rays of a task sharing the sets unshifted would err together)."""

    def __init__(self, bits, shifts, samples, rng, replicas):
        self.bits, self.shifts, self.samples, self.rng, self.replicas = bits, shifts, samples, rng, replicas

    @classmethod
    def make(cls, sampler, n_rays, samples, rng):
        """The draws of ``n_rays`` x ``samples`` paths under ``sampler`` (independent paths where ``samples`` is
        not a multiple of REPLICAS or is under 2 REPLICAS)."""
        if sampler == "random" or samples % REPLICAS or samples < 2 * REPLICAS:
            return cls(None, None, samples, rng, 0)
        dims = SOBOL_EVENTS * DRAWS
        points = np.concatenate([_scrambled_sobol(dims, samples // REPLICAS, rng) for _ in range(REPLICAS)])
        bits = np.round(points * 2.0 ** SOBOL_BITS).astype(np.uint32)      # exact: the points are k / 2^bits
        shifts = rng.integers(0, 2 ** SOBOL_BITS, size=(n_rays, REPLICAS, dims), dtype=np.uint32)
        return cls(bits, shifts, samples, rng, REPLICAS)

    def event(self, i, paths):
        """(DRAWS, len(paths)) the draws of event i of the paths ``paths`` (indices into the task's paths)."""
        if self.bits is None or i >= SOBOL_EVENTS:
            return self.rng.random((DRAWS, len(paths)))
        ray, j = np.divmod(paths, self.samples)
        cols = slice(DRAWS * i, DRAWS * (i + 1))
        shifted = self.bits[j, cols] ^ self.shifts[ray, j // (self.samples // self.replicas), cols]
        return (shifted * 2.0 ** -SOBOL_BITS).T

    def mean_and_variance(self, contrib):
        """(mean, squared standard error of the mean) per row of contrib (rays x samples)."""
        mean = contrib.mean(axis=1)
        if not self.replicas:
            n = contrib.shape[1]
            return mean, (contrib.var(axis=1, ddof=1) / n if n > 1 else np.zeros_like(mean))
        parts = contrib.reshape(len(contrib), self.replicas, -1).mean(axis=2)
        return mean, parts.var(axis=1, ddof=1) / self.replicas


def _scrambled_sobol(dims, n, rng):
    """n points (n, dims) of a scrambled Sobol' set of SOBOL_BITS bits (SciPy warns where n is not a power of
    two, which costs the set its balance, not its points their uniformity)."""
    import warnings
    from scipy.stats import qmc
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        return qmc.Sobol(dims, scramble=True, bits=SOBOL_BITS, seed=rng).random(n)


# ------------------------------------------------------------------ directions
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


def _sample_mie(atm, w, u, u_lobe):
    """cos(theta) drawn from the Mie double Henyey-Greenstein phase function at wavelength index w (u for the
    angle, u_lobe for the lobe)."""
    lobe1 = u_lobe < atm.mie.alpha[w]
    return sample_henyey_greenstein(u, np.where(lobe1, atm.mie.g1[w], atm.mie.g2[w]))


def _sample_phase(atm, w, b_r, b_m, u):
    """cos(theta) between the old and new tracing directions, drawn from the local phase mixture (u: the draws
    of :func:`_new_direction`)."""
    m = len(b_r)
    use_mie = u[_KIND] * (b_r + b_m) < b_m
    cos = np.empty(m)
    a = 1.0 if atm.rayleigh.phase == "rayleigh" else PENNDORF_A
    cos[~use_mie] = sample_rayleigh_like(u[_COS][~use_mie], a)
    if np.any(use_mie):
        cos[use_mie] = _sample_mie(atm, w, u[_COS][use_mie], u[_LOBE][use_mie])
    return cos


def _has_lobe(atm, w) -> bool:
    """Whether the Mie phase function at wavelength index w scatters and has a forward lobe (g > GUIDE_MIN_G)."""
    if atm.mie.scattering_m[w] <= 0.0:
        return False
    lobes = [(atm.mie.g1[w], atm.mie.alpha[w]), (atm.mie.g2[w], 1.0 - atm.mie.alpha[w])]
    return any(g > GUIDE_MIN_G and share > 0.0 for g, share in lobes)


def _guide_sample(atm, w, sun, u):
    """Directions drawn from the guide pdf (:func:`_guide_pdf`; u: the draws of :func:`_new_direction`)."""
    m = len(sun)
    wide = u[_KIND] < (0.5 if _has_lobe(atm, w) else 1.0)
    cos = np.empty(m)
    cos[wide] = sample_henyey_greenstein(u[_COS][wide], GUIDE_SUN_G)
    if np.any(~wide):
        cos[~wide] = _sample_mie(atm, w, u[_COS][~wide], u[_LOBE][~wide])
    return _onb_rotate(sun, cos, 2.0 * np.pi * u[_PHI])


def _guide_pdf(atm, w, sun, d):
    """The guide pdf [1/sr] of direction d: a Henyey-Greenstein lobe of g = GUIDE_SUN_G around the sun,
    mixed half and half, where the Mie phase function has a forward lobe, with that phase function around
    the sun (so that the next event's P_M(d . s) over the pdf stays bounded)."""
    mu = np.clip(np.einsum("ij,ij->i", sun, d), -1.0, 1.0)
    wide = henyey_greenstein(mu, GUIDE_SUN_G)
    if not _has_lobe(atm, w):
        return wide
    return 0.5 * wide + 0.5 * atm.mie.phase_function(mu)[:, w]


def _guide_share(order, guide_events):
    """The probability of drawing the new direction from the guide at a path's event ``order`` (1 its first):
    EPSILON at the first ``guide_events`` events (None: every event), else 0."""
    return EPSILON if guide_events is None else np.where(order <= guide_events, EPSILON, 0.0)


def _new_direction(atm, w, d, sun, b_r, b_m, u, eps=EPSILON):
    """(new direction, phase / pdf weight) at a scattering vertex (b_r, b_m > 0 the local coefficients; u
    (DRAWS, m) the paths' draws at this event; ``eps`` the probability of the guide, :func:`_guide_share`)."""
    m = len(d)
    guided = u[_GUIDED] < eps
    cos = np.empty(m)
    free = ~guided
    cos[free] = _sample_phase(atm, w, b_r[free], b_m[free], u[:, free])
    out = np.empty_like(d)
    out[free] = _onb_rotate(d[free], cos[free], 2.0 * np.pi * u[_PHI][free])
    if np.any(guided):
        out[guided] = _guide_sample(atm, w, sun[guided], u[:, guided])
    mu = np.clip(np.einsum("ij,ij->i", d, out), -1.0, 1.0)
    phase = (b_r * atm.rayleigh.phase_function(mu) + b_m * atm.mie.phase_function(mu)[:, w]) / (b_r + b_m)
    return out, phase / ((1.0 - eps) * phase + eps * _guide_pdf(atm, w, sun, out))


def _ground_direction(atm, w, normal, sun, u, eps=EPSILON):
    """(new direction, (cos / pi) / pdf weight) leaving a Lambertian ground (u (DRAWS, m): the paths' draws;
    ``eps`` the probability of the guide, :func:`_guide_share`)."""
    guided = u[_GUIDED] < eps
    out = np.empty_like(normal)
    free = ~guided
    out[free] = _onb_rotate(normal[free], np.sqrt(u[_COS][free]), 2.0 * np.pi * u[_PHI][free])
    if np.any(guided):
        out[guided] = _guide_sample(atm, w, sun[guided], u[:, guided])
    cos = np.maximum(np.einsum("ij,ij->i", normal, out), 0.0)
    return out, (cos / np.pi) / ((1.0 - eps) * cos / np.pi + eps * _guide_pdf(atm, w, sun, out))


# ------------------------------------------------------------------ optical depth along segments
_GL4_X, _GL4_W = np.polynomial.legendre.leggauss(4)
_GL8_X, _GL8_W = np.polynomial.legendre.leggauss(8)
_SEGMENT_INTERVALS = 64


def _height_along(atm, p, d, t):
    """The altitude [m] of p + t d (t shaped (P, ...)), from the distance to the centre without cancellation."""
    b = np.einsum("ij,ij->i", p, d)
    perp = p - b[:, None] * d
    q = np.einsum("ij,ij->i", perp, perp)
    shape = (len(p),) + (1,) * (t.ndim - 1)
    return np.sqrt((t + b.reshape(shape)) ** 2 + q.reshape(shape)) - atm.bottom_radius_m


def _extinction_along(atm, w, p, d, t):
    """beta_ext [1/m] at p + t d (t shaped (P, ...))."""
    return atm.extinction(_height_along(atm, p, d, t), w)[..., 0]


def _coefficients_along(atm, w, p, d, t):
    """(beta_ext, beta_scat) [1/m] at p + t d (t shaped (P, ...)) at the wavelength index w, each component's
    density computed once for both."""
    h = _height_along(atm, p, d, t)
    ext, scat = np.zeros(h.shape), np.zeros(h.shape)
    for scattering, extinction, profile in atm.components():
        if extinction[w] or scattering[w]:
            rho = profile.density(h)
            if extinction[w]:
                ext += extinction[w] * rho
            if scattering[w]:
                scat += scattering[w] * rho
    return ext, scat


def segment_optical_depth(atm, w, p, d, length):
    """(node distances (P, K+1), cumulative tau at the nodes (P, K+1)) along p + t d, t in [0, length].

    Nodes are uniform in s = sign(t - t_c) sqrt|t - t_c| (t_c: the point of closest approach, where
    grazing rays meet the densest air; 0 for rays going up); each interval by 4-point Gauss-Legendre.
    """
    t, tau, _ = _segment_tables(atm, w, p, d, length, scattering=False)
    return t, tau


def _segment_tables(atm, w, p, d, length, scattering):
    """:func:`segment_optical_depth`'s (node distances, cumulative tau) and, where ``scattering``, the scattering
    mass of each interval without its exp(-tau_k) (P, K) (:func:`_scattering_collision`'s m_k, 4-point
    Gauss-Legendre on the same nodes as tau), else None."""
    tc = np.clip(-np.einsum("ij,ij->i", p, d), 0.0, length)[:, None]
    s = np.linspace(0.0, 1.0, _SEGMENT_INTERVALS + 1)
    s = -np.sqrt(tc) + (np.sqrt(tc) + np.sqrt(length[:, None] - tc)) * s
    t = tc + np.sign(s) * s * s                                       # (P, K+1), dense at t_c
    t[:, 0], t[:, -1] = 0.0, length
    a, b = t[:, :-1], t[:, 1:]
    mid, rad = 0.5 * (a + b), 0.5 * (b - a)
    dtau = np.empty(mid.shape)
    m = np.empty(mid.shape) if scattering else None
    for rows in chunks(len(p), CHUNK_PATHS):
        nodes = mid[rows, :, None] + rad[rows, :, None] * _GL4_X
        if not scattering:
            sig = _extinction_along(atm, w, p[rows], d[rows], nodes)
            dtau[rows] = rad[rows] * (sig * _GL4_W).sum(-1)
            continue
        sig, beta = _coefficients_along(atm, w, p[rows], d[rows], nodes)
        dtau[rows] = rad[rows] * (sig * _GL4_W).sum(-1)
        sigma = np.where(rad[rows] > 0.0, dtau[rows] / np.where(rad[rows] > 0.0, 2.0 * rad[rows], 1.0), 0.0)
        decay = np.exp(-sigma[..., None] * rad[rows, :, None] * (1.0 + _GL4_X))
        m[rows] = np.where(dtau[rows] > 0.0, rad[rows] * (beta * decay * _GL4_W).sum(-1), 0.0)
    tau = np.concatenate([np.zeros((len(p), 1)), np.cumsum(dtau, axis=1)], axis=1)
    return t, tau, m


def _tau_between(atm, w, p, d, a, b):
    """tau along p + t d from t = a to t = b (8-point Gauss-Legendre; b - a is within one table interval)."""
    mid, rad = 0.5 * (a + b), 0.5 * (b - a)
    sig = _extinction_along(atm, w, p, d, mid[:, None] + rad[:, None] * _GL8_X)
    return rad * (sig * _GL8_W).sum(-1)


def _count_at_most(rows, values):
    """For each row of ``rows`` (P, M), ascending, how many of its entries are <= each of its ``values`` (P,) or
    (P, Q): (rows <= value).sum() by a binary search, without a (P, Q, M) array."""
    m = rows.shape[1]
    flat = values.reshape(len(rows), -1)
    count = np.zeros(flat.shape, dtype=np.int64)
    step = 1 << (m.bit_length() - 1)
    while step:
        wider = count + step
        inside = wider <= m
        below = np.take_along_axis(rows, np.minimum(wider, m) - 1, 1) <= flat
        count = np.where(inside & below, wider, count)
        step >>= 1
    return count.reshape(values.shape)


def _at(rows, k):
    """rows (P, M) at the indices k (P,) or (P, Q) of each row."""
    return np.take_along_axis(rows, k.reshape(len(rows), -1), 1).reshape(k.shape)


def _locate(t_nodes, tau, t):
    """(node index k before t, sigma~ = d tau~ / dt there, tau~(t)) of the piecewise-linear tau~ at t (P,) or
    (P, Q)."""
    k = np.clip(_count_at_most(t_nodes, t) - 1, 0, t_nodes.shape[1] - 2)
    t_k, tau_k = _at(t_nodes, k), _at(tau, k)
    dt = _at(t_nodes, k + 1) - t_k
    dtau = _at(tau, k + 1) - tau_k
    sigma = np.where(dt > 0, dtau / np.where(dt > 0, dt, 1.0), 0.0)
    return k, sigma, tau_k + sigma * np.clip(t - t_k, 0.0, dt)


def _invert(t_nodes, tau, target):
    """The distance t where tau~(t) = ``target`` (P,) or (P, Q) (< tau[-1])."""
    k = np.clip(_count_at_most(tau, target) - 1, 0, t_nodes.shape[1] - 2)
    t_k, tau_k = _at(t_nodes, k), _at(tau, k)
    dt = _at(t_nodes, k + 1) - t_k
    dtau = _at(tau, k + 1) - tau_k
    frac = np.where(dtau > 0, (target - tau_k) / np.where(dtau > 0, dtau, 1.0), 0.0)
    return t_k + np.clip(frac, 0.0, 1.0) * dt


def collision_point(atm, w, p, d, t_nodes, tau, t):
    """At p + t d: (point, beta_R^scat, beta_M^scat, exact tau from p, sigma~, tau~).

    The exact tau adds the Gauss-Legendre integral from the node before t to the tabulated tau there, so
    a weight beta exp(-tau) / (density sampled from tau~) is unbiased whatever the tabulation's error.
    """
    k, sigma, tau_t = _locate(t_nodes, tau, t)
    rows = np.arange(len(t))
    tau_exact = tau[rows, k] + _tau_between(atm, w, p, d, t_nodes[rows, k], t)
    x = p + t[:, None] * d
    b_r, b_m = atm.scattering(np.linalg.norm(x, axis=1) - atm.bottom_radius_m)
    return x, b_r[:, w], b_m[:, w], tau_exact, sigma, tau_t


# ------------------------------------------------------------------ paths
class _LitMass:
    """The collision probability along segments p + t d (t in [0, length]) outside the planet's shadow.

    F(t) = 1 - exp(-tau(t)) is the probability of a collision before t; the shadow covers [a, b], so the lit
    mass is m_lit = F(a) + F(end) - F(b). :meth:`mass` is the lit mass before t, :meth:`position` its inverse,
    the shadow skipped."""

    def __init__(self, atm, p, d, sun, length, t_nodes, tau):
        a, b = shadow_interval(p, d, sun, atm.bottom_radius_m)
        shade = a < b
        self.a = np.where(shade, np.clip(a, 0.0, length), length)
        self.b = np.where(shade, np.clip(b, 0.0, length), length)
        self.f_a = -np.expm1(-_locate(t_nodes, tau, self.a)[2])
        self.f_b = -np.expm1(-_locate(t_nodes, tau, self.b)[2])
        self.f_end = -np.expm1(-tau[:, -1])
        self.m_lit = self.f_a + (self.f_end - self.f_b)
        self.t_nodes, self.tau = t_nodes, tau

    def mass(self, ok, t):
        """The lit collision mass before the distances t (P, K) of the segments ``ok`` (t outside the shadow)."""
        f = -np.expm1(-_locate(self.t_nodes[ok], self.tau[ok], t)[2])
        return np.where(t <= self.a[ok, None], f, self.f_a[ok, None] + f - self.f_b[ok, None])

    def position(self, ok, u):
        """Distances (P, K) where the lit collision mass of the segments ``ok`` reaches u (P, K)."""
        m1, f_b, f_end, tn, tb = self.f_a[ok, None], self.f_b[ok, None], self.f_end[ok, None], self.t_nodes[ok], \
            self.tau[ok]
        f = np.where(u < m1, u, f_b + (u - m1))
        with np.errstate(divide="ignore"):                       # f = 1 where the segment is opaque
            target = np.minimum(-np.log1p(-np.minimum(f, f_end)), tb[:, -1:])
        return _invert(tn, tb, target)


def _sun_bound(atm, w, x, sun, t, p, d):
    """T_sun (P, K) at the strata's ends x (P, K, 3) (distances t along p + t d), or 1 along the segments where it
    stays within a factor SUN_FLAT: probed first at the lit part's two ends and at the point of its closest
    approach to the planet (where T_sun is least, unless the sun sets along the segment), one 16-point panel each;
    0 behind the planet. A bound for :func:`_strata`'s pdf, not a term of the estimate."""
    closest = np.clip(-np.einsum("ij,ij->i", p, d), t[:, 0], t[:, -1])
    probes = np.stack([x[:, 0], p + closest[:, None] * d, x[:, -1]], 1)
    probe = sun_transmittance(atm, probes, sun[:, None, :], index=w, panels=1)[..., 0]
    out = np.ones(t.shape)
    varies = probe.min(axis=1) * SUN_FLAT < probe.max(axis=1)
    if np.any(varies):
        out[varies] = sun_transmittance(atm, x[varies], sun[varies][:, None, :], index=w, panels=1)[..., 0]
    return out


def _strata(atm, w, p, d, sun, lit, ok):
    """(bounds (P, STRATA + 1), weights (P, STRATA)): the strata of the lit collision mass of the segments ``ok``
    and the weight of each, over which :func:`_next_event` draws its collision.

    The collision mass follows the extinction, the light the next event finds follows the scattering times
    T_sun: where an absorbing layer holds most of the extinction, or T_sun climbs by orders of magnitude along
    the segment (from the planet's shadow, or through the grazing sunlight of a thick atmosphere), drawing by
    the mass alone finds the light on rare draws of large weight. So the lit part is cut into STRATA strata of
    equal length, and each is weighted by its mass times a bound on q = (beta_scat / beta_ext) T_sun (the larger
    q at its two ends; T_sun from :func:`_sun_bound`) plus DEFENSIVE times the mass-weighted mean bound. Within a
    stratum the collision follows the mass, so a draw's weight is its q over that bound: at most about 1 where q
    is monotonic across the stratum, and no rare draw carries a large weight. Where q is the same everywhere the
    weights are the masses: the plain collision pdf. (q over its largest on the segment, and the mean at least
    1e-6 of it: where T_sun underflows to a subnormal, or the strata where q is large hold no mass, a stratum with
    mass could otherwise weigh 0 and the weights sum to 0.)"""
    m_lit = lit.m_lit[ok, None]
    a, b, length = lit.a[ok, None], lit.b[ok, None], lit.t_nodes[ok][:, -1:]
    s = (a + length - b) * np.linspace(0.0, 1.0, STRATA + 1)                   # distance within the lit part
    t = np.where(s <= a, s, b + (s - a))
    bounds = np.maximum.accumulate(lit.mass(ok, t), axis=1)
    bounds[:, 0], bounds[:, -1] = 0.0, m_lit[:, 0]
    x = p[ok][:, None, :] + t[..., None] * d[ok][:, None, :]
    h = np.linalg.norm(x, axis=-1) - atm.bottom_radius_m
    b_r, b_m = atm.scattering(h)
    ext = atm.extinction(h, w)[..., 0]
    q = np.where(ext > 0.0, (b_r[..., w] + b_m[..., w]) / np.where(ext > 0.0, ext, 1.0), 1.0)
    q = q * _sun_bound(atm, w, x, sun[ok], t, p[ok], d[ok])
    largest = q.max(axis=1, keepdims=True)
    q = np.where(largest > 0.0, q / np.where(largest > 0.0, largest, 1.0), 1.0)
    bound = np.maximum(q[:, :-1], q[:, 1:])
    mass = np.diff(bounds, axis=1)
    mean = (mass * bound).sum(axis=1, keepdims=True) / np.maximum(mass.sum(axis=1, keepdims=True), 1e-300)
    return bounds, mass * (bound + DEFENSIVE * np.maximum(mean, 1e-6))


def _next_event(atm, w, p, d, sun, length, ground, t_nodes, tau, u):
    """Light that the next vertex along p + t d (t in [0, length]) sends straight from the sun toward p.

    1. The lit part of the segment and its collision probability m_lit (:class:`_LitMass`).
    2. One collision drawn from it gives beta_scat exp(-tau) P(d . s) T_sun over its pdf. The lit part is cut
       into STRATA strata of equal length weighted by their collision mass times a bound on the albedo times
       T_sun (:func:`_strata`); the one draw u picks the stratum and the collision mass within it by inverting
       that piecewise-constant distribution, and the collision is found from the optical-depth table.
    3. The directly lit ground at the end adds T(segment) (a / pi) max(0, n . s) T_sun exactly.
    """
    out = np.zeros(len(p))
    lit = _LitMass(atm, p, d, sun, length, t_nodes, tau)
    ok = lit.m_lit > 0.0
    if np.any(ok):
        n_ok = int(ok.sum())
        m_lit = lit.m_lit[ok]
        bounds, weights = _strata(atm, w, p, d, sun, lit, ok)
        cdf = np.cumsum(weights, axis=1)
        target = u[ok] * cdf[:, -1]
        pick = np.minimum((target[:, None] >= cdf).sum(axis=1), STRATA - 1)
        rows = np.arange(n_ok)
        below = np.where(pick > 0, cdf[rows, pick - 1], 0.0)
        chosen = weights[rows, pick]
        within = np.clip((target - below) / np.where(chosen > 0.0, chosen, 1.0), 0.0, 1.0)
        mass = bounds[rows, pick + 1] - bounds[rows, pick]
        share = chosen / np.where(mass > 0.0, mass, 1.0) * m_lit / cdf[:, -1]   # pdf over the plain lit pdf
        t = lit.position(ok, (bounds[rows, pick] + within * mass)[:, None])[:, 0]
        x, b_r, b_m, tau_exact, sigma, tau_t = collision_point(atm, w, p[ok], d[ok], t_nodes[ok], tau[ok], t)
        nu = np.clip(np.einsum("ij,ij->i", d[ok], sun[ok]), -1.0, 1.0)
        phase = b_r * atm.rayleigh.phase_function(nu) + b_m * atm.mie.phase_function(nu)[:, w]
        t_sun = sun_transmittance(atm, x, sun[ok], index=w)[:, 0]
        # exp(-tau) over the sampled density sigma~ exp(-tau~) share / m_lit, as one exponent (no underflow
        # on opaque segments).
        dens = sigma * share                              # 0 only where the air is too thin to represent
        ratio = np.where(dens > 0.0, np.exp(tau_t - tau_exact) / np.where(dens > 0.0, dens, 1.0), 0.0)
        out[ok] = m_lit * ratio * phase * t_sun
    albedo = float(atm.ground_albedo[w])
    if albedo > 0.0 and np.any(ground):
        g = np.nonzero(ground)[0]
        xg = p[g] + length[g, None] * d[g]
        normal = xg / np.linalg.norm(xg, axis=1, keepdims=True)
        cos_s = np.einsum("ij,ij->i", normal, sun[g])
        lit_ground = cos_s > 0.0
        if np.any(lit_ground):
            gl = g[lit_ground]
            t_sun = sun_transmittance(atm, normal[lit_ground] * atm.bottom_radius_m, sun[gl], index=w)[:, 0]
            out[gl] += np.exp(-tau[gl, -1]) * albedo / np.pi * cos_s[lit_ground] * t_sun
    return out


def _trace(atm, w, origin, direction, sun, uniforms, first, limit, guide_events=None, collisions=DEFAULT_COLLISIONS):
    """Contribution of orders ``first`` to ``limit`` of one backward path per row, at wavelength index w; the
    guide around the sun at the first ``guide_events`` events of each path (None: every event; :func:`solve`),
    the collisions drawn as ``collisions`` says (:data:`COLLISIONS`).

    Each step, for the live paths: the segment from the last vertex along its direction to the ground or to
    space and its optical depth; the light of the next vertex straight from the sun (:func:`_next_event`);
    the next vertex itself, a collision in the air (:func:`_collide`) or the ground (:func:`_bounce`), with
    its new direction; Russian roulette past ROULETTE_ORDER events (:func:`_roulette`). Every live path has as
    many events as steps taken, so step i's draws are the paths' coordinates DRAWS i to DRAWS (i + 1) - 1
    (``uniforms``, :class:`_Uniforms`).
    """
    count = len(origin)
    radiance = np.zeros(count)
    start, end = shell_segment(origin, direction, atm.top_radius_m)
    paths = _Paths(pos=origin + start[:, None] * direction, d=direction.copy(), weight=np.ones(count),
                   weight_first=np.ones(count), order=np.zeros(count, dtype=np.int64))
    idx = np.nonzero(end > start)[0]
    step = 0
    while idx.size:
        u = uniforms.event(step, idx)
        step += 1
        p, dd, s = paths.pos[idx], paths.d[idx], sun[idx]
        t_ground = distance_to_ground(p, dd, atm.bottom_radius_m)
        t_top = distance_to_top_exit(p, dd, atm.top_radius_m)
        ground = np.isfinite(t_ground) & (t_ground <= t_top)
        length = np.where(ground, t_ground, t_top)
        t_nodes, tau, m = _segment_tables(atm, w, p, dd, length, scattering=collisions == "scattering")

        nee = (paths.order[idx] + 1 >= first) & (paths.order[idx] + 1 <= limit)
        if np.any(nee):
            k = np.nonzero(nee)[0]
            radiance[idx[k]] += paths.weight[idx[k]] * _next_event(atm, w, p[k], dd[k], s[k], length[k], ground[k],
                                                                   t_nodes[k], tau[k], u[_NEXT_EVENT, k])
        alive = paths.order[idx] + 2 <= limit
        absorbed = -np.expm1(-tau[:, -1])
        p_collide = np.where(absorbed > 0.0, np.where(ground, np.maximum(absorbed, 0.5), 1.0), 0.0)
        collide = alive & (u[_COLLIDE] < p_collide)
        if np.any(collide):
            ci = np.nonzero(collide)[0]
            _collide(atm, w, paths, idx[ci], p[ci], dd[ci], sun, t_nodes[ci], tau[ci], absorbed[ci],
                     p_collide[ci], u[:, ci], guide_events, None if m is None else m[ci])
        hit = alive & ~collide & ground
        alive &= collide | hit
        if np.any(hit):
            gi = np.nonzero(hit)[0]
            _bounce(atm, w, paths, idx[gi], p[gi] + t_ground[gi, None] * dd[gi], sun,
                    np.exp(-tau[gi, -1]) / (1.0 - p_collide[gi]), u[:, gi], guide_events)
        first_event = alive & (paths.order[idx] == 1)
        paths.weight_first[idx[first_event]] = paths.weight[idx[first_event]]
        idx = idx[_roulette(paths, idx, alive, u[_ROULETTE])]
    return radiance


@dataclass
class _Paths:
    """The state of the paths being traced, one row each: last vertex [m], direction, weight, weight after the
    first event (Russian roulette's reference), events so far."""

    pos: np.ndarray
    d: np.ndarray
    weight: np.ndarray
    weight_first: np.ndarray
    order: np.ndarray


def _scattering_collision(t_nodes, tau, m, absorbed, u):
    """(t, share) (P,): a collision along p + t d drawn with the uniforms u in proportion to the scattering mass
    beta_scat exp(-tau~) of the intervals between the nodes t_nodes (tau~ piecewise linear through tau there), and
    its pdf over that of the plain collision mass, sigma~ exp(-tau~) / ``absorbed`` (= 1 - exp(-tau~(length))).

    1. Per interval k (from t_k, optical depth dtau_k, sigma_k = dtau_k / (t_k+1 - t_k)): m_k = int beta_scat
       exp(-sigma_k (t - t_k)) dt by 4-point Gauss-Legendre (``m``, from :func:`_segment_tables`), and its mass
       M_k = exp(-tau_k) m_k [dimensionless]; 0 where dtau_k = 0 (air too thin to represent, which the plain pdf
       leaves out too).
    2. The interval by M_k / sum M, then t within it in proportion to exp(-sigma_k (t - t_k)), as the plain pdf:
       pdf(t) = (M_k / sum M) sigma_k exp(-sigma_k (t - t_k)) / (1 - exp(-dtau_k)).
    3. share = pdf(t) / (sigma_k exp(-tau~(t)) / absorbed) = m_k absorbed / (sum M (1 - exp(-dtau_k))).

    Where the single-scattering albedo is the same along the segment this is the plain pdf (share 1); where an
    absorbing layer holds most of the extinction the collisions go to the scattering air, and the weight of a
    collision, beta_scat exp(-tau) over its pdf, stays near sum M wherever it falls."""
    a, b = t_nodes[:, :-1], t_nodes[:, 1:]
    dtau = np.diff(tau, axis=1)
    sigma = np.where(b > a, dtau / np.where(b > a, b - a, 1.0), 0.0)
    mass = m * np.exp(-tau[:, :-1])
    cdf = np.cumsum(mass, axis=1)
    total = cdf[:, -1]
    target = u * total
    k = np.minimum(_count_at_most(cdf, target), cdf.shape[1] - 1)
    k = _last_with_mass(mass, k)
    rows = np.arange(len(t_nodes))
    below = np.where(k > 0, cdf[rows, np.maximum(k - 1, 0)], 0.0)
    frac = np.clip((target - below) / np.where(mass[rows, k] > 0.0, mass[rows, k], 1.0), 0.0, 1.0)
    dtau_k, sigma_k, a_k = dtau[rows, k], sigma[rows, k], a[rows, k]
    opaque = -np.expm1(-dtau_k)
    t = a_k - np.log1p(-frac * opaque) / np.where(sigma_k > 0.0, sigma_k, 1.0)
    t = np.minimum(t, b[rows, k])
    share = m[rows, k] * absorbed / np.where(total * opaque > 0.0, total * opaque, 1.0)
    return t, share


def _last_with_mass(mass, k):
    """k (P,), moved back to the nearest interval at or before it whose ``mass`` (P, K) is positive (the first
    one where none is): cdf's flat steps, where the mass is 0, are never drawn."""
    positive = mass > 0.0
    idx = np.where(positive, np.arange(mass.shape[1]), -1)
    last = np.maximum.accumulate(idx, axis=1)
    first = np.argmax(positive, axis=1)
    chosen = last[np.arange(len(k)), k]
    return np.where(chosen >= 0, chosen, first)


def _collide(atm, w, paths, g, p, d, sun, t_nodes, tau, absorbed, p_collide, u, guide_events=None,
             scattering_mass=None):
    """A collision along the segments p + t d of the paths ``g`` (forced: probability ``p_collide``), drawn
    from the tabulated optical depth in proportion to the collision mass or, given the intervals'
    ``scattering_mass`` (:func:`_segment_tables`), to its scattering part (:data:`COLLISIONS`); the weight takes
    beta_scat exp(-tau) over the density sampled (exact tau to the point, :func:`collision_point`) and the new
    direction's phase / pdf (:func:`_new_direction`)."""
    if scattering_mass is not None:
        t, share = _scattering_collision(t_nodes, tau, scattering_mass, absorbed, u[_FLIGHT])
    else:
        t, share = _invert(t_nodes, tau, -np.log1p(-u[_FLIGHT] * absorbed)), 1.0
    x, b_r, b_m, tau_exact, sigma, tau_t = collision_point(atm, w, p, d, t_nodes, tau, t)
    dens = sigma * share                          # the density sampled over exp(-tau~) / absorbed
    ratio = np.where(dens > 0.0, np.exp(tau_t - tau_exact) / np.where(dens > 0.0, dens, 1.0), 0.0)
    paths.pos[g] = x
    paths.weight[g] *= (b_r + b_m) * absorbed * ratio / p_collide
    paths.order[g] += 1
    scat = (b_r + b_m) > 0.0
    paths.weight[g[~scat]] = 0.0
    if np.any(scat):
        gs = g[scat]
        paths.d[gs], ratio = _new_direction(atm, w, paths.d[gs], sun[gs], b_r[scat], b_m[scat], u[:, scat],
                                            _guide_share(paths.order[gs], guide_events))
        paths.weight[gs] *= ratio


def _bounce(atm, w, paths, g, x, sun, weight, u, guide_events=None):
    """The paths ``g`` reach the ground at x (the segment's transmittance over the probability of no collision,
    ``weight``): reflected by the Lambertian ground of albedo a, a new direction from :func:`_ground_direction`."""
    normal = x / np.linalg.norm(x, axis=1, keepdims=True)
    paths.pos[g] = normal * atm.bottom_radius_m
    paths.order[g] += 1
    paths.d[g], ratio = _ground_direction(atm, w, normal, sun[g], u, _guide_share(paths.order[g], guide_events))
    paths.weight[g] *= weight * float(atm.ground_albedo[w]) * ratio


def _roulette(paths, idx, alive, u):
    """Which of the paths ``idx`` go on (a mask): those ``alive`` with a weight, past ROULETTE_ORDER events each
    surviving with probability weight / weight after the first event (at least ROULETTE_MIN), its weight
    divided by that probability."""
    alive = alive & (paths.weight[idx] > 0.0)
    rr = alive & (paths.order[idx] >= ROULETTE_ORDER)
    if np.any(rr):
        g = idx[rr]
        q = np.clip(paths.weight[g] / paths.weight_first[g], ROULETTE_MIN, 1.0)
        survive = u[rr] < q
        paths.weight[g] /= q
        alive[np.nonzero(rr)[0][~survive]] = False
    return alive
