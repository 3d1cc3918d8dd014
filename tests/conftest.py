"""Test configuration: off-screen rendering through OSMesa (set before VTK is imported), and a table cache
of the test run's own, so that tests never read or fill the user's ~/.cache/planetviz; it is removed when
the run ends."""
import os
import shutil
import tempfile
from pathlib import Path

os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkOSOpenGLRenderWindow")
TABLE_CACHE = tempfile.mkdtemp(prefix="planetviz-test-cache-")
os.environ["PLANETVIZ_CACHE"] = TABLE_CACHE
#: Stored reference results of the tests and benchmarks.
REFERENCE_DATA = Path(__file__).resolve().parents[1] / "benchmarks" / "data"


def pytest_sessionfinish(session, exitstatus):
    """Remove the run's table cache (about 200 MB after the whole suite)."""
    shutil.rmtree(TABLE_CACHE, ignore_errors=True)


def stored_reference(tag, atm, cameras, views, sun, samples, seed):
    """The reference solver's result for these rays, computed once and kept under benchmarks/data/ (recomputed
    when the atmosphere, the rays, the paths, the seed or the solver's version change)."""
    from planetviz.reference.stored import stored_reference as stored
    return stored(REFERENCE_DATA, tag, atm, cameras, views, sun, samples=samples, seed=seed)
