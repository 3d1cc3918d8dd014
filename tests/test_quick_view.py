"""The quick view (per vertex, no 4D tables): the vertex shader against its NumPy twin (single scattering with
and without Hillaire's table for the orders above), the adaptive mesh, and the progressive switch between the
quick view and the tables."""
import os

import numpy as np
import pytest

os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkOSOpenGLRenderWindow")

from planetviz import load_atmosphere  # noqa: E402
from planetviz.quick_view.single_scattering import quick_view_radiance  # noqa: E402
from planetviz.render import Scene  # noqa: E402
from planetviz.render.direction_mesh import LIMB_STRADDLE, direction_mesh  # noqa: E402

SIZE = (64, 48)


@pytest.fixture(scope="module")
def quick():
    scene = Scene("earth", quality="draft", surface=None, off_screen=True, window_size=SIZE, method="quick")
    yield scene
    scene.close()


@pytest.mark.parametrize("view", ["ground", "standing", "aircraft", "space", "artistic", "single", "twilight"])
def test_vertex_shader_matches_its_numpy_twin(quick, view):
    # One vertex per sampled pixel (a point cloud at the pixels' directions), so each pixel holds one vertex's
    # value with no interpolation: the GLSL and NumPy integrators must agree. Both evaluate the same sums; the
    # shader in float32 (positions to 0.5 m at 6.4e6 m, exp of optical depths to 1e-7 relative): bound 2e-3,
    # measured 2e-4. "standing": 1.7 m up looking 2 deg down, the sun low ahead, where the aerial perspective
    # of the near ground is proportional to the camera's height (a float32 camera radius, 1.5 m, read 6% off).
    # "twilight": the sun 4 deg down, where only the orders above the first light the sky and the ground.
    terms = "artistic" if view == "artistic" else "physical"
    orders = "single" if view == "single" else "all"
    if view == "twilight":
        quick.view_from_ground(latitude=20, altitude=2.0, heading=80, pitch=-3, fov=70)
        quick.set_sun(elevation=-4, azimuth=100, latitude=20, longitude=0)
    elif view in ("ground", "artistic", "single"):
        quick.view_from_ground(latitude=20, altitude=2.0, heading=80, pitch=5, fov=70)
        quick.set_sun(elevation=15, azimuth=100, latitude=20, longitude=0)
    elif view == "standing":
        quick.view_from_ground(latitude=20, altitude=1.7, heading=90, pitch=-2, fov=20)
        quick.set_sun(elevation=1, azimuth=90, latitude=20, longitude=0)
    elif view == "aircraft":
        quick.view_from_ground(latitude=20, altitude=1e4, heading=200, pitch=-10, fov=70)
        quick.set_sun(elevation=5, azimuth=180, latitude=20, longitude=0)
    else:
        quick.view_from_space(distance=2e7, latitude=10, longitude=20, fov=40)
        quick.set_sun(elevation=40, azimuth=120, latitude=10, longitude=20)
    rows, cols = np.meshgrid(np.arange(1, SIZE[1], 4), np.arange(1, SIZE[0], 5), indexing="ij")
    dirs = quick.pixel_directions(rows, cols).reshape(-1, 3)
    quick.quick_terms, quick.quick_orders = terms, orders
    quick.set_atmosphere(quick.atmosphere)                 # rebuilds the quick view with these terms and orders
    quick.quick.directions = dirs
    actor = quick.quick
    try:
        got = quick.render_hdr().radiance[rows, cols].reshape(-1, 3)
    finally:
        quick.quick_terms, quick.quick_orders = "physical", "all"
        quick.set_atmosphere(quick.atmosphere)
    assert (actor.multiple is None) == (view in ("single", "artistic"))
    want, _ = quick_view_radiance(quick.atmosphere, np.tile(quick.camera_location, (len(dirs), 1)), dirs,
                                  quick.sun_direction, samples=quick.quick_samples, terms=terms,
                                  multiple=actor.multiple, ground_sky=actor.ground_sky)
    seen = want.max(-1) > 0
    assert seen.sum() > 50 and np.array_equal(got.max(-1) > 0, seen)
    # Relative to the value, floored at 1e-6 of the brightest: the GPU filters textures with 8-bit weights
    # (llvmpipe), so where a table falls by orders of magnitude from one texel to the next (the sky's irradiance on
    # the night side's ground, 1e-12 of the frame) a read is off by up to 2^-9 of the step, far above 2e-3 of it.
    floor = 1e-6 * want.max()
    assert np.max(np.abs(got - want)[seen] / np.maximum(want, floor)[seen]) < 2e-3


def test_each_kind_of_density_profile_matches_the_numpy_twin():
    # The shader is compiled for the atmosphere's profile kinds (quick_view_actor.shader_constants): the Earth
    # preset's ozone is a tent (the test above), the advanced Earth's a table beside exponential layers. Same sums,
    # same bound as above.
    atm = load_atmosphere("earth-advanced")
    scene = Scene(atm, quality="draft", surface=None, off_screen=True, window_size=SIZE, method="quick",
                  quick_orders="single")
    try:
        scene.view_from_ground(latitude=20, altitude=2.0, heading=80, pitch=5, fov=70)
        scene.set_sun(elevation=15, azimuth=100, latitude=20, longitude=0)
        rows, cols = np.meshgrid(np.arange(1, SIZE[1], 4), np.arange(1, SIZE[0], 5), indexing="ij")
        dirs = scene.pixel_directions(rows, cols).reshape(-1, 3)
        scene.quick.directions = dirs
        got = scene.render_hdr().radiance[rows, cols].reshape(-1, 3)
        want, _ = quick_view_radiance(atm, np.tile(scene.camera_location, (len(dirs), 1)), dirs,
                                      scene.sun_direction, samples=scene.quick_samples)
    finally:
        scene.close()
    seen = want.max(-1) > 0
    assert seen.sum() > 50
    assert np.max(np.abs(got - want)[seen] / want[seen]) < 2e-3


def test_the_mesh_is_dense_around_the_sun_and_straddles_the_horizon():
    atm = load_atmosphere("earth")
    R = atm.bottom_radius_m
    cam = np.array([0.0, 0.0, R + 2.0])
    sun = np.array([np.cos(0.3), 0.0, np.sin(0.3)])
    mesh = direction_mesh(cam, sun, R, atm.top_radius_m)
    dirs, tris = mesh.directions, mesh.triangles
    angle = np.degrees(np.arccos(np.clip(dirs @ sun, -1, 1)))
    # Vertices per square degree within 3 deg of the sun against the sky's average: the paper's adaptive dome.
    near = (angle < 3).sum() / (np.pi * 3 ** 2)
    everywhere = len(dirs) / 41253.0
    assert near > 5 * everywhere, (near, everywhere)
    # Rings LIMB_STRADDLE either side of the horizon (the dip below the horizontal at 2 m): the horizon's step in
    # brightness falls between two rings instead of being smeared over a triangle.
    dip = np.arccos(R / (R + 2.0))
    elevation = np.arcsin(np.clip(dirs @ (cam / np.linalg.norm(cam)), -1, 1))
    for side in (-1, 1):
        assert np.any(np.abs(elevation - (-dip + side * LIMB_STRADDLE)) < 2e-6)
    assert tris.max() < len(dirs)


@pytest.mark.parametrize("sun_angle_deg", [5.0, 100.0, 150.0])
def test_from_space_the_mesh_has_sectors_where_the_planets_shadow_meets_the_halo(sun_angle_deg):
    # The sectors of _shadow_limb_azimuths against an independent search: for each tangent radius r_h of
    # SHADOW_LIMB_SECTORS, the azimuths (about the mesh's nadir) at which the tangent point of the ray grazing the
    # sphere r_h, built from the mesh's own axes, lies on the edge of the planet's shadow cylinder (its dot with
    # the sun -sqrt(r_h^2 - R^2)), found by bisecting a sign change on a grid of 20,000 azimuths. Bisection to 1e-12
    # rad; the mesh's float64 closed form agrees to rounding, so a sector within 1e-9 rad of each root.
    from planetviz.render.direction_mesh import SHADOW_LIMB_SECTORS
    R, top = 6.36e6, 6.46e6
    up = np.array([0.3, -0.2, 0.93])
    up /= np.linalg.norm(up)
    cam = 4.0 * R * up
    a = np.radians(sun_angle_deg)                                   # the sun's angle from the camera's zenith
    side = np.cross(up, [1.0, 0.0, 0.0])
    side /= np.linalg.norm(side)
    sun = np.cos(a) * up + np.sin(a) * side
    mesh = direction_mesh(cam, sun, R, top)

    def edge(phi, r_h):
        sin_t = r_h / (4.0 * R)
        phi = np.atleast_1d(phi)[:, None]
        u = np.cos(phi) * mesh.e1 + np.sin(phi) * mesh.e2
        tangent = 4.0 * R * sin_t * (-sin_t * mesh.down + np.sqrt(1.0 - sin_t ** 2) * u)
        return tangent @ sun + np.sqrt(r_h ** 2 - R ** 2)

    found = 0
    grid = np.linspace(-np.pi, np.pi, 20001)
    for r_h in R + (top - R) * np.linspace(0.0, 1.0, SHADOW_LIMB_SECTORS) ** 2:
        values = edge(grid, r_h)
        for k in np.nonzero(np.sign(values[:-1]) != np.sign(values[1:]))[0]:
            lo, hi = grid[k], grid[k + 1]
            for _ in range(60):
                mid = 0.5 * (lo + hi)
                lo, hi = (mid, hi) if np.sign(edge(mid, r_h)[0]) == np.sign(values[k]) else (lo, mid)
            assert np.min(np.abs(mesh.phi - 0.5 * (lo + hi))) < 1e-9, (r_h - R, 0.5 * (lo + hi))
            found += 1
    # With the sun 100 or 150 deg from the camera's zenith the shadow's edge crosses the halo on both sides of the
    # sun at every tangent radius; with the sun 5 deg from it the whole disc and halo in view are lit (the
    # terminator lies beyond the limb, 85 deg from the sub-camera point against the limb's 75.5).
    assert found == (0 if sun_angle_deg == 5.0 else 2 * SHADOW_LIMB_SECTORS), found


def test_a_change_that_needs_tables_shows_the_quick_view_until_they_are_ready():
    earth = load_atmosphere("earth")
    scene = Scene(earth, quality="draft", surface=None, off_screen=True, window_size=SIZE, cache=False)
    try:
        scene.view_from_ground(latitude=0, heading=90, pitch=10)
        assert scene.renderer_in_use == "tables"
        # The sun, the camera or the exposure need no tables: no switch, no background job.
        scene.set_sun(elevation=20, azimuth=100, latitude=0, longitude=0)
        scene.settings.exposure = 2e-4
        assert scene.renderer_in_use == "tables" and scene.precompute_progress is None
        before = scene.render_hdr().radiance
        # A new albedo needs new multiple-scattering tables: the quick view at once, tables in the background.
        brighter = earth.replace(ground_albedo=[0.6, 0.6, 0.6])
        scene.set_atmosphere(brighter)
        assert scene.renderer_in_use == "quick"
        assert scene.precompute_progress is not None
        quick_image = scene.render_hdr().radiance
        assert np.all(np.isfinite(quick_image)) and quick_image.max() > 0
        scene.wait_for_tables(timeout=120)
        assert scene.renderer_in_use == "tables" and scene.table_error is None
        after = scene.render_hdr().radiance
        # The new tables are the new atmosphere's: a brighter ground reflects more light into the sky.
        sky = before.max(-1) > 0
        assert np.mean(after[sky]) > 1.02 * np.mean(before[sky])
    finally:
        scene.close()
