"""Screenshots of the PyVista window (app.py --no-qt) for docs/gallery.md (needs a display: xvfb-run -a python
docs/window_screenshot.py).

The real window (not off-screen) with its widgets: Earth from orbit, then standing on the ground at sunset, then
an invalid value refused (the message at the top).
"""
import os
from pathlib import Path

os.environ.pop("VTK_DEFAULT_OPENGL_WINDOW", None)

from planetviz.app.parameters import STANDARD  # noqa: E402
from planetviz.app.window import PlanetApp  # noqa: E402
from planetviz.render import Scene  # noqa: E402

OUT = Path(__file__).resolve().parent / "img" / "gallery"

scene = Scene("earth", quality="standard", window_size=(1280, 720), off_screen=False)
app = PlanetApp(scene)
scene.show(interactive_update=True, auto_close=False)
app.set_sun(elevation=25, azimuth=120)
app.refresh()
scene.screenshot(str(OUT / "window-orbit.png"))
app.set_sun(elevation=2, azimuth=250)
app.camera_preset("ground")
app.refresh()
scene.screenshot(str(OUT / "window-ground.png"))
app.change_parameter(next(row for row in STANDARD if row.label.startswith("Mie g1")), 1.0)
app.refresh()
scene.screenshot(str(OUT / "window-refused.png"))
scene.close()
