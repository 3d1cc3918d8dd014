"""Frame time of the table-based renderer (OSMesa / llvmpipe on this machine, or any VTK OpenGL window).

    VTK_DEFAULT_OPENGL_WINDOW=vtkOSOpenGLRenderWindow python benchmarks/render_timing.py [--size 1280x720] [--frames 10]

Views: Earth from orbit (the planet fills ~40% of the frame), from the ground (the whole frame is sky and
ground) and from 1e9 m (the planet is a few pixels: the shell's coverage skips the rest). Median ms per
frame over ``--frames`` after one warm-up frame (shader compile and table upload, reported apart), each frame
finished with WaitForCompletion; plus the float read-back of render_hdr.
"""
import argparse
import os
import time

import numpy as np

os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkOSOpenGLRenderWindow")

from planetviz.render import Scene  # noqa: E402


def frame_ms(scene, frames):
    times = []
    for _ in range(frames):
        t0 = time.perf_counter()
        scene.ren_win.Render()
        scene.ren_win.WaitForCompletion()
        times.append(1e3 * (time.perf_counter() - t0))
    return float(np.median(times))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--size", default="1280x720")
    ap.add_argument("--frames", type=int, default=10)
    ap.add_argument("--quality", default="standard")
    args = ap.parse_args()
    w, h = (int(v) for v in args.size.split("x"))
    t0 = time.perf_counter()
    scene = Scene("earth", quality=args.quality, off_screen=True, window_size=(w, h))
    setup = time.perf_counter() - t0
    scene.view_from_space(latitude=20, longitude=10)
    t0 = time.perf_counter()
    scene.screenshot()
    first = time.perf_counter() - t0
    print(f"renderer: {scene.ren_win.ReportCapabilities().splitlines()[1].strip() if scene.ren_win.ReportCapabilities() else '?'}")
    print(f"size {w}x{h}, quality {args.quality}; set-up (tables from the cache or computed) {setup:.2f} s, "
          f"first frame (compile + upload) {first:.2f} s")
    print("| view | ms per frame |")
    print("|---|---|")
    views = {"orbit (4 radii)": lambda: scene.view_from_space(latitude=20, longitude=10),
             "ground, sky and ground": lambda: scene.view_from_ground(latitude=45, heading=90, pitch=5),
             "1e9 m (a few pixels)": lambda: scene.view_from_space(distance=1e9, fov=30)}
    for name, setview in views.items():
        setview()
        scene.render()
        print(f"| {name} | {frame_ms(scene, args.frames):.1f} |", flush=True)
    t0 = time.perf_counter()
    scene.view_from_space(latitude=20, longitude=10)
    scene.render_hdr()
    print(f"render_hdr (float read-back, {-(-scene.atmosphere.n_wavelengths // 3)} pass): "
          f"{1e3 * (time.perf_counter() - t0):.0f} ms")
    scene.close()


if __name__ == "__main__":
    main()
