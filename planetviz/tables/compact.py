"""Compact mode after Boody's "Atmosphere Plus" notes: a 3D table without the sun-view azimuth.

The in-scattering tables lose their fourth coordinate: C(h, cos(phi), cos(delta)) over altitude, view zenith
and sun zenith, with the phase functions factored out (applied at render time with the true view-sun angle
nu, Mie per wavelength with its double Henyey-Greenstein lobes). Atmosphere Plus's non-linear mappings:

    x_h = sqrt(h / (R_t - R_b))                       (dense near the ground)
    x_mu = (1 + sign(mu) |mu|^(1/3)) / 2              (dense near the horizontal)
    x_mu_s = (1 + sign(mu_s) |mu_s|^(1/3)) / 2        (dense near sunrise and sunset)

and texel centres at (i + 1/2) / n as elsewhere. Each texel holds the 4D tables averaged over the sun-view
azimuth omega (uniform in [0, pi]; Atmosphere Plus takes omega = 0 instead, which is exact toward the sun
and worst away from it): single Rayleigh and Mie without phase, multiple scattering as radiance. What is
lost is the dependence on omega at fixed (h, mu, mu_s) beyond the phase function: the shadowing and path
length of the sunlight along the view ray, and the anisotropy of multiple scattering. Its size is measured
against the 4D tables in benchmarks/compact_error.py (docs/benchmarks.md).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .lookup import get_scattering, ground_row_factor, ray_opacity
from .multiple import forward_factor
from .parameterization import clamp_cosine, ray_intersects_ground, texcoord_from_unit_range, unit_range_from_texcoord
from .sampling import texture3d

#: (n_h, n_mu, n_mu_s) of the compact table.
COMPACT_SIZE = (32, 128, 32)
#: The table sets the renderer and ``planetviz radiance`` read: the 4D tables, or the compact tables made from them
#: (a third of their memory on the GPU, no quadratures along rays; their error against the 4D set:
#: docs/benchmarks.md).
TABLE_KINDS = ("4d", "compact")


def compact_x_from_cosine(c):
    """Atmosphere Plus's zenith-cosine coordinate in [0, 1]: (1 + sign(c) |c|^(1/3)) / 2."""
    return 0.5 * (1.0 + np.sign(c) * np.abs(c) ** (1.0 / 3.0))


def cosine_from_compact_x(x):
    return clamp_cosine((2.0 * x - 1.0) ** 3)


def compact_uvw_from_r_mu_mu_s(r, mu, mu_s, bottom, top, size):
    """(u_mu_s, u_mu, u_h) texture coordinates of the compact table; ``size`` = (n_h, n_mu, n_mu_s)."""
    n_h, n_mu, n_mu_s = size
    x_h = np.sqrt(np.clip((r - bottom) / (top - bottom), 0.0, 1.0))
    return (texcoord_from_unit_range(compact_x_from_cosine(mu_s), n_mu_s),
            texcoord_from_unit_range(compact_x_from_cosine(mu), n_mu),
            texcoord_from_unit_range(x_h, n_h))


@dataclass
class CompactTables:
    """What the compact renderer samples: the 2D tables of the 4D set and three 3D tables (n_h, n_mu, n_mu_s, W)."""

    bottom: float
    top: float
    optical_depth: np.ndarray
    irradiance: np.ndarray
    rayleigh: np.ndarray
    mie: np.ndarray
    multiple: np.ndarray

    @property
    def nbytes(self) -> int:
        return sum(a.nbytes for a in (self.optical_depth, self.irradiance, self.rayleigh, self.mie, self.multiple))


def compact_tables(tables, atm, size=COMPACT_SIZE, azimuths: int = 16) -> CompactTables:
    """The compact tables of a 4D set: each texel the average over ``azimuths`` sun-view azimuths (midpoint rule)."""
    n_h, n_mu, n_mu_s = size
    x_h = unit_range_from_texcoord((np.arange(n_h) + 0.5) / n_h, n_h)
    r = tables.bottom + x_h ** 2 * (tables.top - tables.bottom)
    mu = cosine_from_compact_x(unit_range_from_texcoord((np.arange(n_mu) + 0.5) / n_mu, n_mu))
    mu_s = cosine_from_compact_x(unit_range_from_texcoord((np.arange(n_mu_s) + 0.5) / n_mu_s, n_mu_s))
    omega = (np.arange(azimuths) + 0.5) * np.pi / azimuths
    rr, mm, ss, ww = np.meshgrid(r, mu, mu_s, omega, indexing="ij")
    nu = clamp_cosine(mm * ss + np.sqrt((1 - mm * mm) * (1 - ss * ss)) * np.cos(ww))
    ground = ray_intersects_ground(rr, mm, tables.bottom)
    opacity = ray_opacity(tables, rr, mm, ground)
    single_factor, multiple_factor = (ground_row_factor(tables, rr, mm, ground, table.shape[0])
                                      for table in (tables.rayleigh, tables.multiple))
    read = {name: get_scattering(tables, getattr(tables, name), rr, mm, ss, nu, ground, opacity)
            for name in ("rayleigh", "mie", "multiple", "multiple_mie")}
    out = {name: (read[name] * single_factor).mean(3).astype(np.float32) for name in ("rayleigh", "mie")}
    out["multiple"] = ((read["multiple"] + forward_factor(atm, nu) * read["multiple_mie"]) * multiple_factor) \
        .mean(3).astype(np.float32)
    return CompactTables(tables.bottom, tables.top, tables.optical_depth, tables.irradiance, **out)


def get_compact_scattering(ct: CompactTables, table, r, mu, mu_s):
    """Trilinear read of a compact table (n_h, n_mu, n_mu_s, W) at (r, mu, mu_s), as the shader's texture()."""
    u, v, w = compact_uvw_from_r_mu_mu_s(r, mu, mu_s, ct.bottom, ct.top, table.shape[:3])
    return texture3d(table, u, v, w)


def tables_of_kind(tables, atm, kind: str):
    """The 4D ``tables`` as ``kind`` (one of :data:`TABLE_KINDS`) reads them: themselves, or their compact tables."""
    if kind not in TABLE_KINDS:
        raise ValueError(f"tables: one of {', '.join(TABLE_KINDS)}, got {kind!r}")
    return tables if kind == "4d" else compact_tables(tables, atm)
