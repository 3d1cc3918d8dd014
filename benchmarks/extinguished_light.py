"""The multiple-scattering stage's nodes along rays against a conservation law: the light each ray takes out of a
beam, int beta T dt, is 1 - T(d) (planetviz.validation.ray_nodes), with the three segments of thin atmospheres'
split rays and the five of thick ones (planetviz/tables/nodes.py, split_ray_nodes).

    python benchmarks/extinguished_light.py [--quality standard] [ATMOSPHERE ...]
    python benchmarks/extinguished_light.py --tables earth


ATMOSPHERE as in orders_sum.py (a preset, random-SEED, twin-SEED); default: the thick atmospheres of
docs/tables.md, step 4. Printed per atmosphere: its vertical optical depth per wavelength and, for three and five
segments, the RMS and largest relative error per wavelength over the rays of the multiple-scattering tables'
grid whose 1 - T(d) exceeds 1e-3; and the exact value's own error (16 against 32 panels).

``--tables``: instead, the atmospheres' multiple-scattering tables at the level (no cache) with the split rays on
three segments and on five (forced where the atmosphere is thin), each against the same tables with 16 nodes per
side: RMS, 99th percentile and largest relative difference of the molecules' and the particles' tables over the
texels above 1e-3 of their wavelength's largest. Whether five segments would change a thin atmosphere's tables.
"""
import argparse
from dataclasses import replace

import numpy as np

from orders_sum import atmosphere
from planetviz.tables import QUALITY, multiple, precompute
from planetviz.validation.ray_nodes import extinguished_light_error

THICK = ["twin-100807", "twin-100280", "twin-1", "twin-4", "twin-100221", "twin-100680", "twin-100950",
         "twin-100088", "random-1", "random-4", "random-5", "random-100000", "random-100006", "exo-co2-thick"]


def against_more_nodes(atm, quality):
    """Print the multiple-scattering tables' difference from 16 nodes per side, on three and on five segments."""
    level = QUALITY[quality]
    fine = precompute(atm, replace(level, multiple_samples=16), cache=None)
    as_is = precompute(atm, level, cache=None)
    split = multiple.split_ray_nodes
    multiple.split_ray_nodes = lambda *a, **k: split(*a, **{**k, "thick": True})
    try:
        five = precompute(atm, level, cache=None)
    finally:
        multiple.split_ray_nodes = split
    for key in ("multiple", "multiple_mie"):
        want = getattr(fine, key)
        bright = want > 1e-3 * want.max(axis=tuple(range(want.ndim - 1)))
        for label, tables in (("as it is", as_is), ("five segments", five)):
            rel = np.abs(getattr(tables, key)[bright] / want[bright] - 1.0)
            print(f"| {atm.name} | {key} | {label} | {100 * np.sqrt(np.mean(rel ** 2)):.3f}% | "
                  f"{100 * np.percentile(rel, 99):.3f}% | {100 * rel.max():.2f}% |", flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("atmospheres", nargs="*", default=THICK)
    ap.add_argument("--quality", default="standard", choices=list(QUALITY))
    ap.add_argument("--tables", action="store_true", help="the tables against 16 nodes per side instead")
    args = ap.parse_args()
    if args.tables:
        print(f"quality {args.quality}; against the same tables with 16 nodes per side")
        print("| atmosphere | table | split rays | RMS | p99 | largest |")
        print("|---|---|---|---|---|---|")
        for name in args.atmospheres:
            against_more_nodes(atmosphere(name), args.quality)
        return
    percent = lambda x: " / ".join(f"{100 * v:.2f}%" for v in x)
    print(f"quality {args.quality}; per wavelength, the atmosphere's order")
    print("| atmosphere | vertical optical depth | segments | RMS | largest | exact value's own error |")
    print("|---|---|---|---|---|---|")
    for name in args.atmospheres:
        atm = atmosphere(name)
        tau = " / ".join(f"{v:.2f}" for v in atm.vertical_optical_depth())
        for thick in (False, True):
            error, own = extinguished_light_error(atm, thick, args.quality)
            print(f"| {name} | {tau} | {'five' if thick else 'three'} | {percent(np.sqrt(np.nanmean(error ** 2, 0)))} "
                  f"| {percent(np.nanmax(np.abs(error), 0))} | {own:.1e} |", flush=True)


if __name__ == "__main__":
    main()
