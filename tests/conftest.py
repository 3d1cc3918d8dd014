"""Test configuration: off-screen rendering through OSMesa (set before VTK is imported), and a table cache
of the test run's own, so that tests never read or fill the user's ~/.cache/planetviz; it is removed when
the run ends."""
import os
import shutil
import tempfile

os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkOSOpenGLRenderWindow")
TABLE_CACHE = tempfile.mkdtemp(prefix="planetviz-test-cache-")
os.environ["PLANETVIZ_CACHE"] = TABLE_CACHE


def pytest_sessionfinish(session, exitstatus):
    """Remove the run's table cache (about 200 MB after the whole suite)."""
    shutil.rmtree(TABLE_CACHE, ignore_errors=True)


def stored_reference(tag, atm, cameras, views, sun, samples, seed):
    """The reference solver's result for these rays, computed once and kept under benchmarks/data/ (recomputed
    when the atmosphere, the rays, the paths, the seed or the solver's version change)."""
    import hashlib
    from pathlib import Path

    import numpy as np

    from planetviz.reference.stored import stored_solve
    rays = np.concatenate([np.atleast_2d(np.asarray(a, dtype=float)) for a in (cameras, views, sun)])
    name = f"test-{tag}-{hashlib.sha1(rays.tobytes()).hexdigest()[:10]}.npz"
    return stored_solve(Path(__file__).resolve().parents[1] / "benchmarks" / "data" / name, atm, cameras, views, sun,
                        samples=samples, seed=seed)
