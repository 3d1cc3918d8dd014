"""The range of atmospheres the tables were validated for, and the error measured outside it.

``cd benchmarks && python tables_suite.py --conditions`` compares the standard tables with the reference solver on
random legal atmospheres (both splits and the presets) and groups the daylight errors by the conditions below;
:data:`CONDITIONS` carries what it measured, and :func:`outside_validated_range` names the conditions an
atmosphere meets (``planetviz precompute`` prints them as warnings). The draft and high levels share the
tables' design and are validated on the same range (their errors: docs/benchmarks.md).

Example
-------
>>> from planetviz import load_atmosphere
>>> from planetviz.tables.validated import outside_validated_range
>>> outside_validated_range(load_atmosphere("earth"))
[]
>>> [c.name for c in outside_validated_range(load_atmosphere("mars"))]
['forward lobe']
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

#: A component of the particles' phase function counts toward the lobe condition where its weight exceeds this.
LOBE_WEIGHT = 0.05
#: The particles' share of the scattering above which their lobe decides the light.
PARTICLE_SHARE = 0.5
#: A forward lobe with g above this, where the particles decide the light, is a dominant one: the condition
#: "forward lobe" below, and the multiple-scattering tables' nu texels (``precompute.sizes_for``).
FORWARD_LOBE_G = 0.7
#: The particles' vertical scattering optical depth above which most light is scattered by them more than once,
#: so that their lobe shapes the light of the orders above the first even where molecules hold most of the
#: scattering (``thick_forward_lobe``).
THICK_PARTICLE_DEPTH = 1.0
#: The whole vertical scattering optical depth (molecules and particles) above which most light is scattered more
#: than once, so that the angular shape of the light the particles scatter again decides the orders above the first
#: even where they hold a small share of it (``multiple.thick_forward_range``).
THICK_SCATTERING_DEPTH = 1.0


def largest_vertical_optical_depth(atm) -> float:
    """The vertical optical depth from the ground to the top, at the most extinguished wavelength."""
    return float(np.max(atm.vertical_optical_depth()))


def _vertical_scattering(atm):
    """(W,) the molecules' and (W,) the particles' vertical scattering optical depth [dimensionless], from the
    ground to the top (midpoint rule over 4096 layers)."""
    heights = (np.arange(4096) + 0.5) * atm.thickness_m / 4096
    layer = atm.thickness_m / 4096
    rayleigh = np.sum(atm.rayleigh.profile.density(heights)) * layer * np.asarray(atm.rayleigh.scattering_m)
    mie = np.sum(atm.mie.profile.density(heights)) * layer * np.asarray(atm.mie.scattering_m)
    return rayleigh, mie


def particle_scattering_share(atm) -> np.ndarray:
    """(W,) the particles' share of the vertical scattering optical depth per wavelength."""
    rayleigh, mie = _vertical_scattering(atm)
    return mie / np.maximum(rayleigh + mie, 1e-300)


def scattering_depth(atm) -> np.ndarray:
    """(W,) the whole vertical scattering optical depth per wavelength, molecules and particles [dimensionless]."""
    rayleigh, mie = _vertical_scattering(atm)
    return rayleigh + mie


def particle_scattering_depth(atm) -> np.ndarray:
    """(W,) the particles' vertical scattering optical depth per wavelength [dimensionless]."""
    return _vertical_scattering(atm)[1]


def _forward_lobes(atm) -> np.ndarray:
    """(W,) the largest asymmetry g of a double Henyey-Greenstein component (weight > ``LOBE_WEIGHT``)."""
    g1, g2, alpha = (np.asarray(x, dtype=float) for x in (atm.mie.g1, atm.mie.g2, atm.mie.alpha))
    return np.maximum(np.where(alpha > LOBE_WEIGHT, g1, -1.0), np.where(alpha < 1.0 - LOBE_WEIGHT, g2, -1.0))


def strongest_forward_lobe(atm) -> float:
    """The largest asymmetry g of a double Henyey-Greenstein component (weight > ``LOBE_WEIGHT``) at a wavelength
    where the particles hold more than ``PARTICLE_SHARE`` of the scattering; 0 where they hold less everywhere."""
    dominant = particle_scattering_share(atm) > PARTICLE_SHARE
    return float(np.max(np.where(dominant, _forward_lobes(atm), 0.0), initial=0.0))


def thick_forward_lobe(atm) -> float:
    """The largest asymmetry g of a double Henyey-Greenstein component (weight > ``LOBE_WEIGHT``) at a wavelength
    where the particles' vertical scattering optical depth exceeds ``THICK_PARTICLE_DEPTH``, whatever their share
    of the scattering; 0 where it is less everywhere."""
    thick = particle_scattering_depth(atm) > THICK_PARTICLE_DEPTH
    return float(np.max(np.where(thick, _forward_lobes(atm), 0.0), initial=0.0))


@dataclass(frozen=True)
class Condition:
    """A property outside the validated range: ``measure(atm) > limit``, and the daylight error the suite measured
    on its atmospheres with it (RMS and 95th percentile of the relative error over the rays and wavelengths, and
    the reference's own noise, RMS relative standard error)."""

    name: str
    what: str
    measure: Callable
    limit: float
    rms: float
    p95: float
    noise: float

    def message(self, atm, quality: str) -> str:
        resolved = f"{self.rms:.1%} RMS" if self.noise <= self.rms / 3 else \
            f"{self.rms:.1%} RMS, below the reference's resolution ({self.noise:.1%} noise)"
        return (f"{atm.name}: {self.what} {self.measure(atm):.3g} is above {self.limit:g}, outside the range the "
                f"{quality} tables were validated for; on such atmospheres their daylight radiance was measured "
                f"{resolved}, 95th percentile {self.p95:.0%} off the reference (docs/tables.md, \"Validated range\")")


#: The conditions, with the errors ``tables_suite.py --conditions`` measured (standard tables, 4096-path reference).
CONDITIONS = (
    Condition("optically thick", "the vertical optical depth", largest_vertical_optical_depth, 1.0,
              rms=0.016, p95=0.033, noise=0.015),
    Condition("forward lobe", "the particles' strongest forward lobe g", strongest_forward_lobe, FORWARD_LOBE_G,
              rms=0.013, p95=0.031, noise=0.010),
    Condition("large planet", "the planet radius [m]", lambda atm: atm.bottom_radius_m, 1e8,
              rms=0.013, p95=0.028, noise=0.012),
)


def outside_validated_range(atm) -> list:
    """The :data:`CONDITIONS` that ``atm`` meets (an empty list inside the validated range)."""
    return [c for c in CONDITIONS if c.measure(atm) > c.limit]
