"""The allowed range of every field of an atmosphere, and the checks that enforce them.

:data:`LIMITS` is the one source of the ranges: the dataclasses of :mod:`planetviz.model.atmosphere` and
:mod:`planetviz.model.optics.profiles` check their fields against it, the JSON reader and the advanced mode
report it, and the window's widgets take their ranges from it. An :class:`AtmosphereError` names the field
(dotted, as in the JSON file: ``mie.phase.g1[2]``) and the allowed range.
"""
from __future__ import annotations

import math
from contextlib import contextmanager

import numpy as np

#: Allowed ranges (closed unless :data:`OPEN_BELOW` lists the field).
LIMITS = {
    "wavelength_nm": (100.0, 5000.0),
    "bottom_radius_m": (1.0e4, 1.0e9),
    "scale_height_m": (1.0, 1.0e7),
    "coefficient_m": (0.0, 1.0),
    "g": (-0.999, 0.999),
    "alpha": (0.0, 1.0),
    "ground_albedo": (0.0, 1.0),
    "max_wavelengths": 256,
    "star_temperature_k": (1000.0, 60000.0),
    "star_irradiance_w_m2": (1.0e-3, 1.0e7),
    "star_angular_radius_deg": (0.0, 10.0),
    "profile_altitude_m": (-1.0e7, 1.0e7),
    "half_width_m": (0.0, 1.0e7),
    "density": (0.0, 1.0e30),
}
#: Fields whose lower end is excluded.
OPEN_BELOW = ("half_width_m",)


class AtmosphereError(ValueError):
    """An invalid atmosphere description; ``field`` names the offending entry, ``reason`` says why."""

    def __init__(self, field_name: str, message: str):
        super().__init__(f"{field_name}: {message}")
        self.field = field_name
        self.reason = message


@contextmanager
def fields_of(prefix: str):
    """Inside, an :class:`AtmosphereError` names its field below ``prefix`` (``prefix.field``)."""
    try:
        yield
    except AtmosphereError as exc:
        raise AtmosphereError(f"{prefix}.{exc.field}", exc.reason) from None


def _range_text(lo, hi, lo_open, hi_open):
    return f"{'(' if lo_open else '['}{lo:g}, {hi:g}{')' if hi_open else ']'}"


def check_number(value, name, lo, hi, lo_open=False, hi_open=False) -> float:
    """A finite float within [lo, hi] (open ends where asked), else an AtmosphereError."""
    allowed = f"allowed range {_range_text(lo, hi, lo_open, hi_open)}"
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise AtmosphereError(name, f"must be a number, got {type(value).__name__} ({allowed})")
    value = float(value)
    if not math.isfinite(value):
        raise AtmosphereError(name, f"must be finite, got {value} ({allowed})")
    if value < lo or value > hi or (lo_open and value == lo) or (hi_open and value == hi):
        raise AtmosphereError(name, f"{value:g} is outside the {allowed}")
    return value


def check_limit(value, name: str, limit: str) -> float:
    """:func:`check_number` against ``LIMITS[limit]``."""
    return check_number(value, name, *LIMITS[limit], lo_open=limit in OPEN_BELOW)


def check_numbers(values, name: str, limit: str, n: int | None = None) -> tuple:
    """A tuple of floats, each within ``LIMITS[limit]``; ``n`` values if given (one per wavelength)."""
    if isinstance(values, np.ndarray):
        values = values.tolist() if values.ndim == 1 else values
    if not isinstance(values, (list, tuple)):
        raise AtmosphereError(name, "must be a list of numbers" + (" (one per entry of wavelengths_nm)"
                                                                   if n is not None else ""))
    if n is not None and len(values) != n:
        raise AtmosphereError(name, f"has {len(values)} values, expected {n} (one per entry of wavelengths_nm)")
    return tuple(check_limit(v, f"{name}[{i}]", limit) for i, v in enumerate(values))


def check_choice(value, name: str, choices) -> str:
    """``value`` if it is one of ``choices``, else an AtmosphereError listing them."""
    if value not in choices:
        raise AtmosphereError(name, f"must be one of {', '.join(map(repr, choices))}, got {value!r}")
    return value
