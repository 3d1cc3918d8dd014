"""Planet-centred geometry: stable ray-sphere intersections and the (r, mu, mu_s, nu) coordinates.

Positions are planet-centred, in metres, float64. Intersections use the forms that stay
accurate for a camera 1 mm above a 6.4e6 m sphere and for one 1e12 m away: the
discriminant as R^2 minus the squared distance of closest approach, and
c = (r - R)(r + R) with the root of smaller magnitude taken as c / q.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np


def ray_sphere(origin, direction, radius):
    """Both roots t0 <= t1 of |origin + t direction| = radius (``direction`` unit); NaN where missed.

    The roots are -b -+ sqrt(disc), with b = origin . direction; the one of smaller magnitude is taken as c / q
    (no cancellation) and held within 1e-9 (|b| + radius) of that interval: where the ray grazes the sphere
    from a point on it, disc and c round to values that do not agree (disc >= 0 with c > 0, q ~ 1e-10 m), and c /
    q alone would put the far root thousands of kilometres away.

    Returns arrays shaped like ``origin[..., 0]``.
    """
    o = np.asarray(origin, dtype=float)
    d = np.asarray(direction, dtype=float)
    b = np.einsum("...i,...i->...", o, d)
    r = np.linalg.norm(o, axis=-1)
    perp = o - b[..., None] * d
    disc = radius * radius - np.einsum("...i,...i->...", perp, perp)
    hit = disc >= 0.0
    sq = np.sqrt(np.where(hit, disc, 0.0))
    c = (r - radius) * (r + radius)
    q = -b - np.where(b >= 0.0, sq, -sq)  # q = -(b + sign(b) sq), never a cancellation
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):   # c / q -> inf for a grazing ray from afar
        ta = q
        tb = np.where(q != 0.0, c / q, 0.0)
    spread = 1e-9 * (np.abs(b) + radius)                     # far beyond either form's rounding
    tb = np.clip(tb, -b - sq - spread, -b + sq + spread)
    t0 = np.where(hit, np.minimum(ta, tb), np.nan)
    t1 = np.where(hit, np.maximum(ta, tb), np.nan)
    return t0, t1


def distance_to_ground(origin, direction, bottom_radius):
    """Distance along the ray to the ground, or inf where the ray never reaches it.

    Only rays moving toward the centre (o . d < 0) from on or above the ground can hit it,
    which keeps a point resting on the ground with an upward direction from hitting itself.
    """
    o = np.asarray(origin, dtype=float)
    d = np.asarray(direction, dtype=float)
    t0, _ = ray_sphere(o, d, bottom_radius)
    b = np.einsum("...i,...i->...", o, d)
    ok = np.isfinite(t0) & (b < 0.0)
    return np.where(ok, np.maximum(t0, 0.0), np.inf)


def distance_to_top_exit(origin, direction, top_radius):
    """Distance from a point inside the top sphere to where the ray leaves it (far root, >= 0)."""
    _, t1 = ray_sphere(origin, direction, top_radius)
    return np.maximum(np.nan_to_num(t1, nan=0.0), 0.0)


#: Height of an observer's eyes above the ground [m]: the camera of ``planetviz sky``, of the queries from a site,
#: of a view from the ground (``Scene.view_from_ground``, ``planetviz render --view ground``) and of the end of a
#: flight to the ground.
EYE_HEIGHT_M = 1.7


def local_frame(latitude_deg, longitude_deg):
    """(up, east, north) unit vectors at a site on the planet."""
    lat, lon = np.radians(latitude_deg), np.radians(longitude_deg)
    up = np.array([np.cos(lat) * np.cos(lon), np.cos(lat) * np.sin(lon), np.sin(lat)])
    east = np.array([-np.sin(lon), np.cos(lon), 0.0])
    north = np.array([-np.sin(lat) * np.cos(lon), -np.sin(lat) * np.sin(lon), np.cos(lat)])
    return up, east, north


def site_direction(elevation_deg, azimuth_deg, latitude_deg=0.0, longitude_deg=0.0):
    """Unit vector at elevation and azimuth (from north, through east) seen from a site."""
    up, east, north = local_frame(latitude_deg, longitude_deg)
    el, az = np.radians(elevation_deg), np.radians(azimuth_deg)
    return np.cos(el) * (np.cos(az) * north + np.sin(az) * east) + np.sin(el) * up


def site_of(position):
    """(latitude, longitude) [deg] of the point below a planet-centred position."""
    x, y, z = np.asarray(position, dtype=float)
    return float(np.degrees(np.arctan2(z, np.hypot(x, y)))), float(np.degrees(np.arctan2(y, x)))


@dataclass(frozen=True)
class SunPlacement:
    """The sun at ``elevation`` and ``azimuth`` (from north through east) [deg], seen from the site at
    ``latitude`` and ``longitude`` [deg]; checked when made."""

    elevation: float
    azimuth: float
    latitude: float
    longitude: float

    def __post_init__(self):
        for name, lo, hi in (("elevation", -90, 90), ("azimuth", -360, 360), ("latitude", -90, 90),
                             ("longitude", -360, 360)):
            value = getattr(self, name)
            if not (isinstance(value, (int, float, np.integer, np.floating)) and np.isfinite(value)
                    and lo <= value <= hi):
                raise ValueError(f"sun {name}: [{lo}, {hi}] deg, got {value!r}")
            object.__setattr__(self, name, float(value))

    def direction(self):
        """The sun's planet-centred unit direction (normalised again, as every direction the scene is given)."""
        v = site_direction(self.elevation, self.azimuth, self.latitude, self.longitude)
        return v / np.linalg.norm(v)

    @classmethod
    def seen_from(cls, direction, latitude, longitude):
        """The placement of a planet-centred unit ``direction`` seen from a site."""
        up, east, north = local_frame(latitude, longitude)
        elevation = np.degrees(np.arcsin(np.clip(direction @ up, -1.0, 1.0)))
        azimuth = np.degrees(np.arctan2(direction @ east, direction @ north))
        return cls(float(elevation), float(azimuth), latitude, longitude)
