"""Advanced mode: derive the standard-mode coefficients from physical quantities (paper Sect. 4, Table 1 "(A)").

An advanced file has ``"mode": "advanced"`` and the same geometry fields as a standard file;
its ``rayleigh``, ``mie`` and ``absorption`` entries hold physical quantities instead of
coefficients. :func:`derive` turns it into an :class:`~planetviz.model.atmosphere.Atmosphere`, which
is what everything else uses. The format, field by field, is in docs/atmosphere-format.md.

Rayleigh (one of):
  * Eq. 11: ``refractive_index`` (per wavelength) measured at ``refractive_index_number_density_m3``
    (default: ``number_density_m3``), ``number_density_m3``, ``depolarization``;
  * composition: ``gases`` (mole fractions of N2, O2, Ar, CO2, H2, He, H2O),
    ``surface_pressure_pa``, ``temperature_k`` (N = p / k T);
  and the scale height as ``scale_height_m`` or from ``hydrostatic`` (H = R T / M g; with gases,
  M defaults to the mixture's mean molar mass).
Mie: ``scattering`` from turbidity / Junge exponent / K (Eq. 17) or ``"particles"``; ``extinction``
  as ``scattering_ratio`` (beta_scat / beta_ext) or ``"particles"`` (anomalous diffraction, Eqs. 19-20)
  with ``particles`` = radius, complex refractive index, number density.
Absorption layers: ``O3`` (cross-sections x US Standard 1976 profile, Eq. 15), ``O2`` (Eqs. 13-14; O2-O2 collision-induced
  absorption unless ``cross_section_m2`` is given),
  ``particles`` (small absorbing particles, Eq. 12).
"""
from __future__ import annotations

import numpy as np

from .atmosphere import FieldReader, from_dict
from .limits import LIMITS, AtmosphereError, check_number
from .optics.absorption import (oxygen_absorption, oxygen_cia, oxygen_cia_absorption, ozone_column_du,
                                ozone_cross_section, ozone_profile_table, small_particle_absorption)
from .optics.composition import GASES, mean_molar_mass, mixture_cross_section
from .optics.mie import (mie_absorption_particles, mie_extinction_particles,
                         mie_scattering_turbidity)
from .optics.rayleigh import number_density, rayleigh_scattering, scale_height


def _scale_height(r: FieldReader, default_molar_mass=None) -> float:
    lo, hi = LIMITS["scale_height_m"]
    if r.has("scale_height_m"):
        return r.number("scale_height_m", lo, hi)
    hr = FieldReader(r.get("hydrostatic"), r.name("hydrostatic"))
    if default_molar_mass is not None and not hr.has("molar_mass_kg_mol"):
        molar = default_molar_mass
    else:
        molar = hr.number("molar_mass_kg_mol", 1e-4, 1.0, lo_open=True)
    temp = hr.number("temperature_k", 1.0, 1e5)
    grav = hr.number("gravity_m_s2", 1e-3, 1e4)
    hr.done()
    return check_number(scale_height(molar, temp, grav), r.name("hydrostatic") + " (derived H)", lo, hi)


def _rayleigh(data, lam_m, n):
    r = FieldReader(data, "rayleigh", n)
    if r.has("gases"):
        gases = r.get("gases")
        if not isinstance(gases, dict) or not gases:
            raise AtmosphereError("rayleigh.gases", f"must map gas names ({', '.join(GASES)}) to mole fractions")
        fractions = {}
        for name, x in gases.items():
            if name not in GASES:
                raise AtmosphereError(f"rayleigh.gases.{name}", f"unknown gas; known: {', '.join(GASES)}")
            fractions[name] = check_number(x, f"rayleigh.gases.{name}", 0.0, 1.0)
        if sum(fractions.values()) <= 0:
            raise AtmosphereError("rayleigh.gases", "mole fractions must not all be 0")
        pressure = r.number("surface_pressure_pa", 0.0, 1e9, lo_open=True)
        temperature = r.number("temperature_k", 1.0, 1e5)
        beta = number_density(pressure, temperature) * mixture_cross_section(fractions, lam_m)
        height = _scale_height(r, mean_molar_mass(fractions))
    else:
        index = r.numbers("refractive_index", 1.0, 3.0)
        dens = r.number("number_density_m3", 0.0, 1e30)
        ref = r.number("refractive_index_number_density_m3", 0.0, 1e30, lo_open=True,
                       optional=True, default=None)
        delta = r.number("depolarization", 0.0, 0.5)
        beta = rayleigh_scattering(lam_m, index, dens, delta, ref) if dens > 0 else np.zeros(n)
        height = _scale_height(r)
    phase = r.string("phase", ("rayleigh", "penndorf"))
    r.done()
    return {"scattering_m": [float(b) for b in beta],
            "profile": {"type": "exponential", "scale_height_m": height}, "phase": phase}


def _particles(data, path, lam_m, n):
    pr = FieldReader(data, path, n)
    radius = pr.number("radius_m", 0.0, 1e-3, lo_open=True)
    m = np.array(pr.numbers("refractive_index_real", 1.0, 10.0, lo_open=True))
    k = np.array(pr.numbers("refractive_index_imag", 0.0, 10.0))
    dens = pr.number("number_density_m3", 0.0, 1e30)
    pr.done()
    ext = mie_extinction_particles(lam_m, radius, m, k, dens)
    absorb = mie_absorption_particles(lam_m, radius, k, dens)
    return ext, absorb


def _mie(data, lam_m, n):
    r = FieldReader(data, "mie", n)
    particles = None
    if r.has("particles"):
        particles = _particles(r.get("particles"), "mie.particles", lam_m, n)
    scat_spec = r.get("scattering")
    if scat_spec == "particles":
        if particles is None:
            raise AtmosphereError("mie.scattering", '"particles" needs a mie.particles entry')
        scat = particles[0] - particles[1]
    else:
        sr = FieldReader(scat_spec, "mie.scattering", n)
        scat = mie_scattering_turbidity(lam_m, sr.number("turbidity", 1.0, 64.0),
                                        sr.number("junge_exponent", 2.0, 6.0), np.array(sr.numbers("k", 0.0, 100.0)))
        sr.done()
    ext_spec = r.get("extinction")
    if ext_spec == "particles":
        if particles is None:
            raise AtmosphereError("mie.extinction", '"particles" needs a mie.particles entry')
        ext = particles[0]
    else:
        er = FieldReader(ext_spec, "mie.extinction", n)
        ratio = er.number("scattering_ratio", 0.0, 1.0, lo_open=True)
        er.done()
        ext = scat / ratio
    for i in range(n):
        if scat[i] > ext[i] * (1 + 1e-12):
            raise AtmosphereError("mie", f"derived scattering {scat[i]:.4g} exceeds extinction {ext[i]:.4g} "
                                         f"at {lam_m[i] * 1e9:g} nm")
    height = _scale_height(r)
    phase = r.get("phase")
    r.done()
    return {"scattering_m": [float(v) for v in scat], "extinction_m": [float(v) for v in np.maximum(ext, scat)],
            "profile": {"type": "exponential", "scale_height_m": height}, "phase": phase}


def _absorption(data, i, lam_m, n):
    path = f"absorption[{i}]"
    r = FieldReader(data, path, n)
    species = r.string("species", ("O3", "O2", "particles"))
    if species == "O3":
        alt, dens = ozone_profile_table()
        column = r.number("column_du", 0.0, 1e5, optional=True, default=None)
        if column is not None:
            dens = dens * column / ozone_column_du(alt, dens)
        peak = float(dens.max())
        ext = ozone_cross_section(lam_m * 1e9) * peak
        profile = {"type": "table", "altitudes_m": [float(a) for a in alt],
                   "densities": [float(d / peak) for d in dens]}
    elif species == "O2":
        fraction = r.number("volume_fraction", 0.0, 1.0)
        density = r.number("number_density_m3", 0.0, 1e30)
        height = _scale_height(r)
        if r.has("cross_section_m2"):
            ext = oxygen_absorption(np.array(r.numbers("cross_section_m2", 0.0, 1e-18)), fraction, density)
        else:
            try:
                cia = oxygen_cia(lam_m * 1e9)
            except ValueError as err:
                raise AtmosphereError(f"{path}.cross_section_m2", str(err)) from None
            ext = oxygen_cia_absorption(cia, fraction, density)
            height = height / 2.0
        profile = {"type": "exponential", "scale_height_m": height}
    else:
        m = np.array(r.numbers("refractive_index_real", 0.0, 10.0, lo_open=True))
        k = np.array(r.numbers("refractive_index_imag", 0.0, 10.0))
        ext = small_particle_absorption(lam_m, r.number("radius_m", 0.0, 1e-6, lo_open=True), m, k,
                                        r.number("number_density_m3", 0.0, 1e30))
        profile = {"type": "exponential", "scale_height_m": _scale_height(r)}
    r.done()
    return {"extinction_m": [float(max(v, 0.0)) for v in ext], "profile": profile}


def derive_dict(data: dict) -> dict:
    """The standard-mode dict derived from an advanced-mode dict (raises AtmosphereError)."""
    r = FieldReader(data, "")
    r.string("mode", ("advanced",))
    wl = r.get("wavelengths_nm")
    if not isinstance(wl, list) or not 1 <= len(wl) <= LIMITS["max_wavelengths"]:
        raise AtmosphereError("wavelengths_nm", f"must be a list of 1 to {LIMITS['max_wavelengths']} numbers")
    wl = [check_number(v, f"wavelengths_nm[{i}]", *LIMITS["wavelength_nm"]) for i, v in enumerate(wl)]
    n = len(wl)
    lam_m = np.array(wl) * 1e-9
    out = {"name": r.get("name"), "wavelengths_nm": wl, "bottom_radius_m": r.get("bottom_radius_m"),
           "top_radius_m": r.get("top_radius_m"), "ground_albedo": r.get("ground_albedo"),
           "rayleigh": _rayleigh(r.get("rayleigh"), lam_m, n), "mie": _mie(r.get("mie"), lam_m, n)}
    layers = r.get("absorption")
    if not isinstance(layers, list):
        raise AtmosphereError("absorption", "must be a list of layers (possibly empty)")
    out["absorption"] = [_absorption(layer, i, lam_m, n) for i, layer in enumerate(layers)]
    for key in ("star", "air_mass"):
        if r.has(key):
            out[key] = r.get(key)
    r.done()
    return out


def derive(data: dict):
    """The validated :class:`~planetviz.model.atmosphere.Atmosphere` of an advanced-mode dict."""
    return from_dict(derive_dict(data))

