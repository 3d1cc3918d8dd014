"""Random legal atmospheres and rays in classes, for validating the solvers on what users may write.

:func:`random_atmosphere` draws a standard-mode atmosphere over the ranges docs/atmosphere-format.md
allows (planet radius 1e4-1e9 m, vertical optical depth 1e-4 to 10, double Henyey-Greenstein lobes in
either component and different per wavelength with g up to 0.95, absorbing tent layers, any ground
albedo and star). :func:`rays` places cameras in the classes below and the sun at an elevation, seen
where the ray looks, drawn within a light class. Both are deterministic in their seed; the held-out split
uses seeds no tuning ever reads (:data:`SPLITS`).

Camera classes: ``ground`` (2 m), ``aircraft`` (0.1 H_R), ``stratosphere`` (0.4 H_R), ``top`` (within
100 m below the top), ``space-disc`` and ``space-limb`` (from 3 planet radii; in twilight light the disc
rays look at the terminator, in deep twilight at the night side). Light classes (the sun's elevation where the ray looks: at its ground hit, its point of
closest approach, or the camera for rays going up): ``day`` (>= 2 deg, sun zenith <= 88 deg),
``twilight`` (0 to -6 deg), ``deep-twilight`` (-6 to -18 deg).
"""
from __future__ import annotations

import numpy as np

from ..model.atmosphere import Atmosphere
from ..model.limits import LIMITS
from ..model.presets import load_atmosphere
from ..model.geometry import distance_to_ground

#: Seeds of the tuning split and of the held-out split (never used while tuning; reported separately).
SPLITS = {"tuning": range(0, 1000), "held-out": range(100_000, 101_000)}
CAMERAS = ("ground", "aircraft", "stratosphere", "top", "space-disc", "space-limb")
LIGHT = {"day": (2.0, 88.0), "twilight": (-6.0, 0.0), "deep-twilight": (-18.0, -6.0)}
WAVELENGTHS_NM = (680.0, 550.0, 440.0)


def _log_uniform(rng, lo, hi):
    return float(np.exp(rng.uniform(np.log(lo), np.log(hi))))


def _coefficient(tau, scale_height, thickness):
    """beta at the ground [1/m] giving vertical optical depth tau through an exponential layer."""
    column = scale_height * -np.expm1(-thickness / scale_height)
    return min(tau / column, LIMITS["coefficient_m"][1])


def random_atmosphere(seed: int, name: str | None = None) -> Atmosphere:
    """A legal standard-mode atmosphere drawn from ``seed`` (three wavelengths, 680/550/440 nm).

    Example
    -------
    >>> from planetviz.validation import random_atmosphere
    >>> random_atmosphere(3).n_wavelengths
    3
    """
    rng = np.random.default_rng([20261125, seed])
    lam = np.asarray(WAVELENGTHS_NM)
    radius = _log_uniform(rng, LIMITS["bottom_radius_m"][0] * 10, LIMITS["bottom_radius_m"][1])
    thickness = min(radius * _log_uniform(rng, 1e-3, 0.05), radius)
    h_r = min(thickness * _log_uniform(rng, 0.03, 0.3), LIMITS["scale_height_m"][1])
    h_m = h_r * _log_uniform(rng, 0.1, 1.0)
    tau_total = _log_uniform(rng, 1e-4, 10.0)
    share_m = rng.uniform(0.0, 0.9)
    tau_r = tau_total * (1 - share_m) * (440.0 / lam) ** 4       # Rayleigh: lambda^-4 from its 440 nm value
    tau_m = tau_total * share_m * (440.0 / lam) ** rng.uniform(0.0, 2.0)
    ssa = rng.uniform(0.5, 1.0, 3)
    g1 = rng.uniform(-0.3, 0.95, 3)
    g2 = rng.uniform(-0.5, 0.95, 3)
    alpha = rng.uniform(0.0, 1.0, 3)
    absorption = []
    if rng.random() < 0.5:
        centre = min(rng.uniform(0.05, 0.6) * thickness, LIMITS["profile_altitude_m"][1])
        half = min(rng.uniform(0.02, 0.3) * thickness, LIMITS["half_width_m"][1])
        tau_a = _log_uniform(rng, 1e-3, 1.0) * rng.uniform(0.2, 1.0, 3)
        column = half                                     # a tent of peak 1 and half-width w holds w
        absorption = [{"extinction_m": [min(t / column, 1.0) for t in tau_a],
                       "profile": {"type": "tent", "center_m": centre, "half_width_m": half}}]
    star = {"type": "sun"} if rng.random() < 0.5 else {"type": "blackbody",
                                                         "temperature_k": _log_uniform(rng, 2500.0, 12000.0)}
    data = {
        "name": name or f"random-{seed}",
        "wavelengths_nm": list(WAVELENGTHS_NM),
        "bottom_radius_m": radius,
        "top_radius_m": radius + thickness,
        "ground_albedo": list(rng.uniform(0.0, 1.0, 3)),
        "rayleigh": {"scattering_m": [_coefficient(t, h_r, thickness) for t in tau_r],
                     "profile": {"type": "exponential", "scale_height_m": h_r},
                     "phase": "rayleigh" if rng.random() < 0.7 else "penndorf"},
        "mie": {"scattering_m": [_coefficient(t, h_m, thickness) * a for t, a in zip(tau_m, ssa)],
                "extinction_m": [_coefficient(t, h_m, thickness) for t in tau_m],
                "profile": {"type": "exponential", "scale_height_m": h_m},
                "phase": {"g1": list(g1), "g2": list(g2), "alpha": list(alpha)}},
        "absorption": absorption,
        "star": star,
    }
    return Atmosphere.from_dict(data)


def suite_atmosphere(name: str) -> tuple[Atmosphere, int]:
    """(atmosphere, seed) of a suite name: ``random-<seed>`` (:func:`random_atmosphere`) or a preset, whose rays
    the suite draws with seed 0.

    Example
    -------
    >>> suite_atmosphere("random-3")[1]
    3
    """
    if name.startswith("random-"):
        seed = int(name.split("-")[1])
        return random_atmosphere(seed), seed
    return load_atmosphere(name), 0


def _sun_seen_at(point, elevation_deg, rng):
    """A sun direction at ``elevation_deg`` above the horizon of ``point``, random azimuth."""
    up = point / np.linalg.norm(point)
    side = np.cross(up, rng.normal(size=3))
    side /= np.linalg.norm(side)
    e = np.radians(elevation_deg)
    return np.cos(e) * side + np.sin(e) * up


def look_point(atm, camera, view):
    """Where a ray looks: its ground hit, else its closest approach inside the shell, else the camera."""
    t_ground = distance_to_ground(camera[None], view[None], atm.bottom_radius_m)[0]
    if np.isfinite(t_ground):
        return camera + t_ground * view
    t_closest = max(-float(camera @ view), 0.0)
    return camera + t_closest * view


def sun_elevation_seen(atm, camera, view, sun) -> float:
    """The sun's elevation [deg] above the horizon where the ray looks (:func:`look_point`)."""
    p = look_point(atm, camera, view)
    return float(np.degrees(np.arcsin(np.clip(p @ sun / np.linalg.norm(p), -1.0, 1.0))))


def daylight_check_rays(atm):
    """(cameras (12, 3) [m], views (12, 3), sun (3,)): the fixed daylight rays the tables are checked on against
    the stored reference (tests/test_tables.py, benchmarks/tables_vs_reference.py): six from the ground, three
    from 10 km, three from 1000 km, the sun 60 deg up."""
    r = atm.bottom_radius_m
    cams = np.array([[0, 0, r + 2.0]] * 6 + [[0, 0, r + 1e4]] * 3 + [[0, 0, r + 1e6]] * 3, float)
    views = np.array([[0, 0, 1], [0.7, 0, 0.7], [-0.7, 0, 0.7], [0, 1, 0.1], [0.3, 0.3, 0.9], [0, -1, 0.3],
                      [1, 0, 0], [0, 1, -0.3], [0.2, 0, -1], [0, 0, -1], [0.3, 0, -1], [0, 0.17, -1]], float)
    views /= np.linalg.norm(views, axis=1, keepdims=True)
    return cams, views, np.array([0.5, 0.0, 0.866])


def rays(atm, seed: int, camera_class: str, light: str, n: int = 1):
    """``n`` rays (camera (n, 3) [m], view (n, 3), sun (n, 3)) of a camera class and a light class."""
    rng = np.random.default_rng([20261126, seed, CAMERAS.index(camera_class), list(LIGHT).index(light)])
    r_g, r_t = atm.bottom_radius_m, atm.top_radius_m
    h_r = atm.rayleigh.profile.scale_height_m
    cams, views, suns = [], [], []
    for _ in range(n):
        up = rng.normal(size=3)
        up /= np.linalg.norm(up)
        side = np.cross(up, rng.normal(size=3))
        side /= np.linalg.norm(side)
        altitude = {"ground": 2.0, "aircraft": 0.1 * h_r, "stratosphere": 0.4 * h_r,
                    "top": atm.thickness_m - rng.uniform(1.0, 100.0)}.get(camera_class)
        elevation = rng.uniform(*LIGHT[light])
        if altitude is not None:
            altitude = min(altitude, 0.9 * atm.thickness_m) if camera_class != "top" else max(altitude, 0.5 * atm.thickness_m)
            camera = up * (r_g + altitude)
            mu = rng.uniform(-0.3, 1.0) if rng.random() < 0.7 else rng.uniform(-0.05, 0.05)
            view = mu * up + np.sqrt(1.0 - mu * mu) * side
        else:
            r = 3.0 * r_g
            camera = up * r
            mu_ground = -np.sqrt(1.0 - (r_g / r) ** 2)           # tangent to the ground
            mu_top = -np.sqrt(1.0 - min(r_t / r, 1.0) ** 2)     # tangent to the top
            if camera_class == "space-limb":
                mu = rng.uniform(mu_ground, mu_top)               # through the air, missing the ground
            else:
                mu = rng.uniform(-1.0, mu_ground - 1e-3 * (1 + mu_ground))
            view = mu * up + np.sqrt(1.0 - mu * mu) * side
        sun = _sun_seen_at(look_point(atm, camera, view), elevation, rng)
        cams.append(camera)
        views.append(view)
        suns.append(sun)
    return np.array(cams), np.array(views), np.array(suns)
