"""Whole-sky pictures through the renderer: the six faces of a cube around the camera, each a square frame with a
90 deg field of view read back as linear radiance, and any set of directions (a dome master, a panorama) read
from them.

1. :func:`render_cube` turns the camera toward each face (its forward and up axes in :data:`FACES`, in the
   camera site's local frame), renders it at ``face_size`` square pixels (``Scene.render_hdr``) and puts the
   window and the camera back.
2. :func:`sample_cube` reads each direction from the face it points into: the pixel coordinates of its
   intersection with the face's plane, bilinear between the four nearest pixel centres (clamped at the face's
   edges, half a pixel).

The NumPy evaluator along the same directions (:func:`planetviz.tables.panorama.render_directions`) is the check
(tests/test_cube_faces.py).
"""
from __future__ import annotations

import numpy as np

from ..model.geometry import local_frame, site_of
from .uniforms import camera_uniforms

#: (forward, up) of each face in the site's (east, north, up) frame.
FACES = (((1, 0, 0), (0, 0, 1)), ((-1, 0, 0), (0, 0, 1)), ((0, 1, 0), (0, 0, 1)), ((0, -1, 0), (0, 0, 1)),
         ((0, 0, 1), (0, -1, 0)), ((0, 0, -1), (0, 1, 0)))


def render_cube(scene, face_size, directions=None):
    """(faces (6, n, n, W) radiance per unit solar irradiance [1/sr], bases (6, 3, 3): each face's unit forward,
    right and up vectors, planet-centred) of the view around ``scene``'s camera; with ``directions`` (..., 3),
    only the faces they point into are rendered (the others stay 0: a dome master needs five)."""
    cam = scene.renderer.GetActiveCamera()
    saved = (cam.GetPosition(), cam.GetFocalPoint(), cam.GetViewUp(), cam.GetViewAngle(), tuple(scene.window_size))
    position = np.array(saved[0])
    east_north_up = np.array(local_frame(*site_of(position)))[[1, 2, 0]]       # rows: east, north, up
    faces, bases = [], []
    try:
        scene.window_size = (face_size, face_size)
        needed = _faces_needed(directions, east_north_up)
        for k, (forward, up) in enumerate(FACES):
            f, u = np.asarray(forward, float) @ east_north_up, np.asarray(up, float) @ east_north_up
            scene.set_view(position, f, up=u, fov=90.0)
            view = camera_uniforms(scene.renderer)
            bases.append([view[name][1] / np.linalg.norm(view[name][1])
                          for name in ("camera_forward", "camera_right", "camera_up")])
            faces.append(scene.render_hdr().radiance if needed[k] else None)
    finally:
        scene.window_size = saved[4]
        cam.SetPosition(*saved[0])
        cam.SetFocalPoint(*saved[1])
        cam.SetViewUp(*saved[2])
        cam.SetViewAngle(saved[3])
        scene.renderer.ResetCameraClippingRange()
    shape = next(f.shape for f in faces if f is not None)
    return np.stack([f if f is not None else np.zeros(shape, np.float32) for f in faces]), np.array(bases)


def _faces_needed(directions, east_north_up):
    """Which faces some direction points into (all six without directions)."""
    if directions is None:
        return [True] * len(FACES)
    d = directions.reshape(-1, 3)
    d = d[np.all(np.isfinite(d), axis=1)]
    forwards = np.array([forward for forward, _ in FACES], float) @ east_north_up
    return np.isin(np.arange(len(FACES)), np.unique(np.argmax(d @ forwards.T, axis=1)))


def render_directions(scene, directions, face_size, shading="vertex"):
    """Radiance (..., W) along ``directions`` (..., 3) from ``scene``'s camera, through a cube of ``face_size``
    pixels (:func:`render_cube`, :func:`sample_cube`) whose faces read the tables with ``shading`` (per vertex:
    about 10x faster than per pixel on a software OpenGL, within 0.3% RMS of the NumPy evaluator away from the
    horizon, docs/rendering.md); NaN directions give 0."""
    before = scene.shading
    if scene.planet is not None and shading != before:
        scene.set_shading(shading)
    try:
        faces, bases = render_cube(scene, face_size, directions)
    finally:
        if scene.shading != before:
            scene.set_shading(before)
    return sample_cube(faces, bases, directions)


def sample_cube(faces, bases, directions):
    """Radiance (..., W) along unit ``directions`` (..., 3) from the cube :func:`render_cube` made; NaN
    directions give 0."""
    shape = directions.shape[:-1]
    d = directions.reshape(-1, 3).astype(np.float32)
    out = np.zeros((len(d), faces.shape[-1]), np.float32)
    valid = np.all(np.isfinite(d), axis=1)
    d[~valid] = 0.0
    face = np.argmax(d @ bases[:, 0].T.astype(np.float32), axis=1)
    n = faces.shape[1]
    for k in range(len(faces)):
        sel = np.nonzero(valid & (face == k))[0]
        if not sel.size:
            continue
        forward, right, up = bases[k].astype(np.float32)
        depth = d[sel] @ forward
        x = (d[sel] @ right / depth + 1.0) / 2.0 * n - 0.5            # column, from the left
        y = (1.0 - d[sel] @ up / depth) / 2.0 * n - 0.5               # row, from the top
        x, y = np.clip(x, 0.0, n - 1.0), np.clip(y, 0.0, n - 1.0)
        c0, r0 = np.minimum(x.astype(int), n - 2), np.minimum(y.astype(int), n - 2)
        fx, fy = (x - c0)[:, None], (y - r0)[:, None]
        img = faces[k]
        out[sel] = ((1 - fy) * ((1 - fx) * img[r0, c0] + fx * img[r0, c0 + 1])
                    + fy * ((1 - fx) * img[r0 + 1, c0] + fx * img[r0 + 1, c0 + 1]))
    return out.reshape(shape + (faces.shape[-1],))
