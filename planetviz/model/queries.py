"""Radiance queries: validation of camera positions, view and sun directions (the ``radiance`` contract)."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .geometry import EYE_HEIGHT_M

#: A camera this far below the ground (rounding of a position given on the ground) is put on it.
GROUND_TOLERANCE_M = 1e-3


@dataclass(frozen=True)
class Queries:
    camera_m: np.ndarray   # (N, 3) planet-centred metres, on or above the ground
    view_dir: np.ndarray   # (N, 3) unit
    sun_dir: np.ndarray    # (N, 3) unit


def _directions(value, name, n):
    try:
        a = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name}: must be a numeric (N, 3) or (3,) array") from None
    if a.shape == (3,):
        a = np.broadcast_to(a, (n, 3))
    if a.shape != (n, 3):
        raise ValueError(f"{name}: shape {a.shape} does not match camera_m ({n}, 3); expected ({n}, 3) or (3,)")
    if not np.all(np.isfinite(a)):
        i = int(np.nonzero(~np.all(np.isfinite(a), axis=1))[0][0])
        raise ValueError(f"{name}[{i}]: contains NaN or inf")
    norm = np.linalg.norm(a, axis=1)
    if np.any(norm < 1e-12):
        i = int(np.nonzero(norm < 1e-12)[0][0])
        raise ValueError(f"{name}[{i}]: zero vector; a direction needs a length > 0")
    return a / norm[:, None]


def validate_queries(camera_m, view_dir, sun_dir, bottom_radius_m: float) -> Queries:
    """Check shapes and values; normalise directions; raise ValueError naming the array and row."""
    try:
        cam = np.array(camera_m, dtype=float)
    except (TypeError, ValueError):
        raise ValueError("camera_m: must be a numeric (N, 3) array") from None
    if cam.ndim == 1 and cam.shape == (3,):
        cam = cam[None, :]
    if cam.ndim != 2 or cam.shape[1] != 3 or cam.shape[0] == 0:
        raise ValueError(f"camera_m: shape {cam.shape}, expected (N, 3) with N >= 1")
    if not np.all(np.isfinite(cam)):
        i = int(np.nonzero(~np.all(np.isfinite(cam), axis=1))[0][0])
        raise ValueError(f"camera_m[{i}]: contains NaN or inf")
    n = len(cam)
    view = _directions(view_dir, "view_dir", n)
    sun = _directions(sun_dir, "sun_dir", n)
    r = np.linalg.norm(cam, axis=1)
    below = r < bottom_radius_m - GROUND_TOLERANCE_M
    if np.any(below):
        i = int(np.nonzero(below)[0][0])
        raise ValueError(f"camera_m[{i}]: {bottom_radius_m - r[i]:.6g} m below the ground "
                         f"(radius {r[i]:.10g} m < bottom_radius_m {bottom_radius_m:.10g} m)")
    on = r < bottom_radius_m
    cam[on] *= (bottom_radius_m / r[on])[:, None]
    return Queries(cam, view, sun)


def load_queries(path, bottom_radius_m: float) -> Queries:
    """Read and validate a ``Q.npz`` with ``camera_m``, ``view_dir`` and ``sun_dir``."""
    try:
        with np.load(path, allow_pickle=False) as data:
            missing = [k for k in ("camera_m", "view_dir", "sun_dir") if k not in data]
            if missing:
                raise ValueError(f"queries: missing array {missing[0]!r} in {path}")
            arrays = {k: data[k] for k in ("camera_m", "view_dir", "sun_dir")}
    except (OSError, EOFError) as exc:
        raise ValueError(f"queries: cannot read {path}: {exc}") from None
    except Exception as exc:  # zipfile.BadZipFile, pickle refusal, ...: all mean a bad file
        if isinstance(exc, ValueError) and str(exc).startswith("queries:"):
            raise
        raise ValueError(f"queries: {path} is not a valid .npz file ({exc})") from None
    return validate_queries(arrays["camera_m"], arrays["view_dir"], arrays["sun_dir"], bottom_radius_m)


def site_queries(bottom_radius_m: float, latitude: float = 0.0, longitude: float = 0.0, altitude: float = EYE_HEIGHT_M,
                 sun_elevation: float = 30.0, sun_azimuth: float = 180.0, elevations=(90.0, 45.0, 10.0, 2.0),
                 azimuths=(0.0, 90.0, 180.0, 270.0)) -> Queries:
    """Queries from one site: a camera ``altitude`` [m] above the ground at ``latitude``, ``longitude``
    [deg], looking at every pair of ``elevations`` x ``azimuths`` [deg, azimuth from north through east]
    (once only at the zenith), the sun at ``sun_elevation``, ``sun_azimuth`` [deg] seen from the site.

    Example
    -------
    >>> from planetviz.model.queries import site_queries
    >>> q = site_queries(6360e3, elevations=(90, 10), azimuths=(0, 180))
    >>> q.camera_m.shape
    (3, 3)
    """
    from .geometry import local_frame, site_direction
    for name, value, lo, hi in (("latitude", latitude, -90.0, 90.0), ("longitude", longitude, -360.0, 360.0),
                                ("altitude", altitude, 0.0, np.inf), ("sun_elevation", sun_elevation, -90.0, 90.0),
                                ("sun_azimuth", sun_azimuth, -360.0, 360.0)):
        if not (np.isfinite(value) and lo <= value <= hi):
            raise ValueError(f"{name}: must be in [{lo:g}, {hi:g}], got {value!r}")
    for name, values, lo, hi in (("elevations", elevations, -90.0, 90.0), ("azimuths", azimuths, -360.0, 360.0)):
        values = np.asarray(values, dtype=float)
        if values.size == 0 or not np.all(np.isfinite(values) & (values >= lo) & (values <= hi)):
            raise ValueError(f"{name}: one or more values in [{lo:g}, {hi:g}] deg, got {[float(v) for v in np.ravel(values)]}")
    pairs = [(e, a) for e in elevations for a in (azimuths if e != 90.0 else azimuths[:1])]
    up = local_frame(latitude, longitude)[0]
    camera = np.repeat(((bottom_radius_m + altitude) * up)[None], len(pairs), axis=0)
    view = np.array([site_direction(e, a, latitude, longitude) for e, a in pairs])
    sun = site_direction(sun_elevation, sun_azimuth, latitude, longitude)
    return validate_queries(camera, view, sun, bottom_radius_m)
