"""Test configuration: off-screen rendering through OSMesa (set before VTK is imported), and a table cache
of the test run's own, so that tests never read or fill the user's ~/.cache/planetviz; the run's worker
processes (pytest-xdist, ``-n 2`` in scripts/test.sh) share it, and the process that started them removes it
when the run ends; one BLAS thread per process (set before NumPy is loaded, inherited by the workers)."""
import functools
import os
import shutil
import tempfile
from pathlib import Path

#: One OpenBLAS thread per process: with two workers on the two cores, a worker's second BLAS thread waits by
#: spinning on a core the other worker needs. tests/test_tables_disort.py's large aerosol planet (DISORT's
#: eigensystems) took 52 s with its default two threads beside a busy core, 31 s with one.
for _blas_threads in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS"):
    os.environ.setdefault(_blas_threads, "1")

import numpy as np  # noqa: E402
import pytest  # noqa: E402

os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkOSOpenGLRenderWindow")
#: True in a worker process of pytest-xdist, which inherits the cache of the process that started it.
XDIST_WORKER = "PYTEST_XDIST_WORKER" in os.environ
TABLE_CACHE = os.environ["PLANETVIZ_TEST_CACHE"] if XDIST_WORKER else tempfile.mkdtemp(prefix="planetviz-test-cache-")
os.environ["PLANETVIZ_TEST_CACHE"] = os.environ["PLANETVIZ_CACHE"] = TABLE_CACHE
#: Stored reference results of the tests and benchmarks.
REFERENCE_DATA = Path(__file__).resolve().parents[1] / "benchmarks" / "data"


def pytest_sessionfinish(session, exitstatus):
    """Remove the run's table cache (about 200 MB after the whole suite) once every worker is done."""
    if not XDIST_WORKER:
        shutil.rmtree(TABLE_CACHE, ignore_errors=True)


#: The modules whose slow-marked tests take longest, longest first (their tests' seconds summed, from the slow run of
#: scripts/test.sh with ``--durations=0`` on the 2-core CI machine); every other module's tests take less in all.
SLOWEST_MODULES = ("test_tables_disort.py", "test_reference_slow.py", "test_stability_edges.py", "test_tables.py",
                   "test_readme.py", "test_multiple_scattering.py")


def pytest_collection_modifyitems(config, items):
    """The slowest modules first, each module's tests in their own order: scripts/test.sh's slow run hands whole
    modules to its two workers in this order (``--dist loadscope --no-loadscope-reorder``), so that no long
    module starts last and leaves one worker idle."""
    rank = {name: k for k, name in enumerate(SLOWEST_MODULES)}
    items.sort(key=lambda item: rank.get(item.path.name, len(SLOWEST_MODULES)))


def stored_reference(tag, atm, cameras, views, sun, samples, seed):
    """The reference solver's result for these rays, computed once and kept under benchmarks/data/ (recomputed
    when the atmosphere, the rays, the paths, the seed or the solver's version change)."""
    from planetviz.reference.stored import stored_reference as stored
    return stored(REFERENCE_DATA, tag, atm, cameras, views, sun, samples=samples, seed=seed)


@functools.lru_cache(maxsize=None)
def draft_earth_tables():
    """The Earth preset's draft tables, computed once per test run for every module that reads them."""
    from planetviz import load_atmosphere
    from planetviz.tables import QUALITY, precompute
    return precompute(load_atmosphere("earth"), QUALITY["draft"])


def check_finite_and_bounded(radiance, transmittance):
    """Radiance finite and >= 0, transmittance finite and in [0, 1]."""
    assert np.all(np.isfinite(radiance)) and np.all(radiance >= 0), radiance
    assert np.all(np.isfinite(transmittance)) and np.all((transmittance >= 0) & (transmittance <= 1)), transmittance


def distances_along(tables, alt, mu, n=50):
    """(r, d): the radius of a camera at altitude ``alt`` and n distances d along its view (cosine ``mu``) from 0
    to where the ray leaves the atmosphere or meets the ground."""
    bottom, top = tables.bottom, tables.top
    r = bottom + alt
    ground = mu < 0 and r * r * (mu * mu - 1) + bottom * bottom >= 0
    disc = r * r * (mu * mu - 1) + (bottom if ground else top) ** 2
    end = -r * mu - np.sqrt(max(disc, 0)) if ground else -r * mu + np.sqrt(max(disc, 0))
    return r, np.linspace(0.0, max(end, 0.0), n)


def transmittance_along(tables, alt, mu, n=50):
    """T(x, x + d v) from ``tables`` at the n distances d of :func:`distances_along`: (n, W)."""
    from planetviz.tables.lookup import get_transmittance
    r, d = distances_along(tables, alt, mu, n)
    return get_transmittance(tables, np.full(n, r), np.full(n, mu), d)


@pytest.fixture(scope="session")
def standard_single():
    """The Earth preset's standard tables without multiple scattering, computed once per test run."""
    from planetviz import load_atmosphere
    from planetviz.tables import QUALITY, precompute
    return precompute(load_atmosphere("earth"), QUALITY["standard"], multiple=False)


@pytest.fixture(scope="module")
def scene_pairs():
    """{key: (scene, scene)} that a module's picture tests fill as they go, every scene closed at the module's end."""
    scenes = {}
    yield scenes
    for pair in scenes.values():
        for scene in pair:
            scene.close()


def hold_to_targets(figures, targets, misses, where, ceilings):
    """Assert every figure (name: value) not in ``misses`` within its target, and every one in ``misses`` within
    its ceiling (name: value, the caller's independent bound on a known miss); a figure in ``misses`` that meets
    its target fails (take it out of the list of misses and ``where``'s list in the docs), and known misses within
    their ceilings mark the test as an expected failure naming their values."""
    for name, value in figures.items():
        if name not in misses:
            assert value <= targets[name], f"{name} {value:.4f} above the target {targets[name]}"
        else:
            assert value <= ceilings[name], f"known miss {name} {value:.4f} above its ceiling {ceilings[name]:.4f}"
        if name in misses and value <= targets[name]:
            pytest.fail(f"{name} {value:.4f} now meets the target {targets[name]}: take it out of the known misses "
                        f"and {where}'s list of misses")
    # Reached only when every assertion above held: the figures that meet the targets met them, each known
    # miss stayed under its independent ceiling and none of them met its target. The view still misses the issue's
    # target, so the test is reported as an expected failure naming the figures, not as a pass.
    if misses:
        pytest.xfail(f"a known miss of the issue's targets ({', '.join(f'{n} {figures[n]:.4f}' for n in misses)}), "
                     f"{where}")
