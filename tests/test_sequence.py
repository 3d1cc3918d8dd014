"""Frame sequences (planetviz/app/sequence.py): the same frames in one process and on Dask, resumable, failures
reported by number, and a cluster reached through its scheduler's address."""
import json
import os
import signal
import subprocess
import sys
import time

import numpy as np
import OpenEXR
import pytest

from planetviz import load_atmosphere
from planetviz.app.sequence import Frame, SceneSettings, run_sequence

ENV = {**os.environ, "VTK_DEFAULT_OPENGL_WINDOW": "vtkOSOpenGLRenderWindow"}
# The quick view (no tables) at 48x32: the frames cost little; the sequence machinery is what is tested.
SWEEP = ("render", "--method", "quick", "--size", "48x32", "--view", "ground", "--sweep-sun", "-2", "10", "4")


def run(*args, cwd):
    return subprocess.run([sys.executable, "-m", "planetviz", *map(str, args)], capture_output=True, text=True,
                          cwd=cwd, env=ENV)


def pixels(path):
    return {k: np.asarray(v.pixels) for k, v in OpenEXR.File(str(path)).channels().items()}


def test_a_local_dask_run_writes_the_one_process_frames_bit_for_bit(tmp_path):
    one = run(*SWEEP, "--exr", "one/s.exr", "--workers", "0", cwd=tmp_path)
    dask = run(*SWEEP, "--exr", "dask/s.exr", "--workers", "2", cwd=tmp_path)
    assert one.returncode == 0 and dask.returncode == 0, one.stderr + dask.stderr
    for i in range(4):
        a, b = pixels(tmp_path / f"one/s_{i:04d}.exr"), pixels(tmp_path / f"dask/s_{i:04d}.exr")
        assert a.keys() == b.keys() and all(np.array_equal(a[k], b[k]) for k in a)
    manifest = json.loads((tmp_path / "dask/s.manifest.json").read_text())
    assert [f["sun"]["elevation"] for f in manifest["frames"]] == [-2.0, 2.0, 6.0, 10.0]
    assert len(manifest["atmosphere_sha256"]) == 64 and manifest["settings"]["method"] == "quick"


def test_a_rerun_renders_only_the_missing_frames(tmp_path):
    assert run(*SWEEP, "--exr", "s.exr", cwd=tmp_path).returncode == 0
    stamps = {p.name: p.stat().st_mtime_ns for p in tmp_path.glob("s_*.exr")}
    (tmp_path / "s_0002.exr").unlink()
    proc = run(*SWEEP, "--exr", "s.exr", cwd=tmp_path)
    assert proc.returncode == 0 and "1 frames rendered, 3 already there" in proc.stdout, proc.stdout + proc.stderr
    for name, stamp in stamps.items():
        if name != "s_0002.exr":
            assert (tmp_path / name).stat().st_mtime_ns == stamp      # not rendered twice
    assert (tmp_path / "s_0002.exr").exists()
    # Other parameters into the same files: every frame again (the manifest records what each was made with).
    proc = run(*SWEEP, "--exr", "s.exr", "--exposure", "2e-4", cwd=tmp_path)
    assert proc.returncode == 0 and "4 frames rendered, 0 already there" in proc.stdout, proc.stdout + proc.stderr


def test_killing_a_run_loses_no_finished_frame_and_the_rerun_renders_none_twice(tmp_path):
    # A 24-frame flight killed once three frames are written; the re-run completes it. Frames are renamed into
    # place when complete, so every file under its final name is whole (it opens) and none is rewritten.
    flight = ("render", "--method", "quick", "--size", "48x32", "--flight", "24", "--exr", "f.exr")
    proc = subprocess.Popen([sys.executable, "-m", "planetviz", *flight], cwd=tmp_path, env=ENV,
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline = time.time() + 120
    while len(list(tmp_path.glob("f_*.exr"))) < 3 and time.time() < deadline and proc.poll() is None:
        time.sleep(0.05)
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    before = {p.name: p.stat().st_mtime_ns for p in tmp_path.glob("f_*.exr")}
    assert 3 <= len(before) < 24
    for name in before:
        pixels(tmp_path / name)
    rerun = run(*flight, cwd=tmp_path)
    assert rerun.returncode == 0, rerun.stderr
    assert f"{24 - len(before)} frames rendered, {len(before)} already there" in rerun.stdout
    assert len(list(tmp_path.glob("f_*.exr"))) == 24
    assert all((tmp_path / name).stat().st_mtime_ns == stamp for name, stamp in before.items())


def test_a_frame_that_fails_is_retried_and_reported_by_number(tmp_path):
    settings = SceneSettings(load_atmosphere("earth").to_json(), method="quick", size=(24, 16))
    view = dict(kind="ground", latitude=0.0, longitude=0.0, altitude=1.7, heading=90.0, pitch=5.0, fov=60.0)
    frames = [Frame(i, view, dict(elevation=elevation, azimuth=90.0), (str(tmp_path / f"x_{i:04d}.exr"),))
              for i, elevation in enumerate([5.0, 95.0, 15.0])]      # 95 deg: refused by Scene.set_sun
    with pytest.raises(RuntimeError, match=r"frames 1 \(sun elevation"):
        run_sequence(settings, frames, retries=1)
    assert sorted(p.name for p in tmp_path.glob("x_*.exr")) == ["x_0000.exr", "x_0002.exr"]


def test_a_cluster_reached_through_its_scheduler_renders_the_sequence(tmp_path):
    # The way a farm runs: `dask scheduler` and `dask worker` as their own processes, the sequence sent to the
    # scheduler's address.
    bin_dir = os.path.dirname(sys.executable)
    dask = os.path.join(bin_dir, "dask") if os.path.exists(os.path.join(bin_dir, "dask")) else "dask"
    address_file = tmp_path / "scheduler.json"
    procs = [subprocess.Popen([dask, "scheduler", "--scheduler-file", str(address_file), "--no-dashboard",
                               "--port", "0"], env=ENV, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)]
    try:
        deadline = time.time() + 60
        while not address_file.exists() and time.time() < deadline:
            time.sleep(0.1)
        procs.append(subprocess.Popen([dask, "worker", "--scheduler-file", str(address_file), "--nworkers", "1",
                                       "--nthreads", "1", "--no-dashboard"], env=ENV, stdout=subprocess.DEVNULL,
                                      stderr=subprocess.DEVNULL))
        address = json.loads(address_file.read_text())["address"]
        proc = run(*SWEEP, "--exr", "s.exr", "--scheduler", address, cwd=tmp_path)
        assert proc.returncode == 0, proc.stderr
        assert len(list(tmp_path.glob("s_*.exr"))) == 4
    finally:
        for p in procs[::-1]:
            p.terminate()
            p.wait(30)
