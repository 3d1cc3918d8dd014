"""Precompute time against radiance error of the tables, per atmosphere: quality levels and a sweep.

    python benchmarks/tables_pareto.py [--presets earth mars exo-co2-thick] [--sweep] [--paths 32768]
                                       [--twilight-paths 32768] [--collisions scattering]
                                       [--plot docs/img/tables-pareto.png]

Query set (fixed, 200 rays per atmosphere): cameras at 2 m (ground), 10 km (aircraft), 30 km
(stratosphere), 1000 km and 40000 km (space); sun elevations 90, 60, 30, 10, 4, 2 deg (daylight: sun
zenith <= 88 deg) and 0, -2, -4, -6 deg (twilight); per camera and sun, four views: one random, one 3 deg
from the sun, one grazing the horizon (the limb from space) and one toward the ground (the planet from
space). The reference is the solver with ``--paths`` paths per ray and wavelength (``--twilight-paths`` for
the 40% of rays in twilight; default: the reference's high quality for both; ``--collisions``: how it draws its
collisions), stored in benchmarks/data/reference-<preset>[-twilight]-<paths>[-<collisions> where not the
default].npz with the atmosphere's parameters, the rays, the seed, the solver's version and the standard errors
(planetviz.reference.stored: recomputed when absent, or computed for other parameters or by another version of the
solver).

Errors are relative, over radiances above 1e-5 / sr. The reference has its own noise, so the
RMS error of the tables is estimated with the noise removed: sqrt(mean(e^2) - mean(s^2)), e the relative
difference and s the reference's relative standard error per ray (both averaged over rays and
wavelengths); the noise floor sqrt(mean(s^2)) is printed beside it. p95 is of |e| (noise included).
Times are the precompute on this machine (2 cores), all stages, no cache.
"""
import argparse
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from planetviz import load_atmosphere
from planetviz.reference.montecarlo import COLLISIONS, DEFAULT_COLLISIONS, QUALITY_SAMPLES
from planetviz.reference.stored import stored_solve
from planetviz.tables.evaluator import sky_radiance
from planetviz.tables.precompute import QUALITY, precompute

DATA = Path(__file__).resolve().parent / "data"
ALTITUDES = (2.0, 1e4, 3e4, 1e6, 4e7)
ELEVATIONS = (90.0, 60.0, 30.0, 10.0, 4.0, 2.0, 0.0, -2.0, -4.0, -6.0)


def query_set(atm, seed=1):
    """(cameras, views, suns, sun elevation [deg]) of the fixed query set."""
    rng = np.random.default_rng(seed)
    cams, views, suns, els = [], [], [], []
    for alt in ALTITUDES:
        r = atm.bottom_radius_m + alt
        cam = np.array([0.0, 0.0, r])
        for el in ELEVATIONS:
            az = rng.uniform(0, 2 * np.pi)
            e = np.radians(el)
            sun = np.array([np.cos(e) * np.cos(az), np.cos(e) * np.sin(az), np.sin(e)])
            random = rng.normal(size=3)
            # 3 deg from the sun
            perp = np.cross(sun, [0.0, 0.0, 1.0]) if abs(sun[2]) < 0.99 else np.array([1.0, 0.0, 0.0])
            perp /= np.linalg.norm(perp)
            near_sun = np.cos(np.radians(3)) * sun + np.sin(np.radians(3)) * perp
            # grazing the horizon (ground horizon from inside; the limb, 10 km above the surface, from space)
            graze_r = atm.bottom_radius_m + (1e4 if r > atm.top_radius_m else 0.0)
            mu_h = -np.sqrt(max(1.0 - (graze_r / r) ** 2, 0.0)) + (0.002 if r <= atm.top_radius_m else 0.0)
            phi = rng.uniform(0, 2 * np.pi)
            horizon = np.array([np.sqrt(1 - mu_h ** 2) * np.cos(phi), np.sqrt(1 - mu_h ** 2) * np.sin(phi), mu_h])
            # toward the ground: nadir-ish, 20 deg off
            down = np.array([np.sin(np.radians(20)) * np.cos(phi), np.sin(np.radians(20)) * np.sin(phi),
                             -np.cos(np.radians(20))])
            for v in (random, near_sun, horizon, down):
                cams.append(cam)
                views.append(v / np.linalg.norm(v))
                suns.append(sun)
                els.append(el)
    return np.array(cams), np.array(views), np.array(suns), np.array(els)


def reference(name, atm, queries, paths, twilight_paths, collisions=DEFAULT_COLLISIONS):
    """Reference radiance and standard error: ``paths`` per ray, ``twilight_paths`` for the twilight rays
    (sun below 2 deg), whose Monte Carlo noise is otherwise several times the daylight one, the collisions drawn
    as ``collisions`` says; stored under benchmarks/data/ (planetviz.reference.stored), the way of drawing the
    collisions in the name where it is not the default."""
    way = "" if collisions == DEFAULT_COLLISIONS else f"-{collisions}"
    out = []
    sets = [("", slice(None), paths)] + ([("-twilight", queries[3] < 2, twilight_paths)] if twilight_paths != paths
                                         else [])
    for label, sel, n in sets:
        t0 = time.perf_counter()
        res = stored_solve(DATA / f"reference-{name}{label}-{n}{way}.npz", atm, *(q[sel] for q in queries[:3]),
                           samples=n, seed=3, collisions=collisions)
        print(f"(reference for {name}{label}: {len(res.radiance)} rays x {n} paths, {time.perf_counter() - t0:.0f} s "
              "to compute or load)", flush=True)
        out.append((sel, res.radiance, res.stderr))
    radiance, stderr = out[0][1].copy(), out[0][2].copy()
    for sel, rad, err in out[1:]:
        radiance[sel], stderr[sel] = rad, err
    return radiance, stderr


def errors(lut, ref, stderr, mask):
    e = ((lut - ref) / np.maximum(ref, 1e-30))[mask]
    s = (stderr / np.maximum(ref, 1e-30))[mask]
    rms = np.sqrt(max(np.mean(e ** 2) - np.mean(s ** 2), 0.0))
    return rms, np.percentile(np.abs(e), 95), np.sqrt(np.mean(s ** 2))


SWEEP = {
    # name: changes to the standard level
    "T 128x32, 32 nodes": dict(transmittance=(128, 32), transmittance_samples=32),
    "single 4x16x64x16, 6": dict(scattering=(4, 16, 64, 16), scattering_samples=6),
    "single 8x32x128x32, 16": dict(scattering=(8, 32, 128, 32), scattering_samples=16),
    "single 8x48x64x32": dict(scattering=(8, 48, 64, 32)),
    "single 8x64x64x32": dict(scattering=(8, 64, 64, 32)),
    "single 16x32x64x32": dict(scattering=(16, 32, 64, 32)),
    "multiple 4x16x32x16": dict(multiple=(4, 16, 32, 16)),
    "multiple 4x32x64x8": dict(multiple=(4, 32, 64, 8)),
    "multiple 4x32x32x8": dict(multiple=(4, 32, 32, 8)),
    "dirs 8x8": dict(directions=(8, 8)),
    "dirs 12x12": dict(directions=(12, 12)),
    "dirs 16x16": dict(directions=(16, 16)),
    "ms nodes 3": dict(multiple_samples=3),
    "ms nodes 6": dict(multiple_samples=6),
    "ms nodes 8": dict(multiple_samples=8),
    "tolerance 1e-2": dict(tolerance=1e-2),
    "tolerance 1e-3": dict(tolerance=1e-3),
    "draft + single 8x32x64x32": dict(),        # filled in below from the draft level
}


def configurations(sweep):
    out = [(f"level {q}", sizes) for q, sizes in QUALITY.items()]
    if sweep:
        for name, change in SWEEP.items():
            if name.startswith("draft +"):
                out.append((name, replace(QUALITY["draft"], scattering=(8, 32, 64, 32), scattering_samples=10)))
            else:
                out.append((name, replace(QUALITY["standard"], **change)))
    return out


def pareto(points):
    """Indices of the points not beaten in both time and error."""
    order = sorted(range(len(points)), key=lambda i: (points[i][0], points[i][1]))
    front, best = [], np.inf
    for i in order:
        if points[i][1] < best:
            front.append(i)
            best = points[i][1]
    return front


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--presets", nargs="+", default=["earth", "mars", "exo-co2-thick"])
    ap.add_argument("--sweep", action="store_true", help="also the sweep of sizes, samples and orders")
    ap.add_argument("--paths", type=int, default=QUALITY_SAMPLES["high"])
    ap.add_argument("--twilight-paths", type=int, default=QUALITY_SAMPLES["high"])
    ap.add_argument("--collisions", default=DEFAULT_COLLISIONS, choices=COLLISIONS,
                    help="how the reference draws its collisions (planetviz.reference.montecarlo.COLLISIONS)")
    ap.add_argument("--plot", default=None, help="PNG of time against daylight error, Pareto front marked")
    ap.add_argument("--max-stderr", type=float, default=None,
                    help="only rays the reference resolves to this relative standard error (e.g. 0.02)")
    args = ap.parse_args()
    print("| atmosphere | configuration | precompute [s] | orders | MB | daylight RMS | daylight p95 | "
          "twilight RMS | twilight p95 | noise floor (day / twilight) |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    results = {}
    for name in args.presets:
        atm = load_atmosphere(name)
        queries = query_set(atm)
        ref, stderr = reference(name, atm, queries, args.paths, args.twilight_paths, args.collisions)
        el = queries[3][:, None]
        ok = ref > 1e-5
        if args.max_stderr is not None:
            ok &= stderr / np.maximum(ref, 1e-30) < args.max_stderr
        day, dusk = ok & (el >= 2), ok & (el < 2)
        rows = []
        for label, sizes in configurations(args.sweep):
            t0 = time.perf_counter()
            tables = precompute(atm, sizes)
            seconds = time.perf_counter() - t0
            lut, _ = sky_radiance(tables, atm, *queries[:3])
            d, n = errors(lut, ref, stderr, day), errors(lut, ref, stderr, dusk)
            rows.append((seconds, d[0], n[0], label, d[2]))
            print(f"| {name} | {label} | {seconds:.2f} | {tables.orders} | {tables.nbytes / 1e6:.1f} | "
                  f"{d[0]:.4f} | {d[1]:.4f} | {n[0]:.4f} | {n[1]:.4f} | {d[2]:.4f} / {n[2]:.4f} |", flush=True)
        results[name] = rows
    if args.plot:
        plot(results, args.plot)


def plot(results, path):
    """PNG of precompute time against daylight RMS error, one panel per atmosphere: the quality levels in red,
    the sweep in blue, the Pareto front dashed; points below three times the reference's noise floor (the
    resolution, grey line) drawn hollow: they are not ranked by the measurement."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, len(results), figsize=(5.5 * len(results), 4.5), squeeze=False)
    for ax, (name, rows) in zip(axes[0], results.items()):
        pts = [(r[0], r[1]) for r in rows]
        resolution = 3 * rows[0][4]
        for seconds, rms, _, label, _ in rows:
            colour = "C3" if label.startswith("level") else "C0"
            ax.scatter([seconds], [rms], edgecolors=colour, facecolors=colour if rms >= resolution else "none")
            ax.annotate(label.replace("level ", ""), (seconds, rms), fontsize=6, xytext=(3, 2),
                        textcoords="offset points")
        front = pareto(pts)
        ax.plot([pts[i][0] for i in front], [pts[i][1] for i in front], "k--", lw=1, label="Pareto front")
        ax.axhline(resolution, color="0.5", lw=1, label="3 x reference noise (hollow: below it)")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("precompute [s] (2 cores)")
        ax.set_ylabel("daylight RMS relative error (noise removed)")
        ax.set_title(name)
        ax.legend(fontsize=7)
    fig.tight_layout()
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=120)
    print(f"plot: {path}")

if __name__ == "__main__":
    main()
