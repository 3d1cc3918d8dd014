"""Precompute time and error of the tables against the reference solver, per atmosphere and quality.

    python benchmarks/tables_accuracy.py [--presets earth mars exo-co2-thick] [--qualities draft standard high]
                                         [--rays 120] [--samples 4096]

The query set (fixed seed): cameras at 2 m, 1 km (aircraft), 10 km, 30 km (stratosphere), 1000 km and
40000 km (space); random view directions; sun elevation uniform in [-6, 90] deg. Errors are relative to
the reference (Monte Carlo, ``--samples`` paths per ray, its own standard error printed) over the
radiances above 1e-5 / sr (1e-5 of the top-of-atmosphere irradiance: darker pixels are black on screen).
"""
import argparse
import time

import numpy as np

from planetviz import load_atmosphere
from planetviz.reference import solve
from planetviz.tables.evaluator import sky_radiance
from planetviz.tables.precompute import QUALITY, precompute


def query_set(atm, n, seed=1):
    rng = np.random.default_rng(seed)
    r = atm.bottom_radius_m
    alts = np.array([2.0, 1e3, 1e4, 3e4, 1e6, 4e7])[np.arange(n) % 6]
    cams = np.stack([np.zeros(n), np.zeros(n), r + alts], 1)
    views = rng.normal(size=(n, 3))
    views /= np.linalg.norm(views, axis=1, keepdims=True)
    el = np.radians(rng.uniform(-6, 90, n))
    az = rng.uniform(0, 2 * np.pi, n)
    suns = np.stack([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)], 1)
    return cams, views, suns, np.degrees(el)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--presets", nargs="+", default=["earth", "mars", "exo-co2-thick"])
    ap.add_argument("--qualities", nargs="+", default=list(QUALITY))
    ap.add_argument("--rays", type=int, default=120)
    ap.add_argument("--samples", type=int, default=4096)
    args = ap.parse_args()
    print("| atmosphere | quality | precompute [s] (T / single / multiple) | orders | MB | "
          "RMS rel. err. (sun >= 2 deg) | p95 | RMS (twilight, sun < 2 deg) | reference std. err. |")
    print("|---|---|---|---|---|---|---|---|---|")
    for name in args.presets:
        atm = load_atmosphere(name)
        cams, views, suns, el = query_set(atm, args.rays)
        ref = solve(atm, cams, views, suns, samples=args.samples, seed=3)
        for q in args.qualities:
            t0 = time.perf_counter()
            tab = precompute(atm, QUALITY[q])
            total = time.perf_counter() - t0
            lut, _ = sky_radiance(tab, atm, cams, views, suns)
            ok = ref.radiance > 1e-5
            rel = np.abs(lut - ref.radiance) / np.maximum(ref.radiance, 1e-30)
            day = ok & (el[:, None] >= 2)
            dusk = ok & (el[:, None] < 2)
            tm = tab.timings
            print(f"| {name} | {q} | {total:.1f} ({tm['transmittance']:.2f} / {tm['single_scattering']:.1f} / "
                  f"{tm.get('multiple_scattering', 0):.1f}) | {tab.orders} | {tab.nbytes / 1e6:.1f} | "
                  f"{np.sqrt(np.mean(rel[day] ** 2)):.4f} | {np.percentile(rel[day], 95):.4f} | "
                  f"{np.sqrt(np.mean(rel[dusk] ** 2)) if dusk.any() else float('nan'):.4f} | "
                  f"{np.median(ref.stderr[ok] / ref.radiance[ok]):.4f} |", flush=True)


if __name__ == "__main__":
    main()
