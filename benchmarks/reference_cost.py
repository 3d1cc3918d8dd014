"""Cost and precision of the reference solver at a quality level on a preset's daylight query set.

    python benchmarks/reference_cost.py [--preset earth] [--quality high] [--rays 100]
                                        [--collisions extinction scattering]

The first ``--rays`` daylight rays (sun 2-90 deg up) of benchmarks/tables_pareto.py's fixed query set (ground,
aircraft, stratosphere and space cameras; random, near-sun, horizon and downward views), solved at the
quality's paths per ray and wavelength on every core. Prints the wall time, the cost per ray (all
wavelengths) and the median, 90th percentile and largest relative standard error, over all of them and over
those that are daylight where they look (planetviz.validation.sun_elevation_seen >= 2 deg: a limb ray from
space may look at the night side while the sun is up below the camera); then, over the latter, against the
daylight targets (0.3%, 0.5% where the orders above the first are more than half of the light: their share from
the deterministic first order of planetviz/reference/single.py), the largest and how many values exceed them.
``--collisions``: each way of drawing the solver's collisions to run, one after the other (``solve``'s
``collisions``; by default the solver's).
"""
import argparse
import time

import numpy as np

from planetviz import load_atmosphere
from planetviz.reference import solve
from planetviz.reference.montecarlo import COLLISIONS, DEFAULT_COLLISIONS, QUALITY_SAMPLES
from planetviz.validation import sun_elevation_seen
from planetviz.validation.single_scattering import reference_single_scattering
from tables_pareto import query_set


#: The reference's daylight targets (issue 24): its relative standard error where the first order is at least half
#: of the light, and where the orders above it are more than half.
TARGETS = (0.003, 0.005)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--preset", default="earth")
    ap.add_argument("--quality", default="high", choices=list(QUALITY_SAMPLES))
    ap.add_argument("--rays", type=int, default=100)
    ap.add_argument("--collisions", nargs="+", default=[DEFAULT_COLLISIONS], choices=COLLISIONS)
    args = ap.parse_args()
    for collisions in args.collisions:
        run(args, collisions)


def run(args, collisions):
    atm = load_atmosphere(args.preset)
    cams, views, suns, elevations = query_set(atm)
    day = np.nonzero(elevations >= 2.0)[0][:args.rays]
    paths = QUALITY_SAMPLES[args.quality]
    t0 = time.perf_counter()
    res = solve(atm, cams[day], views[day], suns[day], samples=paths, seed=5, collisions=collisions)
    seconds = time.perf_counter() - t0
    print(f"{args.preset}, {args.quality} ({paths} paths per ray and wavelength), collisions by {collisions}, "
          f"{len(day)} daylight rays x {atm.n_wavelengths} wavelengths: {seconds:.0f} s "
          f"({seconds / len(day):.2f} s per ray)")
    seen = np.array([sun_elevation_seen(atm, cams[i], views[i], suns[i]) for i in day])
    for label, rows in (("all", np.ones(len(day), bool)), ("daylight where they look", seen >= 2.0)):
        ok = (res.radiance > 1e-12) & rows[:, None]
        rel = res.stderr[ok] / res.radiance[ok]
        print(f"  {label} ({rows.sum()} rays): relative standard error median {np.median(rel):.4f}, "
              f"p90 {np.percentile(rel, 90):.4f}, max {rel.max():.4f}")
    # Issue 24's daylight targets: 0.3%, or 0.5% where more than half of the light has scattered more than once
    # (the share of orders >= 2: 1 - the first order, from the deterministic quadrature, over the whole).
    first = reference_single_scattering(atm, cams[day], views[day], suns[day])
    ok = (res.radiance > 1e-12) & (seen >= 2.0)[:, None]
    multiple = 1.0 - first / np.where(ok, res.radiance, 1.0)
    rel = np.where(ok, res.stderr / np.where(ok, res.radiance, 1.0), 0.0)
    for label, part, target in (("first order at least half", ok & (multiple <= 0.5), TARGETS[0]),
                                ("orders >= 2 more than half", ok & (multiple > 0.5), TARGETS[1])):
        if part.any():
            print(f"  {label} ({part.sum()} ray-wavelengths, target {100 * target:.1f}%): largest "
                  f"{100 * rel[part].max():.2f}%, above the target {int((rel[part] > target).sum())}")


if __name__ == "__main__":
    main()
