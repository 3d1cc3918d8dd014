"""The planet's surface map: the cube of faces the shaders read (planetviz/render/surface.py, cube_face_uv in
shaders/pixel.glsl) against the equirectangular map it is built from, in NumPy and through the renderer."""
import dataclasses
import os

import numpy as np
import pytest

os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkOSOpenGLRenderWindow")

from planetviz.model.color import albedo_matrix  # noqa: E402
from planetviz.render import Scene  # noqa: E402
from planetviz.render.surface import (cube_face_uv, equirect_colour, srgb_decode, srgb_encode,  # noqa: E402
                                      surface_cube)
from planetviz.tables.evaluator import sky_radiance  # noqa: E402


def smooth_map(h=128, w=256):
    """An sRGB map whose colours are smooth functions of the direction (no seam at the date line or the
    poles), so resampling it costs only the interpolation error of a slowly varying function."""
    lat = (0.5 - (np.arange(h) + 0.5) / h) * np.pi
    lon = ((np.arange(w) + 0.5) / w - 0.5) * 2 * np.pi
    lat, lon = np.meshgrid(lat, lon, indexing="ij")
    n = np.stack([np.cos(lat) * np.cos(lon), np.cos(lat) * np.sin(lon), np.sin(lat)], -1)
    linear = 0.35 + 0.25 * np.stack([np.sin(2 * n[..., 0] + 1), np.cos(3 * n[..., 1]), n[..., 2] * n[..., 0]], -1)
    return np.rint(255 * srgb_encode(linear)).astype(np.uint8)


def cube_colour(cube, n):
    """NumPy bilinear lookup of the faces at the unit directions n, as the GPU filters a 2D array texture."""
    size = cube.shape[1] - 2
    u, v, layer = cube_face_uv(n, size)
    linear = srgb_decode(cube / 255.0)
    x, y = u * (size + 2) - 0.5, v * (size + 2) - 0.5
    x0, y0 = np.floor(x).astype(int), np.floor(y).astype(int)
    fx, fy = (x - x0)[:, None], (y - y0)[:, None]
    return ((1 - fy) * ((1 - fx) * linear[layer, y0, x0] + fx * linear[layer, y0, x0 + 1])
            + fy * ((1 - fx) * linear[layer, y0 + 1, x0] + fx * linear[layer, y0 + 1, x0 + 1]))


def test_the_cube_reproduces_the_map_on_faces_edges_and_corners():
    image = smooth_map()
    cube = surface_cube(image)
    rng = np.random.default_rng(3)
    n = rng.normal(size=(4000, 3))
    # Directions on the faces' edges and corners (ties between components), where a lookup changes faces.
    edges = np.array([[1, 1, 0.3], [1, -1, -0.2], [-1, 0.4, 1], [0.1, -1, -1], [1, 1, 1], [-1, -1, -1], [0, 0, 1]])
    n = np.concatenate([n, edges])
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    want, got = equirect_colour(image, n), cube_colour(cube, n)
    # Both read the same 8-bit map at different points: its own rounding steps (one sRGB step is at most 6.3e-3
    # in linear value at these levels, 0.1 to 0.6) can fall between the two reads, plus the cube's rounding to 8
    # bits (half a step) and the interpolation error of this slowly varying map (~1e-4): at most 1.5 steps, 9e-3.
    # Measured largest: 4.7e-3 (4.2e-3 without the cube's rounding), near the poles. A face read mirrored or
    # the wrong face is off by ~0.1.
    assert np.abs(got - want).max() < 9e-3


@pytest.mark.parametrize("shading, change", [("pixel", False), ("vertex", False), ("vertex", True)])
def test_the_ground_shows_the_map_through_the_atmosphere(shading, change):
    # The ground's radiance is linear in its albedo: L = L(albedo 0) + albedo (L(albedo 1) - L(albedo 0)) per
    # wavelength, with albedo = colour @ albedo_matrix; the colour read from the cube in NumPy (cube_face_uv, the
    # GLSL function's twin) and the two radiances from the NumPy evaluator. Per vertex the points are the pixels'
    # own directions (no interpolation between vertices). Bound: the shader's 1% float32 agreement
    # (tests/test_render.py); the GPU's 8-bit filtering weights add under 1e-4 here (neighbouring texels of this
    # smooth map differ by a few 1e-3). ``change``: the frame after a change of atmosphere (the map replaces its
    # uniform albedo, so the picture stays), drawn by a new actor with the texture the first actor uploaded, which
    # releasing that actor must leave alive.
    image = smooth_map()
    size = (64, 48)
    scene = Scene("earth", quality="draft", surface=image, off_screen=True, window_size=size, shading=shading)
    try:
        scene.view_from_space(distance=1.8e7, latitude=25, longitude=40, fov=40)
        scene.set_sun(elevation=50, azimuth=200, latitude=25, longitude=40)
        if change:
            scene.render_hdr()
            first = scene.planet.textures._textures["surface_faces"]
            W = len(scene.atmosphere.wavelengths_nm)
            scene.set_atmosphere(scene.atmosphere.replace(ground_albedo=(0.3,) * W), wait=True)
        rows, cols = np.meshgrid(np.arange(1, size[1], 3), np.arange(1, size[0], 3), indexing="ij")
        dirs = scene.pixel_directions(rows, cols).reshape(-1, 3)
        if shading == "vertex":
            scene.planet.directions = dirs
        got = scene.render_hdr().radiance[rows, cols].reshape(-1, 3)
        if change:
            assert scene.planet.textures._textures["surface_faces"] is first
        atm, cam = scene.atmosphere, np.tile(scene.camera_location, (len(dirs), 1))
        W = len(atm.wavelengths_nm)
        dark, _ = sky_radiance(scene.planet.tables, dataclasses.replace(atm, ground_albedo=(0.0,) * W), cam, dirs,
                               scene.sun_direction)
        white, _ = sky_radiance(scene.planet.tables, dataclasses.replace(atm, ground_albedo=(1.0,) * W), cam, dirs,
                                scene.sun_direction)
    finally:
        scene.close()
    ground = white.max(-1) > 1.05 * dark.max(-1)
    t = cam[0] @ -dirs.T                                    # the ground point along each ray (unit sphere)
    hit = cam + dirs * (t - np.sqrt(np.maximum(t ** 2 - cam[0] @ cam[0] + atm.bottom_radius_m ** 2, 0)))[:, None]
    colour = cube_colour(surface_cube(image), hit / np.linalg.norm(hit, axis=1, keepdims=True))
    albedo = colour @ albedo_matrix(atm.wavelengths_nm)
    want = dark + albedo * (white - dark)
    assert ground.sum() > 100
    rel = np.abs(got - want)[ground] / want[ground]
    assert rel.max() < 0.01, rel.max()
