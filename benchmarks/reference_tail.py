"""The reference solver's heavy tail on given rays: the same rays solved with more and more paths, beside the
standard tables.

    python benchmarks/reference_tail.py [--seed 5] [--cameras ground aircraft] [--light deep-twilight]
                                        [--paths 4096 65536] [--wavelength 2] [--guide-events 3]
                                        [--collisions extinction scattering] [--tail CAMERA RAY PATHS]

Rays: planetviz.validation.rays of the random atmosphere ``--seed`` (2 per camera class, the suite's rays). For
each path count the radiance at wavelength index ``--wavelength`` with its standard error, and the tables'
reading. Where the estimator's error bars are honest the estimates agree within a few standard errors whatever
the paths; where a rare path carries most of the light the smaller counts read low by more than that.
``--guide-events``: the solver's ``guide_events`` settings to run (``all``: every event; a number: the guide
around the sun at the paths' first that many events only; default the solver's, GUIDE_EVENTS), each with every
path count; ``--collisions`` the ways of drawing the collisions (``solve``'s ``collisions``; default the solver's),
each with every guide setting.
``--tail``: instead, for one of those rays and each setting, PATHS independent paths' own contributions
(``montecarlo.path_contributions``, orders 2 and above): their mean, its standard error, the largest over the
mean and the share of the sum the top 0.01% and 1% of the paths carry.
"""
import argparse
import time

import numpy as np

from planetviz.reference import solve
from planetviz.reference.montecarlo import COLLISIONS, DEFAULT_COLLISIONS, GUIDE_EVENTS, path_contributions
from planetviz.tables import QUALITY, TableCache, precompute
from planetviz.tables.evaluator import sky_radiance
from planetviz.validation import CAMERAS, LIGHT, random_atmosphere, rays


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seed", type=int, default=5)
    ap.add_argument("--cameras", nargs="+", default=["ground", "aircraft"], choices=list(CAMERAS))
    ap.add_argument("--light", default="deep-twilight", choices=list(LIGHT))
    ap.add_argument("--paths", type=int, nargs="+", default=[4096, 65536])
    ap.add_argument("--wavelength", type=int, default=2)
    ap.add_argument("--guide-events", nargs="+", default=[str(GUIDE_EVENTS)])
    ap.add_argument("--collisions", nargs="+", default=[DEFAULT_COLLISIONS], choices=COLLISIONS)
    ap.add_argument("--tail", nargs=3, metavar=("CAMERA", "RAY", "PATHS"))
    args = ap.parse_args()
    atm = random_atmosphere(args.seed)
    w = args.wavelength
    tables = precompute(atm, QUALITY["standard"], cache=TableCache())
    print(f"random atmosphere {args.seed}, {args.light}, {atm.wavelengths_nm[w]:g} nm")
    settings = [(None if g == "all" else int(g), c) for g in args.guide_events for c in args.collisions]
    if args.tail:
        tail(atm, args.seed, args.light, w, settings, args.tail)
        return
    print("| camera | ray | guide events | collisions | paths | seconds | reference [1/sr] | standard error | tables |")
    print("|---|---|---|---|---|---|---|---|---|")
    for camera in args.cameras:
        cams, views, suns = rays(atm, args.seed, camera, args.light, n=2)
        got, _ = sky_radiance(tables, atm, cams, views, suns)
        for guide, collisions in settings:
            for paths in args.paths:
                t0 = time.perf_counter()
                res = solve(atm, cams, views, suns, samples=paths, seed=123, guide_events=guide,
                            collisions=collisions)
                seconds = time.perf_counter() - t0
                for k in range(len(cams)):
                    print(f"| {camera} | {k} | {'all' if guide is None else guide} | {collisions} | {paths} | "
                          f"{seconds:.0f} | {res.radiance[k, w]:.3e} | {res.stderr[k, w]:.2e} | {got[k, w]:.3e} |",
                          flush=True)


def tail(atm, seed, light, w, settings, which):
    """The paths' own contributions for one ray, per setting (guide events, collisions) (``--tail CAMERA RAY
    PATHS``)."""
    camera, k, paths = which[0], int(which[1]), int(which[2])
    cams, views, suns = rays(atm, seed, camera, light, n=2)
    print(f"{camera} ray {k}, {paths} independent paths, orders 2 and above")
    print("| guide events | collisions | seconds | mean [1/sr] | standard error | largest / mean | top 0.01% | "
          "top 1% |")
    print("|---|---|---|---|---|---|---|---|")
    for guide, collisions in settings:
        t0 = time.perf_counter()
        c = path_contributions(atm, w, cams[k], views[k], suns[k], paths, seed=11, guide_events=guide,
                               collisions=collisions)
        seconds = time.perf_counter() - t0
        top = np.cumsum(np.sort(c)[::-1]) / c.sum()
        print(f"| {'all' if guide is None else guide} | {collisions} | {seconds:.0f} | {c.mean():.3e} | "
              f"{c.std() / np.sqrt(paths) / c.mean():.1%} | {c.max() / c.mean():.0f} | "
              f"{top[max(paths // 10000, 1) - 1]:.1%} | {top[max(paths // 100, 1) - 1]:.1%} |", flush=True)


if __name__ == "__main__":
    main()
