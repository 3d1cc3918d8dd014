"""The tables against DISORT in the plane-parallel limit: all orders, deterministic on both sides, so large
planets' errors are resolved to DISORT's own 0.3% (the Monte Carlo reference's noise is 1-5% there).

    python benchmarks/tables_disort.py [--radii 1e8 3e8 1e9] [--quality standard] [--suns 30 50 70]
                                       [--ratio-limit K]
    python benchmarks/tables_disort.py --random SEED [SEED ...] [--quality standard] [--suns 30 70]
                                       [--thick-samples N] [--wavelengths I [I ...]] [--lobe-texels N_NU N_MU_S]
                                       [--streams 64]

Atmospheres: planetviz.validation.disort.plane_parallel_atmosphere (Earth's Rayleigh layer, 60 km, ground
albedo 0.3; with and without an absorbing aerosol of g1 = 0.85) on planets of each radius. Rays: at the ground
looking up and at the top looking down, view zenith 20, 55 and 78 deg x azimuth 0, 90 and 180 deg from the sun's,
the sun at each zenith angle of ``--suns``. Printed per radius, atmosphere and camera: the RMS and the largest
relative difference of the tables' radiance from DISORT's over rays and wavelengths, and the same of the first
order on the sphere against the slab's (``validation.disort.curvature_error``): what the planet's curvature moves
the sky by, which DISORT's slab leaves out (the 78 deg views cross 290 km sideways; 0.84% at most at 1e8 m, 0.08%
at 1e9 m): figures not three times that are not resolved.
``--ratio-limit`` sets parameterization.RATIO_LIMIT for this run (``inf``: Bruneton's mu and mu_s mappings on the
planet's own radii); ``--no-view-warp`` leaves the view-zenith axis unwarped (``distance_warp`` 0) and the
sun-zenith axis as it is; the tables are then computed afresh, not read from the cache.

``--random``: instead, random legal atmospheres (planetviz.validation.random_atmosphere, any seed of either split)
in their plane-parallel limit (``plane_parallel_twin``: on a planet of 1e9 m, at most 20 km thick with every
optical depth kept, without their absorbing layers), the same views. Printed per atmosphere: the
multiple-scattering tables' nu and mu_s texels (``precompute.sizes_for``), the precompute's time (no cache), the
RMS, 95th percentile and largest relative difference over rays and wavelengths, and the mean per wavelength at the
ground and at the top.
``--wavelengths`` keeps only the wavelengths of those indices (``validation.disort.only_wavelengths``: a channel's
sky alone, and ``sizes_for``'s rules read on it alone). ``--lobe-texels`` sets the multiple-scattering tables' nu
and mu_s texels to N_NU and N_MU_S for every atmosphere, whatever ``sizes_for``'s rules say (``4 32``: the
standard level without them). ``--streams``: DISORT's streams (64: within 0.3% of 128 for the atmospheres of
../shared/notes/disort.md; under a sharp lobe (g near 0.9) 10 deg from the sun 64 streams read up to 9% high,
where 128 are within 0.1% of 192).
``--thick-samples`` sets precompute.THICK_MULTIPLE_SAMPLES for this run (the nodes per side along the
multiple-scattering tables' rays in optically thick atmospheres). DISORT is exact here within its own 0.3% (64
streams, ../shared/notes/disort.md) where the particles' lobes have g up to 0.88, so every figure is resolved; under
a sharper lobe use ``--streams 128``.
"""
import argparse
import importlib
import time
from dataclasses import replace

import numpy as np

from planetviz.tables import QUALITY, TableCache, lookup, parameterization, precompute
from planetviz.tables.evaluator import sky_radiance
from planetviz.tables.precompute import sizes_for
from planetviz.validation import random_atmosphere
from planetviz.validation.disort import (curvature_error, disort_radiance, ground_and_top_views, only_wavelengths,
                                        plane_parallel_atmosphere, plane_parallel_twin)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--radii", type=float, nargs="+", default=[1e8, 3e8, 1e9])
    ap.add_argument("--quality", default="standard", choices=list(QUALITY))
    ap.add_argument("--suns", type=float, nargs="+", default=[30.0, 50.0, 70.0], help="sun zenith angles [deg]")
    ap.add_argument("--ratio-limit", type=float, default=None)
    ap.add_argument("--no-view-warp", action="store_true")
    ap.add_argument("--random", type=int, nargs="+", default=None, help="random atmospheres' seeds")
    ap.add_argument("--thick-samples", type=int, default=None, metavar="N")
    ap.add_argument("--wavelengths", type=int, nargs="+", default=None, metavar="I")
    ap.add_argument("--lobe-texels", type=int, nargs=2, default=None, metavar=("N_NU", "N_MU_S"))
    ap.add_argument("--streams", type=int, default=64)
    args = ap.parse_args()
    if args.thick_samples is not None:
        importlib.import_module("planetviz.tables.precompute").THICK_MULTIPLE_SAMPLES = args.thick_samples
    if args.random:
        sizes = QUALITY[args.quality]
        if args.lobe_texels:
            n_nu, n_mu_s = args.lobe_texels
            sizes = replace(sizes, multiple=(n_nu, n_mu_s) + sizes.multiple[2:], lobe_nu=n_nu, lobe_mu_s=n_mu_s)
        return random_twins(args.random, sizes, args.suns, args.wavelengths, args.streams)
    cache = TableCache()
    if args.ratio_limit is not None:
        parameterization.RATIO_LIMIT = args.ratio_limit
        cache = None
    if args.no_view_warp:
        unwarped = lambda r, bottom, top, ground: np.zeros(np.broadcast(r, ground).shape)
        parameterization.distance_warp = lookup.distance_warp = unwarped
        cache = None
    print("| radius [m] | atmosphere | camera | values | RMS | largest | curvature, RMS | largest |")
    print("|---|---|---|---|---|---|---|---|")
    for radius in args.radii:
        for aerosol in (False, True):
            atm = plane_parallel_atmosphere(aerosol, radius)
            tables = precompute(atm, QUALITY[args.quality], cache=cache)
            views, cams, dirs = ground_and_top_views(atm)
            bent = curvature_error(atm, args.suns)
            curvature = {"ground": bent[..., 0::2].ravel(), "top": bent[..., 1::2].ravel()}
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
                c = curvature[camera]
                print(f"| {radius:g} | {name} | {camera} | {e.size} | {100 * np.sqrt(np.mean(e ** 2)):.2f}% | "
                      f"{100 * e[np.argmax(np.abs(e))]:+.2f}% | {100 * np.sqrt(np.mean(c ** 2)):.2f}% | "
                      f"{100 * c[np.argmax(np.abs(c))]:+.2f}% |", flush=True)


def random_twins(seeds, sizes, suns, wavelengths=None, streams=64):
    """The tables of each random atmosphere's plane-parallel twin (with only the ``wavelengths`` of those indices,
    None: all) against DISORT with ``streams`` streams: one row per atmosphere."""
    print("| atmosphere | nu, mu_s texels | precompute [s] | values | RMS | p95 | largest "
          "| mean per wavelength, ground | at the top |")
    print("|---|---|---|---|---|---|---|---|---|")
    for seed in seeds:
        atm = plane_parallel_twin(random_atmosphere(seed))
        if wavelengths:
            atm = only_wavelengths(atm, wavelengths)
        start = time.perf_counter()
        tables = precompute(atm, sizes)
        seconds = time.perf_counter() - start
        views, cams, dirs = ground_and_top_views(atm)
        rel = []                                                         # (suns, W, views)
        for zenith in suns:
            theta0 = np.radians(zenith)
            got, _ = sky_radiance(tables, atm, cams, dirs, [np.sin(theta0), 0.0, np.cos(theta0)])
            rel.append([got[:, w] / disort_radiance(atm, w, np.cos(theta0), views, n_quad=streams) - 1.0
                        for w in range(atm.n_wavelengths)])
        rel = np.array(rel)
        e = np.abs(rel).ravel()
        n_nu, n_mu_s = sizes_for(atm, sizes).multiple[:2]
        mean = lambda part: " / ".join(f"{100 * m:+.1f}%" for m in part.mean(axis=(0, 2)))
        channels = f" at {', '.join(f'{nm:g}' for nm in atm.wavelengths_nm)} nm" if wavelengths else ""
        print(f"| random-{seed}{channels} | {n_nu}, {n_mu_s} | {seconds:.0f} | {e.size} | "
              f"{100 * np.sqrt(np.mean(e ** 2)):.2f}% | {100 * np.percentile(e, 95):.2f}% | "
              f"{100 * rel.ravel()[np.argmax(e)]:+.2f}% | {mean(rel[..., 0::2])} | {mean(rel[..., 1::2])} |",
              flush=True)


if __name__ == "__main__":
    main()
