"""The atmosphere description: one validated dataclass, saved and loaded as JSON.

Standard mode is the contract of docs/atmosphere-format.md: every field in SI units,
per-wavelength lists with one value per entry of ``wavelengths_nm``. The advanced
and composition modes (:mod:`planetviz.model.advanced`) derive an :class:`Atmosphere`.

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
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .limits import LIMITS, AtmosphereError, check_choice, check_limit, check_number, check_numbers, fields_of
from .optics.phase import (double_henyey_greenstein, penndorf_phase, rayleigh_phase)
from .optics.light import SOLAR_CONSTANT, star_angular_radius, star_irradiance_at_radius
from .optics.profiles import ExponentialProfile, TableProfile, TentProfile

__all__ = ["Absorption", "Atmosphere", "FieldReader", "Mie", "Rayleigh", "Star",
           "from_dict", "parse_json", "to_dict"]

PROFILES = (ExponentialProfile, TentProfile, TableProfile)
RAYLEIGH_PHASES = ("rayleigh", "penndorf")
STAR_TYPES = ("sun", "blackbody")
AIR_MASSES = ("geometric", "pickering")


def _check_profile(profile, name: str):
    if not isinstance(profile, PROFILES):
        raise AtmosphereError(name, f"must be one of {', '.join(c.__name__ for c in PROFILES)}, "
                                    f"got {type(profile).__name__}")


@dataclass(frozen=True)
class Rayleigh:
    """Molecular scattering: beta_R(h) = scattering_m * profile(h); no absorption."""

    scattering_m: tuple
    profile: object
    phase: str = "rayleigh"

    def __post_init__(self):
        object.__setattr__(self, "scattering_m", check_numbers(self.scattering_m, "scattering_m", "coefficient_m"))
        _check_profile(self.profile, "profile")
        check_choice(self.phase, "phase", RAYLEIGH_PHASES)

    def phase_function(self, nu):
        """P_R(nu) [1/sr], the same for every wavelength."""
        return penndorf_phase(nu) if self.phase == "penndorf" else rayleigh_phase(nu)


@dataclass(frozen=True)
class Mie:
    """Particle scattering and extinction with a per-wavelength double Henyey-Greenstein phase.

    In the files the phase's ``g1``, ``g2`` and ``alpha`` sit in ``mie.phase``; errors name them so. The
    :class:`Atmosphere` checks that every list has one value per wavelength."""

    scattering_m: tuple
    extinction_m: tuple
    profile: object
    g1: tuple
    g2: tuple
    alpha: tuple

    def __post_init__(self):
        scat = check_numbers(self.scattering_m, "scattering_m", "coefficient_m")
        ext = check_numbers(self.extinction_m, "extinction_m", "coefficient_m")
        for i, (s, e) in enumerate(zip(scat, ext)):
            if e < s:
                raise AtmosphereError(f"extinction_m[{i}]", f"{e:g} is below scattering_m[{i}] = {s:g} "
                                                            "(extinction = scattering + absorption)")
        _check_profile(self.profile, "profile")
        for key, limit in (("g1", "g"), ("g2", "g"), ("alpha", "alpha")):
            object.__setattr__(self, key, check_numbers(getattr(self, key), f"phase.{key}", limit))
        object.__setattr__(self, "scattering_m", scat)
        object.__setattr__(self, "extinction_m", ext)

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

    def __post_init__(self):
        object.__setattr__(self, "extinction_m", check_numbers(self.extinction_m, "extinction_m", "coefficient_m"))
        _check_profile(self.profile, "profile")


@dataclass(frozen=True)
class Star:
    """The light source: ``sun`` (ASTM G-173 extraterrestrial) or a ``blackbody`` of a temperature, and its
    bolometric irradiance at the top of the atmosphere [W/m^2] (default: the solar constant, Earth's). The
    irradiance sets the spectrum's scale and, with the star's type and temperature, the angular size of its disc
    (:meth:`angular_radius_deg`), which must stay within LIMITS["star_angular_radius_deg"]."""

    type: str = "sun"
    temperature_k: float | None = None
    irradiance_w_m2: float = SOLAR_CONSTANT

    def __post_init__(self):
        check_choice(self.type, "type", STAR_TYPES)
        if self.type == "blackbody":
            object.__setattr__(self, "temperature_k",
                               check_limit(self.temperature_k, "temperature_k", "star_temperature_k"))
        elif self.temperature_k is not None:
            raise AtmosphereError("temperature_k", "only a blackbody star has a temperature")
        irradiance = check_limit(self.irradiance_w_m2, "irradiance_w_m2", "star_irradiance_w_m2")
        object.__setattr__(self, "irradiance_w_m2", irradiance)
        hi = LIMITS["star_angular_radius_deg"][1]
        if not self.angular_radius_deg() <= hi:           # NaN (no disc can give that much) fails too
            most = star_irradiance_at_radius(self.type, self.temperature_k, np.radians(hi))
            raise AtmosphereError("irradiance_w_m2", f"{irradiance:g} W/m^2 would need a disc over {hi:g} deg in "
                                                     f"radius; this star gives at most {most:.4g} W/m^2")

    def angular_radius_deg(self) -> float:
        """Angular radius of the star's disc seen from the planet [deg] (:func:`star_angular_radius`)."""
        return float(np.degrees(star_angular_radius(self.type, self.temperature_k, self.irradiance_w_m2)))


@dataclass(frozen=True)
class Atmosphere:
    """A planet's atmosphere in standard mode (every length in metres, coefficients in 1/m).

    Made from Python or from a file (:func:`from_dict`), it checks every field against
    :data:`~planetviz.model.limits.LIMITS` when it is made: a component when it is made, the atmosphere
    the fields that tie them together (one value per wavelength everywhere, the top above the ground)."""

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
        set_ = lambda key, value: object.__setattr__(self, key, value)
        if not isinstance(self.name, str) or not self.name.strip():
            raise AtmosphereError("name", "must be a non-empty string")
        wl = self.wavelengths_nm
        if not isinstance(wl, (list, tuple, np.ndarray)) or not 1 <= len(wl) <= LIMITS["max_wavelengths"]:
            raise AtmosphereError("wavelengths_nm", f"must be a list of 1 to {LIMITS['max_wavelengths']} numbers")
        wl = check_numbers(wl, "wavelengths_nm", "wavelength_nm")
        if len(set(wl)) != len(wl):
            raise AtmosphereError("wavelengths_nm", "must not repeat a wavelength")
        n = len(wl)
        set_("wavelengths_nm", wl)
        set_("bottom_radius_m", check_limit(self.bottom_radius_m, "bottom_radius_m", "bottom_radius_m"))
        set_("top_radius_m", check_number(self.top_radius_m, "top_radius_m", self.bottom_radius_m,
                                          2.0 * self.bottom_radius_m, lo_open=True))
        set_("ground_albedo", check_numbers(self.ground_albedo, "ground_albedo", "ground_albedo", n))
        if not isinstance(self.rayleigh, Rayleigh):
            raise AtmosphereError("rayleigh", f"must be a Rayleigh, got {type(self.rayleigh).__name__}")
        if not isinstance(self.mie, Mie):
            raise AtmosphereError("mie", f"must be a Mie, got {type(self.mie).__name__}")
        if not isinstance(self.absorption, (list, tuple)) or not all(isinstance(a, Absorption)
                                                                     for a in self.absorption):
            raise AtmosphereError("absorption", "must be a list of Absorption layers (possibly empty)")
        set_("absorption", tuple(self.absorption))
        per_wavelength = [("rayleigh.scattering_m", self.rayleigh.scattering_m),
                          ("mie.scattering_m", self.mie.scattering_m), ("mie.extinction_m", self.mie.extinction_m)]
        per_wavelength += [(f"mie.phase.{key}", getattr(self.mie, key)) for key in ("g1", "g2", "alpha")]
        per_wavelength += [(f"absorption[{i}].extinction_m", a.extinction_m) for i, a in enumerate(self.absorption)]
        for name, values in per_wavelength:
            if len(values) != n:
                raise AtmosphereError(name, f"has {len(values)} values, expected {n} "
                                            "(one per entry of wavelengths_nm)")
        if not isinstance(self.star, Star):
            raise AtmosphereError("star", f"must be a Star, got {type(self.star).__name__}")
        check_choice(self.air_mass, "air_mass", AIR_MASSES)

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
        present = [(ext, profile) for _, ext, profile in self.components() if np.any(ext)]
        if not present:
            return np.zeros(h.shape + (self.n_wavelengths,))
        # One product of the densities (..., C) and the coefficients (C, W): a third of the time of a sum over C.
        return (np.stack([profile.density(h) for _, profile in present], axis=-1)
                @ np.stack([ext for ext, _ in present]))

    def scattering(self, h):
        """(beta_R^scat(h), beta_M^scat(h)) [1/m], each ``h.shape + (W,)``."""
        h = np.asarray(h, dtype=float)[..., None]
        return (self.rayleigh.profile.density(h) * np.asarray(self.rayleigh.scattering_m),
                self.mie.profile.density(h) * np.asarray(self.mie.scattering_m))

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


class FieldReader:
    """Walks a dict from a file: missing and unknown keys, with dotted field names (``mie.phase``).

    The ranges are checked by the dataclasses the values go into; the advanced mode
    (:mod:`planetviz.model.advanced`) also reads its physical quantities with :meth:`number` and
    :meth:`numbers`."""

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
        return check_choice(self.get(key, optional=optional, default=default), self.name(key), choices)


def _profile(data, path: str):
    """A ``profile`` object: its type and that type's fields."""
    r = FieldReader(data, path)
    kind = r.string("type", ("exponential", "tent", "table"))
    keys = {"exponential": ("scale_height_m",), "tent": ("center_m", "half_width_m"),
            "table": ("altitudes_m", "densities")}[kind]
    values = [r.get(key) for key in keys]
    r.done()
    with fields_of(path):
        return {"exponential": ExponentialProfile, "tent": TentProfile, "table": TableProfile}[kind](*values)


def from_dict(data: dict) -> Atmosphere:
    """The :class:`Atmosphere` of a standard-mode dict (raises AtmosphereError).

    The dict's structure (objects, missing and unknown keys) is checked here, the values by the dataclasses."""
    r = FieldReader(data, "")
    values = {key: r.get(key) for key in ("name", "wavelengths_nm", "bottom_radius_m", "top_radius_m",
                                          "ground_albedo")}
    values["rayleigh"] = _rayleigh(r.get("rayleigh"))
    values["mie"] = _mie(r.get("mie"))
    values["absorption"] = _absorption(r.get("absorption"))
    values["star"] = _star(r.get("star")) if r.has("star") else Star()
    values["air_mass"] = r.get("air_mass", optional=True, default="geometric")
    r.done()
    return Atmosphere(**values)


def _rayleigh(data) -> Rayleigh:
    """The ``rayleigh`` object: scattering per wavelength, its profile and phase function."""
    rr = FieldReader(data, "rayleigh")
    scattering, profile, phase = rr.get("scattering_m"), _profile(rr.get("profile"), "rayleigh.profile"), \
        rr.get("phase")
    rr.done()
    with fields_of("rayleigh"):
        return Rayleigh(scattering, profile, phase)


def _mie(data) -> Mie:
    """The ``mie`` object: scattering and extinction per wavelength, its profile and double Henyey-Greenstein
    phase (``g1``, ``g2``, ``alpha`` in ``mie.phase``)."""
    mr = FieldReader(data, "mie")
    scattering, extinction = mr.get("scattering_m"), mr.get("extinction_m")
    profile = _profile(mr.get("profile"), "mie.profile")
    pr = FieldReader(mr.get("phase"), "mie.phase")
    g1, g2, alpha = pr.get("g1"), pr.get("g2"), pr.get("alpha")
    pr.done()
    mr.done()
    with fields_of("mie"):
        return Mie(scattering, extinction, profile, g1, g2, alpha)


def _absorption(layers) -> tuple:
    """The ``absorption`` list: absorbing layers, each an extinction per wavelength and a profile."""
    if not isinstance(layers, list):
        raise AtmosphereError("absorption", "must be a list of layers (possibly empty)")
    out = []
    for i, layer in enumerate(layers):
        ar = FieldReader(layer, f"absorption[{i}]")
        extinction, profile = ar.get("extinction_m"), _profile(ar.get("profile"), f"absorption[{i}].profile")
        ar.done()
        with fields_of(f"absorption[{i}]"):
            out.append(Absorption(extinction, profile))
    return tuple(out)


def _star(data) -> Star:
    """The ``star`` object: the sun, or a black body of a temperature; its irradiance (optional)."""
    sr = FieldReader(data, "star")
    kind = sr.get("type")
    temperature = sr.get("temperature_k") if kind == "blackbody" else None
    irradiance = sr.get("irradiance_w_m2", optional=True, default=SOLAR_CONSTANT)
    sr.done()
    with fields_of("star"):
        return Star(kind, temperature, irradiance)


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
        if atm.star.irradiance_w_m2 != SOLAR_CONSTANT:
            out["star"]["irradiance_w_m2"] = atm.star.irradiance_w_m2
    if atm.air_mass != "geometric":
        out["air_mass"] = atm.air_mass
    return out
