"""Accuracy of the tables at the edges of the accepted atmospheres, against the Monte Carlo reference solver.

    python benchmarks/edge_accuracy.py [--quality standard] [--samples 4096] [NAME ...]

The edge atmospheres of planetviz.validation.edges (scale heights 10 m and 1000 km, thickness 1 km and = the
planet's radius, optical depth 1e-8 and 100, g = +-0.99, albedo 0 and 1, one wavelength, planets of 100 km and
1e8 m; the 64-wavelength one is left out: the reference traces each wavelength separately), each seen along 8
rays: from 2 m above the ground to the zenith, 45 deg up toward and away from the sun, 1 deg above the horizon,
10 deg down; from 3 planet radii to the disc's centre, and just inside the limb; from 1 m below the top, down.
The sun 30 deg up at the ground camera. Per atmosphere: the largest and the RMS relative difference over the
rays and wavelengths where the reference is above 1e-6 of its largest value, and the reference's largest
relative standard error (the noise floor of the comparison).
"""
import argparse
import time

import numpy as np

from planetviz.reference import solve
from planetviz.tables import QUALITY, TableCache, precompute
from planetviz.tables.evaluator import sky_radiance
from planetviz.validation import EDGE_NAMES, edge_atmosphere


def rays(atm):
    """(cameras (8, 3), views (8, 3), sun (3,)) of the comparison."""
    R, top = atm.bottom_radius_m, atm.top_radius_m
    ground = np.array([0.0, 0.0, R + 2.0])
    sun = np.array([np.cos(np.radians(30)), 0.0, np.sin(np.radians(30))])
    elevation = lambda deg, az=0.0: np.array([np.cos(np.radians(deg)) * np.cos(np.radians(az)),
                                              np.cos(np.radians(deg)) * np.sin(np.radians(az)),
                                              np.sin(np.radians(deg))])
    far = np.array([3.0 * top, 0.0, 0.0])
    limb = np.array([-3.0 * top, 0.999 * R, 0.0])
    views = [elevation(90), elevation(45), elevation(45, 180), elevation(1, 90), elevation(-10, 90),
             np.array([-1.0, 0.0, 0.0]), limb / np.linalg.norm(limb), np.array([0.0, 0.0, -1.0])]
    cams = [ground] * 5 + [far, far, np.array([0.0, 0.0, top - 1.0])]
    return np.array(cams), np.array(views), sun


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--quality", default="standard")
    ap.add_argument("--samples", type=int, default=4096)
    ap.add_argument("names", nargs="*", help="edge atmospheres to run (default: all)")
    args = ap.parse_args()
    names = args.names or list(EDGE_NAMES)
    print("| atmosphere | max relative difference | RMS | reference's largest relative standard error | "
          "precompute s | orders |")
    print("|---|---|---|---|---|---|")
    for name in names:
        if name == "64 wavelengths":
            continue
        atm = edge_atmosphere(name)
        t0 = time.time()
        tables = precompute(atm, QUALITY[args.quality], cache=TableCache())
        seconds = time.time() - t0
        cams, views, sun = rays(atm)
        got, _ = sky_radiance(tables, atm, cams, views, sun)
        ref = solve(atm, cams, views, sun, samples=args.samples, seed=5)
        seen = ref.radiance > 1e-6 * ref.radiance.max()
        rel = np.abs(got - ref.radiance)[seen] / ref.radiance[seen]
        noise = (ref.stderr[seen] / ref.radiance[seen]).max()
        print(f"| {name} | {rel.max():.3f} | {np.sqrt(np.mean(rel ** 2)):.3f} | {noise:.3f} | {seconds:.0f} | "
              f"{tables.orders} |", flush=True)


if __name__ == "__main__":
    main()
