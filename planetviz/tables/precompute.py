"""The precomputed tables: transmittance, irradiance and in-scattering (Bruneton and Neyret, paper Sect. 5.1).

Stages (each a function of the atmosphere and the table sizes):

1. ``transmittance``  the optical depth tau(r, mu) = int_0^d beta_ext dt to the top (T = exp(-tau), Eq. 5),
   Gauss-Legendre quadrature split at the ray's closest approach to the centre, nodes clustered there
   (t = t_c +- span u^2). The table stores the mean extinction tau / d along the ray, not T: in a thick
   atmosphere T to the top underflows float32 near the horizon (tau of several hundred), and T(x, y) as a
   ratio of two such T is 0 / 0, while a difference of optical depths keeps its precision; tau / d stays
   smooth next to the top, where tau falls to 0. Beside it, on the same rays, the share of the opacity 1 - T
   that scatters, int_0^d beta^scat T dt / (1 - T) (1 where nothing absorbs).
2. ``single_scattering`` (tables/single.py)  S_R,1 and S_M,1 (r, mu, mu_s, nu) = int_0^d beta_i^scat(h_t) T(x, x_t)
   T_sun(x_t) dt, divided by the ray's scattering opacity (``lookup.ray_opacity``), kept apart and without phase
   (applied at render time, Mie per wavelength with its DHG). The view transmittance and density depend on (r, mu, t)
   only; only T_sun(r_t, mu_s,t) with mu_s,t = (r mu_s + t nu) / r_t is evaluated over the whole 4D grid.
3. ``multiple_scattering`` (tables/multiple.py): orders >= 2, the indirect irradiance, and the top tables of views
   upward at the top of the atmosphere (``multiple.top_source``).

The sun's direct irradiance E_0 = T_sun max(mu_s, 0) (point sun) is not tabulated: it is read from the
transmittance table where needed.

Radiance is per unit solar irradiance; tables are float32: optical depth and scattering share (n_r, n_mu, W), irradiance
(n_r, n_mu_s, W), scattering (n_r, n_mu, n_nu, n_mu_s, W), which is the 3D texture (n_r, n_mu,
n_nu * n_mu_s) the shader samples, the top tables (n_mu / 2, n_nu, n_mu_s, W), a 2D texture (n_mu / 2, n_nu * n_mu_s).
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field, replace

import numpy as np

from .cache import parameters_hash, stage_parameters
from .multiple import multiple_scattering, thick_forward_range
from .nodes import ZERO_RAY_LENGTH, altitude, is_optically_thick, ray_nodes, scattering_share, texel_centres
from .parameterization import distance_to_top_atmosphere_boundary, r_axis, r_mu_from_transmittance_uv
from .single import single_scattering
from .validated import strongest_forward_lobe, thick_forward_lobe


@dataclass(frozen=True)
class TableSizes:
    """Table resolutions and sample counts (see ``QUALITY`` for the named levels)."""

    transmittance: tuple = (256, 256)         # (n_mu, n_r)
    irradiance: tuple = (256, 16)             # (n_mu_s, n_r)
    scattering: tuple = (8, 48, 192, 32)      # (n_nu, n_mu_s, n_mu, n_r)
    transmittance_samples: int = 64           # Gauss-Legendre nodes per side of the closest approach
    scattering_samples: int = 16              # per side of the closest approach, single scattering
    multiple: tuple = (4, 32, 64, 16)         # (n_nu, n_mu_s, n_mu, n_r) of the multiple-scattering table
    lobe_nu: int = 16                         # its n_nu at least, under a forward lobe (``sizes_for``)
    lobe_mu_s: int = 48                       # and its n_mu_s at least
    multiple_samples: int = 8                 # per side, integrating the scattering density
    directions: tuple = (16, 16)              # (cos theta, azimuth over [0, pi]) quadrature of J
    quadrature: str = "lit-band"              # its kind (``multiple.QUADRATURES``)
    tolerance: float = 1e-3                   # stop adding orders below this share of the total


#: Named quality levels (measured in docs/benchmarks.md: precompute time and error against the reference).
QUALITY = {
    "draft": TableSizes(transmittance=(128, 64), irradiance=(64, 8), scattering=(4, 16, 64, 16),
                        transmittance_samples=16, scattering_samples=6, multiple=(4, 16, 32, 8),
                        lobe_nu=4, lobe_mu_s=16, multiple_samples=4, directions=(8, 8), tolerance=1e-2),
    "standard": TableSizes(irradiance=(128, 16), scattering=(8, 48, 118, 32), scattering_samples=8,
                           multiple=(4, 32, 64, 16), multiple_samples=4, directions=(10, 10), tolerance=3e-3),
    "high": TableSizes(),
}


@dataclass
class Tables:
    """Everything the renderer samples, for one atmosphere."""

    bottom: float
    top: float
    sizes: TableSizes
    optical_depth: np.ndarray
    irradiance: np.ndarray
    rayleigh: np.ndarray
    mie: np.ndarray
    multiple: np.ndarray | None = None
    multiple_mie: np.ndarray | None = None
    top_multiple: np.ndarray | None = None       # (n_mu / 2, n_nu, n_mu_s, W) multiple.top_source, molecules
    top_multiple_mie: np.ndarray | None = None   # and particles
    scattering_share: np.ndarray | None = None   # (n_r, n_mu, W) on the transmittance table's grid
    r_axis: np.ndarray | None = None     # the 4D tables' r axis (parameterization.r_axis); None: rho / H
    timings: dict = field(default_factory=dict)
    orders: int = 1
    computed: list = field(default_factory=list)

    @property
    def nbytes(self) -> int:
        tables = (self.optical_depth, self.scattering_share, self.irradiance, self.rayleigh, self.mie, self.multiple,
                  self.multiple_mie, self.top_multiple, self.top_multiple_mie)
        return sum(a.nbytes for a in tables if a is not None)


#: An optically thick atmosphere's multiple-scattering table has at least this many r rows (``sizes_for``).
THICK_MULTIPLE_ROWS = 16
#: An optically thick atmosphere's scattering density is integrated along the multiple-scattering tables' rays with
#: at least this many nodes per side of the closest approach (``sizes_for``; on every segment but the first half as
#: many, ``nodes.split_ray_nodes``): the rays of the tables' texels and, in the density's iteration, the quadrature
#: directions. With the standard level's 4, random atmospheres' plane-parallel twins against DISORT read 5.28% RMS
#: (100088: its particles within the lowest 0.6% of the shell), 1.61% (random atmosphere 1, optical depth 7.1)
#: and 0.90% (100807); with 8, 0.70%, 0.59% and 0.36% (``python benchmarks/tables_disort.py --random``); made
#: conservative over a black ground, random atmosphere 100010 sent out 1.025 times the sun's flux at 440 nm, 0.999
#: with 8 (``python benchmarks/energy_balance.py --random``).
THICK_MULTIPLE_SAMPLES = 8
#: Under a forward lobe above this g, where the particles hold most of the scattering, the multiple-scattering tables
#: have the ``lobe_nu`` and ``lobe_mu_s`` texels (``sizes_for``): random atmosphere 4's plane-parallel twin (one lobe
#: of g = 0.65, optical depth 2.8) read 2.8% RMS off DISORT with the sun 70 deg from the zenith at 4 nu texels,
#: 0.58% at 16 (the view coordinate's offset at 0; benchmarks/lobe_sky_axes.py).
LOBE_TEXELS_G = 0.6
#: The same under a forward lobe above this g where the particles' vertical scattering optical depth exceeds
#: ``validated.THICK_PARTICLE_DEPTH``, whatever their share: the lobe then shapes the multiply scattered light,
#: which the particles' forward factor (``multiple.forward_factor``, weighted by their share) leaves to the nu
#: texels. Random atmosphere 4's 440 nm channel alone (g = 0.56, the particles' share 0.47, their optical depth
#: 2.4) read 3.1% RMS off DISORT at 4 nu texels, 0.63% at 16; random atmosphere 160's lobes of g = 0.44 under an
#: optical depth of 2-4 read 0.37% at 4 (``python benchmarks/tables_disort.py --random``).
THICK_LOBE_TEXELS_G = 0.5
#: The same where the whole vertical scattering optical depth exceeds ``validated.THICK_SCATTERING_DEPTH`` and the
#: particles' forward factor varies by more than this ratio, F(1) / F(-1) (``multiple.thick_forward_range``),
#: whatever their share and depth: the light is broad, and their part stored divided by F varies as 1 / F between
#: 4 nu texels. One channel of tuning atmospheres' plane-parallel twins against DISORT (standard, 4 / 32 nu / mu_s
#: texels against 16 / 32): random-809 at 440 nm (F's range 5.7) 3.61% / 0.46% RMS, random-40 at 550 and 440 nm
#: (2.8, 2.2) 1.05% / 0.27% and 1.09% / 0.38%, random-328 at 550 nm (1.8) 2.11% / 0.37%; random-195 at 440 nm
#: (13.6) and random-473 at 550 nm (13.2) 1.73% / 0.54% and 1.17% / 0.48% (16 / 48, DISORT with 128 streams, which
#: their sharp lobes need); where F varies less more texels do not help:
#: random-410 at 440 nm (1.33) 0.41% / 0.56%, random-328 at 680 nm (1.35) 0.83% at 4 / 32. 1.5 lies between
#: (docs/tables.md, "Quality levels").
THICK_LOBE_TEXELS_RANGE = 1.5


def sizes_for(atm, sizes: TableSizes) -> TableSizes:
    """``sizes`` as the precompute uses them for ``atm``:

    1. in an optically thick atmosphere the multiple-scattering table has at least ``THICK_MULTIPLE_ROWS`` r rows
       (the standard and high levels have as many; the draft level 8). With 8, the 10-bar CO2 planet's 12 test rays
       read 2.2% RMS off the reference at standard (up to 5.4% low at 440 nm, where the light changes with the
       altitude's optical depth); with 16, 1.5% (tests/test_tables.py's rays, the reference's noise 0.9%); and the
       scattering density is integrated with at least ``THICK_MULTIPLE_SAMPLES`` nodes per side;
    2. under a forward lobe (``validated.strongest_forward_lobe`` above ``LOBE_TEXELS_G``,
       ``validated.thick_forward_lobe`` above ``THICK_LOBE_TEXELS_G``, or ``multiple.thick_forward_range`` above
       ``THICK_LOBE_TEXELS_RANGE``) the multiple-scattering tables have at least
       ``sizes.lobe_nu`` nu texels: their particles' part is stored over
       the twice-scattered lobe F(nu), which varies a hundredfold across 4 texels, and the diffuse light seen
       along long rays varies as 1 / F between them; and at least ``sizes.lobe_mu_s`` mu_s texels: with 32, Mars's
       horizontal view toward the sun from 10 km read 5.6% high and the sky opposite the sun 4.8% low, with 48
       within 1.6% and 1.1% (docs/tables.md, "Quality levels").
    """
    n_nu, n_mu_s, n_mu, n_r = sizes.multiple
    samples = sizes.multiple_samples
    if is_optically_thick(atm):
        n_r, samples = max(n_r, THICK_MULTIPLE_ROWS), max(samples, THICK_MULTIPLE_SAMPLES)
    if (strongest_forward_lobe(atm) > LOBE_TEXELS_G or thick_forward_lobe(atm) > THICK_LOBE_TEXELS_G
            or thick_forward_range(atm) > THICK_LOBE_TEXELS_RANGE):
        n_nu, n_mu_s = max(n_nu, sizes.lobe_nu), max(n_mu_s, sizes.lobe_mu_s)
    return replace(sizes, multiple=(n_nu, n_mu_s, n_mu, n_r), multiple_samples=samples)


def transmittance_rays(atm, sizes: TableSizes):
    """(r, mu, d), each (n_r, n_mu): the rays to the top of the atmosphere at the transmittance table's texel
    centres, d their length. The top row's ray next to the zenith has d = 0: it stands for the ray up from
    ``nodes.ZERO_RAY_LENGTH`` times the thickness below the top."""
    n_mu, n_r = sizes.transmittance
    u, v = np.meshgrid(texel_centres(n_mu), texel_centres(n_r))
    r, mu = r_mu_from_transmittance_uv(u, v, atm.bottom_radius_m, atm.top_radius_m, (n_mu, n_r))
    d = distance_to_top_atmosphere_boundary(r, mu, atm.top_radius_m)
    zero = d == 0.0
    r = np.where(zero, atm.top_radius_m - ZERO_RAY_LENGTH * atm.thickness_m, r)
    mu = np.where(zero, 1.0, mu)
    d = np.where(zero, atm.top_radius_m - r, d)
    return r, mu, d


def optical_depth_to_top(atm, sizes: TableSizes) -> np.ndarray:
    """The mean extinction tau(r, mu) / d along the ray to the top of the atmosphere (T = exp(-tau), d the ray's
    length; ``lookup.get_optical_depth_to_top_atmosphere_boundary`` says why), shape (n_r, n_mu, W), on
    :func:`transmittance_rays`, row by row (one row's nodes stay in cache)."""
    r, mu, d = transmittance_rays(atm, sizes)

    def row(i):
        t, w = ray_nodes(r[i], mu[i], d[i], sizes.transmittance_samples)
        ext = atm.extinction(altitude(r[i][:, None], mu[i][:, None], t, atm.bottom_radius_m))
        return np.einsum("...k,...kw->...w", w, ext) / d[i][:, None]
    return np.stack([row(i) for i in range(len(r))])


def scattering_share_to_top(atm, sizes: TableSizes) -> np.ndarray:
    """The share of the opacity 1 - T of the ray to the top of the atmosphere that scatters
    (``nodes.scattering_share``: int_0^d beta^scat T dt / (1 - T), dimensionless, in [0, 1]), shape (n_r, n_mu, W),
    on :func:`transmittance_rays`; times the opacity, the scattering opacity that the 4D tables' sky half is divided
    by (``lookup.ray_opacity``). The share is a mean of the single-scattering albedo, smoother along the ray than
    the extinction: half the optical depth's nodes (32 per side at standard, within 0.5% of 64). Row by row, so
    that one row's nodes stay in cache (0.28 s for the standard Earth table)."""
    r, mu, d = transmittance_rays(atm, sizes)
    n = max(sizes.transmittance_samples // 2, 1)
    return np.stack([scattering_share(atm, r[i], mu[i], d[i], n) for i in range(len(r))])


def stage_shapes(sizes: TableSizes, n_wavelengths: int) -> dict:
    """{stage: {array name: shape}} of the three stages' tables."""
    W = n_wavelengths
    n_nu, n_mu_s, n_mu, n_r = sizes.scattering
    n_mu_t, n_r_t = sizes.transmittance
    m_nu, m_mu_s, m_mu, m_r = sizes.multiple
    return {"transmittance": {"optical_depth": (n_r_t, n_mu_t, W), "scattering_share": (n_r_t, n_mu_t, W)},
            "single_scattering": {"rayleigh": (n_r, n_mu, n_nu, n_mu_s, W), "mie": (n_r, n_mu, n_nu, n_mu_s, W)},
            "multiple_scattering": {"multiple": (m_r, m_mu, m_nu, m_mu_s, W),
                                    "multiple_mie": (m_r, m_mu, m_nu, m_mu_s, W),
                                    "top_multiple": (m_mu // 2, m_nu, m_mu_s, W),
                                    "top_multiple_mie": (m_mu // 2, m_nu, m_mu_s, W),
                                    "irradiance": sizes.irradiance[::-1] + (W,)}}


class _Stages:
    """Runs a stage, or loads it from the cache when its parameters did not change; records its time and
    whether it ran, and reports it to ``progress``."""

    def __init__(self, atm, sizes, cache, progress):
        self.params = stage_parameters(atm, sizes)
        self.keys = {stage: parameters_hash(p) for stage, p in self.params.items()}
        self.shapes = stage_shapes(sizes, atm.n_wavelengths)
        self.wavelengths, self.cache, self.progress = atm.wavelengths_nm, cache, progress
        self.timings, self.computed = {}, []

    def run(self, name, compute):
        """The arrays of stage ``name`` (float32) and their ``attrs``; ``compute() -> (arrays, attrs)``."""
        found = (self.cache.load(name, self.keys[name], self.wavelengths, self.shapes[name])
                 if self.cache is not None else None)
        if found is not None:
            self.timings[name] = 0.0
            if self.progress:
                self.progress(f"{name} (cached)", 1.0)
            return found
        t0 = time.perf_counter()
        arrays, attrs = compute()
        arrays = {k: v.astype(np.float32) for k, v in arrays.items()}
        self.timings[name] = time.perf_counter() - t0
        self.computed.append(name)
        if self.progress:
            self.progress(name, 1.0)
        if self.cache is not None:
            self.cache.store(name, self.keys[name], self.params[name], self.wavelengths, arrays, attrs)
        return {**arrays, "attrs": attrs}


def is_cached(atm, sizes: TableSizes, cache) -> bool:
    """Whether ``cache`` holds every stage of ``atm``'s tables at ``sizes``, so that :func:`precompute` would only
    read them."""
    if cache is None:
        return False
    sizes = sizes_for(atm, sizes)
    params, shapes = stage_parameters(atm, sizes), stage_shapes(sizes, atm.n_wavelengths)
    return all(cache.holds(stage, parameters_hash(params[stage]), shapes[stage]) for stage in shapes)


def precompute(atm, sizes: TableSizes = TableSizes(), multiple: bool = True, progress=None,
               cache=None) -> Tables:
    """All tables for ``atm``: transmittance, single scattering, and (``multiple``) every order above.

    ``cache`` (a :class:`~planetviz.tables.cache.TableCache`, or None for no disk cache) supplies the stages
    whose parameters did not change and stores the ones computed; ``Tables.computed`` lists the stages
    that ran. ``progress(stage, fraction)`` is called as the stages advance (for a progress bar). The steps:

    1. the sizes for this atmosphere (:func:`sizes_for`);
    2. the optical depth to the top of the atmosphere, T(r, mu), and the share of 1 - T that scatters;
    3. single scattering, Rayleigh and Mie, S(r, mu, mu_s, nu), read through the transmittance table;
    4. the orders above the first and the ground irradiance, until they converge (``multiple``; else zeros).

    Example
    -------
    >>> from planetviz import load_atmosphere
    >>> from planetviz.tables.precompute import QUALITY, precompute
    >>> tables = precompute(load_atmosphere("earth"), QUALITY["draft"])
    >>> tables.orders >= 2
    True
    """
    sizes = sizes_for(atm, sizes)
    stages = _Stages(atm, sizes, cache, progress)
    shapes = stages.shapes["multiple_scattering"]
    tau = stages.run("transmittance", lambda: ({"optical_depth": optical_depth_to_top(atm, sizes),
                                                 "scattering_share": scattering_share_to_top(atm, sizes)}, {}))
    tables = Tables(atm.bottom_radius_m, atm.top_radius_m, sizes, tau["optical_depth"],
                    np.zeros(shapes["irradiance"], np.float32), np.empty(0), np.empty(0),
                    scattering_share=tau["scattering_share"],
                    r_axis=r_axis(atm.bottom_radius_m, atm.top_radius_m, atm.extinction))
    single = stages.run("single_scattering",
                        lambda: (dict(zip(("rayleigh", "mie"), single_scattering(tables, atm, progress))), {}))
    tables.rayleigh, tables.mie = single["rayleigh"], single["mie"]
    tables.multiple = np.zeros(shapes["multiple"], np.float32)
    tables.multiple_mie = np.zeros_like(tables.multiple)
    tables.top_multiple = np.zeros(shapes["top_multiple"], np.float32)
    tables.top_multiple_mie = np.zeros_like(tables.top_multiple)
    if multiple:
        def orders():
            out = multiple_scattering(tables, atm, sizes.multiple, *sizes.directions, samples=sizes.multiple_samples,
                                      tolerance=sizes.tolerance, progress=progress, quadrature=sizes.quadrature)
            return ({"multiple": out.multiple, "multiple_mie": out.multiple_mie, "irradiance": out.irradiance,
                     "top_multiple": out.top, "top_multiple_mie": out.top_mie}, {"orders": int(out.orders)})
        ms = stages.run("multiple_scattering", orders)
        tables.multiple, tables.multiple_mie, tables.irradiance = ms["multiple"], ms["multiple_mie"], ms["irradiance"]
        tables.top_multiple, tables.top_multiple_mie = ms["top_multiple"], ms["top_multiple_mie"]
        tables.orders = int(ms["attrs"]["orders"])
    tables.timings, tables.computed = stages.timings, stages.computed
    return tables
