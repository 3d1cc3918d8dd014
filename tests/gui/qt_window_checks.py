"""The Qt window driven as a user drives it (pytest-qt): run by tests/test_app.py under Xvfb, in a process of its
own with a real X11 display, never collected on its own (the name does not start with test_).

Every step goes through the widgets (typing into a box and pressing Enter, choosing from a combo box, moving the
time slider, clicking the picture), then checks what changed and what did not.
"""
import json

import numpy as np
import pandas as pd
import pytest
from qtpy import QtCore, QtGui, QtWidgets

from planetviz.app.probe import probe_directions
from planetviz.model.limits import LIMITS
from planetviz.model.optics.light import star_irradiance
from planetviz.model.sun import parse_time, sun_position

PARIS = (48.85, 2.35)


def picture(window):
    """The 3D view as an (h, w, 3) uint8 array, read from its render window."""
    window.refresh()
    return np.asarray(window.scene.screenshot())


def type_into(qtbot, box, text):
    box.lineEdit().selectAll()
    qtbot.keyClicks(box.lineEdit(), text)
    qtbot.keyClick(box.lineEdit(), QtCore.Qt.Key_Return)


def wait_for_tables(qtbot, window):
    qtbot.waitUntil(lambda: window.scene.precompute_progress is None and window.scene.tables is not None
                    and (window._tick() or True), timeout=180_000)
    window.refresh()


@pytest.fixture()
def window(qtbot):
    from planetviz.app.qt_window import PlanetWindow
    w = PlanetWindow("earth", quality="draft", site=PARIS, time="2026-06-21T12:00+02:00")
    qtbot.addWidget(w)
    w.resize(1280, 800)
    w.show()
    qtbot.waitExposed(w)
    wait_for_tables(qtbot, w)
    return w


def test_window(qtbot, window, tmp_path):
    w, scene = window, window.scene
    assert scene.ren_win.GetClassName() == "vtkGenericOpenGLRenderWindow" and not scene.ren_win.GetOffScreenRendering()
    assert "tables ready" in w.status_text()

    # The time: noon in Paris on the solstice (typed with its UTC offset), then 21:30 on the time slider; the
    # sun where NREL's SPA (pvlib) puts it for those instants.
    w._time_text.setText("2026-06-21T12:00+02:00")
    qtbot.keyClick(w._time_text, QtCore.Qt.Key_Return)
    noon = sun_position(*PARIS, parse_time("2026-06-21T12:00+02:00"))
    assert np.allclose((scene.sun.elevation, scene.sun.azimuth), noon, atol=1e-6)
    w._day.setValue(21 * 60 + 30)
    dusk = sun_position(*PARIS, parse_time("2026-06-21T21:30+02:00"))
    assert w._time_text.text() == "2026-06-21T21:30+02:00"
    assert np.allclose((scene.sun.elevation, scene.sun.azimuth), dusk, atol=1e-6) and dusk[0] < noon[0] - 50

    # The play button runs the clock (PLAY_STEP_MIN minutes every PLAY_TICK_MS ms) until pressed again.
    from planetviz.app.qt_window import PLAY_STEP_MIN
    before_play = w._time
    qtbot.mouseClick(w._play, QtCore.Qt.LeftButton)
    qtbot.waitUntil(lambda: w._time >= before_play + pd.Timedelta(minutes=2 * PLAY_STEP_MIN), timeout=10_000)
    qtbot.mouseClick(w._play, QtCore.Qt.LeftButton)
    stopped = w._time
    qtbot.wait(400)
    assert w._time == stopped and not w._player.isActive()

    # A parameter: the ground albedo typed in its box; the atmosphere and the picture (the ground by day from
    # orbit) change.
    w._day.setValue(12 * 60)
    before = picture(w).astype(float)
    type_into(qtbot, w._boxes["ground albedo"], "0.9")
    assert scene.atmosphere.ground_albedo == (0.9, 0.9, 0.9)
    wait_for_tables(qtbot, w)
    assert picture(w).astype(float).mean() > before.mean() + 5.0

    # A change's first frame is drawn once, by the view's paint (pyvistaqt renders at every paint: rendering
    # before it as well would draw each frame twice), and the new tables start computing after that frame.
    frames = []
    observer = scene.renderer.AddObserver("EndEvent", lambda *_: frames.append(1))
    w._poll.stop()
    type_into(qtbot, w._boxes["ground albedo"], "0.7")
    assert frames == [] and not scene._job.started
    QtWidgets.QApplication.processEvents()
    assert frames == [1]
    qtbot.waitUntil(lambda: scene._job.started, timeout=2000)
    w._poll.start()
    wait_for_tables(qtbot, w)

    # A drag turns the view with one frame per step (the VTK interactor's render asks for the paint that renders).
    w._poll.stop()
    centre = QtCore.QPoint(scene.interactor.width() // 2, scene.interactor.height() // 2)
    qtbot.mousePress(scene.interactor, QtCore.Qt.LeftButton, pos=centre)
    QtWidgets.QApplication.processEvents()
    position, frames[:] = scene.camera.position, []
    for step in range(1, 4):
        moved = QtCore.QPointF(centre.x() + 10 * step, centre.y())
        QtWidgets.QApplication.sendEvent(scene.interactor, QtGui.QMouseEvent(
            QtCore.QEvent.MouseMove, moved, moved, QtCore.Qt.NoButton, QtCore.Qt.LeftButton, QtCore.Qt.NoModifier))
        QtWidgets.QApplication.processEvents()
    qtbot.mouseRelease(scene.interactor, QtCore.Qt.LeftButton, pos=centre)
    assert frames == [1, 1, 1] and scene.camera.position != position
    scene.renderer.RemoveObserver(observer)
    w._poll.start()

    # An invalid value: g1 beyond the dataclass's limit, then a planet smaller than its atmosphere is thick.
    # Refused with the field and its range named; the atmosphere, the box and the picture stay as they were.
    atmosphere, shown = scene.atmosphere, picture(w)
    type_into(qtbot, w._boxes["Mie g1 (forward lobe)"], "1.5")
    assert "Mie g1" in w.message and f"[{LIMITS['g'][0]:g}, {LIMITS['g'][1]:g}]" in w.message
    assert scene.atmosphere is atmosphere and w._boxes["Mie g1 (forward lobe)"].value() == atmosphere.mie.g1[0]
    type_into(qtbot, w._boxes["planet radius [km]"], "40")
    assert "top_radius_m" in w.message and "allowed range" in w.message and scene.atmosphere is atmosphere
    assert np.array_equal(picture(w), shown)
    sun, site, time = scene.sun, w.site, w._time
    w._site.setText("95,0")
    qtbot.keyClick(w._site, QtCore.Qt.Key_Return)
    assert "latitude" in w.message and w.site == site and w._site.text() == "48.85,2.35"
    w._time_text.setText("the longest day")
    qtbot.keyClick(w._time_text, QtCore.Qt.Key_Return)
    assert "ISO 8601" in w.message and w._time == time and scene.sun == sun
    assert not w.set_sun_angles(elevation=float("nan")) and "elevation" in w.message
    type_into(qtbot, w._exposure, "7")
    assert "exposure" in w.message and scene.settings.exposure == 1e-4
    assert np.array_equal(picture(w), shown)

    # The probe: a click on the sky from the ground, read per pixel, against the tables' NumPy evaluator along
    # the same pixel's direction. The shader and the evaluator are twins (tests/test_stability_shader.py bounds
    # them at 0.1%); 1% leaves room for the framebuffer's float32 and the pixel-centre direction.
    w._shading.setCurrentText("pixel")
    w.camera("ground")
    width, height = scene.ren_win.GetSize()
    qtbot.mouseClick(scene.interactor, QtCore.Qt.LeftButton, pos=QtCore.QPoint(width // 2, height // 4))
    reading = w.last_reading
    assert w.last_pixel == (height // 4, width // 2) and "pixel" in w._reading.text()
    direction = scene.pixel_directions(np.array([height // 4]), np.array([width // 2]))[0]
    want = probe_directions(scene.tables, scene.atmosphere, scene.camera_location, direction[None],
                            scene.sun_direction)[0]
    assert np.allclose(reading.radiance, want.radiance, rtol=0.01), (reading.radiance, want.radiance)
    atm = scene.atmosphere
    assert np.allclose(reading.spectral_radiance, reading.radiance * star_irradiance(atm.star, atm.wavelengths_nm))
    assert reading.luminance > 0 and reading.elevation_deg > 5.0

    # The sun's vertical: at the sun's elevation, the side of the sun (Mie's forward lobe, g = 0.8) brighter than
    # the side away from it.
    qtbot.mouseClick(w._vertical_button, QtCore.Qt.LeftButton)
    angle, luminance = w.last_vertical
    assert np.all(np.isfinite(luminance)) and luminance.min() > 0
    near, away = np.interp([scene.sun.elevation + 3.0, 177.0 - scene.sun.elevation], angle, luminance)
    assert near > 1.5 * away, (near, away)

    # A preset: Mars from the combo box; the sun's place by site and time gives way to its angles there.
    w._preset.setCurrentText("mars")
    assert scene.atmosphere.name == "mars" and w._sun_by.currentText() == "elevation and azimuth"
    wait_for_tables(qtbot, w)
    w.camera("orbit")
    mars = picture(w)
    assert mars.mean() > 5.0

    # Save and open the atmosphere file; export a screenshot and an OpenEXR.
    path = tmp_path / "mine.json"
    assert w.save_atmosphere(path) and json.loads(path.read_text())["name"] == "mars"
    assert w.export("screenshot", tmp_path / "shot.png", size=(320, 200)) and (tmp_path / "shot.png").stat().st_size
    assert w.export("exr", tmp_path / "shot.exr", size=(320, 200)) and (tmp_path / "shot.exr").stat().st_size
    w.camera("ground")                     # a dome master from the ground: the sky fills its circle
    assert w.export("dome", tmp_path / "dome.png")
    from PIL import Image
    dome = np.asarray(Image.open(tmp_path / "dome.png"))
    assert dome.shape[:2] == (2048, 2048) and dome[1024, 1024].sum() > 0 and dome[0, 0].sum() == 0
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({**json.loads(path.read_text()), "bottom_radius_m": -1.0}))
    assert not w.open_atmosphere(bad) and "bottom_radius_m" in w.message and scene.atmosphere.name == "mars"
