"""GLSL sources: the files of ``shaders/`` (:func:`planetviz.resources.shader_dir`)."""
from __future__ import annotations

from ..resources import shader_dir

SHADERS = shader_dir()


def load_shader(name: str) -> str:
    """The text of ``shaders/<name>``; a clear error when the file is missing."""
    path = SHADERS / name
    if not path.is_file():
        raise FileNotFoundError(f"shader {name!r} not found in {SHADERS} (is the installation complete?)")
    return path.read_text()


def shader_code(*names: str) -> str:
    """The files ``names`` of ``shaders/`` joined in order (each declares what the later ones use)."""
    return "\n".join(load_shader(name) for name in names)
