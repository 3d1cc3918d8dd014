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


def fisheye_directions(camera, size, field_of_view_deg=180.0, heading_deg=0.0, tilt_deg=0.0):
    """(size, size, 3) unit directions of an equidistant (angular) fisheye, the dome master convention: the
    radius from the centre is proportional to the angle from the dome's axis, ``field_of_view_deg`` across the
    circle, ``heading_deg`` (from north through east) at the bottom of the image; outside the circle NaN. In
    float32 (1e-7 rad, a thousandth of an 8192 dome's pixel): a 4096 x 4096 dome master has 16.7 million.

    The axis is the zenith turned by ``tilt_deg`` toward the heading (a dome tilted forward, its centre
    90 - tilt deg above the horizon): with h the horizontal heading direction and s the horizontal direction
    90 deg to its right, the axis a = cos(tilt) up + sin(tilt) h and the image's downward direction
    b = cos(tilt) h - sin(tilt) up; a pixel at angle z from the centre and phi from the image's bottom
    (counter-clockwise seen from inside) looks along sin(z) (cos(phi) b + sin(phi) s) + cos(z) a."""
    up, east, north = local_frame(*site_of(camera))
    c = ((np.arange(size) + 0.5) / size * 2 - 1).astype(np.float32)
    x, y = c[None, :], -c[:, None]
    rho = np.sqrt(x * x + y * y)
    half = np.float32(np.radians(field_of_view_deg) / 2)
    z = rho * half
    # cos(phi) = -y / rho, sin(phi) = x / rho: sin(z) / rho multiplies (-y, x); it tends to half at the centre
    k = np.divide(np.sin(z), rho, out=np.full_like(rho, half), where=rho > 0)
    heading, tilt = np.radians(heading_deg), np.radians(tilt_deg)
    h = np.cos(heading) * north + np.sin(heading) * east
    s = -np.sin(heading) * north + np.cos(heading) * east
    a = np.cos(tilt) * up + np.sin(tilt) * h
    b = np.cos(tilt) * h - np.sin(tilt) * up
    d = np.stack([-k * y, k * x, np.cos(z)], -1) @ np.stack([b, s, a]).astype(np.float32)
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
