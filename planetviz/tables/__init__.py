"""Precomputed scattering tables (Bruneton and Neyret's method, paper Sect. 5.1) in NumPy.

``parameterization``: the mappings between (r, mu, mu_s, nu) and texture coordinates, shared by name
with the GLSL; ``precompute``: the tables; ``cache``: the OpenEXR disk cache and what each stage depends on;
``evaluator``: radiance for arbitrary rays, sampling the tables exactly as the shader does.
"""
from .cache import TableCache
from .precompute import QUALITY, TableSizes, Tables, precompute

__all__ = ["QUALITY", "TableCache", "TableSizes", "Tables", "precompute"]
