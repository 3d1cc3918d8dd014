"""The compact (Atmosphere Plus) tables: mappings, construction and reads, and their cost against the 4D tables."""
import numpy as np

from planetviz import load_atmosphere
from planetviz.tables import QUALITY, precompute
from planetviz.tables.compact import (compact_tables, compact_uvw_from_r_mu_mu_s, compact_x_from_cosine,
                                      cosine_from_compact_x, get_compact_scattering)
from planetviz.tables.evaluator import sky_radiance
from planetviz.tables.parameterization import unit_range_from_texcoord

EARTH = load_atmosphere("earth")


def test_atmosphere_plus_mappings():
    # The printed forward and inverse mappings (Atmosphere Plus, Sect. 2.4) invert each other, and the
    # zenith-cosine one puts half the texels within |mu| < 1/8 of the horizontal.
    c = np.linspace(-1, 1, 2001)
    assert np.allclose(cosine_from_compact_x(compact_x_from_cosine(c)), c, atol=1e-12)
    assert np.isclose(compact_x_from_cosine(0.125) - compact_x_from_cosine(-0.125), 0.5)


def test_compact_table_of_an_azimuth_free_field_is_exact():
    # 4D tables whose content does not depend on nu lose nothing in the compact form: at the compact
    # texel centres the compact read returns the 4D read (both are interpolations of the same field).
    tables = precompute(EARTH, QUALITY["draft"], multiple=False)
    rng = np.random.default_rng(0)
    shape = tables.rayleigh.shape
    field = rng.random(shape[:2] + (1, shape[3], shape[4])).astype(np.float32)
    tables.rayleigh = np.broadcast_to(field, shape).copy()
    compact = compact_tables(tables, EARTH, size=(8, 16, 8), azimuths=8)
    n_h, n_mu, n_mu_s = compact.rayleigh.shape[:3]
    x_h = unit_range_from_texcoord((np.arange(n_h) + 0.5) / n_h, n_h)
    r = tables.bottom + x_h ** 2 * (tables.top - tables.bottom)
    mu = cosine_from_compact_x(unit_range_from_texcoord((np.arange(n_mu) + 0.5) / n_mu, n_mu))
    mu_s = cosine_from_compact_x(unit_range_from_texcoord((np.arange(n_mu_s) + 0.5) / n_mu_s, n_mu_s))
    rr, mm, ss = (a.ravel() for a in np.meshgrid(r, mu, mu_s, indexing="ij"))
    u, v, w = compact_uvw_from_r_mu_mu_s(rr, mm, ss, tables.bottom, tables.top, (n_h, n_mu, n_mu_s))
    assert np.allclose(u * n_mu_s - 0.5, np.round(u * n_mu_s - 0.5), atol=1e-9)   # texel centres
    got = get_compact_scattering(compact, compact.rayleigh, rr, mm, ss)
    assert np.allclose(got, compact.rayleigh.reshape(-1, 3), rtol=1e-6)
    from planetviz.tables.lookup import get_scattering
    from planetviz.tables.parameterization import ray_intersects_ground
    want = get_scattering(tables, tables.rayleigh, rr, mm, ss, mm * ss, ray_intersects_ground(rr, mm, tables.bottom))
    assert np.allclose(got, want, rtol=1e-5)


def test_compact_daylight_sky_from_the_ground_is_close_to_the_4d_tables():
    # From the ground in daylight, away from the sun and the horizon, dropping the azimuth costs little:
    # measured 0.6% RMS on the benchmark's random views (docs/benchmarks.md). Bound 3%: a compact table
    # built at the wrong coordinates, or phases applied twice or not at all, is off by 20% or more.
    tables = precompute(EARTH, QUALITY["draft"])
    compact = compact_tables(tables, EARTH, azimuths=8)
    rng = np.random.default_rng(3)
    n = 200
    z = np.arccos(rng.uniform(0.2, 1.0, n))
    a = rng.uniform(0, 2 * np.pi, n)
    views = np.stack([np.sin(z) * np.cos(a), np.sin(z) * np.sin(a), np.cos(z)], 1)
    cams = np.tile([0, 0, EARTH.bottom_radius_m + 2.0], (n, 1))
    sun = np.array([0.6, 0.0, 0.8])
    keep = views @ sun < np.cos(np.radians(20))
    full, _ = sky_radiance(tables, EARTH, cams[keep], views[keep], sun)
    small, _ = sky_radiance(compact, EARTH, cams[keep], views[keep], sun)
    rel = (small - full) / full
    assert np.sqrt(np.mean(rel ** 2)) < 0.03
