"""The tables' first two orders of scattering against the reference's, on the suite's random atmospheres and the
presets, per light class and camera class, for the tuning and the held-out split.

    python benchmarks/tables_orders.py [--split tuning held-out] [--atmospheres 8] [--paths 16384]
                                       [--presets earth mars exo-co2-thick] [--directions N_THETA N_PHI ...]
                                       [--quadrature lit-band hemispheres horizon] [--worst 10] [--rows N]
                                       [--collisions extinction|scattering]

The same atmospheres and rays as benchmarks/tables_suite.py. The tables' orders 1 and 2 (the multiple-scattering
stage stopped after order 2, its sky irradiance then that of order 1) against the reference solver's
(``max_order=2``, ``--paths`` per ray and wavelength, stored in benchmarks/data/orders/): in twilight the light of
order 2 comes from a thin band of lit air near the horizontal toward the sun, which the scattering density's
direction quadrature resolves or misses, and the reference resolves it far better than all orders (a path of two
events has no long diffusion into the shadow). ``--directions`` gives one or more direction quadratures of the
scattering density (cosines over both hemispheres, azimuths over half the circle) to compare, each pair in turn;
by default the quality level's own; ``--quadrature`` one or more of its kinds (``multiple.QUADRATURES``, by default
the quality level's ``lit-band``: split at each point's horizon and at the band of lit air seen from the planet's
shadow; ``horizon``: split at the horizon, clustered toward it; ``hemispheres``: Gauss-Legendre on each side of the
horizontal at every point), each with every ``--directions``. ``--rows N``: the multiple-scattering tables get at
least N r rows (``precompute.sizes_for``'s other rules kept). ``--collisions``: how the reference draws its
collisions (``solve``'s ``collisions``; by default the solver's, its results in benchmarks/data/orders/; the
others' in benchmarks/data/orders-<collisions>/).

Printed per quadrature, split and light class: the number of values (ray x wavelength, the reference above 1e-12 /
sr and its relative standard error below 20%, cameras within 100 m of the top apart), the RMS, the RMS with the
reference's noise removed (sqrt(mean(e^2) - mean(s^2)), "below resolution" where the noise is above a third of it),
median and largest relative error, and the RMS of the reference's relative standard error; then the cameras within
100 m of the top, whose radiance of order 2 in deep twilight is 1e-13 to 1e-11 / sr; then, per light class, the
``--worst`` largest errors with their atmosphere and ray class.
"""
import argparse
from dataclasses import replace
from pathlib import Path

import numpy as np

from planetviz.reference.montecarlo import COLLISIONS, DEFAULT_COLLISIONS
from planetviz.reference.stored import stored_reference
from planetviz.tables import QUALITY, TableCache, precompute
from planetviz.tables.evaluator import sky_radiance
from planetviz.tables.multiple import QUADRATURES, first_two_orders
from planetviz.tables.precompute import sizes_for
from planetviz.validation import CAMERAS, LIGHT, SPLITS, rays
from tables_suite import cases, data_folder

DATA = Path(__file__).resolve().parent / "data" / "orders"


def reference_orders(name, atm, seed, light, paths, collisions=DEFAULT_COLLISIONS):
    """(cameras, views, suns, stored reference) of the suite's rays of one light class (2 per camera class) for
    the atmosphere ``name``: the reference's first two orders (``max_order=2``, ``paths`` per ray and wavelength,
    its collisions drawn as ``collisions`` says), stored in DATA (the solver's default) or DATA-<collisions>."""
    batch = [rays(atm, seed, camera, light, n=2) for camera in CAMERAS]
    cams, views, suns = (np.concatenate(x) for x in zip(*batch))
    ref = stored_reference(data_folder(DATA, collisions), f"{name}-{light}", atm, cams, views, suns, samples=paths,
                           seed=seed + 11, max_order=2, collisions=collisions)
    return cams, views, suns, ref


def compare(split, args, quadratures):
    """{quadrature: rows (atmosphere, camera class, light class, relative error (W,), relative noise (W,))}."""
    rows = {q: [] for q in quadratures}
    cache = TableCache()
    for name, atm, seed in cases(split, args.atmospheres, args.presets):
        sizes = sizes_for(atm, QUALITY["standard"])
        if args.rows:
            sizes = replace(sizes, multiple=sizes.multiple[:3] + (max(sizes.multiple[3], args.rows),))
        tables = precompute(atm, QUALITY["standard"], cache=cache)
        two_orders = {q: first_two_orders(tables, atm, sizes, q[1] or sizes.directions, quadrature=q[0])
                      for q in quadratures}
        for light in LIGHT:
            cams, views, suns, ref = reference_orders(name, atm, seed, light, args.paths, args.collisions)
            for q in quadratures:
                got, _ = sky_radiance(two_orders[q], atm, cams, views, suns)
                for k in range(len(cams)):
                    ok = ref.radiance[k] > 1e-12
                    rows[q].append((name, CAMERAS[k // 2], light, got[k][ok] / ref.radiance[k][ok] - 1.0,
                                    ref.stderr[k][ok] / ref.radiance[k][ok]))
        print(f"  {split}: {name} done", flush=True)
    return rows


def report(split, q, rows, worst):
    label = ("the level's own" if q[1] is None else f"{q[1][0]}x{q[1][1]}") + f", {q[0]}"
    print(f"\n{split} split, directions {label}")
    print("| light | cameras | values | RMS error | noise removed | median | largest | reference noise (RMS) |")
    print("|---|---|---|---|---|---|---|---|")
    for light in LIGHT:
        for top in (False, True):
            sel = [(e, n) for r in rows if r[2] == light and (r[1] == "top") == top for e, n in zip(r[3], r[4])
                   if n < 0.2]
            if not sel:
                continue
            err, noise = np.array(sel).T
            rms, floor = np.sqrt(np.mean(err ** 2)), np.sqrt(np.mean(noise ** 2))
            clean = np.sqrt(max(rms ** 2 - floor ** 2, 0.0))
            resolved = f"{100 * clean:.2f}%" if floor <= clean / 3 else f"below resolution ({100 * clean:.2f}%)"
            print(f"| {light} | {'within 100 m of the top' if top else 'all others'} | {err.size} | "
                  f"{100 * rms:.1f}% | {resolved} | {100 * np.median(np.abs(err)):.1f}% | "
                  f"{100 * np.abs(err).max():.0f}% | {100 * np.sqrt(np.mean(noise ** 2)):.1f}% |")
    for light in LIGHT if worst else ():
        flat = [(e, n, r) for r in rows if r[2] == light for e, n in zip(r[3], r[4]) if n < 0.2]
        print(f"\nlargest errors ({split}, directions {label}, {light}):")
        for e, n, r in sorted(flat, key=lambda x: -abs(x[0]))[:worst]:
            print(f"  {e:+.3f} (noise {n:.3f})  {r[0]}, {r[1]}, {r[2]}")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--split", nargs="+", default=list(SPLITS), choices=list(SPLITS))
    ap.add_argument("--atmospheres", type=int, default=8)
    ap.add_argument("--paths", type=int, default=16384)
    ap.add_argument("--presets", nargs="*", default=["earth", "mars", "exo-co2-thick"])
    ap.add_argument("--worst", type=int, default=10)
    ap.add_argument("--quadrature", nargs="+", default=[QUALITY["standard"].quadrature], choices=QUADRATURES)
    ap.add_argument("--directions", type=int, nargs="+", metavar="N",
                    help="pairs N_THETA N_PHI of the scattering density's direction quadrature")
    ap.add_argument("--rows", type=int, default=0, metavar="N",
                    help="at least N r rows in the multiple-scattering tables")
    ap.add_argument("--collisions", default=DEFAULT_COLLISIONS, choices=COLLISIONS)
    args = ap.parse_args()
    if args.directions and len(args.directions) % 2:
        ap.error("--directions: pairs N_THETA N_PHI")
    sizes = [None] if not args.directions else \
        [tuple(args.directions[i:i + 2]) for i in range(0, len(args.directions), 2)]
    quadratures = [(kind, size) for kind in args.quadrature for size in sizes]
    for split in args.split:
        rows = compare(split, args, quadratures)
        for q in quadratures:
            report(split, q, rows[q], args.worst)


if __name__ == "__main__":
    main()
