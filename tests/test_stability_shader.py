"""Stability of the GLSL paths under generated input: cameras from 1 mm to 1e12 m above the ground,
any view, any sun, any field of view; the per-pixel shader and the per-vertex one (one vertex per sampled pixel)
read back as float32 and compared with the float64 NumPy evaluator on the same tables.

Two hypothesis profiles as in test_stability.py: ``FAST`` examples in the default run, ``LONG`` behind
``pytest -m slow``. Counts and the worst differences: docs/stability.md.
"""
import os

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkOSOpenGLRenderWindow")

from planetviz.render import Scene  # noqa: E402
from planetviz.tables.evaluator import sky_radiance  # noqa: E402

SIZE = (24, 18)
FAST, LONG = 20, 300
#: float32 against float64: the shader computes the ray, its (a, mu, mu_s, nu) and the texture coordinates in
#: float32 (relative 6e-8; the camera's height arrives as an altitude computed in double, not as a float32
#: radius, which is 0.5 m coarse at 6.4e6 m) and interpolates the same float32
#: tables; that moves a texture coordinate by < 1e-4 of a texel, where the tables change by at most a factor 2
#: per texel, and each exp of an optical depth up to ~30 carries float32's 1e-7: < 1e-3 relative for most rays.
#: Rays to ground a few hundred metres away from a camera metres above it amplify it (their inscatter is
#: S(x) - T S(y), the difference of two nearly equal lookups). Measured over 300 random views per shader (1 mm
#: to 1e12 m): 5.9e-4 per pixel, 1.8e-3 per vertex; over 300 within 1 km of the ground 1.2e-4 / 1.4e-4
#: (docs/stability.md). With a float32 radius, views 1.7 m up were 5% off and 11 m up 1%. Bound: 0.5% on the
#: relative difference, or 1e-6 of the frame's largest radiance for the near-black rays of the night side and
#: deep space.
BOUND, FLOOR = 5e-3, 1e-6

altitudes = st.floats(-3.0, 12.0).map(lambda e: 10.0 ** e)             # 1 mm above the ground to 1e12 m
unit = st.tuples(*[st.floats(-1.0, 1.0)] * 3).filter(lambda v: np.linalg.norm(v) > 1e-3) \
    .map(lambda v: np.asarray(v) / np.linalg.norm(v))


@pytest.fixture(scope="module")
def scenes():
    made = {shading: Scene("earth", quality="draft", surface=None, off_screen=True, window_size=SIZE,
                           shading=shading) for shading in ("pixel", "vertex")}
    for scene in made.values():
        scene.settings.show_sun = False
    yield made
    for scene in made.values():
        scene.close()


def ambiguous(scene, dirs):
    """Rays whose ground / sky / space classification float32 cannot settle: within 2e-4 rad of the cone of the
    ground's horizon or of the top of the atmosphere's limb, where the float64 and float32 answers may fall on
    different sides of a step."""
    atm = scene.atmosphere
    cam = scene.camera_location
    r = np.linalg.norm(cam)
    theta = np.arccos(np.clip(dirs @ (-cam / r), -1.0, 1.0))              # angle from the nadir
    out = np.zeros(len(dirs), bool)
    for radius in (atm.bottom_radius_m, atm.top_radius_m):
        edge = np.arcsin(min(radius / r, 1.0))
        out |= np.abs(theta - edge) < 2e-4
    return out


#: The direction error of the shader's rays [rad]: it builds them from the camera's basis and the pixel's
#: coordinates in float32, a dozen operations of relative error 6e-8 each.
DIRECTION_ERROR = 1e-6


def ill_conditioned(scene, dirs, want, scale):
    """Rays whose radiance (relative, floored as in :func:`compare`) changes by more than BOUND / 2 when the
    direction turns by DIRECTION_ERROR either way across it: along the top of the atmosphere next to the edge of the
    planet's shadow the radiance changes by a third within 1e-4 rad (a ray 1.9 km under the top, from 223 km, the
    sun 19.6 deg down: 0.75% for 1e-6 rad), and float32's direction alone then moves it beyond the bound."""
    helper = np.where(np.abs(dirs[:, :1]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
    e1 = np.cross(dirs, helper)
    e1 /= np.linalg.norm(e1, axis=1, keepdims=True)
    e2 = np.cross(dirs, e1)
    out = np.zeros(len(dirs), bool)
    cams = np.tile(scene.camera_location, (len(dirs), 1))
    for e in (e1, e2):
        turned = dirs + DIRECTION_ERROR * e
        near, _ = sky_radiance(scene.planet.tables, scene.atmosphere, cams,
                               turned / np.linalg.norm(turned, axis=1, keepdims=True), scene.sun_direction)
        out |= np.any(np.abs(near - want) / np.maximum(want, FLOOR * scale) > BOUND / 2, axis=1)
    return out


def compare(scene, shading):
    """The largest relative difference between the frame read back and the evaluator on the same rays (the
    camera where it is), the ambiguous and the ill-conditioned ones left out."""
    rows, cols = np.meshgrid(np.arange(SIZE[1]), np.arange(SIZE[0]), indexing="ij")
    dirs = scene.pixel_directions(rows, cols).reshape(-1, 3)
    if shading == "vertex":
        scene.planet.directions = dirs
    try:
        got = scene.render_hdr().radiance.reshape(-1, 3)
    finally:
        scene.planet.directions = None
    want, _ = sky_radiance(scene.planet.tables, scene.atmosphere, np.tile(scene.camera_location, (len(dirs), 1)), dirs,
                           scene.sun_direction)
    assert np.all(np.isfinite(got)) and np.all(got >= 0)
    scale = max(want.max(), 1e-30)
    keep = ~ambiguous(scene, dirs) & ~ill_conditioned(scene, dirs, want, scale)
    err = np.abs(got - want)[keep] / np.maximum(want[keep], FLOOR * scale)
    return float(err.max()) if err.size else 0.0


def shader_property(n_examples, shading):
    @settings(max_examples=n_examples, deadline=None,
              suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
    @given(alt=altitudes, up=unit, view=unit, sun=unit, fov=st.floats(10.0, 120.0))
    @example(alt=1e-3, up=np.array([0.0, 0.0, 1.0]), view=np.array([1.0, 0.0, 0.0]),
             sun=np.array([0.0, 0.0, 1.0]), fov=60.0)                # 1 mm up, along the horizon, sun at the zenith
    @example(alt=1e12, up=np.array([1.0, 0.0, 0.0]), view=np.array([-1.0, 0.0, 0.0]),
             sun=np.array([-1.0, 0.0, 0.0]), fov=10.0)               # 1e12 m, the sun behind the planet
    @example(alt=10.0 ** 4.625, up=np.array([0.99969919, 0.0, 0.02452595]) / np.hypot(0.99969919, 0.02452595),
             view=np.array([1.0, 0.0, 0.0]), sun=np.array([0.0, 0.0, 1.0]), fov=10.0)
    # CI's falsifying example: 42 km up looking near the zenith, the whole frame empty (the shell's float32
    # depth fell beyond the far plane; it is drawn at mid-depth now)
    @example(alt=10.0 ** 0.5, up=np.array([0.0, 1.0, 0.0]), view=np.array([0.0, 0.0, 1.0]),
             sun=np.array([0.0, 0.0, 1.0]), fov=10.0)
    # A hard case: 3.16 m up, the sun on the horizon ahead, the ground 650 m away; with the camera's float32
    # radius (3.0 m) in place of its altitude it reads 3.1% off
    @example(alt=222963.1045578224, up=np.array([0.0, 1.0, 0.0]), view=np.array([-0.98691702, -0.16122902, 0.0]),
             sun=np.array([-0.94174191, -0.3363364, 0.0]), fov=10.0)
    # CI's falsifying example: the limb from 223 km next to the edge of the planet's shadow (ill_conditioned)
    @example(alt=59888.54334916461, up=np.array([1.0, 0.0, 0.0]), view=np.array([1.0, 0.0, 0.0]),
             sun=np.array([0.0, 0.0, 1.0]), fov=10.0)
    # CI's falsifying example: 112 m under the top looking up, the sun at the zenith; the distance to the top as
    # -r mu + sqrt(disc) in float32 read 0.67% off (common.glsl takes the stable root)
    @example(alt=10.0 ** 0.25, up=np.array([0.0, 0.0, 1.0]), view=np.array([0.0, 0.0, 1.0]),
             sun=np.array([0.0, 0.0, -1.0]), fov=10.0)
    # CI's falsifying example: the night sky of a sun at the nadir, extrapolated below the tables' last sun angle;
    # with acos(mu_s) in the sun-zenith coordinate float32's rounding of mu_s read 0.64% off
    # (parameterization.sun_zenith_angle continues it linearly in mu_s)
    def check(scenes, alt, up, view, sun, fov):
        scene = scenes[shading]
        r = scene.atmosphere.bottom_radius_m + alt
        scene.set_view(up * r, view, fov=fov)
        scene.sun_direction = sun
        assert compare(scene, shading) < BOUND
    return check


test_generated_views_per_pixel_shader = shader_property(FAST, "pixel")
test_generated_views_per_vertex_shader = shader_property(FAST, "vertex")
test_generated_views_per_pixel_shader_long = pytest.mark.slow(shader_property(LONG, "pixel"))
test_generated_views_per_vertex_shader_long = pytest.mark.slow(shader_property(LONG, "vertex"))


@pytest.mark.parametrize("shading", ["pixel", "vertex"])
def test_a_camera_metres_up_is_drawn_where_it_is(scenes, shading):
    # A ground camera 1.7 m up, the sun on the horizon ahead (the ground's own light is then small and the aerial
    # perspective of the near ground, proportional to the camera's height, dominates), against the evaluator at
    # the true camera. Bound as the generated views'. With the camera's radius passed as a float32 (drawn from
    # 1.5 m) in place of its altitude in double, this reads 5.2% off.
    scene = scenes[shading]
    up, view = np.array([0.0, 1.0, 0.0]), np.array([0.0, 0.0, 1.0])
    scene.set_view(up * (scene.atmosphere.bottom_radius_m + 1.7), view, fov=10.0)
    scene.sun_direction = view
    assert compare(scene, shading) < BOUND


@pytest.mark.parametrize("shading", ["pixel", "vertex"])
def test_twilight_rays_are_integrated_in_the_shaders_as_in_the_evaluator(shading, monkeypatch):
    # tables/horizon.py's twilight share (GLSL twin in shaders/horizon.glsl): a thin atmosphere over a small planet
    # (random atmosphere 2: 6.8 km of air over a 705 km planet), 100 m up, the sun 5 deg below the horizon ahead,
    # where every ray's single scattering comes from the quadrature. The shaders against the evaluator, bound as
    # the generated views'; the tables' own reading differs from the evaluator's by far more there (measured 40%),
    # so a shader that read the tables would fail.
    import importlib
    from planetviz.validation import random_atmosphere
    horizon = importlib.import_module("planetviz.tables.horizon")
    atm = random_atmosphere(2)
    scene = Scene(atm, quality="draft", surface=None, off_screen=True, window_size=SIZE, shading=shading)
    scene.settings.show_sun = False
    try:
        scene.set_sun(elevation=-5.0, azimuth=90.0, latitude=10.0, longitude=0.0)
        scene.view_from_ground(latitude=10, heading=90, pitch=8, fov=60, altitude=100.0)
        rows, cols = np.meshgrid(np.arange(SIZE[1]), np.arange(SIZE[0]), indexing="ij")
        dirs = scene.pixel_directions(rows, cols).reshape(-1, 3)
        if shading == "vertex":
            scene.planet.directions = dirs
        got = scene.render_hdr().radiance.reshape(-1, atm.n_wavelengths)
        cams = np.tile(scene.camera_location, (len(dirs), 1))
        want, _ = sky_radiance(scene.planet.tables, atm, cams, dirs, scene.sun_direction)
        with monkeypatch.context() as m:
            m.setattr(horizon, "quadrature_share", lambda r, mu, *rest: np.zeros(np.shape(mu)))
            tables, _ = sky_radiance(scene.planet.tables, atm, cams, dirs, scene.sun_direction)
    finally:
        scene.close()
    floor = FLOOR * want.max()
    assert np.max(np.abs(got - want) / np.maximum(want, floor)) < BOUND
    assert np.max(np.abs(tables - want) / np.maximum(want, floor)) > 10 * BOUND


@pytest.mark.parametrize("shading", ["pixel", "vertex"])
def test_a_large_planets_sun_angles_are_read_as_in_the_evaluator(shading):
    # parameterization.limited_geometry and distance_warp (GLSL twins in shaders/table_lookup.glsl,
    # x_mu_s_from_mu_s and distance_warp): on a 1e9 m planet under 60 km of air the sun-zenith texels are placed on
    # a smaller planet's geometry and the view-zenith texels spread as on it; the shaders must read them where the
    # evaluator does. From the ground looking up and from 1000 km looking down, the sun 50 deg from the zenith;
    # bound as the generated views'. Read on the planet's own geometry instead, the coordinate of a sun 50 deg
    # from the zenith moves by 1.2 of the multiple-scattering tables' 32 texels (a shader that did so read 17% off).
    from planetviz.tables.parameterization import distance_warp, limited_geometry
    from planetviz.validation.disort import plane_parallel_atmosphere
    atm = plane_parallel_atmosphere(False, 1e9)
    assert limited_geometry(atm.bottom_radius_m, atm.top_radius_m)[0] < atm.bottom_radius_m
    assert distance_warp(atm.bottom_radius_m, atm.bottom_radius_m, atm.top_radius_m, False) > 0.0
    scene = Scene(atm, quality="draft", surface=None, off_screen=True, window_size=SIZE, shading=shading)
    scene.settings.show_sun = False
    try:
        scene.set_sun(elevation=40.0, azimuth=90.0, latitude=0.0, longitude=0.0)
        for altitude, pitch in ((2.0, 60.0), (1e6, -60.0)):
            scene.view_from_ground(latitude=0, heading=30, pitch=pitch, fov=40, altitude=altitude)
            rows, cols = np.meshgrid(np.arange(SIZE[1]), np.arange(SIZE[0]), indexing="ij")
            dirs = scene.pixel_directions(rows, cols).reshape(-1, 3)
            if shading == "vertex":
                scene.planet.directions = dirs
            got = scene.render_hdr().radiance.reshape(-1, atm.n_wavelengths)
            scene.planet.directions = None
            want, _ = sky_radiance(scene.planet.tables, atm, np.tile(scene.camera_location, (len(dirs), 1)), dirs,
                                   scene.sun_direction)
            keep = ~ambiguous(scene, dirs)
            err = np.abs(got - want)[keep] / np.maximum(want[keep], FLOOR * want.max())
            assert err.max() < BOUND, (altitude, err.max())
    finally:
        scene.close()


@pytest.mark.slow
def test_sixty_four_wavelengths_render_as_the_evaluator_says():
    # The most wavelengths the renderer takes (16 groups of 4: MAX_GROUPS): 22 read-back passes, every one of
    # them against the evaluator on the same tables, per pixel and per vertex (bound as above).
    from planetviz.validation import spectral_earth
    from planetviz import Atmosphere
    atm = Atmosphere.from_dict(spectral_earth(64))
    for shading in ("pixel", "vertex"):
        scene = Scene(atm, quality="draft", surface=None, off_screen=True, window_size=SIZE, shading=shading)
        scene.settings.show_sun = False
        try:
            for view in ("ground", "space"):
                if view == "ground":
                    scene.view_from_ground(latitude=10, heading=80, pitch=3, fov=70)
                    scene.set_sun(elevation=8, azimuth=100, latitude=10, longitude=0)
                else:
                    scene.view_from_space(distance=2e7, latitude=10, longitude=20, fov=40)
                    scene.set_sun(elevation=20, azimuth=120, latitude=10, longitude=20)
                rows, cols = np.meshgrid(np.arange(SIZE[1]), np.arange(SIZE[0]), indexing="ij")
                dirs = scene.pixel_directions(rows, cols).reshape(-1, 3)
                if shading == "vertex":
                    scene.planet.directions = dirs
                got = scene.render_hdr().radiance.reshape(-1, 64)
                scene.planet.directions = None
                want, _ = sky_radiance(scene.planet.tables, atm, np.tile(scene.camera_location, (len(dirs), 1)),
                                       dirs, scene.sun_direction)
                keep = ~ambiguous(scene, dirs)
                assert got.shape == want.shape and np.all(np.isfinite(got)) and np.all(got >= 0)
                err = np.abs(got - want)[keep] / np.maximum(want[keep], FLOOR * want.max())
                assert err.max() < BOUND, (shading, view, err.max())
        finally:
            scene.close()



COMPARISON = r"vec[234]\((?:greaterThan|lessThan|greaterThanEqual|lessThanEqual|equal|notEqual)\("


def float_weighted_selects(code):
    """The mix calls of GLSL ``code`` whose weight is a float vector made from a comparison, inline or through a
    variable assigned one (a select written as arithmetic)."""
    import re
    masks = set(re.findall(r"\bvec[234]\s+(\w+)\s*=[^;]*" + COMPARISON, code))
    found = []
    for start in (m.end() for m in re.finditer(r"\bmix\(", code)):
        depth, args, arg = 1, [], ""
        for ch in code[start:]:
            depth += (ch == "(") - (ch == ")")
            if depth == 0 or (ch == "," and depth == 1):
                args.append(arg.strip())
                arg = ""
                if depth == 0:
                    break
                continue
            arg += ch
        weight = args[-1]
        if re.match(COMPARISON, weight) or weight in masks:
            found.append("mix(" + ", ".join(args) + ")")
    return found


def test_no_float_weighted_select_in_the_shaders():
    # mix(x, y, w) with w a float vector of 0s and 1s from a comparison is a select written as arithmetic, which
    # NVIDIA's compiler evaluates as x + w (y - x): with x = 1 and y = 1e-37 that is 0, not y (log(0 / 0) then
    # made twilight rays from orbit lose a wavelength on an H100: docs/stability.md). llvmpipe computes it
    # exactly, so the renders here cannot show it; a select must be a boolean mix (mix(x, y, bvecN)).
    from pathlib import Path
    found = {path.name: float_weighted_selects(path.read_text())
             for path in sorted(Path(__file__).resolve().parents[1].glob("shaders/*.glsl"))}
    assert not any(found.values()), found
    # The check finds the form that caused the bug (a float mask in a variable) and the inline one.
    assert float_weighted_selects("vec4 lit = max(vec4(greaterThan(a, vec4(0.0))), vec4(greaterThan(b, vec4(0.0))));\n"
                                  "vec4 a_f = mix(vec4(1.0), max(a, 1e-37), lit);")
    assert float_weighted_selects("return mix(x, f(y, z), vec3(greaterThan(c, vec3(0.5))));")


@pytest.mark.parametrize("shading", ["pixel", "vertex"])
@pytest.mark.parametrize("depth, zenith_deg", [(33.0, 5.0), (33.0, 60.0), (3000.0, 80.0)])
def test_upward_views_under_the_top_read_the_top_tables_as_in_the_evaluator(shading, depth, zenith_deg):
    # Cameras within Mars's top row interval looking up read the multiple-scattering tables' top tables in the top
    # row's place (lookup.get_scattering with top; the shaders' get_multiple_scattering). Under Mars's forward lobe
    # they differ from the top row's reading by up to 4 times (benchmarks/top_views.py), so a shader that read the
    # top row, or the top tables at another zenith angle, would be far outside the bound (that of the generated
    # views).
    scene = Scene("mars", quality="draft", surface=None, off_screen=True, window_size=SIZE, shading=shading)
    try:
        scene.settings.show_sun = False
        atm = scene.atmosphere
        up = np.array([0.0, 0.0, 1.0])
        zenith = np.radians(zenith_deg)
        view = np.array([np.sin(zenith), 0.0, np.cos(zenith)])
        scene.set_view(up * (atm.top_radius_m - depth), view, fov=10.0)
        scene.sun_direction = np.array([np.cos(np.radians(24.0)), 0.3, np.sin(np.radians(24.0))])
        scene.sun_direction /= np.linalg.norm(scene.sun_direction)
        assert compare(scene, shading) < BOUND
    finally:
        scene.close()
