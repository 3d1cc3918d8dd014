"""Background work (planetviz/render/background.py): a job runs only once started, at its CPU priority, and
reports its result or its error; a scene starts the precompute a change asks for after the next frame, and never
the precompute of a change superseded before that frame."""
import os
import sys
import threading

import pytest

os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkOSOpenGLRenderWindow")

from planetviz.render import Scene  # noqa: E402
from planetviz.render.background import BACKGROUND_NICENESS, BackgroundJob  # noqa: E402
from planetviz.tables import QUALITY  # noqa: E402


def test_a_job_runs_once_started_at_its_priority_and_keeps_its_result_or_error():
    ran = threading.Event()

    def work():
        ran.set()
        return os.getpriority(os.PRIO_PROCESS, threading.get_native_id())

    job = BackgroundJob(work, niceness=BACKGROUND_NICENESS)
    assert not ran.wait(0.2) and not job.started and not job.done
    job.join(10)
    assert job.done and job.error is None
    if sys.platform.startswith("linux"):
        assert job.result == BACKGROUND_NICENESS
    failing = BackgroundJob(lambda: 1 / 0)
    failing.join(10)
    assert failing.done and isinstance(failing.error, ZeroDivisionError) and failing.result is None


@pytest.fixture()
def scene():
    s = Scene("earth", quality="draft", surface=None, off_screen=True, window_size=(64, 48), cache=False)
    s.screenshot()                                   # an off-screen plotter renders on render() once it has drawn
    yield s
    s.close()


def test_a_change_computes_after_the_next_frame_and_a_superseded_change_never(scene):
    base = scene.atmosphere
    scene.set_atmosphere(base.replace(ground_albedo=(0.5,) * 3))
    superseded = scene._job
    scene.set_atmosphere(base.replace(ground_albedo=(0.6,) * 3))
    current = scene._job
    assert not superseded.started and not current.started and not scene.quick._job.started
    assert scene.renderer_in_use == "quick"
    scene.render()                                   # the quick view's first frame, then the work starts
    assert current.started and scene.quick._job.started and not superseded.started
    scene.wait_for_tables()
    assert scene.renderer_in_use == "tables" and scene.atmosphere.ground_albedo == (0.6,) * 3
    assert not superseded.started


def test_a_change_at_standard_quality_shows_draft_tables_until_the_final_ones_are_ready():
    # Above the draft quality the background job makes draft tables first (0.6 s for Earth against 4 s): they stand
    # in for the final ones, which then replace them. A change whose final tables are in the cache goes straight to
    # them (a draft there would only delay them). A job that made no draft hands none out, so a draft shown comes
    # from this job.
    scene = Scene("earth", quality="standard", surface=None, off_screen=True, window_size=(64, 48), cache=False)
    try:
        scene.set_atmosphere(scene.atmosphere.replace(ground_albedo=(0.5,) * 3))
        assert scene.renderer_in_use == "quick" and not scene.showing_draft
        scene.render()                               # the quick view's frame, then the job starts
        job = scene._job
        while not scene.showing_draft and not job.done:
            job.join(0.05)
            scene.collect()
        assert scene.showing_draft and scene.renderer_in_use == "tables" and scene._job is job
        assert scene.tables.sizes.scattering == QUALITY["draft"].scattering
        scene.wait_for_tables()
        assert not scene.showing_draft and scene.tables.sizes.scattering == QUALITY["standard"].scattering
    finally:
        scene.close()
    cached = Scene("earth", quality="standard", surface=None, off_screen=True, window_size=(64, 48))
    try:                                             # the test run's own cache now holds Earth's standard tables
        earth = cached.atmosphere
        cached.set_atmosphere(earth.replace(ground_albedo=(0.5,) * 3))
        cached.set_atmosphere(earth)                 # back: new tables, all of them in the cache
        job = cached._job
        job.join()
        assert job.error is None and job.take_preview() is None
        cached.wait_for_tables()
        assert not cached.showing_draft and cached.tables.sizes.scattering == QUALITY["standard"].scattering
    finally:
        cached.close()
