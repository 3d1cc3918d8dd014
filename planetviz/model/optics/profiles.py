"""Density profiles rho(h): dimensionless factors multiplying a coefficient at the ground.

A coefficient beta(h) [1/m] of a component is ``beta_0 * profile.density(h)`` with
``h`` the altitude above the ground in metres. Three shapes are supported:

* ``exponential``: rho(h) = exp(-h / H) (the hydrostatic concentration of paper Eq. 11).
* ``tent``: rho(h) = max(0, 1 - |h - center| / half_width) (a thin absorbing layer).
* ``table``: rho(h) from tabulated (altitude, density) pairs, interpolated by a
  monotone piecewise cubic (Fritsch-Carlson / PCHIP, no overshoot), held at the
  end values outside the table; used for the US Standard Atmosphere ozone (Sect. 4.2.2).

Each profile checks its fields against :data:`planetviz.model.limits.LIMITS` when it is made.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..limits import AtmosphereError, check_limit, check_numbers


@dataclass(frozen=True)
class ExponentialProfile:
    """rho(h) = exp(-h / H), H = ``scale_height_m`` [m]."""

    scale_height_m: float

    def __post_init__(self):
        object.__setattr__(self, "scale_height_m", check_limit(self.scale_height_m, "scale_height_m",
                                                               "scale_height_m"))

    def density(self, h):
        return np.exp(-np.asarray(h, dtype=float) / self.scale_height_m)

    def max_density(self, h0: float, h1: float) -> float:
        """Largest rho on [h0, h1] (used as a majorant by the reference solver)."""
        return float(np.exp(-h0 / self.scale_height_m))

    def to_dict(self) -> dict:
        return {"type": "exponential", "scale_height_m": self.scale_height_m}


@dataclass(frozen=True)
class TentProfile:
    """rho(h) = max(0, 1 - |h - center| / half_width), lengths in metres."""

    center_m: float
    half_width_m: float

    def __post_init__(self):
        object.__setattr__(self, "center_m", check_limit(self.center_m, "center_m", "profile_altitude_m"))
        object.__setattr__(self, "half_width_m", check_limit(self.half_width_m, "half_width_m", "half_width_m"))

    def density(self, h):
        h = np.asarray(h, dtype=float)
        return np.maximum(0.0, 1.0 - np.abs(h - self.center_m) / self.half_width_m)

    def max_density(self, h0: float, h1: float) -> float:
        nearest = min(max(self.center_m, h0), h1)
        return float(self.density(nearest))

    def to_dict(self) -> dict:
        return {"type": "tent", "center_m": self.center_m, "half_width_m": self.half_width_m}


@dataclass(frozen=True)
class TableProfile:
    """rho(h) interpolated monotonically between ``(altitudes_m[i], densities[i])``."""

    altitudes_m: tuple
    densities: tuple

    def __post_init__(self):
        altitudes = check_numbers(self.altitudes_m, "altitudes_m", "profile_altitude_m")
        densities = check_numbers(self.densities, "densities", "density", n=None)
        if len(altitudes) < 2 or len(altitudes) != len(densities):
            raise AtmosphereError("altitudes_m", "altitudes_m and densities must be lists of equal length >= 2")
        if any(b <= a for a, b in zip(altitudes, altitudes[1:])):
            raise AtmosphereError("altitudes_m", "must be strictly increasing")
        object.__setattr__(self, "altitudes_m", altitudes)
        object.__setattr__(self, "densities", densities)
        from scipy.interpolate import PchipInterpolator     # here, so the renderer imports without SciPy
        interp = PchipInterpolator(np.asarray(self.altitudes_m, float),
                                   np.asarray(self.densities, float), extrapolate=False)
        object.__setattr__(self, "_interp", interp)

    def density(self, h):
        h = np.clip(np.asarray(h, dtype=float), self.altitudes_m[0], self.altitudes_m[-1])
        return np.maximum(self._interp(h), 0.0)

    def max_density(self, h0: float, h1: float) -> float:
        # PCHIP never overshoots the data, so the maximum on [h0, h1] is at a node or an end.
        a = np.asarray(self.altitudes_m)
        inside = np.asarray(self.densities)[(a >= h0) & (a <= h1)]
        ends = self.density(np.array([h0, h1]))
        return float(max(ends.max(), inside.max() if inside.size else 0.0))

    def to_dict(self) -> dict:
        return {"type": "table", "altitudes_m": list(self.altitudes_m),
                "densities": list(self.densities)}
