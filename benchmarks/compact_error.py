"""Error of the compact (Atmosphere Plus) tables against the 4D tables they are made from, and memory.

    python benchmarks/compact_error.py [--presets earth mars exo-co2-thick] [--quality standard]

Same query set as benchmarks/tables_pareto.py (200 rays: ground, aircraft, stratosphere, space; sun from the
zenith to 6 deg below the horizon; random, near-sun, horizon/limb and ground views). The difference is
relative to the 4D tables' radiance (above 1e-5 / sr): it is the cost of dropping the sun-view azimuth and
of Atmosphere Plus's mappings, not the tables' own error.
"""
import argparse
import time

import numpy as np

from planetviz import load_atmosphere
from planetviz.tables import QUALITY, TableCache, precompute
from planetviz.tables.compact import compact_tables
from planetviz.tables.evaluator import sky_radiance
from tables_pareto import query_set

VIEWS = ("random", "near the sun", "horizon / limb", "toward the ground")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--presets", nargs="+", default=["earth", "mars", "exo-co2-thick"])
    ap.add_argument("--quality", default="standard", choices=list(QUALITY))
    args = ap.parse_args()
    print("| atmosphere | view | daylight RMS | daylight p95 | twilight RMS | twilight p95 |")
    print("|---|---|---|---|---|---|")
    for name in args.presets:
        atm = load_atmosphere(name)
        tables = precompute(atm, QUALITY[args.quality], cache=TableCache())
        t0 = time.perf_counter()
        compact = compact_tables(tables, atm)
        build = time.perf_counter() - t0
        cams, views, suns, el = query_set(atm)
        full, _ = sky_radiance(tables, atm, cams, views, suns)
        small, _ = sky_radiance(compact, atm, cams, views, suns)
        rel = np.abs(small - full) / np.maximum(full, 1e-30)
        ok = full > 1e-5
        kind = (np.arange(len(el)) % 4)[:, None]
        for k, view in list(enumerate(VIEWS)) + [(None, "all")]:
            sel = ok & ((kind == k) if k is not None else True)
            cells = []
            for part in (sel & (el[:, None] >= 2), sel & (el[:, None] < 2)):
                cells += ([f"{np.sqrt(np.mean(rel[part] ** 2)):.3f}", f"{np.percentile(rel[part], 95):.3f}"]
                          if part.any() else ["-", "-"])
            print(f"| {name} | {view} | " + " | ".join(cells) + " |")
        print(f"| {name} | memory: 4D {tables.nbytes / 1e6:.1f} MB, compact {compact.nbytes / 1e6:.1f} MB "
              f"(built from the 4D tables in {build:.1f} s) | | | | |", flush=True)


if __name__ == "__main__":
    main()
