"""The quick view: Keller and Bohn's single scattering along the ray, with no precomputed tables; shown while
the tables compute. :func:`quick_view_radiance` is the NumPy twin of shaders/quick_view_vertex.glsl."""
from .single_scattering import quick_view_radiance

__all__ = ["quick_view_radiance"]
