"""Atmospheres at the edges of what the files accept, conservative atmospheres and the energy balance.

:func:`edge_atmosphere` moves one field of the standard Earth to an end of its range (:data:`EDGE_NAMES`);
:func:`conservative` (of any atmosphere; :func:`conservative_atmosphere` of a preset) has no absorption and a white
ground, so that the energy entering the top
leaves it again (:func:`flux_balance`); :func:`spectral_earth` is the Earth at any number of wavelengths.
"""
from __future__ import annotations

import numpy as np

from ..model.atmosphere import Atmosphere
from ..model.presets import load_atmosphere
from ..tables.evaluator import sky_radiance
from ..tables.lookup import get_transmittance_to_sun

def spectral_earth(n):
    """The Earth at ``n`` wavelengths from 400 to 700 nm: Rayleigh scattering as lambda^-4 through the 550 nm
    value, the aerosols and their phase as at 550 nm, ozone interpolated between the preset's three values."""
    d = load_atmosphere("earth").to_dict()
    d["name"] = f"earth-{n}-wavelengths"
    wl = np.linspace(400.0, 700.0, n)
    order = np.argsort(d["wavelengths_nm"])
    at = lambda values: list(np.interp(wl, np.asarray(d["wavelengths_nm"])[order], np.asarray(values)[order]))
    d["rayleigh"]["scattering_m"] = list(d["rayleigh"]["scattering_m"][1] * (550.0 / wl) ** 4)
    for key in ("scattering_m", "extinction_m"):
        d["mie"][key] = [d["mie"][key][1]] * n
    for key in ("g1", "g2", "alpha"):
        d["mie"]["phase"][key] = [d["mie"]["phase"][key][1]] * n
    d["absorption"] = [{**a, "extinction_m": at(a["extinction_m"])} for a in d["absorption"]]
    d["ground_albedo"] = [0.3] * n
    d["wavelengths_nm"] = list(wl)
    return d


def edge_atmosphere(name: str) -> Atmosphere:
    """An atmosphere at an edge of what the files accept (one of :data:`EDGE_NAMES`), from the standard Earth."""
    d = load_atmosphere("earth").to_dict()
    d["name"] = name
    W = len(d["wavelengths_nm"])
    scale = lambda f: [d.update({"rayleigh": {**d["rayleigh"], "scattering_m": [x * f for x in d["rayleigh"]["scattering_m"]]},
                                 "mie": {**d["mie"], "scattering_m": [x * f for x in d["mie"]["scattering_m"]],
                                         "extinction_m": [x * f for x in d["mie"]["extinction_m"]]},
                                 "absorption": [{**a, "extinction_m": [x * f for x in a["extinction_m"]]}
                                                for a in d["absorption"]]})]
    if name == "scale heights 10 m":
        d["rayleigh"]["profile"]["scale_height_m"] = d["mie"]["profile"]["scale_height_m"] = 10.0
    elif name == "scale heights 1000 km":
        d["rayleigh"]["profile"]["scale_height_m"] = d["mie"]["profile"]["scale_height_m"] = 1e6
    elif name == "thickness 1 km":
        d["top_radius_m"] = d["bottom_radius_m"] + 1e3
        d["absorption"] = []
    elif name == "thickness = radius":
        d["top_radius_m"] = 2 * d["bottom_radius_m"]
    elif name == "optical depth 1e-8":
        scale(1e-8 / 0.13)
    elif name == "optical depth 100":
        scale(100 / 0.13)
    elif name in ("g = 0.99", "g = -0.99"):
        d["mie"]["phase"]["g1"] = [0.99 if name == "g = 0.99" else -0.99] * W
    elif name in ("albedo 0", "albedo 1"):
        d["ground_albedo"] = [0.0 if name == "albedo 0" else 1.0] * W
    elif name == "one wavelength":
        for key in ("wavelengths_nm", "ground_albedo"):
            d[key] = d[key][1:2]
        for part, keys in (("rayleigh", ("scattering_m",)), ("mie", ("scattering_m", "extinction_m"))):
            for k in keys:
                d[part][k] = d[part][k][1:2]
        for k in ("g1", "g2", "alpha"):
            d["mie"]["phase"][k] = d["mie"]["phase"][k][1:2]
        d["absorption"] = [{**a, "extinction_m": a["extinction_m"][1:2]} for a in d["absorption"]]
    elif name == "64 wavelengths":
        d = spectral_earth(64)
    elif name == "no molecules, low haze":
        d["rayleigh"]["scattering_m"] = [0.0] * W
        d["mie"]["profile"]["scale_height_m"] = 115.0           # the air above a few km is empty to float64
        d["absorption"] = []
    elif name in ("planet 100 km", "planet 1e8 m"):
        radius = 1e5 if name == "planet 100 km" else 1e8
        d["top_radius_m"] = radius + (d["top_radius_m"] - d["bottom_radius_m"])
        d["bottom_radius_m"] = radius
    return Atmosphere.from_dict(d)


#: The edge atmospheres of :func:`edge_atmosphere` (the tests run "optical depth 100" and "64 wavelengths" in
#: their slow run).
EDGE_NAMES = ("scale heights 10 m", "scale heights 1000 km", "thickness 1 km", "thickness = radius",
              "optical depth 1e-8", "g = 0.99", "g = -0.99", "albedo 0", "albedo 1", "one wavelength",
              "planet 100 km", "planet 1e8 m", "no molecules, low haze", "optical depth 100", "64 wavelengths")


def conservative(atm, albedo=1.0, radius=None, name=None) -> Atmosphere:
    """``atm`` with nothing absorbed: no absorbing layers, the particles' extinction = their scattering, a ground
    of ``albedo`` (white); with ``radius``, on a planet of that radius (the same thickness of air); named ``name``
    (by default ``atm``'s name with "-conservative" and the radius)."""
    d = atm.to_dict()
    d["name"] = name or f"{atm.name}-conservative" + ("" if radius is None else f"-{radius:g}")
    d["absorption"] = []
    d["mie"]["extinction_m"] = list(d["mie"]["scattering_m"])
    d["ground_albedo"] = [albedo] * len(d["wavelengths_nm"])
    if radius is not None:
        d["top_radius_m"] = radius + (d["top_radius_m"] - d["bottom_radius_m"])
        d["bottom_radius_m"] = radius
    return Atmosphere.from_dict(d)


def conservative_atmosphere(radius=None, preset="earth", albedo=1.0) -> Atmosphere:
    """The preset (the Earth) made :func:`conservative`: no absorbing layers (ozone), the particles' extinction =
    their scattering, a ground of ``albedo`` (white); with ``radius``, on a planet of that radius."""
    return conservative(load_atmosphere(preset), albedo, radius,
                        name=f"{preset}-conservative" + ("" if radius is None else f"-{radius:g}"))


def upward_flux_at_the_top(atm, radiance, n=64):
    """(pi F_up / F_sun, its standard error) at the top of the atmosphere above the sub-solar point, per unit
    solar irradiance: the radiance leaving the atmosphere, seen from 1 m below its top looking down, times |mu|,
    over the lower hemisphere (the sun at the zenith makes it symmetric in azimuth): 2 pi int L(mu) |mu| dmu,
    Gauss-Legendre on each side of the horizon's direction, where L steps from the ground to the limb.
    ``radiance(cameras, views, sun)`` gives (radiance (n, W), standard error (n, W))."""
    r = atm.top_radius_m - 1.0
    mu_h = -np.sqrt(1.0 - (atm.bottom_radius_m / r) ** 2)
    x, w = np.polynomial.legendre.leggauss(n)
    flux, variance = np.zeros(atm.n_wavelengths), np.zeros(atm.n_wavelengths)
    for a, b in ((-1.0, mu_h), (mu_h, 0.0)):
        mu = 0.5 * (b - a) * x + 0.5 * (b + a)
        views = np.stack([np.sqrt(1 - mu ** 2), np.zeros_like(mu), mu], axis=1)
        value, error = radiance(np.tile([0.0, 0.0, r], (n, 1)), views, [0.0, 0.0, 1.0])
        k = 2 * np.pi * 0.5 * (b - a) * (w * np.abs(mu))[:, None]
        flux += (k * value).sum(0)
        variance += ((k * error) ** 2).sum(0)
    return flux, np.sqrt(variance)


def flux_balance(tables, atm, elevation_deg=60.0, n_mu=48, n_phi=64):
    """(F_up(top) + E_sky(ground) + E_sun(ground)) / mu_s per wavelength, every flux from ``tables``: over a black
    ground with nothing absorbed every photon of the sun's beam either leaves at the top or reaches the ground,
    so this is 1 (above a plane; the Earth's sphere, the sun 60 deg up: within 0.003 of it). Radiance 1 m inside
    the top looking down and 1 mm above the ground looking up, Gauss-Legendre in mu (n_mu) and the midpoint rule
    in azimuth (n_phi) over each hemisphere. The ground's point is that low because the air below it scatters
    light back up, which the sum leaves out: 1 m above the ground of an atmosphere whose particles have a
    scale height of 20 m (random atmosphere 100014) holds 5% of their optical depth below it, and the sum read
    1.011-1.027 there against DISORT's 1 for the same fluxes."""
    x, w = np.polynomial.legendre.leggauss(n_mu)
    mu, phi = np.meshgrid(0.5 * (x + 1.0), (np.arange(n_phi) + 0.5) * 2 * np.pi / n_phi, indexing="ij")
    weight = (np.outer(0.5 * w, np.full(n_phi, 2 * np.pi / n_phi)) * mu).reshape(-1, 1)
    sin = np.sqrt(1.0 - mu * mu)
    up = np.stack([sin * np.cos(phi), sin * np.sin(phi), mu], -1).reshape(-1, 3)
    mu_s = np.sin(np.radians(elevation_deg))
    sun = np.array([np.cos(np.radians(elevation_deg)), 0.0, mu_s])
    total = 0.0
    ground = tables.bottom + 1e-3
    for r, views in ((tables.top - 1.0, up * [1.0, 1.0, -1.0]), (ground, up)):
        radiance, _ = sky_radiance(tables, atm, np.tile([0.0, 0.0, r], (len(views), 1)), views, sun)
        total = total + (radiance * weight).sum(0)
    direct = get_transmittance_to_sun(tables, np.array([ground]), np.array([mu_s]))[0] * mu_s
    return (total + direct) / mu_s
