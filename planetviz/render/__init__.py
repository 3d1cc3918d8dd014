"""Rendering with VTK and PyVista: the planet, its atmosphere and the sun from the precomputed tables.

:class:`Scene` (a ``pyvista.Plotter``) is the entry point; :class:`AtmosphereActor` is the plain-VTK core
(importable without PyVista, e.g. in the GPU timing bundle).
"""
from .atmosphere_actor import AtmosphereActor
from .uniforms import DisplaySettings
from .vertex_actor import VertexAtmosphereActor

__all__ = ["AtmosphereActor", "DisplaySettings", "HDRImage", "Scene", "VertexAtmosphereActor"]


def __getattr__(name):
    if name in ("Scene", "HDRImage"):
        from . import scene
        return getattr(scene, name)
    raise AttributeError(f"module 'planetviz.render' has no attribute {name!r}")
