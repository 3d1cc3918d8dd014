"""Frames per second of a sequence in one process, on a local Dask cluster and on a scheduler with separate worker
processes (the way a farm runs), for the throughput model of docs/rendering.md.

    VTK_DEFAULT_OPENGL_WINDOW=vtkOSOpenGLRenderWindow python benchmarks/sequence_throughput.py \\
        [--frames 20] [--size 1280x720] [--quality standard] [--workers 1 2]

The sequence is a sun sweep from the ground (Earth, tables read per pixel, PNG frames), rendered afresh in a
temporary folder each time. Printed per run: the wall time, frames per second, and the time to the first frame
(start-up: the cluster, the scene, the tables read from the cache). The model: wall = start-up + frames x (time
per frame) / workers on separate machines; on one machine the workers share its cores, which llvmpipe already
uses, so the time per frame does not fall.
"""
import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

COMMAND = [sys.executable, "-m", "planetviz", "render", "--view", "ground", "--heading", "270", "--pitch", "5"]


def run(args, extra, folder):
    """(wall time [s], time to the first frame [s]) of one sequence, its frames under ``folder``."""
    shutil.rmtree(folder, ignore_errors=True)
    folder.mkdir(parents=True)
    sweep = ["--sweep-sun", "-4", str(-4 + 2 * (args.frames - 1)), "2"]
    t0 = time.perf_counter()
    proc = subprocess.Popen(COMMAND + ["--size", args.size, "--quality", args.quality, *sweep,
                                       "--screenshot", str(folder / "f.png"), *extra],
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    first = None
    while proc.poll() is None:
        if first is None and any(folder.glob("f_*.png")):
            first = time.perf_counter() - t0
        time.sleep(0.02)
    wall = time.perf_counter() - t0
    if proc.returncode:
        raise RuntimeError(proc.stderr.read())
    return wall, first if first is not None else wall


def scheduler_cluster(n_workers, folder):
    """A `dask scheduler` and ``n_workers`` `dask worker` processes; (address, processes)."""
    dask = str(Path(sys.executable).with_name("dask"))
    address_file = folder / "scheduler.json"
    procs = [subprocess.Popen([dask, "scheduler", "--scheduler-file", str(address_file), "--no-dashboard",
                               "--port", "0"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)]
    while not address_file.exists():
        time.sleep(0.1)
    for _ in range(n_workers):
        procs.append(subprocess.Popen([dask, "worker", "--scheduler-file", str(address_file), "--nworkers", "1",
                                       "--nthreads", "1", "--no-dashboard"],
                                      stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL))
    time.sleep(3.0)                                  # the workers register
    return json.loads(address_file.read_text())["address"], procs


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--frames", type=int, default=20)
    ap.add_argument("--size", default="1280x720")
    ap.add_argument("--quality", default="standard")
    ap.add_argument("--workers", type=int, nargs="+", default=[1, 2])
    args = ap.parse_args()
    os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkOSOpenGLRenderWindow")
    root = Path(tempfile.mkdtemp(prefix="planetviz-sequence-"))
    run(args, ["--workers", "0"], root / "warm")    # the tables into the cache
    rows = [("one process", *run(args, ["--workers", "0"], root / "one"))]
    for n in args.workers:
        rows.append((f"local Dask, {n} worker(s)", *run(args, ["--workers", str(n)], root / f"local{n}")))
    for n in args.workers:
        address, procs = scheduler_cluster(n, root)
        try:
            rows.append((f"scheduler + {n} worker process(es)", *run(args, ["--scheduler", address], root / f"s{n}")))
        finally:
            for p in procs[::-1]:
                p.terminate()
                p.wait(30)
            (root / "scheduler.json").unlink(missing_ok=True)
    print(f"{args.frames} frames, {args.size}, {args.quality} tables, per pixel, {os.cpu_count()} cores")
    print("| run | wall [s] | frames/s | first frame after [s] | per frame after the first [s] |")
    print("|---|---|---|---|---|")
    for name, wall, first in rows:
        print(f"| {name} | {wall:.1f} | {args.frames / wall:.2f} | {first:.1f} | "
              f"{(wall - first) / max(args.frames - 1, 1):.2f} |")
    shutil.rmtree(root, ignore_errors=True)


if __name__ == "__main__":
    main()
