"""The tables' single scattering against the reference quadrature (planetviz/reference/single.py), on rays
from one altitude: how the seams and the quadratures near the ground and the horizon are checked."""
from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..reference.single import single_scattering
from ..tables.evaluator import sky_radiance


def single_scattering_only(tables):
    """``tables`` with the multiple-scattering and sky-irradiance tables set to 0: what they read is their single
    scattering and directly lit ground, the part reference/single.py computes."""
    return replace(tables, multiple=np.zeros_like(tables.multiple), multiple_mie=np.zeros_like(tables.multiple_mie),
                   top_multiple=np.zeros_like(tables.top_multiple),
                   top_multiple_mie=np.zeros_like(tables.top_multiple_mie), irradiance=np.zeros_like(tables.irradiance))


def altitude_rays(atm, altitude, mus, sun_elevations_deg=(5, 20, 60), azimuths_deg=(0, 45, 90, 135, 180)):
    """(cameras, views, suns) from ``altitude`` [m] above the pole: every view cosine ``mus`` x view azimuth
    ``azimuths_deg`` (from the sun's) x sun elevation ``sun_elevations_deg``."""
    mu, az, el = (a.ravel() for a in np.meshgrid(np.asarray(mus, dtype=float), np.radians(azimuths_deg),
                                                 np.radians(sun_elevations_deg), indexing="ij"))
    views = np.stack([np.sqrt(1 - mu ** 2) * np.cos(az), np.sqrt(1 - mu ** 2) * np.sin(az), mu], 1)
    suns = np.stack([np.cos(el), np.zeros_like(el), np.sin(el)], 1)
    cams = np.tile([0.0, 0.0, atm.bottom_radius_m + altitude], (len(mu), 1))
    return cams, views, suns


def reference_single_scattering(atm, cams, views, suns):
    """Single scattering plus directly lit ground along the rays, by the reference quadrature (the slow part)."""
    scatter, ground = single_scattering(atm, cams, views, suns)
    return scatter + ground


def single_scattering_error(tables, atm, cams, views, suns, reference):
    """Per ray, the largest relative error over the wavelengths of the tables' single scattering and directly lit
    ground against ``reference`` (:func:`reference_single_scattering` of the same rays)."""
    got, _ = sky_radiance(single_scattering_only(tables), atm, cams, views, suns)
    return np.max(np.abs(got - reference) / reference, axis=1)
