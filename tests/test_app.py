"""The desktop app: the real window under Xvfb driven with mouse and key events, and the off-screen command line."""
import ctypes
import ctypes.util
import json
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from planetviz.model.limits import LIMITS

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture()
def xvfb():
    """A virtual X display started by the test itself (scripts/test.sh installs Xvfb)."""
    exe = shutil.which("Xvfb")
    assert exe, "Xvfb is missing: scripts/test.sh installs it (apt package xvfb)"
    # Xvfb picks a free display number itself and writes it to the pipe once it accepts connections (two test
    # processes may start one at the same time).
    read_end, write_end = os.pipe()
    proc = subprocess.Popen([exe, "-displayfd", str(write_end), "-screen", "0", "1024x768x24", "-nolisten", "tcp"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, pass_fds=(write_end,))
    os.close(write_end)
    with os.fdopen(read_end) as pipe:
        display = pipe.readline().strip()
    assert display, f"Xvfb did not start (exit status {proc.poll()})"
    assert _accepts_clients(f":{display}"), f"Xvfb's display :{display} refuses clients for 10 s"
    yield f":{display}"
    proc.terminate()
    proc.wait(10)


def _accepts_clients(display, seconds=10.0):
    """Whether an X client can open ``display`` within ``seconds`` (libX11's XOpenDisplay): where it cannot, VTK's
    render window factory falls back to EGL without saying so, and the window test would read that instead."""
    x11 = ctypes.CDLL(ctypes.util.find_library("X11"))
    x11.XOpenDisplay.restype = ctypes.c_void_p
    x11.XOpenDisplay.argtypes = [ctypes.c_char_p]
    x11.XCloseDisplay.argtypes = [ctypes.c_void_p]
    deadline = time.monotonic() + seconds
    while True:
        handle = x11.XOpenDisplay(display.encode())
        if handle:
            x11.XCloseDisplay(handle)
            return True
        if time.monotonic() > deadline:
            return False
        time.sleep(0.1)


def test_the_window_opens_responds_to_widgets_and_refuses_invalid_values(xvfb, tmp_path):
    env = {k: v for k, v in os.environ.items() if k != "VTK_DEFAULT_OPENGL_WINDOW"}
    env["DISPLAY"] = xvfb
    out = tmp_path / "result.json"
    proc = subprocess.run([sys.executable, str(ROOT / "tests" / "gui" / "drive_window.py"), str(out)], env=env,
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr[-3000:]
    r = json.loads(out.read_text())
    assert r["window"] == "vtkXOpenGLRenderWindow" and not r["off_screen"]      # a real X11 window
    # Xvfb's OpenGL is Mesa's llvmpipe: "auto" shading reads the tables per vertex there; h toggles it.
    assert "llvmpipe" in r["gl_renderer"] and r["shading_auto"] == "vertex" and r["shading_after_h"] == "pixel"
    # Dragging the albedo slider from 0.1 toward 0.9 (the mouse lands within a few pixels of the mark) changes
    # the atmosphere and the picture: the ground gets brighter.
    assert r["albedo"] > 0.8 and r["albedo_change"] > 5.0
    # The g1 slider ends where the dataclass's limit does (one source of truth): dragged to its end, g1 = 0.999.
    assert r["g1_slider"] == LIMITS["g"][1] and r["g1_after"] == LIMITS["g"][1]
    # A hand-edited file with an invalid field, reloaded: refused with the field named, the scene unchanged.
    assert "bottom_radius_m" in r["file_message"] and r["file_refused_kept"]
    assert r["picture_change_after_refusal"] < 0.5
    assert r["after_key_F2"] == "mars"
    assert "renderer:" in r["status"]


def test_the_qt_window_under_xvfb(xvfb, tmp_path):
    # The Qt window driven through its widgets with pytest-qt (tests/gui/qt_window_checks.py holds the steps and
    # what each must change) in a process of its own on the virtual display.
    env = {k: v for k, v in os.environ.items() if k != "VTK_DEFAULT_OPENGL_WINDOW"}
    env["DISPLAY"] = xvfb
    proc = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "--basetemp",
                           str(tmp_path / "qt"), str(ROOT / "tests" / "gui" / "qt_window_checks.py")],
                          cwd=ROOT, env=env, capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stdout[-4000:] + proc.stderr[-2000:]


def run_app(*args, cwd):
    env = dict(os.environ, VTK_DEFAULT_OPENGL_WINDOW="vtkOSOpenGLRenderWindow")
    return subprocess.run([sys.executable, str(ROOT / "app.py"), *args], cwd=cwd, env=env, capture_output=True,
                          text=True, timeout=600)


def test_off_screen_screenshot_exr_and_invalid_values(tmp_path):
    import OpenEXR
    proc = run_app("--preset", "mars", "--view", "ground", "--sun-elevation", "3", "--sun-azimuth", "0", "--size",
                   "160x90", "--quality", "draft", "--screenshot", "out.png", "--exr", "out.exr", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert (tmp_path / "out.png").stat().st_size > 1000
    with OpenEXR.File(str(tmp_path / "out.exr"), separate_channels=True) as f:
        assert f.channels()["R"].pixels.shape == (90, 160)
    bad = run_app("--preset", "mars", "--sun-elevation", "120", "--screenshot", "x.png", "--quality", "draft",
                  cwd=tmp_path)
    assert bad.returncode == 2 and "sun elevation: [-90, 90] deg" in bad.stderr and "Traceback" not in bad.stderr


def test_batch_sweep_dome_and_panorama(tmp_path):
    import OpenEXR
    proc = run_app("--quality", "draft", "--view", "ground", "--size", "64x36", "--sweep-sun", "-4", "4", "4",
                   "--screenshot", "frames/sun.png", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert sorted(p.name for p in (tmp_path / "frames").iterdir()) == ["sun.manifest.json", "sun_0000.png",
                                                                       "sun_0001.png", "sun_0002.png"]
    assert "sun sweep [" in proc.stdout
    proc = run_app("--quality", "draft", "--view", "ground", "--size", "64x36", "--sun-elevation", "20",
                   "--fisheye", "dome.exr", "--fisheye-size", "64", "--panorama", "sky.exr", "--panorama-size",
                   "64x32", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    with OpenEXR.File(str(tmp_path / "sky.exr"), separate_channels=True) as f:
        sky = f.channels()["G"].pixels
    # Equirectangular: the upper half (sky) lit, the lower half the ground seen from 1.7 m (lit, darker).
    assert sky.shape == (32, 64) and sky[:16].mean() > 0 and sky[16:].mean() > 0
    with OpenEXR.File(str(tmp_path / "dome.exr"), separate_channels=True) as f:
        dome = f.channels()["G"].pixels
    # Dome master: the 180 deg circle is lit, the corners outside it are black.
    assert dome[32, 32] > 0 and dome[0, 0] == 0


def test_advanced_mode_sliders_act_on_the_physical_quantities():
    # Off-screen, the window's logic: in advanced mode the earth-advanced preset shows its Table 1 "(A)"
    # quantities; doubling the molecular refractivity n - 1 must multiply the Rayleigh scattering coefficient
    # by about 4 (Eq. 11: beta ~ (n^2 - 1)^2 ~ 4 (n - 1)^2; exactly ((n'^2 - 1) / (n^2 - 1))^2, checked here).
    os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkOSOpenGLRenderWindow")
    from planetviz.app.window import PlanetApp
    from planetviz.render import Scene
    scene = Scene("earth", quality="draft", surface=None, off_screen=True, window_size=(240, 160))
    try:
        app = PlanetApp(scene)
        assert app.load_preset("earth-advanced")
        app.toggle_mode()
        assert {"molecular refractivity (n - 1) x", "depolarisation delta", "turbidity T",
                "Junge exponent v"} <= set(app.sliders)
        before = np.asarray(scene.atmosphere.rayleigh.scattering_m)
        n = np.asarray(app._source["rayleigh"]["refractive_index"])
        label = "molecular refractivity (n - 1) x"
        row = [row for row in app._advanced_rows() if row.label == label][0]
        assert app.change_parameter(row, 2.0)
        after = np.asarray(scene.atmosphere.rayleigh.scattering_m)
        n2 = 1 + 2 * (n - 1)
        assert np.allclose(after / before, ((n2 ** 2 - 1) / (n ** 2 - 1)) ** 2, rtol=1e-6)
        assert scene.renderer_in_use == "quick"             # new tables are being computed
        scene.wait_for_tables(120)
        assert scene.renderer_in_use == "tables"
    finally:
        scene.close()


def test_standard_mode_turbidity_slider_follows_eq_17():
    # Eq. 17 written out here: beta_M = 0.434 C(T) pi (2 pi / lambda)^(v - 2) K, C(T) = (0.65 T - 0.65) 1e-16,
    # with the slider's v = 4 and K = 0.0092; extinction keeps the file's extinction/scattering ratio.
    import copy
    from planetviz.app.parameters import set_turbidity, turbidity_of
    from planetviz.model.presets import load_atmosphere
    d = load_atmosphere("earth").to_dict()
    base = copy.deepcopy(d)
    set_turbidity(d, base, 4.0)
    lam = np.asarray(d["wavelengths_nm"]) * 1e-9
    want = 0.434 * (0.65 * 4.0 - 0.65) * 1e-16 * np.pi * (2 * np.pi / lam) ** 2 * 0.0092
    assert np.allclose(d["mie"]["scattering_m"], want, rtol=1e-12)
    ratio = np.asarray(base["mie"]["extinction_m"]) / np.asarray(base["mie"]["scattering_m"])
    assert np.allclose(np.asarray(d["mie"]["extinction_m"]) / want, ratio)
    assert np.isclose(turbidity_of(d, base), 4.0)


def app_sequences(n_examples):
    """Generated sequences of what a user (or a script driving PlanetApp) does: any slider set to any float
    (NaN, infinities and values far outside the slider's range included), the sun and the exposure set to any
    float, keys that switch renderer, shading, mode, tone mapping and camera. After every step the scene must
    hold a valid atmosphere; a refused step must leave the atmosphere, sun and exposure as they were and say so;
    the picture at the end of each sequence must be finite and non-negative."""
    from hypothesis import HealthCheck, given, settings
    from hypothesis import strategies as st

    values = st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.floats(-2.0, 2.0))
    action = st.one_of(
        st.tuples(st.just("slider"), st.integers(0, 9), values),
        st.tuples(st.just("sun"), values, st.floats(-720.0, 720.0)),
        st.tuples(st.just("exposure"), values, st.just(0.0)),
        st.tuples(st.just("key"), st.sampled_from(["toggle_renderer", "toggle_shading", "toggle_mode",
                                                   "cycle_tone_mapping", "orbit", "ground", "limb"]), st.just(0.0)))

    @settings(max_examples=n_examples, deadline=None,
              suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
    @given(steps=st.lists(action, min_size=1, max_size=6))
    def check(app, steps):
        from planetviz import Atmosphere
        from planetviz.app.parameters import STANDARD
        scene = app.scene
        for kind, a, b in steps:
            before = (scene.atmosphere, scene.sun, scene.settings.exposure)
            if kind == "slider":
                rows = STANDARD if app.mode == "standard" else app._advanced_rows()
                ok = app.change_parameter(rows[a % len(rows)], b)
            elif kind == "sun":
                ok = app.set_sun(elevation=a, azimuth=b)
            elif kind == "exposure":
                ok = app.set_exposure(a)
            else:
                ok = getattr(app, a)() if a.startswith(("toggle", "cycle")) else app.camera_preset(a)
            assert Atmosphere.from_dict(scene.atmosphere.to_dict()) == scene.atmosphere
            if ok is False:
                assert app.message and (scene.atmosphere, scene.sun, scene.settings.exposure) == before
        scene.wait_for_tables(120)
        hdr = scene.render_hdr()
        assert np.all(np.isfinite(hdr.radiance)) and np.all(hdr.radiance >= 0), hdr.radiance.min()
    return check


@pytest.fixture(scope="module")
def app():
    """One off-screen window for all generated sequences: a user's session is one long sequence anyway."""
    os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkOSOpenGLRenderWindow")
    from planetviz.app.window import PlanetApp
    from planetviz.render import Scene
    scene = Scene("earth", quality="draft", surface=None, off_screen=True, window_size=(48, 32))
    yield PlanetApp(scene)
    scene.close()


test_generated_app_input = app_sequences(10)
test_generated_app_input_long = pytest.mark.slow(app_sequences(60))


def test_a_sequence_writes_a_tilted_dome_master_per_frame_and_resumes(tmp_path):
    import OpenEXR
    args = ("--quality", "draft", "--view", "ground", "--size", "48x32", "--sweep-sun", "-2", "2", "4",
            "--fisheye", "dome/sky.exr", "--fisheye-size", "48", "--fisheye-tilt", "30", "--heading", "90")
    proc = run_app(*args, cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert sorted(p.name for p in (tmp_path / "dome").iterdir()) == ["sky.manifest.json", "sky_0000.exr",
                                                                     "sky_0001.exr"]
    for name in ("sky_0000.exr", "sky_0001.exr"):
        with OpenEXR.File(str(tmp_path / "dome" / name), separate_channels=True) as f:
            dome = f.channels()["G"].pixels
            projection = json.loads(f.header()["planetviz"])["projection"]
        assert dome.shape == (48, 48) and dome[24, 24] > 0 and dome[0, 0] == 0
        assert "60 deg above the horizon at heading 90 deg" in projection
    again = run_app(*args, cwd=tmp_path)
    assert again.returncode == 0 and "0 frames rendered, 2 already there" in again.stdout
    bad = run_app(*args[:-4], "--fisheye-tilt", "120", cwd=tmp_path)
    assert bad.returncode == 2 and "fisheye-tilt: 0 to 90 deg, got 120" in bad.stderr
