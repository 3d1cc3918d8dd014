"""The desktop window in Qt (``python app.py``): the 3D view beside a panel of grouped controls.

The view is a :class:`QtScene`, the scene's planet in a ``pyvistaqt.QtInteractor`` (drag to turn the view, the
wheel to zoom). The panel holds, top to bottom:

- **Atmosphere**: a preset, open and save of atmosphere files (JSON), standard or advanced parameters
  (planetviz/app/parameters.py: each labelled with its unit and allowed range; a value outside it, or one that
  makes an invalid atmosphere, is refused with a message naming the field and its range and the picture keeps
  the last good atmosphere);
- **Sun**: from a site and a time on Earth (ISO 8601 with or without a UTC offset, "now", a time-of-day slider
  and a play button that runs the day) or by elevation and azimuth (the only way on other planets);
- **Camera**: orbit, limb, aircraft and ground presets looking at the site;
- **Display**: exposure, tone mapping, table quality, renderer (tables or quick view), shading, table kind;
- **Probe**: click a pixel for its radiance per wavelength, spectral radiance, luminance and linear sRGB
  (planetviz/app/probe.py), and a plot of the sky's luminance along the sun's vertical.

The File menu exports a screenshot, OpenEXR, a dome master and a panorama (rendered off-screen from the same
state at the size asked for); the status bar shows the precompute's progress while the window stays responsive
(the tables are computed in a background thread and the quick view is shown meanwhile). The window only wires:
the physics, the tables and the renderer know nothing of Qt.
"""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd
from matplotlib.backends.backend_qtagg import FigureCanvasQTAgg
from matplotlib.figure import Figure
from pyvistaqt import QtInteractor
from qtpy import QtCore, QtGui, QtWidgets
from vtkmodules.vtkCommonCore import vtkCommand

from ..model.limits import AtmosphereError
from ..model.presets import PRESETS
from ..model.sun import parse_site, parse_time, sun_position
from ..render.scene import SHADINGS, PlanetView
from ..render.uniforms import TONE_MAPPINGS
from ..tables.compact import TABLE_KINDS
from ..tables.precompute import QUALITY
from .parameters import GEOMETRY, STANDARD, advanced_parameters, apply_parameter, current_value, load_with_form
from .probe import probe_pixel, sun_vertical
from .render_options import CAMERA_PRESETS, SITE, camera_preset

#: Minutes the play button advances the clock per tick, and the tick [ms].
PLAY_STEP_MIN, PLAY_TICK_MS = 5, 100
#: Whole-sky exports' sizes [pixels]: the dome master's side, the panorama's width and height.
DOME_SIZE, PANORAMA_SIZE = 2048, (2048, 1024)
#: The exposure's range in the panel [log10 m^2/cd].
EXPOSURE_LOG10 = (-9.0, 3.0)
SUN_BY = ("site and time", "elevation and azimuth")


class QtScene(PlanetView, QtInteractor):
    """The planet, its atmosphere, the sun and the camera of :class:`~planetviz.render.Scene` in a Qt widget
    (``pyvistaqt.QtInteractor``); keywords as :class:`~planetviz.render.Scene`'s, plus ``parent``.

    >>> view = QtScene("earth", quality="draft", parent=None)   # doctest: +SKIP
    """

    def __init__(self, atmosphere="earth", parent=None, **kwargs):
        super().__init__(atmosphere, parent=parent, auto_update=False, **kwargs)
        interactor = self.iren.interactor
        interactor.EnableRenderOff()               # its Render() then only signals RenderEvent
        interactor.AddObserver(vtkCommand.RenderEvent, self._interactor_render)

    def request_frame(self):
        """Ask for a frame of the current state: drawn when Qt next paints the view (pyvistaqt renders at every
        paint, so :meth:`render`, which renders at once and then asks for a paint, draws each frame twice)."""
        self._prepare_frame()
        self.interactor.update()

    def _after_frame(self, caller=None, event=None):
        """At the end of a frame: start the background work once Qt has finished the paint (it composes the
        window after the render; work started now would compete with that)."""
        QtCore.QTimer.singleShot(0, self._start_background)

    def _interactor_render(self, caller=None, event=None):
        """The VTK interactor's render (camera drags, the view's paint): inside the paint, render; elsewhere ask
        for a paint, which renders (rendering here as well would draw every step of a drag twice)."""
        if getattr(self.interactor, "_in_paint", True):
            self.ren_win.Render()
        else:
            self.interactor.update()


class NumberBox(QtWidgets.QDoubleSpinBox):
    """A spin box that shows six significant digits and takes any number typed (the window checks it)."""

    def __init__(self, value, step=None, parent=None):
        super().__init__(parent)
        self.setRange(-1e300, 1e300)
        self.setDecimals(15)
        self.setKeyboardTracking(False)
        self.setStepType(QtWidgets.QAbstractSpinBox.AdaptiveDecimalStepType)
        if step is not None:
            self.setSingleStep(step)
        self.setValue(value)

    def textFromValue(self, value):
        return f"{value:.6g}"

    def valueFromText(self, text):
        try:
            return float(text)
        except ValueError:
            return self.value()

    def validate(self, text, pos):
        return QtGui.QValidator.Acceptable, text, pos

    def set_quietly(self, value):
        """Show ``value`` without signalling a change."""
        self.blockSignals(True)
        self.setValue(value)
        self.blockSignals(False)


def _combo(items, current, on_change):
    box = QtWidgets.QComboBox()
    box.addItems(list(items))
    box.setCurrentText(current)
    box.currentTextChanged.connect(on_change)
    return box


def _button(text, on_click):
    button = QtWidgets.QPushButton(text)
    button.clicked.connect(on_click)
    return button


class ProgressBar(QtWidgets.QWidget):
    """A bar filled to a fraction, repainted with the window's next paint. (QProgressBar.setValue repaints at
    once, and a repaint of a window that holds the OpenGL view draws a whole frame: about 90 ms on llvmpipe at
    each step of a precompute.)"""

    def __init__(self, width=160):
        super().__init__()
        self.fraction = 0.0
        self.setFixedSize(width, 14)

    def set_fraction(self, fraction):
        fraction = min(max(float(fraction), 0.0), 1.0)
        if fraction != self.fraction:
            self.fraction = fraction
            self.update()

    def paintEvent(self, event):
        painter = QtGui.QPainter(self)
        palette = self.palette()
        painter.fillRect(self.rect(), palette.color(QtGui.QPalette.Base))
        painter.fillRect(0, 0, round(self.fraction * self.width()), self.height(),
                         palette.color(QtGui.QPalette.Highlight))
        painter.end()


class PlanetWindow(QtWidgets.QMainWindow):
    """The main window around a :class:`QtScene`.

    >>> window = PlanetWindow("earth", quality="draft")   # doctest: +SKIP
    >>> window.show()                                       # doctest: +SKIP
    """

    def __init__(self, atmosphere="earth", quality="standard", method="tables", shading="auto", exposure=1e-4,
                 tone_mapping="exponential", tables="4d", site=SITE, time=None, sun=None, mode="standard",
                 atmosphere_file=None):
        super().__init__()
        self.setWindowTitle("planetviz")
        self.message = ""
        self.mode = mode
        self.site = tuple(site)
        self._file = atmosphere_file
        atm, source = load_with_form(atmosphere)
        self._remember(atm, source)
        central = QtWidgets.QSplitter(QtCore.Qt.Horizontal)
        self.scene = QtScene(atm, parent=central, quality=quality, method=method, shading=shading,
                             exposure=exposure, tone_mapping=tone_mapping, tables=tables)
        central.addWidget(self.scene.interactor)
        central.addWidget(self._panel())
        central.setStretchFactor(0, 1)
        self._show_preset(atmosphere if isinstance(atmosphere, str) and atmosphere in PRESETS else None)
        self.setCentralWidget(central)
        self._menus()
        self._status = QtWidgets.QLabel()
        self._progress = ProgressBar()
        self.statusBar().addWidget(self._status, 1)
        self.statusBar().addPermanentWidget(self._progress)
        self.scene.track_click_position(self._clicked, side="left", viewport=True)
        self._poll = QtCore.QTimer(self, interval=200, timeout=self._tick)
        self._poll.start()
        self._player = QtCore.QTimer(self, interval=PLAY_TICK_MS, timeout=self._play_step)
        self._time, self._zone = parse_time("now"), None
        if time is not None:
            self.set_time(time)
        if sun is not None or not self._is_earth():
            self.set_sun_angles(*(sun or (self.scene.sun.elevation, self.scene.sun.azimuth)))
        else:
            self._place_sun()
        self._show_time()
        self.camera("orbit")

    # -------------------------------------------------------------------------------------------- panel
    def _panel(self):
        """Tabs: the atmosphere; the sun, the camera and the display; the probe. A message line above them."""
        panel = QtWidgets.QWidget(minimumWidth=420)
        layout = QtWidgets.QVBoxLayout(panel)
        self._alert = QtWidgets.QLabel(wordWrap=True, styleSheet="color: #c0392b")
        layout.addWidget(self._alert)
        self._tabs = QtWidgets.QTabWidget()
        for title, groups in (("Atmosphere", (self._atmosphere_group(),)),
                              ("Sun and view", (self._sun_group(), self._camera_group(), self._display_group())),
                              ("Probe", (self._probe_group(),))):
            page = QtWidgets.QWidget()
            column = QtWidgets.QVBoxLayout(page)
            for group in groups:
                column.addWidget(group)
            column.addStretch(1)
            scroll = QtWidgets.QScrollArea(widgetResizable=True)
            scroll.setWidget(page)
            self._tabs.addTab(scroll, title)
        layout.addWidget(self._tabs)
        return panel

    def _atmosphere_group(self):
        group = QtWidgets.QGroupBox("Atmosphere")
        form = QtWidgets.QFormLayout(group)
        self._preset = QtWidgets.QComboBox()
        self._preset.addItems(list(PRESETS))
        self._preset.setCurrentIndex(-1)
        self._preset.setPlaceholderText("(a file)")
        self._preset.currentTextChanged.connect(self.load_preset)
        form.addRow("preset", self._preset)
        files = QtWidgets.QHBoxLayout()
        files.addWidget(_button("Open...", self._open_dialog))
        files.addWidget(_button("Save...", self._save_dialog))
        form.addRow("file (JSON)", files)
        self._mode = _combo(("standard", "advanced"), self.mode, self.set_mode)
        form.addRow("parameters", self._mode)
        self._parameters = QtWidgets.QFormLayout()
        form.addRow(self._parameters)
        self._boxes = {}
        self._fill_parameters()
        return group

    def _show_preset(self, name):
        """The preset combo shows ``name`` (None: a file's atmosphere) without loading it again."""
        self._preset.blockSignals(True)
        if name is None:
            self._preset.setCurrentIndex(-1)
        else:
            self._preset.setCurrentText(name)
        self._preset.blockSignals(False)

    def _rows(self):
        if self.mode == "standard":
            return GEOMETRY + STANDARD
        return advanced_parameters(self._source_base)

    def _form(self):
        """The file form the parameter rows read and write: the atmosphere's own (standard) or the file's."""
        return self.scene.atmosphere.to_dict() if self.mode == "standard" else self._source

    def _fill_parameters(self):
        while self._parameters.rowCount():
            self._parameters.removeRow(0)
        self._boxes = {}
        form = self._form()
        for row in self._rows():
            value = current_value(row, form, self._base)
            if value is None:
                continue                                # not in this atmosphere's form
            lo, hi = row.allowed_range(self._base)
            box = NumberBox(value)
            box.setToolTip(f"{row.label}: allowed {lo:g} to {hi:g}" if np.isfinite([lo, hi]).all()
                           else f"{row.label}: its range is the atmosphere file reader's")
            box.valueChanged.connect(lambda v, row=row: self.set_parameter(row.label, v))
            self._parameters.addRow(row.label, box)
            self._boxes[row.label] = box

    def _sun_group(self):
        group = QtWidgets.QGroupBox("Sun")
        form = QtWidgets.QFormLayout(group)
        self._sun_by = _combo(SUN_BY, SUN_BY[0], lambda _: self._place_sun())
        form.addRow("placed by", self._sun_by)
        self._site = QtWidgets.QLineEdit(f"{self.site[0]:g},{self.site[1]:g}")
        self._site.editingFinished.connect(lambda: self.set_site(self._site.text()))
        form.addRow("site LAT,LON [deg]", self._site)
        self._time_text = QtWidgets.QLineEdit()
        self._time_text.editingFinished.connect(lambda: self.set_time(self._time_text.text()))
        form.addRow("time (ISO 8601)", self._time_text)
        self._day = QtWidgets.QSlider(QtCore.Qt.Horizontal, minimum=0, maximum=24 * 60 - 1)
        self._day.valueChanged.connect(self.set_time_of_day)
        form.addRow("time of day", self._day)
        buttons = QtWidgets.QHBoxLayout()
        buttons.addWidget(_button("now", lambda: self.set_time("now")))
        self._play = _button("play the day", lambda: self.play(not self._player.isActive()))
        buttons.addWidget(self._play)
        form.addRow(buttons)
        self._elevation, self._azimuth = NumberBox(30.0, step=1.0), NumberBox(135.0, step=1.0)
        self._elevation.valueChanged.connect(lambda v: self.set_sun_angles(elevation=v))
        self._azimuth.valueChanged.connect(lambda v: self.set_sun_angles(azimuth=v))
        form.addRow("elevation [deg]", self._elevation)
        form.addRow("azimuth [deg from N]", self._azimuth)
        return group

    def _camera_group(self):
        group = QtWidgets.QGroupBox("Camera (drag to look around, wheel to zoom)")
        row = QtWidgets.QHBoxLayout(group)
        for name in CAMERA_PRESETS:
            row.addWidget(_button(name, lambda _=False, n=name: self.camera(n)))
        return group

    def _display_group(self):
        group = QtWidgets.QGroupBox("Display")
        form = QtWidgets.QFormLayout(group)
        self._exposure = NumberBox(-4.0, step=0.1)
        self._exposure.valueChanged.connect(lambda v: self.set_exposure(10.0 ** v if np.isfinite(v) else v))
        form.addRow("exposure log10 [m^2/cd]", self._exposure)
        self._tone = _combo(TONE_MAPPINGS, "exponential", lambda v: self._display(tone_mapping=v))
        form.addRow("tone mapping", self._tone)
        self._quality = _combo(QUALITY, "standard", lambda v: self._display(quality=v))
        form.addRow("table quality", self._quality)
        self._method = _combo(("tables", "quick"), self.scene.renderer_in_use, lambda v: self._display(method=v))
        form.addRow("renderer", self._method)
        self._shading = _combo(SHADINGS, self.scene.shading, lambda v: self._display(shading=v))
        form.addRow("shading", self._shading)
        self._table_kind = _combo(TABLE_KINDS, "4d", lambda v: self._display(tables=v))
        form.addRow("tables", self._table_kind)
        return group

    def _probe_group(self):
        group = QtWidgets.QGroupBox("Probe (click the picture)")
        layout = QtWidgets.QVBoxLayout(group)
        self._reading = QtWidgets.QLabel("click a pixel", wordWrap=True,
                                         textInteractionFlags=QtCore.Qt.TextSelectableByMouse)
        self._reading.setFont(QtGui.QFontDatabase.systemFont(QtGui.QFontDatabase.FixedFont))
        layout.addWidget(self._reading)
        self.figure = Figure(figsize=(3.8, 4.2), tight_layout=True)
        self._spectrum_axes, self._vertical_axes = self.figure.subplots(2, 1)
        self._canvas = FigureCanvasQTAgg(self.figure)
        self._canvas.setMinimumHeight(320)
        layout.addWidget(self._canvas)
        self._vertical_button = _button("plot the sun's vertical", self.plot_sun_vertical)
        layout.addWidget(self._vertical_button)
        self.last_reading = self.last_pixel = self.last_vertical = None
        return group

    def _menus(self):
        menu = self.menuBar().addMenu("&File")
        for text, slot in (("Open atmosphere...", self._open_dialog), ("Save atmosphere...", self._save_dialog)):
            menu.addAction(text, slot)
        menu.addSeparator()
        for kind, text, pattern in (("screenshot", "Export screenshot...", "PNG (*.png)"),
                                    ("exr", "Export OpenEXR...", "OpenEXR (*.exr)"),
                                    ("dome", "Export dome master...", "PNG or OpenEXR (*.png *.exr)"),
                                    ("panorama", "Export panorama...", "PNG or OpenEXR (*.png *.exr)")):
            menu.addAction(text, lambda k=kind, p=pattern: self._export_dialog(k, p))
        menu.addSeparator()
        menu.addAction("Quit", self.close)

    # ------------------------------------------------------------------------------------- atmosphere
    def _remember(self, atm, source):
        self._atmosphere = atm
        self._base, self._source, self._source_base = atm.to_dict(), source, json.loads(json.dumps(source))

    def _show_atmosphere(self, atm, source):
        self._remember(atm, source)
        self.scene.set_atmosphere(atm)
        if self._sun_by.currentText() == SUN_BY[0] and not self._is_earth():
            self._sun_by.setCurrentText(SUN_BY[1])
        self._fill_parameters()
        self.refuse("")
        self.refresh()

    def load_preset(self, name):
        """Show the preset ``name``."""
        try:
            atm, source = load_with_form(name)
        except (AtmosphereError, ValueError, OSError) as exc:
            return self.refuse(f"{name}: {exc}")
        self._show_atmosphere(atm, source)
        return True

    def open_atmosphere(self, path):
        """Show the atmosphere file at ``path``; an invalid file is refused with a message, the picture stays."""
        try:
            if not Path(path).is_file():
                raise OSError(f"no such file: {path}")
            atm, source = load_with_form(Path(path))
        except (AtmosphereError, ValueError, OSError) as exc:
            return self.refuse(f"{path}: {exc}")
        self._file = str(path)
        self._show_preset(None)
        self._show_atmosphere(atm, source)
        return True

    def save_atmosphere(self, path):
        """Write the atmosphere shown, in its file form, to ``path`` (JSON)."""
        Path(path).write_text(json.dumps(self._source, indent=2))
        self.statusBar().showMessage(f"saved {path}", 5000)
        return True

    def set_parameter(self, label, value):
        """Set the parameter row ``label`` to ``value``; refused with a message (the field and its range) when
        invalid, the atmosphere and the picture kept."""
        row = next((r for r in self._rows() if r.label == label), None)
        if row is None:
            return self.refuse(f"{label}: no such parameter in {self.mode} mode")
        try:
            atm, source = apply_parameter(row, self._form(), self._base, value)
        except (AtmosphereError, ValueError, KeyError, TypeError) as exc:
            box = self._boxes.get(label)
            if box is not None:
                box.set_quietly(current_value(row, self._form(), self._base))
            return self.refuse(f"{label} = {value:.6g} refused: {exc}")
        self._atmosphere, self._source = atm, source    # the "x" rows keep scaling the loaded atmosphere
        if self._boxes.get(label) is not None:
            self._boxes[label].set_quietly(float(value))
        self.scene.set_atmosphere(atm)
        self.refuse("")
        self.refresh()
        return True

    def set_mode(self, mode):
        self.mode = mode
        self._fill_parameters()

    # -------------------------------------------------------------------------------------------- sun
    def _is_earth(self):
        return "earth" in self._atmosphere.name.lower()

    def set_site(self, text):
        """The site ``LAT,LON`` [deg] the sun is seen from and the camera presets look at."""
        try:
            self.site = parse_site(text)
        except ValueError as exc:
            self._site.setText(f"{self.site[0]:g},{self.site[1]:g}")
            return self.refuse(str(exc))
        self._place_sun()
        return True

    def set_time(self, text):
        """The date and time (ISO 8601, with or without a UTC offset; ``now``)."""
        try:
            self._time = parse_time(text)
        except ValueError as exc:
            self._show_time()
            return self.refuse(str(exc))
        self._zone = None if str(text).strip().lower() == "now" else pd.Timestamp(text).tzinfo    # its UTC offset
        self._show_time()
        self._place_sun()
        return True

    def set_time_of_day(self, minutes):
        """The time of day [minutes after midnight in the time's zone], the date kept."""
        local = self._local_time()
        midnight = local.normalize()
        self._time = (midnight + pd.Timedelta(minutes=int(minutes))).tz_convert("UTC")
        self._show_time()
        self._place_sun()

    def _local_time(self):
        return self._time.tz_convert(self._zone or "UTC")

    def _show_time(self):
        local = self._local_time()
        self._time_text.setText(local.isoformat(timespec="minutes"))
        self._day.blockSignals(True)
        self._day.setValue(local.hour * 60 + local.minute)
        self._day.blockSignals(False)

    def play(self, on=True):
        """Run the clock (``PLAY_STEP_MIN`` minutes every ``PLAY_TICK_MS`` ms) or stop it."""
        if on and self._sun_by.currentText() != SUN_BY[0]:
            self._sun_by.setCurrentText(SUN_BY[0])
        (self._player.start if on else self._player.stop)()
        self._play.setText("pause" if on else "play the day")

    def _play_step(self):
        self._time = self._time + pd.Timedelta(minutes=PLAY_STEP_MIN)
        self._show_time()
        self._place_sun()

    def _place_sun(self):
        """Put the sun where the site and the time say (Earth), or keep its angles, seen from the site."""
        by_time = self._sun_by.currentText() == SUN_BY[0]
        if by_time and not self._is_earth():
            self._sun_by.setCurrentText(SUN_BY[1])
            self.refuse(f"the sun from a site and a time is Earth's; {self._atmosphere.name}: elevation and azimuth")
            by_time = False
        for widget in (self._time_text, self._day, self._play):
            widget.setEnabled(by_time)
        self._elevation.setReadOnly(by_time)
        self._azimuth.setReadOnly(by_time)
        sun = self.scene.sun
        elevation, azimuth = (sun_position(*self.site, self._time) if by_time else (sun.elevation, sun.azimuth))
        self.scene.set_sun(elevation=elevation, azimuth=azimuth, latitude=self.site[0], longitude=self.site[1])
        self._elevation.set_quietly(self.scene.sun.elevation)
        self._azimuth.set_quietly(self.scene.sun.azimuth)
        self.refresh()

    def set_sun_angles(self, elevation=None, azimuth=None):
        """The sun's elevation and azimuth [deg] seen from the site; refused with a message when invalid."""
        if self._sun_by.currentText() == SUN_BY[0]:
            self._sun_by.setCurrentText(SUN_BY[1])
        try:
            self.scene.set_sun(elevation=elevation, azimuth=azimuth, latitude=self.site[0], longitude=self.site[1])
        except ValueError as exc:
            self._elevation.set_quietly(self.scene.sun.elevation)
            self._azimuth.set_quietly(self.scene.sun.azimuth)
            return self.refuse(f"sun refused: {exc}")
        self._elevation.set_quietly(self.scene.sun.elevation)
        self._azimuth.set_quietly(self.scene.sun.azimuth)
        self.refuse("")
        self.refresh()
        return True

    # ------------------------------------------------------------------------------- camera and display
    def camera(self, name):
        """A camera preset (``CAMERA_PRESETS``) looking at the site."""
        camera_preset(self.scene, name, self.site)
        self.refresh()

    def set_exposure(self, value):
        """The exposure [m^2/cd]: a positive finite number, else refused."""
        if not (np.isfinite(value) and value > 0) or not (EXPOSURE_LOG10[0] <= np.log10(value) <= EXPOSURE_LOG10[1]):
            self._exposure.set_quietly(np.log10(self.scene.settings.exposure))
            return self.refuse(f"exposure: 10^{EXPOSURE_LOG10[0]:g} to 10^{EXPOSURE_LOG10[1]:g} m^2/cd, "
                               f"got {value!r}")
        self.scene.settings.exposure = float(value)
        self.refresh()
        return True

    def _display(self, tone_mapping=None, quality=None, method=None, shading=None, tables=None):
        s = self.scene
        if tone_mapping is not None:
            s.settings.tone_mapping = tone_mapping
        if quality is not None:
            s.set_quality(quality)
        if method is not None:
            s.set_method(method)
        if shading is not None:
            s.set_shading(shading)
        if tables is not None:
            s.set_table_kind(tables)
        self.refresh()

    # ------------------------------------------------------------------------------------------- probe
    def _clicked(self, position):
        """A click without a drag at ``position``: the render window's pixel (x, y from the bottom left)."""
        w, h = self.scene.ren_win.GetSize()
        x, y = position
        self.probe(int(np.clip(h - 1 - round(y), 0, h - 1)), int(np.clip(round(x), 0, w - 1)))

    def probe(self, row, col):
        """Read the pixel (``row`` from the top, ``col``) and show it in the panel and its plot."""
        reading = probe_pixel(self.scene, row, col)
        self.refresh()              # the window's own frame again after the float passes, before anything else
        self.last_reading, self.last_pixel = reading, (row, col)
        self._reading.setText("\n".join([f"pixel ({row}, {col})", *reading.lines()]))
        ax = self._spectrum_axes
        ax.clear()
        ax.plot(reading.wavelengths_nm, reading.spectral_radiance, "o-")
        ax.set_xlabel("wavelength [nm]")
        ax.set_ylabel("W m$^{-2}$ sr$^{-1}$ nm$^{-1}$")
        ax.set_title(f"pixel ({row}, {col}): {reading.luminance:.4g} cd/m$^2$", fontsize=9)
        self._canvas.draw_idle()
        return reading

    def plot_sun_vertical(self):
        """Plot the sky's luminance along the sun's vertical from the camera (or the ground below it)."""
        tables = self.scene.tables
        if tables is None:
            return self.refuse("the sun's vertical reads the tables: wait until they are computed")
        s = self.scene
        angle, luminance, at = sun_vertical(tables, s.atmosphere, s.camera_location, s.sun_direction)
        self.last_vertical = (angle, luminance)
        ax = self._vertical_axes
        ax.clear()
        ax.semilogy(angle, np.maximum(luminance, 1e-12))
        ax.set_xlabel("from the horizon below the sun (zenith at 90) [deg]", fontsize=8)
        ax.set_ylabel("luminance [cd/m$^2$]")
        altitude = np.linalg.norm(at) - s.atmosphere.bottom_radius_m
        ax.set_title(f"the sun's vertical, seen {altitude:.4g} m up", fontsize=9)
        self._canvas.draw_idle()
        return True

    # ------------------------------------------------------------------------------------------ export
    def export(self, kind, path, size=(1920, 1080)):
        """Write the current view: ``kind`` "screenshot" (PNG), "exr" (OpenEXR, linear), "dome" (a dome master,
        PNG or OpenEXR) or "panorama"; rendered off-screen from the window's state at ``size``."""
        from ..render import Scene
        from .sky_images import SkyImage, write_sky_image
        s = self.scene
        cam = s.renderer.GetActiveCamera()
        shot = Scene(s.atmosphere, quality=s.quality, method="tables" if s.tables is not None else "quick",
                     shading="pixel", exposure=s.settings.exposure, tone_mapping=s.settings.tone_mapping,
                     tables=s.table_kind, off_screen=True, window_size=size)
        try:
            shot.set_sun(**vars(s.sun))
            position = np.array(cam.GetPosition())
            shot.set_view(position, np.array(cam.GetFocalPoint()) - position, up=cam.GetViewUp(),
                          fov=cam.GetViewAngle())
            if kind == "screenshot":
                shot.screenshot(str(path))
            elif kind == "exr":
                shot.render_hdr(str(path))
            elif kind in ("dome", "panorama"):
                width, height = (DOME_SIZE, DOME_SIZE) if kind == "dome" else PANORAMA_SIZE
                write_sky_image(shot, SkyImage(str(path), "fisheye" if kind == "dome" else "panorama", width, height,
                                               heading_deg=s.sun.azimuth))
            else:
                raise ValueError(f"export: screenshot, exr, dome or panorama, got {kind!r}")
        finally:
            shot.close()
        self.statusBar().showMessage(f"wrote {path}", 5000)
        return True

    def _export_dialog(self, kind, pattern):
        path, _ = QtWidgets.QFileDialog.getSaveFileName(self, f"Export {kind}", "", pattern)
        if path:
            self.export(kind, path)

    def _open_dialog(self):
        path, _ = QtWidgets.QFileDialog.getOpenFileName(self, "Open atmosphere", "", "JSON (*.json)")
        if path:
            self.open_atmosphere(path)

    def _save_dialog(self):
        path, _ = QtWidgets.QFileDialog.getSaveFileName(self, "Save atmosphere", "", "JSON (*.json)")
        if path:
            self.save_atmosphere(path)

    # ------------------------------------------------------------------------------------------ status
    def refuse(self, text):
        """Show ``text`` as the panel's message (empty: clear it); returns False for the refusing caller."""
        self.message = text
        self._alert.setText(text)
        self._alert.setVisible(bool(text))
        return False

    def status_text(self):
        s = self.scene
        job = s.precompute_progress
        tables = f"tables: {job[0]} {100 * job[1]:.0f}%" if job else \
            (f"tables failed: {s.table_error}" if s.table_error else "tables ready")
        sun = s.sun
        shown = f"{s.renderer_in_use}{' (draft)' if s.showing_draft else ''}"
        return (f"{s.atmosphere.name} | {shown} (per {s.shading}) | {tables} | {s.quality} | "
                f"sun {sun.elevation:.2f} deg, azimuth {sun.azimuth:.1f} deg")

    def refresh(self):
        """Update the status bar and ask for a frame."""
        self._show_status()
        self.scene.request_frame()

    def _show_status(self):
        self._status.setText(self.status_text())
        self._shading.blockSignals(True)
        self._shading.setCurrentText(self.scene.shading)           # "auto" settles after the first frame
        self._shading.blockSignals(False)
        job = self.scene.precompute_progress
        self._progress.setVisible(job is not None)
        if job is not None:
            self._progress.set_fraction(job[1])

    def _tick(self):
        """Timer: render when finished background work changes the picture, else only the status bar (a frame
        on a software OpenGL takes the CPU the precompute needs)."""
        if self.scene.collect():
            self.refresh()
        else:
            self._show_status()

    def closeEvent(self, event):
        self._poll.stop()
        self._player.stop()
        self.scene.close()
        super().closeEvent(event)


def run_qt(**keywords):
    """Open the Qt window (keywords as :class:`PlanetWindow`'s) and run until it is closed."""
    app = QtWidgets.QApplication.instance() or QtWidgets.QApplication([])
    window = PlanetWindow(**keywords)
    window.resize(1440, 860)
    window.show()
    return app.exec()
