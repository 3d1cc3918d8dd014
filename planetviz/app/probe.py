"""The radiance probe: the numbers behind a pixel of the picture, behind a list of directions, and along the
sun's vertical (the window's probe panel and ``planetviz sky`` read them).

Radiance is per unit solar irradiance at the top of the atmosphere [1/sr], as ``planetviz radiance`` gives it;
spectral radiance is that times the star's spectral irradiance [W m^-2 sr^-1 nm^-1]; luminance is CIE Y of the
spectral radiance [cd/m^2] (planetviz/model/color.py), linear sRGB on the same scale (Y = luminance).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..model.color import linear_srgb, radiance_to_xyz
from ..model.geometry import EYE_HEIGHT_M, local_frame, site_of
from ..model.optics.light import star_irradiance

#: Points along the sun's vertical, horizon to horizon through the zenith.
VERTICAL_POINTS = 181


@dataclass(frozen=True)
class Reading:
    """What the probe reads along one direction (see the module's docstring for the units)."""

    wavelengths_nm: tuple
    radiance: np.ndarray
    spectral_radiance: np.ndarray
    luminance: float
    linear_srgb: np.ndarray
    elevation_deg: float
    azimuth_deg: float
    source: str

    def lines(self) -> list:
        """The reading as text, one quantity per line."""
        out = [f"direction: elevation {self.elevation_deg:.2f} deg, azimuth {self.azimuth_deg:.2f} deg "
               f"({self.source})"]
        for lam, radiance, spectral in zip(self.wavelengths_nm, self.radiance, self.spectral_radiance):
            out.append(f"{lam:g} nm: {radiance:.4e} /sr, {spectral:.4e} W/(m2 sr nm)")
        out.append(f"luminance: {self.luminance:.4g} cd/m^2")
        out.append("linear sRGB: " + ", ".join(f"{c:.4g}" for c in self.linear_srgb))
        return out


def angles_seen_from(camera, direction) -> tuple:
    """(elevation, azimuth from north through east) [deg] of ``direction`` seen from the site below ``camera``."""
    up, east, north = local_frame(*site_of(camera))
    d = np.asarray(direction, dtype=float)
    d = d / np.linalg.norm(d)
    return (float(np.degrees(np.arcsin(np.clip(d @ up, -1.0, 1.0)))),
            float(np.degrees(np.arctan2(d @ east, d @ north)) % 360.0))


def readings(radiance, atm, camera, directions, source) -> list:
    """A :class:`Reading` per row of ``radiance`` (n, W) [1/sr] along ``directions`` (n, 3) from ``camera``."""
    radiance = np.atleast_2d(np.asarray(radiance, dtype=float))
    spectral = radiance * star_irradiance(atm.star, atm.wavelengths_nm)
    luminance = radiance_to_xyz(radiance, atm)[:, 1]
    rgb = linear_srgb(radiance, atm)
    return [Reading(tuple(atm.wavelengths_nm), radiance[i], spectral[i], float(luminance[i]), rgb[i],
                    *angles_seen_from(camera, d), source)
            for i, d in enumerate(np.atleast_2d(directions))]


def probe_pixel(scene, row, col) -> Reading:
    """The pixel (``row`` from the top, ``col``) of ``scene``'s picture as drawn: read back in float from the
    renderer in use (the tables per pixel or per vertex, or the quick view), the ground's texture included."""
    hdr = scene.render_hdr()
    h, w = hdr.radiance.shape[:2]
    if not (0 <= row < h and 0 <= col < w):
        raise ValueError(f"pixel: row 0 to {h - 1} and column 0 to {w - 1}, got ({row}, {col})")
    direction = scene.pixel_directions(np.array([row]), np.array([col]))[0]
    source = f"the picture: {scene.renderer_in_use}" + (f" per {scene.shading}" if scene.planet is not None else "")
    return readings(hdr.radiance[row, col], scene.atmosphere, scene.camera_location, direction[None], source)[0]


def probe_directions(tables, atm, camera, directions, sun_direction) -> list:
    """Readings along ``directions`` (n, 3) from ``camera`` [m] by the tables' NumPy evaluator (what the
    per-pixel shader computes)."""
    from ..tables.panorama import render_directions
    directions = np.atleast_2d(np.asarray(directions, dtype=float))
    radiance = render_directions(tables, atm, np.asarray(camera, dtype=float), directions, sun_direction)
    return readings(radiance, atm, camera, directions, "tables, NumPy evaluator")


def vertical_viewpoint(atm, camera):
    """Where the sun's vertical is seen from: the camera inside the atmosphere, else eye height above the point
    below it."""
    camera = np.asarray(camera, dtype=float)
    r = np.linalg.norm(camera)
    if r < atm.top_radius_m:
        return camera
    return camera / r * (atm.bottom_radius_m + EYE_HEIGHT_M)


def sun_vertical(tables, atm, camera, sun_direction, points=VERTICAL_POINTS):
    """The sky's luminance [cd/m^2] along the sun's vertical: (angle [deg] from the horizon below the sun, 0,
    through the zenith, 90, to the opposite horizon, 180; luminance; the point it is seen from). The CIE
    sky models are compared with measurements along this line."""
    at = vertical_viewpoint(atm, camera)
    up = at / np.linalg.norm(at)
    sun = np.asarray(sun_direction, dtype=float)
    toward = sun - (sun @ up) * up
    if np.linalg.norm(toward) < 1e-9:              # the sun at the zenith: any vertical is the sun's
        toward = np.cross(up, [0.0, 0.0, 1.0]) if abs(up[2]) < 0.9 else np.cross(up, [1.0, 0.0, 0.0])
    toward /= np.linalg.norm(toward)
    angle = np.linspace(0.0, 180.0, points)
    a = np.radians(angle)[:, None]
    directions = np.cos(a) * toward + np.sin(a) * up
    luminance = np.array([r.luminance for r in probe_directions(tables, atm, at, directions, sun)])
    return angle, luminance, at
