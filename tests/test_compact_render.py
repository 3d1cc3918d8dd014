"""The compact (Atmosphere Plus) tables drawn by the renderer (``Scene(tables="compact")``, ``--tables compact``):
the shader against the NumPy evaluator reading the same compact tables, per pixel and per vertex, and the
commands that take them."""
import os
import subprocess
import sys

import numpy as np
import pytest

os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkOSOpenGLRenderWindow")

from planetviz.render import Scene  # noqa: E402
from planetviz.tables.compact import CompactTables  # noqa: E402
from planetviz.tables.evaluator import sky_radiance  # noqa: E402
from test_vertex_shading import SIZE, set_view  # noqa: E402


@pytest.fixture(scope="module", params=["pixel", "vertex"])
def compact(request):
    scene = Scene("earth", quality="draft", surface=None, off_screen=True, window_size=SIZE, shading=request.param,
                  tables="compact")
    yield scene
    scene.close()


@pytest.mark.parametrize("view", ["space", "ground", "aircraft", "terminator"])
def test_compact_tables_render_as_the_evaluator_reads_them(compact, view):
    # The shader's float read-back against the NumPy evaluator on the same compact tables, at sampled pixels (per
    # vertex: one vertex per sampled pixel's direction, so no interpolation between vertices). Bound 1%, as for the
    # 4D tables (tests/test_render.py): float32 arithmetic on the same tables; a wrong mapping or a missing
    # component is off by far more (the compact tables differ from the 4D ones by 2-100%, docs/benchmarks.md).
    set_view(compact, view)
    assert isinstance(compact.planet.tables, CompactTables) and compact.table_kind == "compact"
    rows, cols = np.meshgrid(np.arange(1, SIZE[1], 4), np.arange(1, SIZE[0], 5), indexing="ij")
    dirs = compact.pixel_directions(rows, cols).reshape(-1, 3)
    if compact.shading == "vertex":
        compact.planet.directions = dirs
    try:
        got = compact.render_hdr().radiance[rows, cols].reshape(-1, 3)
    finally:
        if compact.shading == "vertex":
            compact.planet.directions = None
    want, _ = sky_radiance(compact.planet.tables, compact.atmosphere, np.tile(compact.camera_location, (len(dirs), 1)),
                           dirs, compact.sun_direction)
    away = dirs @ compact.sun_direction < np.cos(np.radians(1.0))        # the evaluator has no sun disc
    seen = away & (want.max(-1) > 1e-6 * want.max())
    assert seen.sum() > 50
    assert np.max(np.abs(got - want)[seen] / want[seen]) < 0.01


def test_switching_between_4d_and_compact_tables_keeps_the_view(tmp_path):
    scene = Scene("earth", quality="draft", surface=None, off_screen=True, window_size=SIZE)
    try:
        set_view(scene, "ground")
        full = scene.render_hdr().radiance
        scene.set_table_kind("compact")
        small = scene.render_hdr().radiance
        with pytest.raises(ValueError, match="tables: one of 4d, compact"):
            scene.set_table_kind("3d")
        assert scene.table_kind == "compact" and isinstance(scene.planet.tables, CompactTables)
        sky = full.max(-1) > 0
        rel = np.abs(small - full)[sky] / full[sky]
        assert 0 < np.median(rel) < 0.2                   # the same sky, read from other tables
    finally:
        scene.close()


def test_the_commands_take_compact_tables(tmp_path):
    run = lambda *a: subprocess.run([sys.executable, "-m", "planetviz", *map(str, a)], capture_output=True, text=True,
                                    cwd=tmp_path)
    q = tmp_path / "q.npz"
    assert run("queries", "--out", q, "--sun-elevation", 20).returncode == 0
    out = {}
    for kind in ("4d", "compact"):
        proc = run("radiance", "--atmosphere", "earth", "--queries", q, "--out", tmp_path / f"{kind}.npz",
                   "--method", "tables", "--quality", "draft", "--tables", kind)
        assert proc.returncode == 0, proc.stderr
        out[kind] = np.load(tmp_path / f"{kind}.npz")["radiance"]
    assert not np.array_equal(out["4d"], out["compact"]) and np.allclose(out["4d"], out["compact"], rtol=0.3)
    bad = run("radiance", "--atmosphere", "earth", "--queries", q, "--out", tmp_path / "x.npz", "--tables", "compact")
    assert bad.returncode == 2 and "tables: compact tables are read with --method tables" in bad.stderr
    png = tmp_path / "compact.png"
    proc = run("render", "--quality", "draft", "--size", "64x48", "--tables", "compact", "--screenshot", png)
    assert proc.returncode == 0 and png.stat().st_size > 0, proc.stderr
