"""The atmosphere's parameters as the windows show them: a label with its unit, the value read from the
atmosphere's file form, how a new value is written back, and its range.

Both windows (planetviz/app/window.py, the PyVista sliders; planetviz/app/qt_window.py, the Qt panel) read these
rows. A row's ``allowed`` range is the dataclass's own (:data:`~planetviz.model.limits.LIMITS`, in the label's
unit; the "x" rows: the factors that keep every coefficient within its limit); ``slider`` is the part of it a
slider spans, where the pictures change. Every value goes through :func:`apply_parameter`, so an invalid one,
or one that breaks a rule tying fields together (the top of the atmosphere at most one planet radius up, Mie
extinction at least its scattering), is refused with the field named and its range.
"""
from __future__ import annotations

import copy
import json
import math
from pathlib import Path
from typing import Callable, NamedTuple

import numpy as np

from ..model.limits import LIMITS, check_number
from ..model.optics.mie import TURBIDITY_JUNGE, TURBIDITY_K, mie_scattering_turbidity, turbidity_from_scattering
from ..model.atmosphere import parse_json
from ..model.presets import PRESETS, load_atmosphere, load_dict


class Parameter(NamedTuple):
    """One row: ``get(d, b)`` reads the value from the file form ``d`` (``b``: the form the "x" rows scale),
    ``put(d, b, v)`` writes it; ``allowed(b)`` is the range a value may take (default: ``slider``)."""

    label: str
    slider: tuple
    get: Callable
    put: Callable
    allowed: Callable | None = None

    def allowed_range(self, base) -> tuple:
        """(lo, hi) in the label's unit."""
        return tuple(self.allowed(base)) if self.allowed is not None else tuple(self.slider)


def _any_finite(b):
    """allowed(b) of a row whose field the atmosphere's reader checks itself (the advanced quantities, the
    turbidity through the coefficients it makes): any finite number here, the reader's range in its refusal."""
    return -math.inf, math.inf


def _scaled(values, factor):
    return [float(v) * factor for v in values]


def _factor_range(get):
    """allowed(b) of a scale factor on the coefficients ``get(b)``: 0 to the factor that takes the largest of them
    to the coefficients' upper limit (0 to 3 where there are none: the factor changes nothing)."""
    def allowed(b):
        values = get(b)
        if not values:
            return 0.0, 3.0
        return 0.0, LIMITS["coefficient_m"][1] / max(max(values), 1e-300)
    return allowed


def _scaled_limit(limit, unit):
    lo, hi = LIMITS[limit]
    return lambda b: (lo / unit, hi / unit)


def turbidity_of(d, b):
    """The turbidity of the dict ``d`` (:func:`~planetviz.model.optics.mie.turbidity_from_scattering`)."""
    return turbidity_from_scattering(np.asarray(d["wavelengths_nm"]) * 1e-9, d["mie"]["scattering_m"])


def set_turbidity(d, b, turbidity):
    """Set the dict ``d``'s Mie scattering from Eq. 17 at ``turbidity``, keeping ``b``'s extinction / scattering."""
    scat = mie_scattering_turbidity(np.asarray(d["wavelengths_nm"]) * 1e-9, turbidity, TURBIDITY_JUNGE, TURBIDITY_K)
    ratio = np.asarray(b["mie"]["extinction_m"]) / np.maximum(np.asarray(b["mie"]["scattering_m"]), 1e-300)
    d["mie"].update(scattering_m=[float(x) for x in scat], extinction_m=[float(x) for x in scat * ratio])


def _set_radius(d, b, radius_km):
    """The planet's radius, the atmosphere's thickness kept."""
    thickness = d["top_radius_m"] - d["bottom_radius_m"]
    d.update(bottom_radius_m=radius_km * 1e3, top_radius_m=radius_km * 1e3 + thickness)


#: The planet's size (the Qt panel; the thickness may be at most the radius).
GEOMETRY = [
    Parameter("planet radius [km]", (1e3, 1e5), lambda d, b: d["bottom_radius_m"] / 1e3, _set_radius,
              _scaled_limit("bottom_radius_m", 1e3)),
    Parameter("atmosphere thickness [km]", (10.0, 1000.0),
              lambda d, b: (d["top_radius_m"] - d["bottom_radius_m"]) / 1e3,
              lambda d, b, v: d.update(top_radius_m=d["bottom_radius_m"] + v * 1e3),
              lambda b: (0.0, b["bottom_radius_m"] / 1e3)),
]

#: Standard mode: the coefficients' scales, the profiles' scale heights, the Mie phase, ozone and the ground.
STANDARD = [
    Parameter("Rayleigh x (scattering scale)", (0.1, 5.0), lambda d, b: 1.0,
              lambda d, b, v: d["rayleigh"].update(scattering_m=_scaled(b["rayleigh"]["scattering_m"], v)),
              _factor_range(lambda b: b["rayleigh"]["scattering_m"])),
    Parameter("Mie x (scattering and extinction scale)", (0.0, 10.0), lambda d, b: 1.0,
              lambda d, b, v: d["mie"].update(scattering_m=_scaled(b["mie"]["scattering_m"], v),
                                              extinction_m=_scaled(b["mie"]["extinction_m"], v)),
              _factor_range(lambda b: b["mie"]["extinction_m"])),
    Parameter("turbidity T (Eq. 17: Junge 4, K 0.0092)", (1.0, 10.0), turbidity_of, set_turbidity, _any_finite),
    Parameter("Rayleigh scale height [km]", (0.5, 50.0),
              lambda d, b: d["rayleigh"]["profile"]["scale_height_m"] / 1e3,
              lambda d, b, v: d["rayleigh"]["profile"].update(scale_height_m=v * 1e3),
              _scaled_limit("scale_height_m", 1e3)),
    Parameter("Mie scale height [km]", (0.1, 20.0), lambda d, b: d["mie"]["profile"]["scale_height_m"] / 1e3,
              lambda d, b, v: d["mie"]["profile"].update(scale_height_m=v * 1e3),
              _scaled_limit("scale_height_m", 1e3)),
    Parameter("Mie g1 (forward lobe)", LIMITS["g"], lambda d, b: d["mie"]["phase"]["g1"][0],
              lambda d, b, v: d["mie"]["phase"].update(g1=[v] * len(d["wavelengths_nm"]))),
    Parameter("Mie g2 (second lobe)", LIMITS["g"], lambda d, b: d["mie"]["phase"]["g2"][0],
              lambda d, b, v: d["mie"]["phase"].update(g2=[v] * len(d["wavelengths_nm"]))),
    Parameter("Mie alpha (weight of g1)", LIMITS["alpha"], lambda d, b: d["mie"]["phase"]["alpha"][0],
              lambda d, b, v: d["mie"]["phase"].update(alpha=[v] * len(d["wavelengths_nm"]))),
    Parameter("ozone x (absorbers' scale, 0 = off)", (0.0, 3.0), lambda d, b: 1.0 if b["absorption"] else 0.0,
              lambda d, b, v: d.update(absorption=[{**layer, "extinction_m": _scaled(layer["extinction_m"], v)}
                                                   for layer in b["absorption"]]),
              _factor_range(lambda b: [x for layer in b["absorption"] for x in layer["extinction_m"]])),
    Parameter("ground albedo", LIMITS["ground_albedo"], lambda d, b: d["ground_albedo"][0],
              lambda d, b, v: d.update(ground_albedo=[v] * len(d["wavelengths_nm"]))),
]


def advanced_parameters(source_base):
    """Advanced mode: the physical quantities of the paper's Table 1 "(A)" in the file form (a row whose field the
    file lacks reads as None and is not shown); the "x" rows scale ``source_base``'s values. The advanced reader
    (planetviz/model/advanced.py) checks each quantity's range, so these rows take any finite number."""
    rows = [
        Parameter("molecular refractivity (n - 1) x", (0.1, 10.0),
                  lambda d, b: 1.0 if "refractive_index" in d["rayleigh"] else None,
                  lambda d, b, v: d["rayleigh"].update(refractive_index=[
                      1.0 + (n - 1.0) * v for n in source_base["rayleigh"]["refractive_index"]])),
        Parameter("number density N [1/m3]", (1e22, 1e27), lambda d, b: d["rayleigh"]["number_density_m3"],
                  lambda d, b, v: d["rayleigh"].update(number_density_m3=v)),
        Parameter("surface pressure [kPa]", (1.0, 2000.0), lambda d, b: d["rayleigh"]["surface_pressure_pa"] / 1e3,
                  lambda d, b, v: d["rayleigh"].update(surface_pressure_pa=v * 1e3)),
        Parameter("depolarisation delta", (0.0, 0.5), lambda d, b: d["rayleigh"]["depolarization"],
                  lambda d, b, v: d["rayleigh"].update(depolarization=v)),
        Parameter("turbidity T", (1.0, 10.0), lambda d, b: d["mie"]["scattering"]["turbidity"],
                  lambda d, b, v: d["mie"]["scattering"].update(turbidity=v)),
        Parameter("Junge exponent v", (2.0, 6.0), lambda d, b: d["mie"]["scattering"]["junge_exponent"],
                  lambda d, b, v: d["mie"]["scattering"].update(junge_exponent=v)),
        Parameter("particle radius r [um]", (0.01, 20.0), lambda d, b: d["mie"]["particles"]["radius_m"] * 1e6,
                  lambda d, b, v: d["mie"]["particles"].update(radius_m=v * 1e-6)),
        Parameter("particle index, real part", (1.0, 2.0),
                  lambda d, b: d["mie"]["particles"]["refractive_index_real"][0],
                  lambda d, b, v: d["mie"]["particles"].update(
                      refractive_index_real=[v] * len(d["mie"]["particles"]["refractive_index_real"]))),
        Parameter("particle index, imaginary k", (0.0, 0.1),
                  lambda d, b: d["mie"]["particles"]["refractive_index_imag"][-1],
                  lambda d, b, v: d["mie"]["particles"].update(
                      refractive_index_imag=[v] * len(d["mie"]["particles"]["refractive_index_imag"]))),
        Parameter("particle K x (Eq. 17's K, scale)", (0.1, 5.0),
                  lambda d, b: 1.0 if "k" in d["mie"]["scattering"] else None,
                  lambda d, b, v: d["mie"]["scattering"].update(k=_scaled(source_base["mie"]["scattering"]["k"], v))),
        Parameter("dust amount x (particle number density, scale)", (0.0, 5.0),
                  lambda d, b: 1.0 if "number_density_m3" in d["mie"]["particles"] else None,
                  lambda d, b, v: d["mie"]["particles"].update(
                      number_density_m3=source_base["mie"]["particles"]["number_density_m3"] * v)),
        Parameter("ground albedo", LIMITS["ground_albedo"], lambda d, b: d["ground_albedo"][0],
                  lambda d, b, v: d.update(ground_albedo=[v] * len(d["wavelengths_nm"]))),
    ]
    return [row if row.allowed is not None or row.label == "ground albedo" else row._replace(allowed=_any_finite)
            for row in rows]


def current_value(row, source, base):
    """The row's value in the file form ``source``, or None when the form lacks its field."""
    try:
        value = row.get(source, base)
    except (KeyError, TypeError, IndexError):
        return None
    return None if value is None else float(value)


def apply_parameter(row, source, base, value):
    """(atmosphere, file form) with ``row`` set to ``value`` in a copy of ``source``.

    Raises :class:`~planetviz.model.limits.AtmosphereError` naming the row and its allowed range when ``value`` is
    outside it, or the field and its range when the atmosphere it makes is invalid."""
    lo, hi = row.allowed_range(base)
    value = check_number(value, row.label, lo, hi)
    d = copy.deepcopy(source)
    row.put(d, base, value)
    return load_dict(d), d


def load_with_form(key):
    """(atmosphere, its file form) of a preset name, an atmosphere file or an Atmosphere: the file form is the
    preset's or the file's own JSON (advanced fields where it has them; what the advanced rows read and write),
    else the atmosphere's standard form. Raises AtmosphereError, ValueError or OSError for an invalid one."""
    if isinstance(key, str) and key in PRESETS:
        return load_atmosphere(key), json.loads(PRESETS[key].read_text())
    if isinstance(key, (str, Path)) and Path(key).is_file():
        source = parse_json(Path(key).read_text(), source=str(key))
        return load_dict(source), source
    atm = load_atmosphere(key)
    return atm, atm.to_dict()
