"""A screenshot of the Qt window for the README (needs a display: xvfb-run -a -s "-screen 0 1600x1000x24"
python docs/qt_window_screenshot.py).

Earth seen from the ground in Paris at 20:45 on the summer solstice (the site and time typed in the panel), a
pixel of the sky probed and the sun's vertical plotted.
"""
import os
from pathlib import Path

os.environ.pop("VTK_DEFAULT_OPENGL_WINDOW", None)

from qtpy import QtWidgets  # noqa: E402

from planetviz.app.qt_window import PlanetWindow  # noqa: E402

OUT = Path(__file__).resolve().parent / "img" / "gallery" / "qt-window.png"

app = QtWidgets.QApplication([])
window = PlanetWindow("earth", quality="standard", site=(48.85, 2.35), time="2026-06-21T20:45+02:00")
window.resize(1560, 940)
window.show()
window.scene.wait_for_tables()
window.camera("ground")
window.scene.view_from_ground(latitude=48.85, longitude=2.35, heading=window.scene.sun.azimuth - 20.0, pitch=10.0,
                              fov=70.0)
window._tabs.setCurrentIndex(2)
for _ in range(20):
    app.processEvents()
width, height = window.scene.ren_win.GetSize()
window.probe(height // 3, width // 4)
window.plot_sun_vertical()
for _ in range(20):
    app.processEvents()
window.grab().save(str(OUT))
print(f"wrote {OUT}")
window.close()
