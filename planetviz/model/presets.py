"""Shipped atmospheres (assets/atmospheres/*.json) and the loader for presets and files."""
from __future__ import annotations

from pathlib import Path

from .atmosphere import Atmosphere, AtmosphereError, from_dict, parse_json
from ..resources import asset_dir

PRESET_DIR = asset_dir("atmospheres")

#: Preset name -> file. ``earth`` is the issue's standard-mode contract; the others are advanced.
PRESETS = {p.stem: p for p in sorted(PRESET_DIR.glob("*.json"))}


def load_dict(data: dict) -> Atmosphere:
    """An Atmosphere from a standard- or advanced-mode dict."""
    if data.get("mode") == "advanced":
        from .advanced import derive
        return derive(data)
    return from_dict(data)


def load_atmosphere(preset_or_path) -> Atmosphere:
    """Load a preset by name (``earth``, ``earth-advanced``, ``mars``, ...) or a JSON file by path.

    Raises :class:`AtmosphereError` (a ValueError) naming the field for any invalid content,
    and for an unknown preset or a missing file.

    Example
    -------
    >>> from planetviz import load_atmosphere
    >>> load_atmosphere("mars").name
    'mars'
    """
    if isinstance(preset_or_path, Atmosphere):
        return preset_or_path
    key = str(preset_or_path)
    path = PRESETS.get(key, Path(key))
    if not path.is_file():
        raise AtmosphereError("atmosphere", f"{key!r} is neither a preset ({', '.join(PRESETS)}) "
                                            "nor an existing file")
    try:
        text = path.read_text()
    except (OSError, UnicodeDecodeError) as exc:
        raise AtmosphereError("atmosphere", f"cannot read {path}: {exc}") from None
    return load_dict(parse_json(text, source=str(path)))
