"""The reference solver: planetviz's own ground truth for radiance, written for correctness.

* :func:`optical_depth` integrates extinction along straight segments by Gauss-Legendre
  quadrature clustered at the point of closest approach.
* :func:`single_scattering` is the deterministic single-scattering integral (plus the
  sun-lit ground seen through the atmosphere), cut at the ends of the planet's shadow.
* :func:`solve` is the full problem (all orders, Lambertian ground lit by sun and sky): single
  scattering by that quadrature, the higher orders by unbiased Monte Carlo path tracing with next-event
  estimation along each segment's sun-lit part, with its own standard error.
* :func:`~planetviz.reference.stored.stored_solve` keeps a result in a file with everything it depends on.
"""
from .montecarlo import QUALITY_SAMPLES, ReferenceResult, solve
from .optical_depth import ground_sun_transmittance, optical_depth, sun_transmittance, view_transmittance
from .single import single_scattering

__all__ = ["QUALITY_SAMPLES", "ReferenceResult", "ground_sun_transmittance", "optical_depth", "single_scattering",
           "solve", "sun_transmittance", "view_transmittance"]
