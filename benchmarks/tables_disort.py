"""The tables against DISORT in the plane-parallel limit: all orders, deterministic on both sides, so large
planets' errors are resolved to DISORT's own 0.3% (the Monte Carlo reference's noise is 1-5% there).

    python benchmarks/tables_disort.py [--radii 1e8 3e8 1e9] [--quality standard] [--suns 30 50 70]
                                       [--ratio-limit K]

Atmospheres: planetviz.validation.disort.plane_parallel_atmosphere (Earth's Rayleigh layer, 60 km, ground
albedo 0.3; with and without an absorbing aerosol of g1 = 0.85) on planets of each radius. Rays: at the ground
looking up and at the top looking down, view zenith 20, 55 and 78 deg x azimuth 0, 90 and 180 deg from the sun's,
the sun at each zenith angle of ``--suns``. Printed per radius, atmosphere and camera: the RMS and the largest
relative difference of the tables' radiance from DISORT's over rays and wavelengths. The planet's curvature
moves the answer by under 1e-3 at 1e8 m for these views (60 km over 1e8 m; the 78 deg views cross 290 km).
``--ratio-limit`` sets parameterization.RATIO_LIMIT for this run (``inf``: Bruneton's mu and mu_s mappings on the
planet's own radii); ``--no-view-warp`` leaves the view-zenith axis unwarped (``distance_warp`` 0) and the
sun-zenith axis as it is; the tables are then computed afresh, not read from the cache.
"""
import argparse

import numpy as np

from planetviz.tables import QUALITY, TableCache, lookup, parameterization, precompute
from planetviz.tables.evaluator import sky_radiance
from planetviz.validation.disort import disort_radiance, ground_and_top_views, plane_parallel_atmosphere


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--radii", type=float, nargs="+", default=[1e8, 3e8, 1e9])
    ap.add_argument("--quality", default="standard", choices=list(QUALITY))
    ap.add_argument("--suns", type=float, nargs="+", default=[30.0, 50.0, 70.0], help="sun zenith angles [deg]")
    ap.add_argument("--ratio-limit", type=float, default=None)
    ap.add_argument("--no-view-warp", action="store_true")
    args = ap.parse_args()
    cache = TableCache()
    if args.ratio_limit is not None:
        parameterization.RATIO_LIMIT = args.ratio_limit
        cache = None
    if args.no_view_warp:
        unwarped = lambda r, bottom, top, ground: np.zeros(np.broadcast(r, ground).shape)
        parameterization.distance_warp = lookup.distance_warp = unwarped
        cache = None
    print("| radius [m] | atmosphere | camera | values | RMS | largest |")
    print("|---|---|---|---|---|---|")
    for radius in args.radii:
        for aerosol in (False, True):
            atm = plane_parallel_atmosphere(aerosol, radius)
            tables = precompute(atm, QUALITY[args.quality], cache=cache)
            views, cams, dirs = ground_and_top_views(atm)
            errors = {"ground": [], "top": []}
            for zenith in args.suns:
                theta0 = np.radians(zenith)
                sun = np.array([np.sin(theta0), 0.0, np.cos(theta0)])
                got, _ = sky_radiance(tables, atm, cams, dirs, sun)
                for w in range(atm.n_wavelengths):
                    want = disort_radiance(atm, w, np.cos(theta0), views)
                    rel = (got[:, w] - want) / want
                    errors["ground"].append(rel[0::2])
                    errors["top"].append(rel[1::2])
            name = "rayleigh + aerosol" if aerosol else "rayleigh"
            for camera, e in errors.items():
                e = np.concatenate(e)
                print(f"| {radius:g} | {name} | {camera} | {e.size} | {100 * np.sqrt(np.mean(e ** 2)):.2f}% | "
                      f"{100 * e[np.argmax(np.abs(e))]:+.2f}% |", flush=True)


if __name__ == "__main__":
    main()
