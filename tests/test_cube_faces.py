"""Dome masters and panoramas through the renderer (planetviz/render/cube_faces.py) against the NumPy evaluator
along the same directions (planetviz/tables/panorama.py)."""
import numpy as np
import pytest

from planetviz.app.sky_images import SkyImage
from planetviz.model.geometry import local_frame, site_of
from planetviz.render import Scene
from planetviz.render.cube_faces import render_cube, render_directions, sample_cube
from planetviz.tables.panorama import equirectangular_directions, fisheye_directions
from planetviz.tables.panorama import render_directions as evaluator_directions


@pytest.fixture(scope="module")
def earth():
    # The atmosphere file's ground albedo (no texture): the evaluator has no surface texture.
    scene = Scene("earth", quality="draft", surface=None, off_screen=True, window_size=(64, 48))
    scene.settings.show_sun = False            # the evaluator draws no sun disc
    yield scene
    scene.close()


def relative_errors(scene, dirs, got):
    """Per direction and wavelength |got - evaluator| / evaluator, and whether the direction is more than 0.5 deg
    from the horizon's (the dip included)."""
    cam = scene.camera_location
    want = evaluator_directions(scene.planet.tables, scene.atmosphere, cam, dirs, scene.sun_direction)
    ok = np.all(np.isfinite(dirs), axis=-1)
    up = local_frame(*site_of(cam))[0]
    dip = np.degrees(np.arccos(min(1.0, scene.atmosphere.bottom_radius_m / np.linalg.norm(cam))))
    elevation = np.degrees(np.arcsin(np.clip(dirs[ok] @ up, -1.0, 1.0)))
    return np.abs(got[ok] - want[ok]) / want[ok], np.abs(elevation + dip) > 0.5


@pytest.mark.parametrize("altitude, sun", [(1.7, 15.0), (1e4, 3.0)])
def test_dome_and_panorama_through_the_renderer_match_the_evaluator(earth, altitude, sun):
    # The faces read the tables per vertex (docs/benchmarks.md: 0.4% RMS against per pixel from the ground) and
    # are resampled bilinearly at 0.7 deg per face pixel (128 across 90 deg) over a sky that changes by well
    # under 1% per pixel away from the sun and the horizon: within 1% RMS and 3% at the 99th percentile. The
    # horizon (a step between sky and ground) is blurred over a face pixel by any resampling and is left out
    # (0.5 deg either side).
    earth.view_from_ground(latitude=30, altitude=altitude, heading=90, pitch=5)
    earth.set_sun(elevation=sun, azimuth=100, latitude=30, longitude=0)
    cam = earth.camera_location
    for dirs in (fisheye_directions(cam, 256), equirectangular_directions(cam, 512, 256)):
        rel, away = relative_errors(earth, dirs, render_directions(earth, dirs, 128))
        assert np.sqrt(np.mean(rel[away] ** 2)) < 0.01
        assert np.percentile(rel[away], 99) < 0.03


def test_no_seam_where_the_faces_meet(earth):
    # Directions within a face pixel of a face's edge are read from that face's outermost pixels: they must
    # match the evaluator as the rest do (the bound above), and a face read mirrored or turned would be tens of
    # percent off there.
    earth.view_from_ground(latitude=30, altitude=1e4, heading=90, pitch=5)
    earth.set_sun(elevation=20, azimuth=100, latitude=30, longitude=0)
    cam = earth.camera_location
    dirs = equirectangular_directions(cam, 512, 256)
    faces, bases = render_cube(earth, 128, dirs)
    d = dirs.reshape(-1, 3)
    along = d @ bases[:, 0].T
    k = np.argmax(along, axis=1)
    u = np.einsum("ij,ij->i", d, bases[k, 1]) / along[np.arange(len(d)), k]
    v = np.einsum("ij,ij->i", d, bases[k, 2]) / along[np.arange(len(d)), k]
    edge = (np.maximum(np.abs(u), np.abs(v)) > 1 - 2.0 / 128).reshape(dirs.shape[:-1])
    rel, away = relative_errors(earth, dirs[edge], sample_cube(faces, bases, dirs[edge]))
    assert edge.sum() > 1000
    assert np.sqrt(np.mean(rel[away] ** 2)) < 0.01


@pytest.mark.parametrize("tilt", [0.0, 25.0, 90.0])
def test_a_tilted_dome_master_points_its_centre_and_edges_where_the_tilt_says(tilt):
    # The dome's centre is turned from the zenith toward the heading: it looks 90 - tilt deg above the horizon at
    # the heading; the middle of the image's bottom edge (90 deg from the centre toward the bottom) looks tilt deg
    # below the horizon at the heading, the top edge's middle tilt deg above it behind; the left and right edges'
    # middles along the horizon 90 deg right and left of the heading. Closed forms in the site's frame; the
    # directions are float32 (bound 1e-6, against an angle of 4e-3 rad between neighbouring pixels here).
    cam = np.array([0.0, 0.0, 6.36e6 + 2.0])                    # over the north pole: up = +z
    heading = 30.0
    up, east, north = local_frame(*site_of(cam))
    h = np.cos(np.radians(heading)) * north + np.sin(np.radians(heading)) * east
    side = -np.sin(np.radians(heading)) * north + np.cos(np.radians(heading)) * east
    t = np.radians(tilt)
    n = 401                                                         # an odd size: pixels at the centre lines
    d = fisheye_directions(cam, n, heading_deg=heading, tilt_deg=tilt)
    mid = n // 2
    assert np.allclose(d[mid, mid], np.cos(t) * up + np.sin(t) * h, atol=1e-6)
    edge = 1.0 - 1.0 / n                                            # the outermost pixel centre's radius
    for pixel, angle_sign in (((n - 1, mid), 1), ((0, mid), -1)):
        z = np.radians(90.0) * edge
        axis = np.cos(t) * up + np.sin(t) * h
        down = np.cos(t) * h - np.sin(t) * up
        want = np.cos(z) * axis + angle_sign * np.sin(z) * down
        assert np.allclose(d[pixel], want, atol=1e-6)
    assert np.allclose(d[mid, n - 1] @ up, np.cos(np.radians(90.0) * edge) * np.cos(t), atol=1e-6)
    assert np.allclose(d[mid, n - 1] @ side, np.sin(np.radians(90.0) * edge), atol=1e-6)
    with pytest.raises(ValueError, match="fisheye-tilt: 0 to 90 deg"):
        SkyImage("dome.png", "fisheye", 64, 64, tilt_deg=95.0)
