"""Order 2 of the tables seen upward from just under the top of the atmosphere, per view zenith angle, against the
reference solver's first two orders less the deterministic first order.

    python benchmarks/top_views.py [--atmosphere mars] [--depth 33] [--paths 16384]

The camera and the sun of the suite's first daylight ray of the class "within 100 m of the top" (the tuning split's
seed 0 for a preset), the camera moved to ``--depth`` metres under the top; views in the vertical plane of that
ray's view at zenith cosines 1, 0.9, 0.6, 0.31 and 0.1. Order 2 of the tables is their first two orders
(``multiple.first_two_orders``, standard) less their first (``single_scattering_only``); the reference's is its
``max_order=2`` radiance (``--paths`` per ray and wavelength, its relative standard error printed beside) less
planetviz/reference/single.py's quadrature, which has no noise. About a minute on this machine.
"""
import argparse

import numpy as np

from planetviz.reference import solve
from planetviz.tables import QUALITY, TableCache, precompute
from planetviz.tables.evaluator import sky_radiance
from planetviz.tables.multiple import first_two_orders
from planetviz.tables.precompute import sizes_for
from planetviz.validation import rays, suite_atmosphere
from planetviz.validation.single_scattering import reference_single_scattering, single_scattering_only

ZENITH_COSINES = (1.0, 0.9, 0.6, 0.31, 0.1)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--atmosphere", default="mars", help="a preset or random-<seed>")
    ap.add_argument("--depth", type=float, default=33.0, help="the camera's depth under the top [m]")
    ap.add_argument("--paths", type=int, default=16384)
    args = ap.parse_args()
    atm, seed = suite_atmosphere(args.atmosphere)
    cams, views, suns = rays(atm, seed, "top", "day", n=2)
    up = cams[0] / np.linalg.norm(cams[0])
    camera = up * (atm.top_radius_m - args.depth)
    across = views[0] - (views[0] @ up) * up
    across /= np.linalg.norm(across)
    mu = np.array(ZENITH_COSINES)
    v = mu[:, None] * up + np.sqrt(1.0 - mu * mu)[:, None] * across
    c = np.broadcast_to(camera, v.shape)
    sun = suns[0]
    tables = precompute(atm, QUALITY["standard"], cache=TableCache())
    two, _ = sky_radiance(first_two_orders(tables, atm, sizes_for(atm, QUALITY["standard"])), atm, c, v, sun)
    one, _ = sky_radiance(single_scattering_only(tables), atm, c, v, sun)
    single = reference_single_scattering(atm, c, v, np.broadcast_to(sun, c.shape))
    ref = solve(atm, c, v, sun, samples=args.paths, seed=4, max_order=2)
    order2 = ref.radiance - single
    print(f"{args.atmosphere}: camera {args.depth:g} m under the top, sun elevation "
          f"{np.degrees(np.arcsin(sun @ up)):.1f} deg; wavelengths {atm.wavelengths_nm} nm")
    print("| view zenith cosine | nu | order 2, tables / reference | reference's relative standard error |")
    print("|---|---|---|---|")
    for i, m in enumerate(mu):
        ratio = (two[i] - one[i]) / order2[i]
        noise = ref.stderr[i] / order2[i]
        print(f"| {m:.2f} | {v[i] @ sun:+.2f} | " + " / ".join(f"{x:.3f}" for x in ratio) + " | "
              + " / ".join(f"{x:.3f}" for x in noise) + " |")


if __name__ == "__main__":
    main()
