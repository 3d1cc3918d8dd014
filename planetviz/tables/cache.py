"""Disk cache of the precomputed tables, as OpenEXR files keyed by exactly what each stage depends on.

Each stage's tables are one or two float32 OpenEXR files named ``<table>-<hash>.exr`` in
``$PLANETVIZ_CACHE`` (default ``~/.cache/planetviz``). The hash covers the stage's parameters
(:func:`stage_parameters`), which include those of the stages it reads, so a change recomputes that
stage and everything after it, and nothing before:

==================== ================================================================================
stage                depends on
==================== ================================================================================
transmittance        radii, wavelengths, every extinction coefficient and profile, its table size
single_scattering    the above, the Rayleigh and Mie scattering coefficients, its table size
multiple_scattering  the above, both phase functions, the ground albedo, its sizes and tolerance
==================== ================================================================================

The sun, the camera and the exposure are inputs of the evaluation, not of any table: changing them
recomputes nothing.

File layout (so that any HDR viewer opens them and another renderer can load them): a 2D table
(n_r, n_x) is an image n_r rows high; a 4D table (n_r, n_mu, n_nu, n_mu_s) is the 3D texture the
shader samples, its n_r slices of (n_mu, n_nu * n_mu_s) stacked vertically. One channel per table and
wavelength, named ``<table>.<index>_<wavelength>nm``. The header holds ``planetviz_format``,
``planetviz_stage``, ``planetviz_hash``, ``planetviz_parameters`` (JSON), ``planetviz_shapes`` (JSON) and
``planetviz_checksum`` (SHA-256 of the pixel data). Files are written to a temporary name and renamed
(atomic on POSIX); on load, an unreadable, truncated, mismatched or corrupt file is reported with a
warning and the stage is recomputed.
"""
from __future__ import annotations

import hashlib
import json
import os
import tempfile
import warnings
from pathlib import Path

import numpy as np

#: Bump when the content or layout of any table changes: older files are then recomputed.
FORMAT_VERSION = 46

def default_directory() -> Path:
    return Path(os.environ.get("PLANETVIZ_CACHE") or Path.home() / ".cache" / "planetviz")


def stage_parameters(atm, sizes) -> dict:
    """{stage: the parameters it depends on (JSON-able)}: each includes its predecessors'."""
    d = atm.to_dict()
    extinction = {
        "bottom_radius_m": d["bottom_radius_m"], "top_radius_m": d["top_radius_m"],
        "wavelengths_nm": d["wavelengths_nm"],
        "rayleigh": {"scattering_m": d["rayleigh"]["scattering_m"], "profile": d["rayleigh"]["profile"]},
        "mie": {"extinction_m": d["mie"]["extinction_m"], "scattering_m": d["mie"]["scattering_m"],
                "profile": d["mie"]["profile"]},
        "absorption": d["absorption"],
    }
    t = {"atmosphere": extinction,
         "sizes": {"transmittance": list(sizes.transmittance), "samples": sizes.transmittance_samples}}
    s = {"transmittance": t,
         "sizes": {"scattering": list(sizes.scattering), "samples": sizes.scattering_samples}}
    m = {"single_scattering": s, "rayleigh_phase": d["rayleigh"]["phase"], "mie_phase": d["mie"]["phase"],
         "ground_albedo": d["ground_albedo"],
         "sizes": {"multiple": list(sizes.multiple), "samples": sizes.multiple_samples,
                   "directions": list(sizes.directions), "quadrature": sizes.quadrature,
                   "irradiance": list(sizes.irradiance),
                   "tolerance": sizes.tolerance}}
    return {"transmittance": t, "single_scattering": s, "multiple_scattering": m}


def parameters_hash(params: dict) -> str:
    return hashlib.sha256(json.dumps(params, sort_keys=True).encode()).hexdigest()[:24]


def _as_image(a: np.ndarray) -> np.ndarray:
    """(..., W) -> (rows, columns, W): 2D tables as they are, 3D and 4D ones (n_r, n_mu, n_nu, n_mu_s, W) as stacked
    texture slices (n_r n_mu, n_nu n_mu_s, W)."""
    if a.ndim == 3:
        return a
    return a.reshape(-1, a.shape[-3] * a.shape[-2], a.shape[-1])


def _checksum(arrays: dict) -> str:
    h = hashlib.sha256()
    for name in sorted(arrays):
        h.update(name.encode())
        h.update(np.ascontiguousarray(arrays[name], dtype=np.float32).tobytes())
    return h.hexdigest()


class TableCache:
    """Tables on disk (OpenEXR) and in memory, by stage and parameter hash.

    Example
    -------
    >>> from planetviz import load_atmosphere
    >>> from planetviz.tables import QUALITY, TableCache, precompute
    >>> cache = TableCache("/tmp/planetviz-doc-cache")
    >>> atm = load_atmosphere("earth")
    >>> first = precompute(atm, QUALITY["draft"], cache=cache)
    >>> again = precompute(atm.replace(ground_albedo=[0.1, 0.1, 0.1]), QUALITY["draft"], cache=cache)
    >>> again.computed          # transmittance and single scattering came from the cache
    ['multiple_scattering']
    """

    def __init__(self, directory=None):
        self.directory = Path(directory) if directory is not None else default_directory()
        self._memory: dict = {}

    def _path(self, table: str, key: str) -> Path:
        return self.directory / f"{table}-{key}.exr"

    def load(self, stage: str, key: str, wavelengths, tables: dict):
        """{table: array} for ``stage`` under ``key``, or None (absent or bad: warns, never raises).

        ``tables`` maps each table name to its expected array shape; ``attrs`` extra header values are
        returned under the ``"attrs"`` key.
        """
        if (stage, key) in self._memory:
            return self._memory[(stage, key)]
        out = {"attrs": {}}
        for table, shape in tables.items():
            path = self._path(table, key)
            if not path.exists():
                return None
            try:
                arrays, attrs = _read(path, stage, key, table, wavelengths, shape)
            except (OSError, RuntimeError, ValueError, KeyError, TypeError) as err:
                warnings.warn(f"planetviz: cached table {path} is unusable ({err}); recomputing", stacklevel=3)
                return None
            out[table] = arrays
            out["attrs"].update(attrs)
        self._memory[(stage, key)] = out
        return out

    def holds(self, stage: str, key: str, tables) -> bool:
        """Whether every table of ``stage`` under ``key`` is in memory or on disk (not read: :meth:`load` may still
        find a file unusable)."""
        return (stage, key) in self._memory or all(self._path(table, key).exists() for table in tables)

    def store(self, stage: str, key: str, params: dict, wavelengths, arrays: dict, attrs=None):
        """Write each table of ``stage`` atomically; failures to write only warn (the tables stay in memory)."""
        self._memory[(stage, key)] = {**arrays, "attrs": dict(attrs or {})}
        try:
            self.directory.mkdir(parents=True, exist_ok=True)
            for table, a in arrays.items():
                _write(self._path(table, key), stage, key, params, table, wavelengths, a, attrs or {})
        except (OSError, RuntimeError) as err:
            warnings.warn(f"planetviz: could not write the table cache in {self.directory} ({err})", stacklevel=3)


def _channel_names(table, wavelengths):
    return [f"{table}.{i}_{wl:g}nm" for i, wl in enumerate(wavelengths)]


def _write(path: Path, stage, key, params, table, wavelengths, a, attrs):
    import OpenEXR
    image = _as_image(np.asarray(a, dtype=np.float32))
    channels = {name: np.ascontiguousarray(image[..., i]) for i, name in enumerate(_channel_names(table, wavelengths))}
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage,
              "planetviz_format": FORMAT_VERSION, "planetviz_stage": stage, "planetviz_hash": key,
              "planetviz_parameters": json.dumps(params, sort_keys=True),
              "planetviz_shapes": json.dumps({table: list(a.shape)}),
              "planetviz_checksum": _checksum(channels),
              **{f"planetviz_{k}": v for k, v in attrs.items()}}
    fd, tmp = tempfile.mkstemp(prefix=f".{path.stem}.", suffix=".exr", dir=path.parent)
    os.close(fd)
    try:
        OpenEXR.File(header, channels).write(tmp)
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)


def _read(path: Path, stage, key, table, wavelengths, shape):
    import OpenEXR
    f = OpenEXR.File(str(path), separate_channels=True)
    h = f.header()
    if h.get("planetviz_format") != FORMAT_VERSION:
        raise ValueError(f"format {h.get('planetviz_format')}, expected {FORMAT_VERSION}")
    if h.get("planetviz_stage") != stage or h.get("planetviz_hash") != key:
        raise ValueError("its header names another stage or parameter set")
    if json.loads(h["planetviz_shapes"]).get(table) != list(shape):
        raise ValueError(f"shape {h['planetviz_shapes']}, expected {list(shape)}")
    channels = {name: f.channels()[name].pixels for name in _channel_names(table, wavelengths)}
    if _checksum(channels) != h.get("planetviz_checksum"):
        raise ValueError("checksum mismatch (corrupt data)")
    image = np.stack([channels[n] for n in _channel_names(table, wavelengths)], -1).astype(np.float32)
    if not np.all(np.isfinite(image)):
        raise ValueError("non-finite values")
    attrs = {k[len("planetviz_"):]: v for k, v in h.items()
             if k.startswith("planetviz_") and k[len("planetviz_"):] not in
             ("format", "stage", "hash", "parameters", "shapes", "checksum")}
    return image.reshape(shape), attrs
