"""The standard tables against tables with 4 times the multiple-scattering rows and twice the single-scattering
ones, over a range of camera altitudes: where the standard rows miss structure along r (an absorbing layer's edge
between two rows), the two disagree.

    python benchmarks/row_convergence.py [--atmosphere earth] [--altitudes 0.5 60] [--bands 10]
                                         [--suns 60 20 5] [--views 2]

``--atmosphere``: a preset or ``random-N`` (the suite's random atmosphere N, planetviz.validation.random_suite).
Cameras at 120 altitudes uniform over ``--altitudes`` [km]; for each and each sun elevation [deg], a view 3 deg
above the sun's direction and ``--views`` - 1 random ones (fixed seed). Printed per altitude band: the RMS and the
largest relative difference over the rays and wavelengths whose radiance with the finer tables is above 1e-14 / sr,
then the largest differences with their ray.
"""
import argparse
from dataclasses import replace

import numpy as np

from planetviz.tables import QUALITY, TableCache, precompute
from planetviz.tables.evaluator import sky_radiance
from planetviz.validation import suite_atmosphere


def finer(sizes):
    """``sizes`` with 4 times the multiple-scattering rows and twice the single-scattering rows."""
    n_nu, n_mu_s, n_mu, n_r = sizes.multiple
    s_nu, s_mu_s, s_mu, s_r = sizes.scattering
    return replace(sizes, multiple=(n_nu, n_mu_s, n_mu, 4 * n_r), scattering=(s_nu, s_mu_s, s_mu, 2 * s_r))


def queries(atm, altitudes_km, suns_deg, views, seed=5):
    """(cameras, views, suns, altitudes [m]) of the module docstring."""
    rng = np.random.default_rng(seed)
    cams, dirs, suns, heights = [], [], [], []
    for elevation in np.radians(suns_deg):
        sun = np.array([np.cos(elevation), 0.0, np.sin(elevation)])
        near_sun = np.array([np.cos(elevation + np.radians(3.0)), 0.0, np.sin(elevation + np.radians(3.0))])
        for h in np.linspace(altitudes_km[0], altitudes_km[1], 120) * 1e3:
            random_views = rng.normal(size=(views - 1, 3))
            for v in [near_sun, *(random_views / np.linalg.norm(random_views, axis=1, keepdims=True))]:
                cams.append([0.0, 0.0, atm.bottom_radius_m + h])
                dirs.append(v)
                suns.append(sun)
                heights.append(h)
    return np.array(cams), np.array(dirs), np.array(suns), np.array(heights)


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--atmosphere", default="earth")
    p.add_argument("--altitudes", type=float, nargs=2, default=(0.5, 60.0))
    p.add_argument("--bands", type=int, default=6)
    p.add_argument("--suns", type=float, nargs="+", default=(60.0, 20.0, 5.0))
    p.add_argument("--views", type=int, default=2)
    p.add_argument("--worst", type=int, default=5)
    args = p.parse_args()
    name = args.atmosphere
    atm = suite_atmosphere(name)[0]
    cache = TableCache()
    standard = QUALITY["standard"]
    cams, views, suns, heights = queries(atm, args.altitudes, args.suns, args.views)
    coarse, _ = sky_radiance(precompute(atm, standard, cache=cache), atm, cams, views, suns)
    fine, _ = sky_radiance(precompute(atm, finer(standard), cache=cache), atm, cams, views, suns)
    seen = fine > 1e-14
    error = np.where(seen, coarse / np.where(seen, fine, 1.0) - 1.0, 0.0)
    print(f"{name}: standard tables against 4x the multiple-scattering rows and 2x the single-scattering rows")
    print("| altitudes [km] | values | RMS | largest |")
    print("|---|---|---|---|")
    edges = np.linspace(args.altitudes[0], args.altitudes[1], args.bands + 1) * 1e3
    for lo, hi in zip(edges[:-1], edges[1:]):
        band = (heights >= lo) & ((heights < hi) | (hi == edges[-1]))
        e = error[band][seen[band]]
        print(f"| {lo / 1e3:.1f}-{hi / 1e3:.1f} | {e.size} | {np.sqrt(np.mean(e ** 2)):.2%} | "
              f"{np.max(np.abs(e)):.2%} |")
    print(f"all: RMS {np.sqrt(np.mean(error[seen] ** 2)):.2%}")
    for k in np.argsort(-np.abs(error).max(1))[:args.worst]:
        mu = views[k] @ cams[k] / np.linalg.norm(cams[k])
        print(f"  {heights[k] / 1e3:7.1f} km, sun {np.degrees(np.arcsin(suns[k][2])):+5.1f} deg, view mu {mu:+.3f}: "
              f"{np.round(error[k], 3)} (radiance {fine[k]})")


if __name__ == "__main__":
    main()
