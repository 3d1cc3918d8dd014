"""Precision, honesty and cost of the reference solver on random legal atmospheres and the presets.

    python benchmarks/reference_precision.py [--split tuning|held-out] [--atmospheres 8] [--paths 2048]
                                             [--presets earth mars exo-co2-thick] [--seeds 1 2]
                                             [--sampler sobol|random] [--guide-events N|all]
                                             [--collisions extinction|scattering]

For each atmosphere (planetviz.validation.random_atmosphere over the split's seeds, then the presets), one
ray per camera class and light class (planetviz.validation.rays), solved twice with independent seeds.
Printed per light class: the median and 90th percentile of the relative standard error, the RMS of the
z-scores (difference of the two runs over their combined standard errors; 1 for honest error bars) and
the largest |z|, and the cost per ray and wavelength (both runs, both cores). Values below 1e-12 / sr
(no light reaches the ray) are left out. ``--guide-events N``: the solver's guide around the sun at the paths'
first N events only (``solve(..., guide_events=N)``; ``all``: every event; default the solver's, GUIDE_EVENTS).
``--collisions``: how the solver draws its collisions (``solve``'s ``collisions``; default the solver's).
"""
import argparse
import time

import numpy as np

from planetviz import load_atmosphere
from planetviz.reference import solve
from planetviz.reference.montecarlo import COLLISIONS, DEFAULT_COLLISIONS, GUIDE_EVENTS, SAMPLERS
from planetviz.validation import CAMERAS, LIGHT, SPLITS, random_atmosphere, rays


def cases(args):
    seeds = list(SPLITS[args.split])[:args.atmospheres]
    for s in seeds:
        yield f"random-{s}", random_atmosphere(s), s
    for name in args.presets:
        yield name, load_atmosphere(name), 0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--split", default="tuning", choices=list(SPLITS))
    ap.add_argument("--atmospheres", type=int, default=8)
    ap.add_argument("--presets", nargs="*", default=["earth", "mars", "exo-co2-thick"])
    ap.add_argument("--paths", type=int, default=2048)
    ap.add_argument("--seeds", type=int, nargs=2, default=[1, 2])
    ap.add_argument("--sampler", default="sobol", choices=list(SAMPLERS))
    ap.add_argument("--guide-events", default=str(GUIDE_EVENTS))
    ap.add_argument("--collisions", default=DEFAULT_COLLISIONS, choices=COLLISIONS)
    ap.add_argument("--verbose", action="store_true")
    args = ap.parse_args()
    args.guide_events = None if args.guide_events == "all" else int(args.guide_events)
    rows = {light: {"rel": [], "z": [], "seconds": 0.0, "n": 0} for light in LIGHT}
    for name, atm, seed in cases(args):
        for light in LIGHT:
            batch = [rays(atm, seed, c, light) for c in CAMERAS]
            cam, view, sun = (np.concatenate(x) for x in zip(*batch))
            t0 = time.perf_counter()
            a, b = (solve(atm, cam, view, sun, samples=args.paths, seed=s, sampler=args.sampler,
                          guide_events=args.guide_events, collisions=args.collisions) for s in args.seeds)
            rows[light]["seconds"] += time.perf_counter() - t0
            rows[light]["n"] += len(cam) * atm.n_wavelengths
            ok = (a.radiance > 1e-12) & (b.radiance > 1e-12)
            rel = a.stderr[ok] / a.radiance[ok]
            z = (a.radiance[ok] - b.radiance[ok]) / np.maximum(np.hypot(a.stderr[ok], b.stderr[ok]), 1e-300)
            rows[light]["rel"].extend(rel)
            rows[light]["z"].extend(z)
            if args.verbose:
                worst = np.argmax(np.abs(z)) if z.size else None
                print(f"  {name:>14} {light:>13}: median rel {np.median(rel) if rel.size else np.nan:.4f}, "
                      f"max |z| {np.abs(z).max() if z.size else np.nan:.2f}"
                      + (f" ({CAMERAS[np.nonzero(ok)[0][worst]]})" if worst is not None else ""), flush=True)
    print(f"split {args.split}, {args.atmospheres} random atmospheres + {args.presets}, {args.paths} paths per ray "
          f"and wavelength, seeds {args.seeds}, sampler {args.sampler}, guide events "
          f"{'all' if args.guide_events is None else args.guide_events}, collisions by {args.collisions}")
    print(f"{'light':>14} {'values':>7} {'median rel. s.e.':>17} {'p90':>7} {'RMS z':>6} {'max |z|':>8} "
          f"{'s per ray-wavelength':>21}")
    for light, r in rows.items():
        rel, z = np.asarray(r["rel"]), np.asarray(r["z"])
        print(f"{light:>14} {rel.size:7d} {np.median(rel):17.4f} {np.percentile(rel, 90):7.4f} "
              f"{np.sqrt(np.mean(z ** 2)):6.2f} {np.abs(z).max():8.2f} {r['seconds'] / r['n'] / 2:21.3f}")


if __name__ == "__main__":
    main()
