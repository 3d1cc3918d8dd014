"""Whole-sky images for planetaria and other renderers, from the tables (the NumPy evaluator, the same model as
the shader): an equirectangular panorama (an HDR environment map) and a fisheye dome master.

Directions are in the camera's local frame: up the local vertical (away from the planet's centre), azimuth from
north through east. Radiance per unit solar irradiance, (h, w, W).
"""
from __future__ import annotations

import numpy as np

from ..model.geometry import local_frame, site_of
from .evaluator import sky_radiance


def equirectangular_directions(camera, width, height):
    """(height, width, 3) unit directions: longitude = azimuth from north (-180 at the left edge, through east),
    latitude = elevation (+90 at the top row); pixel centres."""
    up, east, north = local_frame(*site_of(camera))
    az = ((np.arange(width) + 0.5) / width * 2 - 1) * np.pi
    el = (0.5 - (np.arange(height) + 0.5) / height) * np.pi
    az, el = np.meshgrid(az, el)
    return (np.cos(el)[..., None] * (np.cos(az)[..., None] * north + np.sin(az)[..., None] * east)
            + np.sin(el)[..., None] * up)


def fisheye_directions(camera, size, field_of_view_deg=180.0, heading_deg=0.0):
    """(size, size, 3) unit directions of an equidistant (angular) fisheye looking at the zenith, the dome
    master convention: the radius from the centre is proportional to the zenith angle, ``field_of_view_deg``
    across the circle, ``heading_deg`` at the bottom of the image; outside the circle NaN."""
    up, east, north = local_frame(*site_of(camera))
    c = (np.arange(size) + 0.5) / size * 2 - 1
    x, y = np.meshgrid(c, -c)
    rho = np.hypot(x, y)
    zenith = rho * np.radians(field_of_view_deg) / 2
    az = np.radians(heading_deg) + np.arctan2(x, -y)
    d = (np.sin(zenith)[..., None] * (np.cos(az)[..., None] * north + np.sin(az)[..., None] * east)
         + np.cos(zenith)[..., None] * up)
    d[rho > 1] = np.nan
    return d


def render_directions(tables, atm, camera, directions, sun_dir, chunk=65536):
    """Radiance (..., W) along ``directions`` (..., 3) from ``camera``; NaN directions give 0."""
    shape = directions.shape[:-1]
    d = directions.reshape(-1, 3)
    out = np.zeros((len(d), atm.n_wavelengths))
    valid = np.all(np.isfinite(d), axis=1)
    idx = np.nonzero(valid)[0]
    cam = np.asarray(camera, dtype=float)
    for start in range(0, len(idx), chunk):
        sel = idx[start:start + chunk]
        out[sel], _ = sky_radiance(tables, atm, np.broadcast_to(cam, (len(sel), 3)), d[sel], sun_dir)
    return out.reshape(shape + (atm.n_wavelengths,))
