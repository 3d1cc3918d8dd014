"""The Qt window's responsiveness: the time from a parameter change (the ground albedo typed) to its first frame
on screen, the longest the event loop waits while the new tables are computed in the background, and the time
and the frames per step of a mouse drag that turns the view.

    xvfb-run -a -s "-screen 0 1600x1000x24" python benchmarks/window_latency.py [--changes 3] [--drag 20]

Standard tables of Earth, the window 1600x900 (the view about 1150x850), the sun from a site and a time. The
change to the first frame: from the typed value to the end of the render window's frame, buffers swapped (the
frame on screen: Scene.set_atmosphere with the quick view, single scattering first; the status bar; the render),
and to the end of the event processing in which the view's paint drew it (what Qt paints after it, and the start
of the background work); then the time to the draft tables shown (they stand in while the standard ones are
computed) and to the standard tables.
"""
import argparse
import os
import time

os.environ.pop("VTK_DEFAULT_OPENGL_WINDOW", None)      # a real window (the OSMesa class cannot be embedded)

from qtpy import QtCore, QtGui, QtWidgets  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--changes", type=int, default=3)
    ap.add_argument("--drag", type=int, default=20, help="steps of the mouse drag")
    args = ap.parse_args()
    app = QtWidgets.QApplication([])
    from planetviz.app.qt_window import PlanetWindow
    window = PlanetWindow("earth", quality="standard", site=(45.0, 0.0), time="2026-06-21T10:00Z")
    window.resize(1600, 900)
    window.show()
    for _ in range(20):
        app.processEvents()
        time.sleep(0.02)
    window.scene.wait_for_tables()
    window.refresh()
    scene = window.scene
    print(f"view {scene.ren_win.GetSize()}, {scene.gl_renderer}, tables per {scene.shading}")
    frames, shown = [], []
    scene.renderer.AddObserver("EndEvent", lambda *_: frames.append(time.perf_counter()))
    scene.ren_win.AddObserver("EndEvent", lambda *_: shown.append(time.perf_counter()))
    print("| change | to the frame on screen, ms | to the end of that event processing, ms | longest event-loop wait "
          "while the tables compute, ms | draft tables shown, s | tables, s |")
    print("|---|---|---|---|---|---|")
    for k in range(args.changes):
        albedo = 0.35 + 0.05 * k
        frames.clear()
        shown.clear()
        t0 = time.perf_counter()
        window.set_parameter("ground albedo", albedo)
        while not frames:                             # the paint that draws the new frame
            app.processEvents()
        app.processEvents()                           # and what Qt does after it (the window's composition)
        first = 1e3 * (time.perf_counter() - t0)
        on_screen = 1e3 * (shown[0] - t0)
        last = start = time.perf_counter()
        longest, draft = 0.0, None
        while scene.precompute_progress is not None or scene.quick_pending:
            app.processEvents(QtCore.QEventLoop.AllEvents, 10)
            now = time.perf_counter()
            longest, last = max(longest, now - last), now
            if draft is None and scene.showing_draft:
                draft = now - t0
            time.sleep(0.005)
        draft_cell = "-" if draft is None else f"{draft:.1f}"
        print(f"| albedo {albedo:.2f} | {on_screen:.0f} | {first:.0f} | {1e3 * longest:.0f} | {draft_cell} | "
              f"{time.perf_counter() - t0:.1f} |", flush=True)
    drag(app, scene, frames, args.drag)
    window.close()


def drag(app, scene, frames, steps):
    """A left-button drag across the view, one 5-pixel move per step, each step's events processed in full."""
    view = scene.interactor
    centre = QtCore.QPointF(view.width() / 2, view.height() / 2)
    view.mousePressEvent(QtGui.QMouseEvent(QtCore.QEvent.MouseButtonPress, centre, centre, QtCore.Qt.LeftButton,
                                           QtCore.Qt.LeftButton, QtCore.Qt.NoModifier))
    app.processEvents()
    frames.clear()
    t0 = time.perf_counter()
    for k in range(1, steps + 1):
        moved = QtCore.QPointF(centre.x() + 5 * k, centre.y())
        app.sendEvent(view, QtGui.QMouseEvent(QtCore.QEvent.MouseMove, moved, moved, QtCore.Qt.NoButton,
                                              QtCore.Qt.LeftButton, QtCore.Qt.NoModifier))
        app.processEvents()
    per_step = 1e3 * (time.perf_counter() - t0) / steps
    print(f"\ndrag: {per_step:.0f} ms and {len(frames) / steps:.1f} frames per step ({steps} steps)")


if __name__ == "__main__":
    main()
