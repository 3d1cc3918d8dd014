"""Rendering with VTK and PyVista: the planet, its atmosphere and the sun from the precomputed tables.

:class:`Scene` (a ``pyvista.Plotter``) is the entry point; :class:`AtmosphereActor` is the plain-VTK core.
"""
from .atmosphere_actor import AtmosphereActor, DisplaySettings
from .scene import HDRImage, Scene

__all__ = ["AtmosphereActor", "DisplaySettings", "HDRImage", "Scene"]
