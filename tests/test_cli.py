"""The planetviz command: the radiance contract, its errors, and the other subcommands."""
import subprocess
import sys

import numpy as np
import pytest

from planetviz import load_atmosphere
from planetviz.reference import single_scattering, solve
from planetviz.reference.montecarlo import QUALITY_SAMPLES

EARTH = load_atmosphere("earth")
R = EARTH.bottom_radius_m


def run(*args):
    return subprocess.run([sys.executable, "-m", "planetviz", *map(str, args)], capture_output=True, text=True)


def write_queries(path, camera, view, sun):
    np.savez(path, camera_m=np.asarray(camera, float), view_dir=np.asarray(view, float),
             sun_dir=np.asarray(sun, float))
    return path


def test_radiance_reference_contract(tmp_path):
    camera = [[0, 0, R], [0, 0, R + 1e4], [0, 0, 1e12], [0, -2e7, 0], [0, 0, R + 400e3]]
    view = [[0, 0.3, 1.0], [1, 0, 0], [0, 0, -2.0], [1, 0, 0], [0, 0, -1]]   # not normalised on purpose
    q = write_queries(tmp_path / "q.npz", camera, view, [0, 0.6, 0.8])
    out = tmp_path / "out.npz"
    proc = run("radiance", "--atmosphere", "earth", "--queries", q, "--out", out, "--method", "reference",
               "--quality", "draft")
    assert proc.returncode == 0, proc.stderr
    with np.load(out) as r:
        assert r["radiance"].shape == (5, 3) and r["transmittance"].shape == (5, 3)
        assert np.array_equal(r["wavelengths_nm"], [680.0, 550.0, 440.0])
        rad, trans = r["radiance"], r["transmittance"]
    assert np.all(np.isfinite(rad)) and np.all(rad >= 0)
    assert np.all((trans >= 0) & (trans <= 1))
    # Ray 3 (1e12 m away, straight down) sees the lit ground through the whole atmosphere: its direct
    # ground term alone is T (a / pi) cos(theta_s) T_sun; the total must exceed it.
    _, ground = single_scattering(EARTH, [camera[2]], [[0, 0, -1.0]], [0, 0.6, 0.8])
    assert np.all(rad[2] > ground[0]) and np.all(rad[2] < 1.5 * ground[0] + 0.05)
    # Ray 4 misses the atmosphere entirely: nothing in the way.
    assert np.all(rad[3] == 0) and np.all(trans[3] == 1)
    # The same rays through the Python API with the same seed give the same numbers.
    v = np.asarray(view, float)
    api = solve(EARTH, np.asarray(camera, float), v / np.linalg.norm(v, axis=1, keepdims=True),
                np.array([0, 0.6, 0.8]), samples=QUALITY_SAMPLES["draft"], seed=0)
    assert np.allclose(api.radiance, rad, rtol=1e-12)


@pytest.mark.parametrize("camera,view,sun,message", [
    ([[0, 0, R + 10]], [[0, 0, 0]], [0, 0, 1], "view_dir[0]: zero vector"),
    ([[0, 0, R + 10]], [[0, np.nan, 1]], [0, 0, 1], "view_dir[0]: contains NaN"),
    ([[0, 0, R + 10]], [[0, 0, 1]], [np.nan, 0, 1], "sun_dir[0]: contains NaN"),
    ([[0, 0, R - 5]], [[0, 0, 1]], [0, 0, 1], "camera_m[0]: 5 m below the ground"),
    ([[0, 0, R + 10], [0, 0, R + 20]], [[0, 0, 1]], [0, 0, 1], "view_dir: shape (1, 3) does not match"),
    ([[0, 0, np.inf]], [[0, 0, 1]], [0, 0, 1], "camera_m[0]: contains NaN or inf"),
])
def test_bad_queries_exit_2_with_one_line(tmp_path, camera, view, sun, message):
    q = write_queries(tmp_path / "q.npz", camera, view, sun)
    proc = run("radiance", "--atmosphere", "earth", "--queries", q, "--out", tmp_path / "o.npz")
    assert proc.returncode == 2
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and message in lines[0], proc.stderr
    assert not (tmp_path / "o.npz").exists()


def test_missing_and_corrupt_query_files(tmp_path):
    proc = run("radiance", "--atmosphere", "earth", "--queries", tmp_path / "none.npz", "--out", tmp_path / "o.npz")
    assert proc.returncode == 2 and "queries: cannot read" in proc.stderr
    bad = tmp_path / "bad.npz"
    bad.write_bytes(b"PK\x03\x04 truncated")
    proc = run("radiance", "--atmosphere", "earth", "--queries", bad, "--out", tmp_path / "o.npz")
    assert proc.returncode == 2 and "not a valid .npz" in proc.stderr and "Traceback" not in proc.stderr
    np.savez(tmp_path / "partial.npz", camera_m=np.zeros((1, 3)))
    proc = run("radiance", "--atmosphere", "earth", "--queries", tmp_path / "partial.npz", "--out", tmp_path / "o.npz")
    assert proc.returncode == 2 and "missing array 'view_dir'" in proc.stderr


def test_quick_view_sample_count_out_of_range_is_refused_clearly(tmp_path):
    q = write_queries(tmp_path / "q.npz", [[0, 0, R + 10]], [[0, 0, 1]], [0, 0, 1])
    proc = run("radiance", "--atmosphere", "earth", "--queries", q, "--out", tmp_path / "o.npz", "--method", "quick",
               "--samples", "0")
    assert proc.returncode == 2 and "samples: an integer in [1, 256]" in proc.stderr
    assert "Traceback" not in proc.stderr


def test_camera_a_millimetre_below_ground_rounds_onto_it(tmp_path):
    q = write_queries(tmp_path / "q.npz", [[0, 0, R - 5e-4]], [[0, 0, 1]], [0, 0, 1])
    proc = run("radiance", "--atmosphere", "earth", "--queries", q, "--out", tmp_path / "o.npz", "--samples", "64")
    assert proc.returncode == 0, proc.stderr


def test_atmosphere_command_prints_the_documented_optical_depths():
    proc = run("atmosphere", "earth-advanced")
    assert proc.returncode == 0
    rows = [line.split() for line in proc.stdout.splitlines() if line.strip().startswith(("680.0", "550.0", "440.0"))]
    tau = [float(r[8]) for r in rows]
    assert np.allclose(tau, load_atmosphere("earth-advanced").vertical_optical_depth(), atol=1e-4)


def test_sky_command_main_job():
    proc = run("sky", "--quality", "draft")
    assert proc.returncode == 0, proc.stderr
    lines = [line for line in proc.stdout.splitlines() if "zenith" in line]
    values = [float(x) for x in lines[0].split()[3:12:3]]     # after the name and "elevation, azimuth"
    assert values[2] > values[0]   # the noon-ish zenith is bluer (440 nm) than red (680 nm)


def test_precompute_warns_outside_the_validated_range(tmp_path, monkeypatch):
    # Mars's dust puts over 97% of the scattering in a g = 0.86-0.91 forward lobe: the warning names that
    # condition and the error measured on such atmospheres; the Earth preset is inside the range and gets none.
    # The conditions themselves, on atmospheres built to meet exactly one each.
    from planetviz.tables.validated import CONDITIONS, outside_validated_range
    monkeypatch.setenv("PLANETVIZ_CACHE", str(tmp_path))
    mars = run("precompute", "--atmosphere", "mars", "--quality", "draft")
    earth = run("precompute", "--atmosphere", "earth", "--quality", "draft")
    assert mars.returncode == 0 and earth.returncode == 0, (mars.stderr, earth.stderr)
    assert "warning: mars: the particles' strongest forward lobe g 0.911 is above 0.7" in mars.stderr
    assert "draft tables were validated for" in mars.stderr and "RMS" in mars.stderr
    assert "warning" not in earth.stderr
    data = EARTH.to_dict()
    thick = {**data, "rayleigh": {**data["rayleigh"], "scattering_m": [3e-4, 3e-4, 3e-4]}}
    large = {**data, "bottom_radius_m": 2e8, "top_radius_m": 2e8 + 6e4}
    names = {key: [c.name for c in outside_validated_range(type(EARTH).from_dict(d))]
             for key, d in (("thick", thick), ("large", large))}
    assert names == {"thick": ["optically thick"], "large": ["large planet"]}
    assert [c.name for c in CONDITIONS] == ["optically thick", "forward lobe", "large planet"]
