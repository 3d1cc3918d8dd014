"""Precomputed scattering tables (Bruneton and Neyret's method, paper Sect. 5.1) in NumPy.

``parameterization``: the mappings between (r, mu, mu_s, nu) and texture coordinates, shared by name
with the GLSL; ``precompute``: the tables; ``evaluator``: radiance for arbitrary rays, sampling the
tables exactly as the shader does.
"""
