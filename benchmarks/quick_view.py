"""The quick view (Keller and Bohn, no tables): error against sample counts, power-law against equidistant
sampling, what single scattering alone misses, and frame time.

    python benchmarks/quick_view.py [--presets earth mars exo-co2-thick] [--plot docs/img/quick-view.png]
    VTK_DEFAULT_OPENGL_WINDOW=vtkOSOpenGLRenderWindow python benchmarks/quick_view.py --frames 3   # + frame time

Errors on the fixed query set of benchmarks/tables_pareto.py (200 rays per atmosphere), relative, over
radiances above 1e-5 / sr, RMS: against the deterministic single-scattering integral (reference.single_scattering,
48 panels: the quantity the quick view computes), and against the Monte Carlo reference with all orders
(benchmarks/data, noise removed as in tables_pareto.py): what single scattering alone misses. n points on
each view path and n on each optical-depth path.
"""
import argparse
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
                L, _ = quick_view_radiance(atm, *q[:3], samples=n, sampling=sampling)
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


def frame_times(size, frames):
    os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkOSOpenGLRenderWindow")
    from planetviz.render import Scene
    from render_timing import frame_ms
    w, h = (int(v) for v in size.split("x"))
    print(f"\n| quick view, {size} | ms per frame (median of {frames}) | vertices |")
    print("|---|---|---|")
    for n in (4, 8, 16):
        scene = Scene("earth", off_screen=True, window_size=(w, h), method="quick", quick_samples=n)
        scene.view_from_ground(latitude=45, heading=90, pitch=5)
        scene.screenshot()
        ms = frame_ms(scene, frames)
        verts = scene.quick.mapper.GetInput().GetNumberOfPoints()
        print(f"| n = {n}, ground | {ms:.1f} | {verts} |", flush=True)
        scene.close()


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--presets", nargs="+", default=["earth", "mars", "exo-co2-thick"])
    ap.add_argument("--plot", default=None)
    ap.add_argument("--frames", type=int, default=0, help="also time frames (needs OpenGL)")
    ap.add_argument("--size", default="1280x720")
    args = ap.parse_args()
    accuracy(args.presets, args.plot)
    if args.frames:
        frame_times(args.size, args.frames)


if __name__ == "__main__":
    main()
