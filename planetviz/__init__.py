"""planetviz: planets with physically based atmospheres (Costa et al., TVCG 2020).

Example
-------
>>> import planetviz
>>> atm = planetviz.load_atmosphere("earth")
>>> round(float(atm.vertical_optical_depth()[1]), 3)   # Rayleigh + Mie + ozone at 550 nm
0.129
"""
from .model.atmosphere import Atmosphere
from .model.limits import AtmosphereError
from .model.presets import PRESETS, load_atmosphere

__all__ = ["Atmosphere", "AtmosphereError", "PRESETS", "Scene", "load_atmosphere"]


def __getattr__(name):
    # The renderer imports VTK and PyVista: loaded on first use, so the physics stays light to import.
    if name == "Scene":
        from .render.scene import Scene
        return Scene
    raise AttributeError(f"module 'planetviz' has no attribute {name!r}")
__version__ = "0.1.0"
