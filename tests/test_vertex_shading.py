"""The table-based renderer read per vertex (``Scene(shading="vertex")``): the same model as the per-pixel
renderer at its vertices, a mesh split that never puts a ground ray in the sky's part, a view culling that
leaves no pixel uncovered, a culling of empty space that drops no ray to the atmosphere or the sun, and the
interpolation error between vertices."""
import os

import numpy as np
import pytest

os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkOSOpenGLRenderWindow")

from planetviz import load_atmosphere  # noqa: E402
from planetviz.model.geometry import distance_to_ground  # noqa: E402
from planetviz.render import Scene  # noqa: E402
from planetviz.render.direction_mesh import direction_mesh  # noqa: E402
from planetviz.render.scene import is_software_renderer  # noqa: E402
from planetviz.render.uniforms import camera_uniforms  # noqa: E402
from planetviz.validation.pictures import VIEWS, floored_difference, view_luminance  # noqa: E402
from planetviz.tables.evaluator import sky_radiance  # noqa: E402

from conftest import hold_to_targets  # noqa: E402

SIZE = (64, 48)


@pytest.fixture(scope="module")
def vertex():
    scene = Scene("earth", quality="draft", surface=None, off_screen=True, window_size=SIZE, shading="vertex")
    yield scene
    scene.close()


def set_view(scene, view):
    if view == "space":
        scene.view_from_space(distance=1.6e7, latitude=10, longitude=20, fov=40)
        scene.set_sun(elevation=40, azimuth=120, latitude=10, longitude=20)
    elif view == "ground":
        scene.view_from_ground(latitude=20, altitude=2.0, heading=80, pitch=5, fov=70)
        scene.set_sun(elevation=15, azimuth=100, latitude=20, longitude=0)
    elif view == "aircraft":
        scene.view_from_ground(latitude=20, altitude=1e4, heading=200, pitch=-10, fov=70)
        scene.set_sun(elevation=5, azimuth=180, latitude=20, longitude=0)
    else:                                               # space, the terminator across the disc
        scene.view_from_space(distance=2e7, latitude=0, longitude=0, fov=40)
        scene.set_sun(elevation=0, azimuth=90, latitude=0, longitude=0)


@pytest.mark.parametrize("view", ["space", "ground", "aircraft", "terminator"])
def test_vertex_shading_matches_the_evaluator_at_its_vertices(vertex, view):
    # One vertex per sampled pixel (points at the pixels' directions), so each of those pixels holds one vertex's
    # inscatter and its own ground light with no interpolation: the result must be the NumPy evaluator's (same
    # bound and reasons as the per-pixel test in test_render.py: float32 arithmetic on the same tables, 1%).
    set_view(vertex, view)
    rows, cols = np.meshgrid(np.arange(1, SIZE[1], 4), np.arange(1, SIZE[0], 5), indexing="ij")
    dirs = vertex.pixel_directions(rows, cols).reshape(-1, 3)
    vertex.planet.directions = dirs
    try:
        got = vertex.render_hdr().radiance[rows, cols].reshape(-1, 3)
    finally:
        vertex.planet.directions = None
    want, _ = sky_radiance(vertex.planet.tables, vertex.atmosphere, np.tile(vertex.camera_location, (len(dirs), 1)),
                           dirs, vertex.sun_direction)
    seen = want.max(-1) > 1e-6 * want.max()
    assert seen.sum() > 50
    assert np.max(np.abs(got - want)[seen] / want[seen]) < 0.01


def rays_inside(dirs, tris):
    """Unit rays sampled inside each flat triangle (edges and corners included): the normalised convex
    combinations of its vertices, (m * k, 3)."""
    w = np.random.default_rng(1).dirichlet(np.ones(3), 40)
    w = np.concatenate([w, np.eye(3), [[0.5, 0.5, 0.0], [0.0, 0.5, 0.5], [0.5, 0.0, 0.5]]])
    rays = np.einsum("kj,tjc->tkc", w, dirs[tris]).reshape(-1, 3)
    return rays / np.linalg.norm(rays, axis=1, keepdims=True)


@pytest.mark.parametrize("altitude", [1e5, 1e6, 1.9e7, 1e9, 1e12])
@pytest.mark.parametrize("sun_from_nadir", [0.0, 10.0, 60.0, 120.0, 179.9, 180.0])
def test_culling_empty_space_drops_no_ray_to_the_atmosphere_or_the_sun(altitude, sun_from_nadir):
    # Triangles whose rays all miss the top of the atmosphere and the sun's disc are not drawn (the background is
    # black): rays sampled inside every dropped triangle must miss both, for cameras above the atmosphere and the
    # sun anywhere, including the nadir itself (behind the planet) and straight away from it, where the mesh's
    # sun refinement degenerates.
    atm = load_atmosphere("earth")
    R, top = atm.bottom_radius_m, atm.top_radius_m
    cam = np.array([0.3, -0.5, 0.8]) / np.linalg.norm([0.3, -0.5, 0.8]) * (R + altitude)
    down = -cam / np.linalg.norm(cam)
    side = np.cross(down, [1.0, 0.0, 0.0])
    side /= np.linalg.norm(side)
    a = np.radians(sun_from_nadir)
    sun = np.cos(a) * down + np.sin(a) * side
    mesh = direction_mesh(cam, sun, R, top)
    dirs = mesh.directions
    radius = np.radians(0.2666)
    kept = mesh.may_meet_sphere(cam, top) | mesh.may_meet_disc(sun, radius)
    assert 0 < np.count_nonzero(kept) < len(kept)
    rays = rays_inside(dirs, mesh.triangles_of(~kept))
    assert np.all(np.isinf(distance_to_ground(np.broadcast_to(cam, rays.shape), rays, top)))
    assert np.all(rays @ sun < np.cos(radius))
    # The mesh has a vertex in the disc, and the triangles around it are drawn.
    centre = np.argmax(dirs @ sun)
    assert dirs[centre] @ sun > np.cos(radius) and np.any(mesh.triangles_of(kept) == centre)


def test_sphere_and_disc_tests_are_conservative_on_coarse_meshes():
    # The margins of may_meet_sphere (an edge dipping inside the cone) and may_meet_disc (a disc inside a
    # triangle away from its vertices) matter where triangles are large: on coarse meshes (6 rings, 8 sectors),
    # with the disc away from the mesh's refinement and the sphere anywhere from a grazing to a wide cone, every
    # ray inside a rejected triangle must miss the sphere and the disc.
    rng = np.random.default_rng(7)
    R = 6.36e6
    for _ in range(60):
        cam = rng.normal(size=3)
        cam *= R * np.exp(rng.uniform(np.log(1.001), np.log(50.0))) / np.linalg.norm(cam)
        mesh_sun, disc = (v / np.linalg.norm(v) for v in rng.normal(size=(2, 3)))
        mesh = direction_mesh(cam, mesh_sun, R, 1.01 * R, rings=6, sectors=8)
        radius = np.radians(rng.uniform(0.3, 10.0))
        sphere = R * rng.uniform(0.5, 1.0)
        rays = rays_inside(mesh.directions, mesh.triangles_of(~mesh.may_meet_sphere(cam, sphere)))
        assert np.all(np.isinf(distance_to_ground(np.broadcast_to(cam, rays.shape), rays, sphere)))
        assert np.all(rays_inside(mesh.directions, mesh.triangles_of(~mesh.may_meet_disc(disc, radius))) @ disc
                      < np.cos(radius))


@pytest.mark.parametrize("altitude", [2.0, 1e4, 1e5, 1.9e7, 1e9])
def test_the_sky_part_of_the_mesh_holds_no_ray_to_the_ground(altitude):
    # The sky part's fragments leave out the ground's code, so any ray to the ground inside one of its triangles
    # would show the inscatter alone. Rays sampled inside every sky triangle (edges included; the triangles are
    # flat, so their rays are the normalised convex combinations of the vertices) must all miss the ground.
    atm = load_atmosphere("earth")
    R = atm.bottom_radius_m
    cam = np.array([0.3, -0.5, 0.8]) / np.linalg.norm([0.3, -0.5, 0.8]) * (R + altitude)
    sun = np.array([0.0, 0.6, 0.8])
    mesh = direction_mesh(cam, sun, R, atm.top_radius_m)
    sky = mesh.triangles_of(~mesh.may_meet_sphere(cam, R))
    assert len(sky) > 0.3 * len(mesh.triangles)
    rays = rays_inside(mesh.directions, sky)
    assert np.all(np.isinf(distance_to_ground(np.broadcast_to(cam, rays.shape), rays, R)))


def test_opengl_gets_the_same_triangles_in_strips_over_the_strided_vertex_buffer():
    # buffer_triangles_of hands OpenGL the triangles of triangles_of renumbered to the vertex buffer of
    # grid_points, whose vertex at each index holds the (ring, sector) that triangles_of's number stands for; in
    # strips of STRIP_SECTORS sectors (sector // STRIP_SECTORS never decreases along the list); and the vertices of
    # 15 consecutive rings of a strip fall on distinct entries of llvmpipe's 256-entry table (index modulo 256).
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from planetviz.render.direction_mesh import STRIP_SECTORS, VERTEX_STRIDE, grid_points
    atm = load_atmosphere("earth")
    cam = np.array([0.0, 0.0, 4.0 * atm.bottom_radius_m])
    mesh = direction_mesh(cam, np.array([0.6, 0.0, 0.8]), atm.bottom_radius_m, atm.top_radius_m)
    n_t, n_p = len(mesh.theta), len(mesh.phi)
    drawn = np.random.default_rng(3).random((n_t - 1) * n_p) < 0.7
    ring_numbered = mesh.triangles_of(drawn)
    buffered = mesh.buffer_triangles_of(drawn)
    grid = vtk_to_numpy(grid_points(n_t).GetData())
    ring_j = grid[buffered][..., :2].astype(int)                           # (m, 3, 2): ring and sector
    assert {tuple(t) for t in ring_j[..., 0] * n_p + ring_j[..., 1]} == {tuple(t) for t in ring_numbered}
    assert len(buffered) == len(ring_numbered) and np.all(np.diff(ring_j[:, 0, 1] // STRIP_SECTORS) >= 0)
    rows, cols = np.meshgrid(np.arange(15), np.arange(STRIP_SECTORS + 1), indexing="ij")
    for first in (0, STRIP_SECTORS, 4 * STRIP_SECTORS):
        assert len(np.unique((rows * VERTEX_STRIDE + first + cols) % 256)) == rows.size


@pytest.mark.parametrize("heading,pitch,fov", [(0, 5, 60), (137, -30, 90), (250, 80, 30), (10, -89, 120)])
def test_culling_to_the_view_leaves_no_pixel_uncovered(vertex, heading, pitch, fov):
    # Triangles wholly beyond one side of the view are dropped; the rest must still cover every pixel: in
    # daylight every ray from the ground carries light, so a pixel left at 0 is a hole in the mesh.
    vertex.view_from_ground(latitude=30, altitude=50.0, heading=heading, pitch=pitch, fov=fov)
    vertex.set_sun(elevation=50, azimuth=200, latitude=30, longitude=0)
    lum = vertex.render_hdr().linear_srgb[..., 1]
    assert np.all(lum > 0), np.argwhere(lum <= 0)[:5]
    forward = vertex.pixel_directions(np.array([SIZE[1] / 2 - 0.5]), np.array([SIZE[0] / 2 - 0.5]))[0]
    mesh = direction_mesh(vertex.camera_location, vertex.sun_direction, vertex.atmosphere.bottom_radius_m,
                          vertex.atmosphere.top_radius_m)
    assert np.all(np.isclose(np.linalg.norm(mesh.directions, axis=1), 1.0)) and np.dot(forward, forward) > 0.99
    view = camera_uniforms(vertex.renderer)
    seen = mesh.in_view(*(view[k][1] for k in ("camera_forward", "camera_right", "camera_up")))
    assert np.count_nonzero(seen) < len(seen)


@pytest.mark.parametrize("view", ["ground", "space"])
def test_interpolation_error_against_the_per_pixel_renderer(view):
    # What reading the 4D tables per vertex costs in accuracy: the same frame per pixel and per vertex. From the
    # ground the mesh is dense toward the horizon and around the sun (bound 2% RMS); from space what is left
    # gathers in a few pixels at the limb where it crosses the terminator (docs/benchmarks.md), so the bound is on
    # the median: 1%.
    size = (160, 120)
    images = []
    for shading in ("pixel", "vertex"):
        scene = Scene("earth", quality="draft", surface="texture", off_screen=True, window_size=size,
                      shading=shading)
        scene.settings.show_sun = False
        try:
            if view == "ground":
                scene.view_from_ground(latitude=45, heading=90, pitch=5)
                scene.set_sun(elevation=10, azimuth=100, latitude=45, longitude=0)
            else:
                scene.view_from_space(latitude=20, longitude=10)
                scene.set_sun(elevation=30, azimuth=100, latitude=20, longitude=10)
            images.append(scene.render_hdr().linear_srgb[..., 1])
        finally:
            scene.close()
    pixel, vertex_image = images
    lit = pixel > 1e-3 * np.percentile(pixel, 99)
    rel = np.abs(vertex_image - pixel)[lit] / pixel[lit]
    assert lit.sum() > 0.2 * pixel.size
    if view == "ground":
        assert np.sqrt(np.mean(rel ** 2)) < 0.02
    else:
        assert np.median(rel) < 0.01


def test_auto_shading_reads_per_vertex_on_a_software_renderer():
    # OSMesa is llvmpipe here: "auto" settles on per-vertex reading at the frame after the first; a GPU's
    # renderer string keeps per-pixel reading.
    scene = Scene("earth", quality="draft", surface=None, off_screen=True, window_size=SIZE, shading="auto")
    try:
        scene.screenshot()
        scene.screenshot()
        assert "llvmpipe" in scene.gl_renderer and scene.shading == "vertex"
        assert type(scene.planet).__name__ == "VertexAtmosphereActor"
    finally:
        scene.close()
    assert is_software_renderer("llvmpipe (LLVM 15.0.6, 256 bits)")
    assert not is_software_renderer("NVIDIA H100 80GB HBM3/PCIe/SSE2")
    with pytest.raises(ValueError, match="shading: one of pixel, vertex, auto"):
        Scene("earth", quality="draft", off_screen=True, window_size=SIZE, shading="gouraud")


@pytest.mark.parametrize("method,shading", [("tables", "vertex"), ("quick", "pixel")])
def test_interpolation_never_extrapolates_below_zero(method, shading):
    # Found by the app's generated input (tests/test_app.py): from orbit, with no Rayleigh scattering and the sun
    # just below the horizon, one pixel at the top of the atmosphere's limb read -3e-4 in the float read-back:
    # the rasteriser's barycentric weights on the slivers straddling the limb were slightly negative and
    # extrapolated the (non-negative) vertex values. Spectral radiance is clamped at 0 per fragment now.
    d = load_atmosphere("earth").to_dict()
    d["rayleigh"]["scattering_m"] = [0.0, 0.0, 0.0]
    atm = type(load_atmosphere("earth")).from_dict(d)
    scene = Scene(atm, quality="draft", surface=None, off_screen=True, window_size=(48, 32), method=method,
                  shading=shading)
    try:
        scene.view_from_space(latitude=30.0, longitude=0.0)
        scene.set_sun(elevation=-0.14304245423328377, azimuth=-6.0, latitude=30.0, longitude=0.0)
        radiance = scene.render_hdr().radiance
    finally:
        scene.close()
    assert radiance.max() > 0 and radiance.min() >= 0, radiance.min()


def test_an_actor_taken_out_of_the_scene_stops_rebuilding_its_mesh(vertex):
    # Every change of atmosphere or shading makes a new actor; the old one must stop following the camera, or
    # each frame of a moving camera rebuilds one mesh per actor ever shown (the app's sliders make many).
    old = vertex.planet
    vertex.set_shading("pixel")
    try:
        key = old._mesh_key
        vertex.view_from_ground(latitude=5, altitude=100.0, heading=33, pitch=4)
        vertex.screenshot()
        assert old._mesh_key == key and not old._observers
    finally:
        vertex.set_shading("vertex")
    quick = Scene("earth", quality="draft", surface=None, off_screen=True, window_size=SIZE, method="quick")
    try:
        first = quick.quick
        quick.set_atmosphere(quick.atmosphere)             # a new quick view replaces the first
        key = first._mesh_key
        quick.view_from_ground(latitude=5, altitude=100.0, heading=33, pitch=4)
        quick.screenshot()
        assert first._mesh_key == key and quick.quick._mesh_key != key
    finally:
        quick.close()


def _both_renderers(atmosphere, view):
    """CIE Y of the view class ``view`` (planetviz.validation.pictures.VIEWS) of ``atmosphere``, drawn per pixel and
    per vertex (320x180, draft tables)."""
    images = []
    for shading in ("pixel", "vertex"):
        scene = Scene(atmosphere, quality="draft", surface="texture", off_screen=True, window_size=(320, 180),
                      shading=shading)
        try:
            images.append(view_luminance(scene, VIEWS[view]))
        finally:
            scene.close()
    return images


@pytest.mark.parametrize("preset", ["earth", "mars"])
def test_the_limb_from_low_orbit_matches_the_per_pixel_renderer(preset):
    # The limb's halo seen from 400 km: its radiance falls by e every scale height of the rays' tangent altitude.
    # The mesh has rings at tangent altitudes between the planet's limb and the top's (LIMB_RINGS), and the
    # fragments correct the interpolated inscatter by their own scattering opacity (inscatter_factor.glsl). Bounds:
    # the targets, 1% RMS and 3% at the 99th percentile (floored difference); measured here (320x180, draft
    # tables) 0.29% / 0.70% (Earth) and 0.11% / 0.55% (Mars), 4.6% and 6.2% RMS without the rings and the
    # correction.
    pixel, vertex_image = _both_renderers(preset, "limb from 400 km")
    assert np.mean(pixel > 1e-3 * np.percentile(pixel, 99)) > 0.2
    difference = floored_difference(vertex_image, pixel)
    assert np.sqrt(np.mean(difference ** 2)) < 0.01
    assert np.percentile(difference, 99) < 0.03


@pytest.mark.parametrize("preset", ["earth", "mars", "exo-co2-thick"])
def test_the_terminator_from_orbit_matches_the_per_pixel_renderer(preset):
    # Seen from space the inscatter over the ground's twilight band and along the limb over the terminator falls with
    # the height of the planet's shadow faster than the mesh resolves; the fragments correct the interpolated
    # inscatter by their own factor (ray_factors: the scattering opacity, the sky irradiance and the phases, read per
    # pixel) over the interpolated one. Measured here (320x180, draft tables, floored difference): RMS 0.9-1.4% and
    # p99 2.9-5.9% over the three atmospheres, 4.6-48% and 13-16% without the correction; the bounds, 4% and 8%, sit
    # between (the targets, 1% and 3%, are missed by the limb's pixels over the terminator, a few pixels at
    # this size).
    pixel, vertex_image = _both_renderers(preset, "orbit, terminator")
    difference = floored_difference(vertex_image, pixel)
    assert np.sqrt(np.mean(difference ** 2)) < 0.04
    assert np.percentile(difference, 99) < 0.08


@pytest.mark.parametrize("view", ["aircraft, 10 km", "ground, sunset"])
def test_the_forward_lobe_around_the_sun_matches_the_per_pixel_renderer(view):
    # Mars's dust puts 95-97% of its scattering in a forward lobe (g = 0.86-0.91), which changes the sky around the
    # sun faster than the mesh resolves; the fragments evaluate phase_factor at their own view-sun angle. Bounds: the
    # issue's targets, 1% RMS and 3% at the 99th percentile (floored difference); measured here (320x180, draft
    # tables) 0.13-0.29% / 0.5-1.1%, and 1.0-1.2% / 4.2-5.4% without the phase factor.
    pixel, vertex_image = _both_renderers("mars", view)
    difference = floored_difference(vertex_image, pixel)
    assert np.sqrt(np.mean(difference ** 2)) < 0.01
    assert np.percentile(difference, 99) < 0.03


def test_the_path_opacity_table_follows_the_camera_altitude(vertex):
    # The per-pixel path opacities come from a table made for the frame's ray altitude (shaders/inscatter_factor.glsl);
    # moved from 2 m to 10 km up, the scene must draw what a scene made at 10 km draws. A table left at 2 m reads
    # every ray's opacity at the wrong place (several times off along the horizon).
    set_view(vertex, "ground")
    vertex.render_hdr()
    set_view(vertex, "aircraft")
    moved = vertex.render_hdr().radiance
    fresh = Scene("earth", quality="draft", surface=None, off_screen=True, window_size=SIZE, shading="vertex")
    try:
        set_view(fresh, "aircraft")
        want = fresh.render_hdr().radiance
    finally:
        fresh.close()
    np.testing.assert_allclose(moved, want, rtol=1e-5, atol=0)   # the same draw: equal but for float rounding


#: The rows of docs/benchmarks.md's per-vertex accuracy table that miss the issue's targets, and which of the two
#: they miss (1280x720, standard): the night side from orbit on Earth and the thick planet, 2.2-2.5% RMS (p99 within
#: 3%). What limits it is written there: on Earth the ground's terminator seen edge-on 3-30 pixels inside the limb,
#: where the aerial perspective falls 2-3 times per pixel and the mesh's rings are 4-5 pixels apart; on the thick
#: planet also the halo within 3 pixels above the limb where the planet's shadow meets it.
KNOWN_MISSES = {(preset, "orbit, night side"): {"rms"} for preset in ("earth", "exo-co2-thick")}
#: The issue's targets: RMS and 99th percentile of the floored relative difference.
TARGETS = {"rms": 0.01, "p99": 0.03}
#: What a known miss may not exceed: twice the targets, the RMS ceiling what the draft tables read per vertex
#: differ from the standard ones per pixel in Earth's daylight views (0.5-2.0%, docs/rendering.md), the error of a
#: coarser table; or, where it errs more in the same frame, the quick view, which reads no 4D table (a per-vertex
#: reading of the tables that errs more than a picture without them would be a broken interpolation, not a miss of
#: the issue's finer target).
MISS_CEILINGS = {"rms": 0.02, "p99": 0.06}


@pytest.mark.slow
@pytest.mark.parametrize("preset", ["earth", "mars", "exo-co2-thick"])
@pytest.mark.parametrize("view", list(VIEWS))
def test_every_view_class_per_vertex_is_the_per_pixel_picture(scene_pairs, preset, view):
    # The targets, in the frames of docs/benchmarks.md's table (1280x720, standard tables, CIE Y, the
    # difference floored at 1% of the frame's 99th percentile): 1% RMS and 3% at the 99th percentile. Both sides
    # read the same tables, so the bound is the interpolation's alone, with nothing to allow for noise. Every figure
    # a row meets is held to its target; a figure in KNOWN_MISSES that misses it marks the test as an expected
    # failure, and one that meets it fails the test, so that the docs and KNOWN_MISSES are brought up to date.
    if preset not in scene_pairs:
        scene_pairs[preset] = tuple(
            Scene(preset, quality="standard", surface="texture", off_screen=True, window_size=(1280, 720),
                  shading=shading) for shading in ("pixel", "vertex"))
    pixel, vertex = (view_luminance(scene, VIEWS[view]) for scene in scene_pairs[preset])

    def figures_of(picture):
        difference = floored_difference(picture, pixel)
        return {"rms": np.sqrt(np.mean(difference ** 2)), "p99": np.percentile(difference, 99)}
    misses = KNOWN_MISSES.get((preset, view), set())
    ceilings = MISS_CEILINGS
    if misses:
        quick = Scene(preset, surface="texture", off_screen=True, window_size=(1280, 720), method="quick")
        try:
            quick_figures = figures_of(view_luminance(quick, VIEWS[view]))
        finally:
            quick.close()
        ceilings = {name: max(value, quick_figures[name]) for name, value in MISS_CEILINGS.items()}
    hold_to_targets(figures_of(vertex), TARGETS, misses, "docs/benchmarks.md 'Accuracy of per-vertex reading'",
                    ceilings=ceilings)
