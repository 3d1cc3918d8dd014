"""Drives the planetviz window as a user would (run by tests/test_app.py under Xvfb, never on its own).

Opens the real window (X11, no off-screen rendering), drags the ground-albedo slider with mouse events, drags the
Mie g1 slider to 1 (an invalid value), presses keys, and writes what it saw to the JSON file named on the command
line, with screenshots next to it.
"""
import json
import sys
from pathlib import Path

import numpy as np

from planetviz.app.window import PlanetApp
from planetviz.model.presets import PRESETS
from planetviz.render import Scene


def drag(scene, widget, value):
    """What a user does: aim at the slider's handle, press, move the mouse along the tube pixel by pixel while
    watching the value, release when it reads ``value`` or the handle stops at the end of the tube. A press
    that misses the handle (the value does not follow the mouse) is released and aimed again nearby."""
    rep = widget.GetRepresentation()
    w, h = scene.ren_win.GetSize()
    p1 = np.array(rep.GetPoint1Coordinate().GetValue()[:2]) * [w, h]
    p2 = np.array(rep.GetPoint2Coordinate().GetValue()[:2]) * [w, h]
    lo, hi = rep.GetMinimumValue(), rep.GetMaximumValue()
    y = int(round(p1[1]))
    iren = scene.iren.interactor
    guess = int(round(p1[0] + (p2[0] - p1[0]) * (rep.GetValue() - lo) / (hi - lo)))
    step = 1 if value > rep.GetValue() else -1
    for offset in (0, -4, 4, -8, 8, -12, 12, -16, 16):
        x = guess + offset
        iren.SetEventInformation(x, y)
        iren.MouseMoveEvent()
        iren.LeftButtonPressEvent()
        start = rep.GetValue()
        for _ in range(3):
            x += step
            iren.SetEventInformation(x, y)
            iren.MouseMoveEvent()
        if rep.GetValue() != start:
            break
        iren.LeftButtonReleaseEvent()
    else:
        raise AssertionError("could not grab the slider's handle")
    end = int(p2[0]) + 8 if step > 0 else int(p1[0]) - 8
    while x != end and (rep.GetValue() < value if step > 0 else rep.GetValue() > value):
        x += step
        iren.SetEventInformation(x, y)
        iren.MouseMoveEvent()
    iren.LeftButtonReleaseEvent()


def press(scene, key):
    iren = scene.iren.interactor
    iren.SetKeyEventInformation(0, 0, key if len(key) == 1 else "\0", 0, key)
    iren.KeyPressEvent()
    iren.CharEvent()
    iren.KeyReleaseEvent()


def main(out):
    out = Path(out)
    atmosphere_file = out.with_name("my-planet.json")
    atmosphere_file.write_text(PRESETS["earth"].read_text())
    scene = Scene(str(atmosphere_file), quality="draft", window_size=(480, 300), off_screen=False, shading="auto")
    app = PlanetApp(scene, atmosphere_file=atmosphere_file)
    scene.show(interactive_update=True, auto_close=False)
    result = {"window": scene.ren_win.GetClassName(), "off_screen": bool(scene.ren_win.GetOffScreenRendering())}
    app.camera_preset("ground")
    app.refresh()
    app.refresh()                                       # "auto" shading is settled at the frame after the first
    result["gl_renderer"], result["shading_auto"] = scene.gl_renderer, scene.shading
    press(scene, "h")
    result["shading_after_h"] = scene.shading
    press(scene, "h")
    before = scene.screenshot(str(out.with_name("window-before.png")))
    drag(scene, app.sliders["ground albedo"], 0.9)
    scene.wait_for_tables(120)
    app.refresh()
    after = scene.screenshot(str(out.with_name("window-albedo.png")))
    result["albedo"] = float(scene.atmosphere.ground_albedo[0])
    result["albedo_change"] = float(np.abs(after.astype(float) - before).mean())
    # The slider's range is the dataclass's: dragged to the end of its tube, g1 reaches the largest legal g.
    drag(scene, app.sliders["Mie g1 (forward lobe)"], 1.0)
    scene.wait_for_tables(120)
    app.refresh()
    after = scene.screenshot(str(out.with_name("window-g1.png")))
    result["g1_slider"] = app.sliders["Mie g1 (forward lobe)"].GetRepresentation().GetValue()
    result["g1_after"] = float(scene.atmosphere.mie.g1[0])
    # The file edited by hand with a negative radius, then reloaded (F6): refused, named, nothing changes.
    good = scene.atmosphere
    data = json.loads(atmosphere_file.read_text())
    data["bottom_radius_m"] = -5.0
    atmosphere_file.write_text(json.dumps(data))
    press(scene, "F6")
    app.refresh()
    refused = scene.screenshot(str(out.with_name("window-refused.png")))
    result["file_message"] = app.message
    result["file_refused_kept"] = scene.atmosphere is good
    h = refused.shape[0]
    # The picture between the message line (drawn at the top edge) and the status line (the bottom edge, with
    # the last frame's time): unchanged.
    result["picture_change_after_refusal"] = float(np.abs(refused[h // 5:-h // 10].astype(float)
                                                          - after[h // 5:-h // 10]).mean())
    press(scene, "F2")                                      # the Mars preset
    app.refresh()
    scene.screenshot(str(out.with_name("window-mars.png")))
    result["after_key_F2"] = scene.atmosphere.name
    result["status"] = app.status_text()
    out.write_text(json.dumps(result))
    scene.close()


if __name__ == "__main__":
    main(sys.argv[1])
