"""Optical properties of planetary atmospheres (paper Sect. 4), in SI units.

Everything here is plain NumPy and knows nothing of tables or rendering:
density profiles, phase functions, and the physical formulas (Rayleigh, Mie,
absorption, gas composition) that derive the standard-mode coefficients.
"""
