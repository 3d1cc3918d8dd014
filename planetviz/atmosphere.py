"""The atmosphere description: one validated dataclass, saved and loaded as JSON.

Standard mode is the contract of docs/atmosphere-format.md: every field in SI units,
per-wavelength lists with one value per entry of ``wavelengths_nm``. The advanced
and composition modes (:mod:`planetviz.physical`) derive an :class:`Atmosphere`.

Example
-------
>>> from planetviz import load_atmosphere
>>> atm = load_atmosphere("earth")
>>> atm.wavelengths_nm
(680.0, 550.0, 440.0)
>>> thicker = atm.replace(top_radius_m=6.43e6)
"""
from __future__ import annotations

import dataclasses
import json
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .optics.phase import (double_henyey_greenstein, penndorf_phase, rayleigh_phase)
from .optics.profiles import ExponentialProfile, TableProfile, TentProfile

#: Allowed ranges, shown in error messages and in the app's widgets.
LIMITS = {
    "wavelength_nm": (100.0, 5000.0),
    "bottom_radius_m": (1.0e4, 1.0e9),
    "scale_height_m": (1.0, 1.0e7),
    "coefficient_m": (0.0, 1.0),
    "g": (-0.999, 0.999),
    "max_wavelengths": 256,
    "star_temperature_k": (1000.0, 60000.0),
}


class AtmosphereError(ValueError):
    """An invalid atmosphere description; ``field`` names the offending entry."""

    def __init__(self, field_name: str, message: str):
        super().__init__(f"{field_name}: {message}")
        self.field = field_name


@dataclass(frozen=True)
class Rayleigh:
    """Molecular scattering: beta_R(h) = scattering_m * profile(h); no absorption."""

    scattering_m: tuple
    profile: object
    phase: str = "rayleigh"

    def phase_function(self, nu):
        """P_R(nu) [1/sr], the same for every wavelength."""
        return penndorf_phase(nu) if self.phase == "penndorf" else rayleigh_phase(nu)


@dataclass(frozen=True)
class Mie:
    """Particle scattering and extinction with a per-wavelength double Henyey-Greenstein phase."""

    scattering_m: tuple
    extinction_m: tuple
    profile: object
    g1: tuple
    g2: tuple
    alpha: tuple

    def phase_function(self, nu):
        """P_M(nu) [1/sr], shape ``nu.shape + (W,)``."""
        nu = np.asarray(nu, dtype=float)[..., None]
        return double_henyey_greenstein(nu, np.asarray(self.g1), np.asarray(self.g2),
                                        np.asarray(self.alpha))


@dataclass(frozen=True)
class Absorption:
    """A purely absorbing layer (ozone, oxygen, ...): beta_abs(h) = extinction_m * profile(h)."""

    extinction_m: tuple
    profile: object


@dataclass(frozen=True)
class Star:
    """The light source: ``sun`` (ASTM G-173 extraterrestrial) or a ``blackbody`` of a temperature."""

    type: str = "sun"
    temperature_k: float | None = None


@dataclass(frozen=True)
class Atmosphere:
    """A planet's atmosphere in standard mode (every length in metres, coefficients in 1/m)."""

    name: str
    wavelengths_nm: tuple
    bottom_radius_m: float
    top_radius_m: float
    ground_albedo: tuple
    rayleigh: Rayleigh
    mie: Mie
    absorption: tuple = ()
    star: Star = field(default_factory=Star)
    air_mass: str = "geometric"

    def __post_init__(self):
        # Validate through the dict form so that Python construction and JSON agree.
        from_dict(to_dict(self))

    # ----------------------------------------------------------------- derived
    @property
    def n_wavelengths(self) -> int:
        return len(self.wavelengths_nm)

    @property
    def thickness_m(self) -> float:
        return self.top_radius_m - self.bottom_radius_m

    def components(self):
        """(scattering [W], extinction [W], profile) of every component, Rayleigh first, Mie second."""
        out = [(np.asarray(self.rayleigh.scattering_m), np.asarray(self.rayleigh.scattering_m),
                self.rayleigh.profile),
               (np.asarray(self.mie.scattering_m), np.asarray(self.mie.extinction_m),
                self.mie.profile)]
        for layer in self.absorption:
            out.append((np.zeros(self.n_wavelengths), np.asarray(layer.extinction_m), layer.profile))
        return out

    def extinction(self, h, index=None):
        """beta_ext(h) [1/m], shape ``h.shape + (W,)``, or ``h.shape + (1,)`` for one wavelength index."""
        h = np.asarray(h, dtype=float)
        if index is not None:
            one = np.zeros(h.shape)
            for _, ext, profile in self.components():
                if ext[index]:
                    one += ext[index] * profile.density(h)
            return one[..., None]
        total = np.zeros(h.shape + (self.n_wavelengths,))
        for _, ext, profile in self.components():
            ext = ext if index is None else ext[[index]]
            if np.any(ext):
                total += profile.density(h)[..., None] * ext
        return total

    def scattering(self, h):
        """(beta_R^scat(h), beta_M^scat(h)) [1/m], each ``h.shape + (W,)``."""
        h = np.asarray(h, dtype=float)[..., None]
        return (self.rayleigh.profile.density(h) * np.asarray(self.rayleigh.scattering_m),
                self.mie.profile.density(h) * np.asarray(self.mie.scattering_m))

    def extinction_majorant(self) -> np.ndarray:
        """An upper bound of beta_ext(h) over the whole shell, per wavelength [1/m]."""
        total = np.zeros(self.n_wavelengths)
        for _, ext, profile in self.components():
            total += ext * profile.max_density(0.0, self.thickness_m)
        return total

    def component_optical_depths(self, n: int = 4001) -> list:
        """Vertical optical depth of each component of :meth:`components` (Simpson's rule, n nodes)."""
        h = np.linspace(0.0, self.thickness_m, n)
        w = np.full(n, 2.0)
        w[1:-1:2] = 4.0
        w[0] = w[-1] = 1.0
        step = (h[1] - h[0]) / 3.0
        return [ext * float(np.dot(w, profile.density(h))) * step for _, ext, profile in self.components()]

    def vertical_optical_depth(self, n: int = 4001) -> np.ndarray:
        """tau(lambda) from the ground to the top along the zenith."""
        return sum(self.component_optical_depths(n))

    # ------------------------------------------------------------------ I/O
    def replace(self, **changes) -> "Atmosphere":
        """A validated copy with some fields changed."""
        return dataclasses.replace(self, **changes)

    def to_dict(self) -> dict:
        return to_dict(self)

    def to_json(self) -> str:
        return json.dumps(to_dict(self), indent=2)

    def save(self, path) -> None:
        Path(path).write_text(self.to_json() + "\n")

    @classmethod
    def from_dict(cls, data: dict) -> "Atmosphere":
        return from_dict(data)

    @classmethod
    def from_json(cls, text: str) -> "Atmosphere":
        return from_dict(parse_json(text))


# ====================================================================== parsing
def parse_json(text: str, source: str = "atmosphere file") -> dict:
    """json.loads that refuses NaN/Infinity and reports syntax errors as ValueError."""
    def refuse(token):
        raise AtmosphereError(source, f"{token} is not a finite number")
    try:
        data = json.loads(text, parse_constant=refuse)
    except json.JSONDecodeError as exc:
        raise AtmosphereError(source, f"malformed JSON at line {exc.lineno} column {exc.colno}: "
                                      f"{exc.msg}") from None
    if not isinstance(data, dict):
        raise AtmosphereError(source, "must be a JSON object")
    return data


class _Reader:
    """Walks a dict, checking types, ranges and unknown/missing keys with dotted field names."""

    def __init__(self, data, path: str, n: int | None = None):
        if not isinstance(data, dict):
            raise AtmosphereError(path or "atmosphere", "must be a JSON object")
        self.data, self.path, self.n, self.used = data, path, n, set()

    def name(self, key):
        return f"{self.path}.{key}" if self.path else key

    def get(self, key, optional=False, default=None):
        if key not in self.data:
            if optional:
                return default
            raise AtmosphereError(self.name(key), "missing")
        self.used.add(key)
        return self.data[key]

    def has(self, key):
        return key in self.data

    def done(self):
        extra = sorted(set(self.data) - self.used)
        if extra:
            raise AtmosphereError(self.name(extra[0]), "unknown field")

    def number(self, key, lo, hi, lo_open=False, hi_open=False, optional=False, default=None):
        if optional and key not in self.data:
            return default
        return check_number(self.get(key), self.name(key), lo, hi, lo_open, hi_open)

    def numbers(self, key, lo, hi, lo_open=False, hi_open=False):
        value = self.get(key)
        name = self.name(key)
        if not isinstance(value, list):
            raise AtmosphereError(name, f"must be a list of {self.n} numbers")
        if self.n is not None and len(value) != self.n:
            raise AtmosphereError(name, f"has {len(value)} values, expected {self.n} "
                                        "(one per entry of wavelengths_nm)")
        return tuple(check_number(v, f"{name}[{i}]", lo, hi, lo_open, hi_open)
                     for i, v in enumerate(value))

    def string(self, key, choices, optional=False, default=None):
        value = self.get(key, optional=optional, default=default)
        if value not in choices:
            raise AtmosphereError(self.name(key), f"must be one of {', '.join(map(repr, choices))}, "
                                                  f"got {value!r}")
        return value


def _range_text(lo, hi, lo_open, hi_open):
    return f"{'(' if lo_open else '['}{lo:g}, {hi:g}{')' if hi_open else ']'}"


def check_number(value, name, lo, hi, lo_open=False, hi_open=False) -> float:
    """A finite float within [lo, hi] (open ends where asked), else an AtmosphereError."""
    allowed = f"allowed range {_range_text(lo, hi, lo_open, hi_open)}"
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise AtmosphereError(name, f"must be a number, got {type(value).__name__} ({allowed})")
    value = float(value)
    if not math.isfinite(value):
        raise AtmosphereError(name, f"must be finite, got {value} ({allowed})")
    if value < lo or value > hi or (lo_open and value == lo) or (hi_open and value == hi):
        raise AtmosphereError(name, f"{value:g} is outside the {allowed}")
    return value


def _profile(data, path: str):
    r = _Reader(data, path)
    kind = r.string("type", ("exponential", "tent", "table"))
    lo, hi = LIMITS["scale_height_m"]
    if kind == "exponential":
        out = ExponentialProfile(r.number("scale_height_m", lo, hi))
    elif kind == "tent":
        out = TentProfile(r.number("center_m", -1e7, 1e7),
                          r.number("half_width_m", 0.0, 1e7, lo_open=True))
    else:
        alt = r.get("altitudes_m")
        den = r.get("densities")
        if not isinstance(alt, list) or not isinstance(den, list) or len(alt) < 2 or len(alt) != len(den):
            raise AtmosphereError(f"{path}.altitudes_m",
                                  "altitudes_m and densities must be lists of equal length >= 2")
        alt = tuple(check_number(v, f"{path}.altitudes_m[{i}]", -1e7, 1e7) for i, v in enumerate(alt))
        den = tuple(check_number(v, f"{path}.densities[{i}]", 0.0, 1e30) for i, v in enumerate(den))
        if any(b <= a for a, b in zip(alt, alt[1:])):
            raise AtmosphereError(f"{path}.altitudes_m", "must be strictly increasing")
        out = TableProfile(alt, den)
    r.done()
    return out


def from_dict(data: dict) -> Atmosphere:
    """Validate a standard-mode dict and build the :class:`Atmosphere` (raises AtmosphereError)."""
    r = _Reader(data, "")
    name = r.get("name")
    if not isinstance(name, str) or not name.strip():
        raise AtmosphereError("name", "must be a non-empty string")
    wl = r.get("wavelengths_nm")
    if not isinstance(wl, list) or not 1 <= len(wl) <= LIMITS["max_wavelengths"]:
        raise AtmosphereError("wavelengths_nm",
                              f"must be a list of 1 to {LIMITS['max_wavelengths']} numbers")
    wl = tuple(check_number(v, f"wavelengths_nm[{i}]", *LIMITS["wavelength_nm"])
               for i, v in enumerate(wl))
    if len(set(wl)) != len(wl):
        raise AtmosphereError("wavelengths_nm", "must not repeat a wavelength")
    n = len(wl)
    r.n = n
    bottom = r.number("bottom_radius_m", *LIMITS["bottom_radius_m"])
    top = r.number("top_radius_m", bottom, 2.0 * bottom, lo_open=True)
    albedo = r.numbers("ground_albedo", 0.0, 1.0)
    rayleigh = _rayleigh(r.get("rayleigh"), n)
    mie = _mie(r.get("mie"), n)
    absorption = _absorption(r.get("absorption"), n)
    star = _star(r.get("star")) if r.has("star") else Star()
    air_mass = r.string("air_mass", ("geometric", "pickering"), optional=True, default="geometric")
    r.done()
    atm = object.__new__(Atmosphere)
    for key, value in dict(name=name, wavelengths_nm=wl, bottom_radius_m=bottom, top_radius_m=top,
                           ground_albedo=albedo, rayleigh=rayleigh, mie=mie,
                           absorption=absorption, star=star, air_mass=air_mass).items():
        object.__setattr__(atm, key, value)
    return atm


def _rayleigh(data, n: int) -> Rayleigh:
    """The ``rayleigh`` object: scattering per wavelength, its profile and phase function."""
    c_lo, c_hi = LIMITS["coefficient_m"]
    rr = _Reader(data, "rayleigh", n)
    rayleigh = Rayleigh(rr.numbers("scattering_m", c_lo, c_hi), _profile(rr.get("profile"), "rayleigh.profile"),
                        rr.string("phase", ("rayleigh", "penndorf")))
    rr.done()
    return rayleigh


def _mie(data, n: int) -> Mie:
    """The ``mie`` object: scattering and extinction per wavelength (extinction >= scattering), its profile and
    double Henyey-Greenstein phase."""
    c_lo, c_hi = LIMITS["coefficient_m"]
    mr = _Reader(data, "mie", n)
    scat = mr.numbers("scattering_m", c_lo, c_hi)
    ext = mr.numbers("extinction_m", c_lo, c_hi)
    for i, (s, e) in enumerate(zip(scat, ext)):
        if e < s:
            raise AtmosphereError(f"mie.extinction_m[{i}]",
                                  f"{e:g} is below mie.scattering_m[{i}] = {s:g} "
                                  "(extinction = scattering + absorption)")
    profile = _profile(mr.get("profile"), "mie.profile")
    pr = _Reader(mr.get("phase"), "mie.phase", n)
    g1 = pr.numbers("g1", *LIMITS["g"])
    g2 = pr.numbers("g2", *LIMITS["g"])
    alpha = pr.numbers("alpha", 0.0, 1.0)
    pr.done()
    mr.done()
    return Mie(scat, ext, profile, g1, g2, alpha)


def _absorption(layers, n: int) -> tuple:
    """The ``absorption`` list: absorbing layers, each an extinction per wavelength and a profile."""
    if not isinstance(layers, list):
        raise AtmosphereError("absorption", "must be a list of layers (possibly empty)")
    c_lo, c_hi = LIMITS["coefficient_m"]
    out = []
    for i, layer in enumerate(layers):
        ar = _Reader(layer, f"absorption[{i}]", n)
        out.append(Absorption(ar.numbers("extinction_m", c_lo, c_hi),
                              _profile(ar.get("profile"), f"absorption[{i}].profile")))
        ar.done()
    return tuple(out)


def _star(data) -> Star:
    """The ``star`` object: the sun, or a black body of a temperature."""
    sr = _Reader(data, "star")
    kind = sr.string("type", ("sun", "blackbody"))
    temp = sr.number("temperature_k", *LIMITS["star_temperature_k"]) if kind == "blackbody" else None
    sr.done()
    return Star(kind, temp)


def to_dict(atm: Atmosphere) -> dict:
    """The standard-mode dict (optional fields only when they differ from their defaults)."""
    def floats(values):
        return [float(v) for v in values]

    out = {
        "name": atm.name,
        "wavelengths_nm": floats(atm.wavelengths_nm),
        "bottom_radius_m": atm.bottom_radius_m,
        "top_radius_m": atm.top_radius_m,
        "ground_albedo": floats(atm.ground_albedo),
        "rayleigh": {"scattering_m": floats(atm.rayleigh.scattering_m),
                     "profile": atm.rayleigh.profile.to_dict(),
                     "phase": atm.rayleigh.phase},
        "mie": {"scattering_m": floats(atm.mie.scattering_m),
                "extinction_m": floats(atm.mie.extinction_m),
                "profile": atm.mie.profile.to_dict(),
                "phase": {"g1": floats(atm.mie.g1), "g2": floats(atm.mie.g2), "alpha": floats(atm.mie.alpha)}},
        "absorption": [{"extinction_m": floats(a.extinction_m), "profile": a.profile.to_dict()}
                       for a in atm.absorption],
    }
    if atm.star != Star():
        out["star"] = {"type": atm.star.type}
        if atm.star.temperature_k is not None:
            out["star"]["temperature_k"] = atm.star.temperature_k
    if atm.air_mass != "geometric":
        out["air_mass"] = atm.air_mass
    return out
