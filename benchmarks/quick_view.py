"""The quick view (no 4D tables): Keller and Bohn's single scattering against sample counts, power-law against
equidistant sampling, what single scattering alone misses; the orders above the first from Hillaire's table
against the tables; pictures against the per-pixel tables per view; frame time.

    python benchmarks/quick_view.py [--presets earth mars exo-co2-thick] [--plot docs/img/quick-view.png]
    VTK_DEFAULT_OPENGL_WINDOW=vtkOSOpenGLRenderWindow python benchmarks/quick_view.py --views     # + pictures
    VTK_DEFAULT_OPENGL_WINDOW=vtkOSOpenGLRenderWindow python benchmarks/quick_view.py --frames 3   # + frame time

Errors on the fixed query set of benchmarks/tables_pareto.py (200 rays per atmosphere), relative, over
radiances above 1e-5 / sr, RMS: against the deterministic single-scattering integral (reference.single_scattering,
48 panels: the quantity the quick view computes), and against the Monte Carlo reference with all orders
(benchmarks/data, noise removed as in tables_pareto.py): what single scattering alone misses. n points on
each view path and n on each optical-depth path.
"""
import argparse
import itertools
import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from tables_pareto import errors, query_set, reference  # noqa: E402

from planetviz import load_atmosphere  # noqa: E402
from planetviz.quick_view.single_scattering import quick_view_radiance  # noqa: E402
from planetviz.reference import QUALITY_SAMPLES, single_scattering  # noqa: E402
from planetviz.validation.pictures import VIEWS, floored_difference, view_luminance  # noqa: E402

SAMPLES = (3, 4, 6, 8, 12, 16, 24, 32)


def rms(x, ref, mask):
    e = ((x - ref) / np.maximum(ref, 1e-30))[mask]
    return float(np.sqrt(np.mean(e ** 2)))


def accuracy(presets, plot):
    print("| atmosphere | sampling | n | ms per 1000 rays | vs single scattering: day RMS | twilight RMS | "
          "vs all orders: day RMS | twilight RMS |")
    print("|---|---|---|---|---|---|---|---|")
    curves = {}
    for name in presets:
        atm = load_atmosphere(name)
        q = query_set(atm)
        a, g = single_scattering(atm, *q[:3], panels=48)
        single = a + g
        full, stderr = reference(name, atm, q, QUALITY_SAMPLES["standard"], QUALITY_SAMPLES["standard"])
        el = q[3][:, None]
        ok = (single > 1e-5) & (full > 1e-5)
        day, dusk = ok & (el >= 2), ok & (el < 2)
        for sampling in ("power", "equidistant"):
            for n in SAMPLES:
                t0 = time.perf_counter()
                L, _ = quick_view_radiance(atm, *q[:3], samples=n, density_samples=n, sampling=sampling)
                ms = 1e3 * (time.perf_counter() - t0) / len(L) * 1000
                row = (rms(L, single, day), rms(L, single, dusk), errors(L, full, stderr, day)[0],
                       errors(L, full, stderr, dusk)[0])
                curves.setdefault((name, sampling), []).append((n, *row))
                print(f"| {name} | {sampling} | {n} | {ms:.0f} | {row[0]:.4f} | {row[1]:.4f} | {row[2]:.4f} | "
                      f"{row[3]:.4f} |", flush=True)
        exact = (rms(single, full, day), rms(single, full, dusk))
        print(f"| {name} | exact single scattering | - | - | 0 | 0 | {exact[0]:.4f} | {exact[1]:.4f} |")
    if plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, axes = plt.subplots(1, len(presets), figsize=(5 * len(presets), 4), squeeze=False)
        for ax, name in zip(axes[0], presets):
            for sampling, style in (("power", "-o"), ("equidistant", "--s")):
                c = np.array(curves[name, sampling])
                ax.plot(c[:, 0], c[:, 1], style, label=f"{sampling}: vs single scattering (day)")
                ax.plot(c[:, 0], c[:, 3], style, alpha=0.5, label=f"{sampling}: vs all orders (day)")
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.set_xticks(SAMPLES, [str(n) for n in SAMPLES])
            ax.minorticks_off()
            ax.set_xlabel("points per path (view and optical depth)")
            ax.set_ylabel("RMS relative error")
            ax.set_title(name)
            ax.legend(fontsize=7)
        fig.tight_layout()
        Path(plot).parent.mkdir(parents=True, exist_ok=True)
        fig.savefig(plot, dpi=120)
        print(f"plot: {plot}")


def all_orders(presets):
    """The quick view with the table of Psi (orders above the first, the sky's light on the ground) against the
    standard 4D tables read by the NumPy evaluator, on the same query set: day (the sun 2 deg up or more where
    the ray looks) and twilight (0 to -6 deg), over radiances above 1e-5 of the set's largest; and the time to
    make the table."""
    from planetviz.quick_view.multiple_scattering import quick_view_tables
    from planetviz.tables import QUALITY, TableCache, precompute
    from planetviz.tables.evaluator import sky_radiance
    print("\n| atmosphere | orders | n | table ms | day RMS | day p99 | twilight RMS | twilight p99 |")
    print("|---|---|---|---|---|---|---|---|")
    for name in presets:
        atm = load_atmosphere(name)
        q = query_set(atm)
        want, _ = sky_radiance(precompute(atm, QUALITY["standard"], cache=TableCache()), atm, *q[:3])
        el = q[3][:, None]
        ok = want > 1e-5 * want.max()
        day, dusk = ok & (el >= 2), ok & (el < 2) & (el >= -6)
        best = np.inf
        for _ in range(3):
            t0 = time.perf_counter()
            psi, sky = quick_view_tables(atm)
            best = min(best, time.perf_counter() - t0)
        for orders, multiple, ground_sky in (("single", None, None), ("all", psi, sky)):
            for n in (8, 20):
                got, _ = quick_view_radiance(atm, *q[:3], samples=n, multiple=multiple, ground_sky=ground_sky)
                rel = np.abs(got / np.where(want > 0, want, 1.0) - 1.0)
                cells = [f"{np.sqrt(np.mean(rel[m] ** 2)):.4f} | {np.percentile(rel[m], 99):.4f}" for m in (day, dusk)]
                ms = f"{1e3 * best:.0f}" if multiple is not None else "-"
                print(f"| {name} | {orders} | {n} | {ms} | {cells[0]} | {cells[1]} |", flush=True)


def psi_against_disort():
    """Psi against DISORT's mean radiance of the diffuse light, (1/2) int u0 dmu, on plane-parallel planets whose only
    scatterers are isotropic (where Psi's model is exact), at the ground and three altitudes: the table's quadrature
    error alone."""
    from planetviz.quick_view.multiple_scattering import multiple_scattering_table, read_table
    from planetviz.validation.disort import disort_mean_radiance, isotropic_atmosphere
    heights = np.array([0.0, 2000.0, 10000.0, 30000.0])
    print("\nPsi / DISORT, isotropic scatterers (scale height 8 km), ground albedo 0.3")
    print("| optical depth | single-scattering albedo | sun zenith cosine | ground | 2 km | 10 km | 30 km |")
    print("|---|---|---|---|---|---|---|")
    for depths, omega in (((0.1, 1.0, 5.0), 0.95), ((0.3, 2.0, 8.0), 0.999)):
        atm = isotropic_atmosphere(depths, omega)
        psi = multiple_scattering_table(atm)
        for w, depth in enumerate(depths):
            for mu_s in (0.9, 0.5, 0.15):
                got = read_table(psi, atm, heights, np.full(heights.shape, mu_s), geometric=True)[:, w]
                ratio = got / disort_mean_radiance(atm, w, mu_s, heights)
                print(f"| {depth} | {omega} | {mu_s} | " + " | ".join(f"{x:.3f}" for x in ratio) + " |", flush=True)


def random_atmospheres(split, count):
    """The quick view (single scattering; all orders) against the standard 4D tables read by the NumPy evaluator
    on ``count`` random legal atmospheres of ``split`` (planetviz.validation.random_suite), 6 daylight rays per
    camera class each; relative error over radiances above 1e-6 of each atmosphere's largest."""
    from planetviz.quick_view.multiple_scattering import quick_view_tables
    from planetviz.tables import QUALITY, precompute
    from planetviz.tables.evaluator import sky_radiance
    from planetviz.validation.random_suite import CAMERAS, SPLITS, random_atmosphere, rays
    errors_of = {("single", c): [] for c in CAMERAS} | {("all", c): [] for c in CAMERAS}
    for seed in list(SPLITS[split])[:count]:
        atm = random_atmosphere(seed)
        tables = precompute(atm, QUALITY["standard"], cache=None)
        psi, sky = quick_view_tables(atm)
        for k, camera_class in enumerate(CAMERAS):
            cams, views, suns = rays(atm, 10 * seed + k, camera_class, "day", n=6)[:3]
            for c, v, s in zip(cams, views, suns):
                want = sky_radiance(tables, atm, c[None], v[None], s)[0][0]
                for orders, multiple, ground_sky in (("single", None, None), ("all", psi, sky)):
                    got = quick_view_radiance(atm, c[None], v[None], s, multiple=multiple,
                                              ground_sky=ground_sky)[0][0]
                    errors_of[orders, camera_class].append(np.stack([got, want]))
    print(f"\n{split}: {count} random atmospheres, 6 daylight rays per camera class, quick view (default points "
          "per path) against the standard tables: RMS relative error")
    print("| orders | all rays: RMS | median | p95 | " + " | ".join(CAMERAS) + " |")
    print("|---|---|---|---|" + "---|" * len(CAMERAS))
    for orders in ("single", "all"):
        per_class, every = [], []
        for c in CAMERAS:
            pairs = np.array(errors_of[orders, c])                    # (rays, 2, W)
            got, want = pairs[:, 0], pairs[:, 1]
            ok = want > 1e-6 * want.max()
            rel = np.abs(got[ok] / want[ok] - 1.0)
            every.append(rel)
            per_class.append(f"{np.sqrt(np.mean(rel ** 2)):.3f}")
        rel = np.concatenate(every)
        print(f"| {orders} | {np.sqrt(np.mean(rel ** 2)):.3f} | {np.median(rel):.3f} | {np.percentile(rel, 95):.3f} | "
              + " | ".join(per_class) + " |", flush=True)


def compared_pictures(preset, size, kinds, compared, views=tuple(VIEWS)):
    """(view, cells) for each of ``views``: the frames of ``preset`` drawn by the scenes ``kinds`` (name: Scene
    keywords; "tables" the one compared with) in CIE Y (``render_hdr``), the sun's disc left out, and for each
    name in ``compared`` 'RMS | p99' of its relative difference from "tables", floored at 1% of that frame's 99th
    percentile (a pixel darker than that counts against that level; planetviz.validation.pictures)."""
    os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkOSOpenGLRenderWindow")
    from planetviz.render import Scene
    w, h = (int(v) for v in size.split("x"))
    scenes = {kind: Scene(preset, off_screen=True, window_size=(w, h), **options) for kind, options in kinds.items()}
    try:
        for view in views:
            y = {kind: view_luminance(scene, VIEWS[view]) for kind, scene in scenes.items()}
            cells = []
            for kind in compared:
                rel = floored_difference(y[kind], y["tables"])
                cells.append(f"{np.sqrt(np.mean(rel ** 2)):.4f} | {np.percentile(rel, 99):.4f}")
            yield view, " | ".join(cells)
    finally:
        for scene in scenes.values():
            scene.close()


def views(presets, size):
    """The quick view's pictures (single scattering; all orders), and the draft tables' read per vertex (what the
    window shows after the quick view while the standard tables compute), against the per-pixel standard tables'
    (:func:`compared_pictures`); the atmosphere's uniform albedo on both sides, so that the atmospheres are
    compared, not the texture."""
    print(f"\n{size}: quick view and draft tables against the per-pixel standard tables, CIE Y, floored at 1% of "
          "the frame's p99")
    print("| atmosphere | view | single: RMS | p99 | all orders: RMS | p99 | draft tables per vertex: RMS | p99 |")
    print("|---|---|---|---|---|---|---|---|")
    kinds = {"tables": dict(quality="standard", shading="pixel", surface=None),
             "single": dict(quality="standard", method="quick", quick_orders="single", surface=None),
             "all": dict(quality="standard", method="quick", quick_orders="all", surface=None),
             "draft": dict(quality="draft", shading="vertex", surface=None)}
    for name in presets:
        for view, cells in compared_pictures(name, size, kinds, ("single", "all", "draft")):
            print(f"| {name} | {view} | {cells} |", flush=True)


def textured_views(size):
    """Earth's quick view with the surface texture against the per-pixel standard tables with it (the quick view
    completes the ground per pixel with the texture), and the quick view with the file's uniform albedo against
    the same textured tables: what the texture closes (:func:`compared_pictures`)."""
    print(f"\n{size}, Earth with its surface texture: the quick view against the per-pixel standard tables")
    print("| view | textured quick view: RMS | p99 | uniform albedo: RMS | p99 |")
    print("|---|---|---|---|---|")
    kinds = {"tables": dict(method="tables", surface="texture"), "quick": dict(method="quick", surface="texture"),
             "uniform": dict(method="quick", surface=None)}
    kinds = {kind: dict(options, quality="standard", shading="pixel") for kind, options in kinds.items()}
    for view, cells in compared_pictures("earth", size, kinds, ("quick", "uniform"),
                                         ("orbit, day", "orbit, terminator", "aircraft, 10 km", "ground, noon")):
        print(f"| {view} | {cells} |", flush=True)


def frame_times(size, frames):
    """The quick view's frame time from the ground and from space, single scattering and all orders, and the time
    from a change of the atmosphere to its next frame (the tables of the orders above the first made in NumPy
    first)."""
    os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkOSOpenGLRenderWindow")
    from planetviz.render import Scene
    from render_timing import frame_ms
    w, h = (int(v) for v in size.split("x"))
    print(f"\n| quick view, {size} | orders | ms per frame (median of {frames}) | change to first frame, ms | "
          "change to the frame with all orders, ms | vertices drawn |")
    print("|---|---|---|---|---|---|")
    cameras = {"ground": ("view_from_ground", dict(latitude=45, heading=90, pitch=5)),
               "space": ("view_from_space", dict(latitude=20, longitude=10))}
    for (where, (call, keywords)), n, orders in itertools.product(cameras.items(), (8, 20, 24), ("single", "all")):
        scene = Scene("earth", off_screen=True, window_size=(w, h), method="quick", quick_samples=n,
                      quick_orders=orders)
        getattr(scene, call)(**keywords)
        scene.screenshot()
        ms = frame_ms(scene.ren_win, frames)
        first, whole = [], []
        for k in range(frames):
            albedo = 0.2 + 0.1 * (k % 2)
            t0 = time.perf_counter()
            scene.set_atmosphere(scene.atmosphere.replace(ground_albedo=(albedo,) * 3))
            scene.render()
            first.append(1e3 * (time.perf_counter() - t0))
            while scene.quick_pending:                  # an interactive window renders on until it is whole
                scene.render()
            whole.append(1e3 * (time.perf_counter() - t0))
        verts = len(np.unique(np.concatenate([cells for cells, _ in scene.quick._cells])))   # drawn, both parts
        print(f"| n = {n}, {where} | {orders} | {ms:.1f} | {np.median(first):.0f} | {np.median(whole):.0f} | "
              f"{verts} |", flush=True)
        scene.close()


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--presets", nargs="+", default=["earth", "mars", "exo-co2-thick"])
    ap.add_argument("--plot", default=None)
    ap.add_argument("--frames", type=int, default=0, help="also time frames (needs OpenGL)")
    ap.add_argument("--views", action="store_true", help="also compare pictures per view (needs OpenGL)")
    ap.add_argument("--size", default="1280x720")
    ap.add_argument("--views-size", default="320x200")
    ap.add_argument("--random", type=int, default=0, help="also this many random atmospheres per split")
    ap.add_argument("--disort", action="store_true", help="also Psi against DISORT (isotropic scatterers)")
    args = ap.parse_args()
    accuracy(args.presets, args.plot)
    all_orders(args.presets)
    if args.disort:
        psi_against_disort()
    for split in ("tuning", "held-out") if args.random else ():
        random_atmospheres(split, args.random)
    if args.views:
        views(args.presets, args.views_size)
        textured_views(args.views_size)
    if args.frames:
        frame_times(args.size, args.frames)


if __name__ == "__main__":
    main()
