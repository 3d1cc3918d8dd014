"""Validation suites: random legal atmospheres and rays in classes, with a held-out split
(:mod:`.random_suite`); atmospheres at the edges of the format and the energy balance (:mod:`.edges`);
the CIE standard general sky (:mod:`.cie_sky`); pictures compared in CIE Y (:mod:`.pictures`); the
multiple-scattering stage's nodes along rays against a conservation law (:mod:`.ray_nodes`)."""
from .edges import EDGE_NAMES, conservative, conservative_atmosphere, edge_atmosphere, flux_balance, spectral_earth, \
    upward_flux_at_the_top
from .random_suite import CAMERAS, LIGHT, SPLITS, WAVELENGTHS_NM, daylight_check_rays, look_point, \
    random_atmosphere, rays, suite_atmosphere, sun_elevation_seen

__all__ = ["CAMERAS", "EDGE_NAMES", "LIGHT", "SPLITS", "WAVELENGTHS_NM", "conservative", "conservative_atmosphere",
           "daylight_check_rays", "edge_atmosphere", "flux_balance", "look_point", "random_atmosphere", "rays",
           "spectral_earth", "suite_atmosphere", "sun_elevation_seen", "upward_flux_at_the_top"]
