"""Reference results computed once and kept in .npz files with everything they depend on.

A stored result holds the radiance, its standard error and the view transmittance, with the atmosphere's
parameters (JSON, :func:`radiance_parameters`), the rays, the paths per ray, the seed, :data:`~planetviz.reference.montecarlo.SOLVER_VERSION`,
for a result of the first orders only ``max_order``, the solver's ``guide_events`` where it changes the
estimator (a result of orders up to ``guide_events + 1`` draws every new direction from the guide whatever it is),
and its ``collisions`` where they are not drawn from the extinction (a file without it was solved so).
:func:`stored_solve` returns it while all of those match the request and recomputes (and rewrites) it when any
differs or the file cannot be read. :func:`stored_reference` names the file after a tag and the rays, for a
folder of such results (the repository's benchmarks/data/ for its tests and benchmarks).
"""
from __future__ import annotations

import hashlib
import json
import os
import zipfile
from pathlib import Path

import numpy as np

from .montecarlo import DEFAULT_COLLISIONS, GUIDE_EVENTS, SOLVER_VERSION, ReferenceResult, solve

#: How the collisions of a result stored without ``collisions`` were drawn (``montecarlo.COLLISIONS``).
UNMARKED_COLLISIONS = "extinction"


def stored_solve(path, atm, camera, view_dir, sun_dir, samples: int, seed: int = 0,
                 max_order: int | None = None, guide_events: int | None = GUIDE_EVENTS,
                 collisions: str = DEFAULT_COLLISIONS) -> ReferenceResult:
    """:func:`~planetviz.reference.solve` through the file ``path`` (.npz), recomputed when stale. ``max_order``:
    the orders of scattering solved (all by default), ``guide_events`` and ``collisions`` the solver's, stored
    with the result.

    Example
    -------
    >>> from planetviz import load_atmosphere
    >>> from planetviz.reference.stored import stored_solve
    >>> atm = load_atmosphere("earth")
    >>> res = stored_solve("/tmp/zenith.npz", atm, [[0, 0, 6360002.0]], [[0, 0, 1.0]], [0, 0.5, 0.866], 64)
    >>> res.radiance.shape
    (1, 3)
    """
    path = Path(path)
    camera = np.atleast_2d(np.asarray(camera, dtype=float))
    view_dir = np.atleast_2d(np.asarray(view_dir, dtype=float))
    sun_dir = np.broadcast_to(np.asarray(sun_dir, dtype=float), camera.shape)
    wanted = {"parameters": radiance_parameters(atm), "solver_version": SOLVER_VERSION, "paths": samples,
              "seed": seed}
    if max_order is not None:
        wanted["max_order"] = max_order
    if guide_events is not None and (max_order is None or max_order > guide_events + 1):
        wanted["guide_events"] = guide_events
    if collisions != UNMARKED_COLLISIONS:
        wanted["collisions"] = collisions
    stored = _load(path, wanted, (camera, view_dir, sun_dir))
    if stored is not None:
        return stored
    res = solve(atm, camera, view_dir, sun_dir, samples=samples, seed=seed, max_order=max_order,
                guide_events=guide_events, collisions=collisions)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(path.name + ".tmp.npz")
    np.savez(tmp, radiance=res.radiance, radiance_stderr=res.stderr, transmittance=res.transmittance,
             camera_m=camera, view_dir=view_dir, sun_dir=sun_dir,
             wavelengths_nm=np.asarray(atm.wavelengths_nm, dtype=float), **wanted)
    os.replace(tmp, path)
    return res


def radiance_parameters(atm) -> str:
    """The atmosphere's parameters that its radiance per unit solar irradiance depends on, as JSON: all but the
    star (which scales the light, not the radiance per unit irradiance)."""
    return json.dumps({key: value for key, value in atm.to_dict().items() if key != "star"}, indent=2)


def stored_reference(folder, tag, atm, camera, view_dir, sun_dir, samples: int, seed: int = 0,
                     max_order: int | None = None, guide_events: int | None = GUIDE_EVENTS,
                     collisions: str = DEFAULT_COLLISIONS) -> ReferenceResult:
    """:func:`stored_solve` through ``folder/test-<tag>-<hash of the rays>.npz`` (the rays hashed in float32, so
    that rays computed on another machine, which may differ in the last bit of float64, name the same file)."""
    rays = np.concatenate([np.atleast_2d(np.asarray(a, dtype=float)) for a in (camera, view_dir, sun_dir)])
    name = f"test-{tag}-{hashlib.sha1(rays.astype(np.float32).tobytes()).hexdigest()[:10]}.npz"
    return stored_solve(Path(folder) / name, atm, camera, view_dir, sun_dir, samples=samples, seed=seed,
                        max_order=max_order, guide_events=guide_events, collisions=collisions)


#: Relative tolerance of the match between stored and requested rays and parameters: rays and atmospheres drawn
#: from the same seed on another machine differ in the last bits of float64 (exp, log and sqrt are not correctly
#: rounded everywhere), far below anything that changes a reference result.
MATCH_RTOL = 1e-12


def _same(a, b) -> bool:
    """Whether two JSON values are equal, numbers within ``MATCH_RTOL``."""
    if isinstance(a, dict) and isinstance(b, dict):
        return a.keys() == b.keys() and all(_same(a[k], b[k]) for k in a)
    if isinstance(a, list) and isinstance(b, list):
        return len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b))
    if isinstance(a, float) or isinstance(b, float):
        return isinstance(a, (int, float)) and isinstance(b, (int, float)) and np.isclose(a, b, rtol=MATCH_RTOL,
                                                                                         atol=0.0)
    return a == b


def _load(path, wanted, rays):
    """The stored result if it was computed for ``wanted`` and these rays, else None (absent or unreadable)."""
    try:
        with np.load(path) as f:
            if not _same(json.loads(str(f["parameters"])), json.loads(wanted["parameters"])):
                return None
            if any((key in f.files) != (key in wanted) for key in ("max_order", "guide_events", "collisions")) or \
                    any(str(f[key]) != str(value) for key, value in wanted.items() if key != "parameters"):
                return None
            scale = max(float(np.max(np.abs(rays[0]))), 1.0)            # cameras in metres, directions unit
            if any(np.shape(f[key]) != np.shape(ray) or not np.allclose(f[key], ray, rtol=0.0, atol=MATCH_RTOL * s)
                   for key, ray, s in zip(("camera_m", "view_dir", "sun_dir"), rays, (scale, 1.0, 1.0))):
                return None
            return ReferenceResult(f["radiance"], f["radiance_stderr"], f["transmittance"], int(f["paths"]))
    except (OSError, KeyError, ValueError, EOFError, zipfile.BadZipFile):
        return None
