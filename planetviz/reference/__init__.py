"""The reference solver: planetviz's own ground truth for radiance, written for correctness.

* :func:`optical_depth` integrates extinction along straight segments by Gauss-Legendre
  quadrature clustered at the point of closest approach.
* :func:`single_scattering` is the deterministic single-scattering integral (plus the
  sun-lit ground seen through the atmosphere), for analytic checks.
* :func:`solve` is an unbiased Monte Carlo solution of the full problem (all orders,
  Lambertian ground lit by sun and sky) with next-event estimation and its own
  standard error.
"""
from .montecarlo import ReferenceResult, solve
from .optical_depth import ground_sun_transmittance, optical_depth, sun_transmittance, view_transmittance
from .single import single_scattering

__all__ = ["ReferenceResult", "ground_sun_transmittance", "optical_depth", "single_scattering", "solve",
           "sun_transmittance", "view_transmittance"]
