"""Planet surface colour maps: equirectangular sRGB images in ``assets/textures`` (see the README there)."""
from __future__ import annotations

import hashlib
from pathlib import Path

import numpy as np

from ..resources import asset_dir
from .textures import upload

TEXTURES = asset_dir("textures")

#: Texture file per planet, by the start of the atmosphere's name.
PLANET_TEXTURES = {"earth": "earth.jpg", "mars": "mars.png"}


def read_image(path):
    """(h, w, 3) uint8 image, top row first; a clear error when the file is missing or unreadable."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkIOImage import vtkImageReader2Factory
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"surface texture {path} not found")
    reader = vtkImageReader2Factory.CreateImageReader2(str(path))
    if reader is None:
        raise ValueError(f"surface texture {path}: not an image format VTK reads (PNG, JPEG)")
    reader.SetFileName(str(path))
    reader.Update()
    image = reader.GetOutput()
    w, h, _ = image.GetDimensions()
    data = vtk_to_numpy(image.GetPointData().GetScalars()).reshape(h, w, -1)
    if data.shape[-1] < 3 or data.dtype != np.uint8:
        raise ValueError(f"surface texture {path}: an 8-bit RGB image is needed")
    return np.ascontiguousarray(data[::-1, :, :3])


def write_image(path, rgb):
    """Write an (h, w, 3) uint8 image, top row first, as PNG."""
    from vtkmodules.util.numpy_support import numpy_to_vtk
    from vtkmodules.vtkCommonDataModel import vtkImageData
    from vtkmodules.vtkIOImage import vtkPNGWriter
    h, w, _ = rgb.shape
    image = vtkImageData()
    image.SetDimensions(w, h, 1)
    image.GetPointData().SetScalars(numpy_to_vtk(np.ascontiguousarray(rgb[::-1]).reshape(-1, 3)))
    writer = vtkPNGWriter()
    writer.SetFileName(str(path))
    writer.SetInputData(image)
    writer.Write()


def surface_texture(atm):
    """The colour map of the atmosphere's planet, or None (uniform ground albedo) when there is none."""
    for prefix, name in PLANET_TEXTURES.items():
        if atm.name.startswith(prefix):
            return read_image(TEXTURES / name)
    return None


def srgb_decode(c):
    """sRGB-encoded values in [0, 1] -> linear (IEC 61966-2-1, the GPU's GL_SRGB8 decoding)."""
    c = np.asarray(c, dtype=np.float64)
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def srgb_encode(c):
    """Linear values in [0, 1] -> sRGB-encoded (the inverse of :func:`srgb_decode`), in the input's float type."""
    c = np.clip(c, 0.0, 1.0)
    return np.where(c <= 0.0031308, 12.92 * c, 1.055 * c ** (1 / 2.4) - 0.055)


def equirect_colour(image, n):
    """Linear colour (..., 3) of the equirectangular sRGB ``image`` (h, w, 3 uint8, top row north) at the unit
    directions ``n`` (..., 3), bilinear in linear values with longitude wrapping: the map read directly, which
    :func:`surface_cube` resamples and is tested against."""
    return _bilinear(_linear_rows(image), np.asarray(n))


def _linear_rows(image):
    """The sRGB ``image`` decoded to linear float32, south row first (as the sampling counts rows)."""
    return srgb_decode(np.arange(256) / 255.0).astype(np.float32)[np.asarray(image)[::-1]]


def _bilinear(linear, n):
    h, w, _ = linear.shape
    x = (np.arctan2(n[..., 1], n[..., 0]) / (2 * np.pi) + 0.5) * w - 0.5
    y = (np.arcsin(np.clip(n[..., 2], -1.0, 1.0)) / np.pi + 0.5) * h - 0.5
    x0, y0 = np.floor(x), np.floor(y)
    fx, fy = (x - x0)[..., None].astype(np.float32), (y - y0)[..., None].astype(np.float32)
    xa = x0.astype(np.int64) % w
    xb = (xa + 1) % w
    ya = np.clip(y0.astype(np.int64), 0, h - 1) * w
    yb = np.clip(y0.astype(np.int64) + 1, 0, h - 1) * w
    flat = linear.reshape(-1, 3)
    return ((1 - fy) * ((1 - fx) * np.take(flat, ya + xa, axis=0) + fx * np.take(flat, ya + xb, axis=0))
            + fy * ((1 - fx) * np.take(flat, yb + xa, axis=0) + fx * np.take(flat, yb + xb, axis=0)))


#: The cube's faces in layer order: (major axis, sign, the axes of the face's s and t coordinates).
CUBE_FACES = ((0, 1.0, 1, 2), (0, -1.0, 1, 2), (1, 1.0, 0, 2), (1, -1.0, 0, 2), (2, 1.0, 0, 1), (2, -1.0, 0, 1))


def cube_face_uv(n, face_size):
    """(u, v, layer) in the texture array of :func:`surface_cube` for the unit directions ``n`` (..., 3): the face
    of the largest component (x before y before z on ties), the two others divided by it, and the texel border.
    The twin of shaders/pixel.glsl ``cube_face_uv``."""
    n = np.asarray(n, dtype=np.float64)
    a = np.abs(n)
    major = np.where((a[..., 0] >= a[..., 1]) & (a[..., 0] >= a[..., 2]), 0, np.where(a[..., 1] >= a[..., 2], 1, 2))
    m = np.take_along_axis(n, major[..., None], -1)[..., 0]
    s_axis = np.where(major == 0, 1, 0)
    t_axis = np.where(major == 2, 1, 2)
    s = np.take_along_axis(n, s_axis[..., None], -1)[..., 0] / np.abs(m)
    t = np.take_along_axis(n, t_axis[..., None], -1)[..., 0] / np.abs(m)
    layer = 2 * major + (m <= 0)
    u = ((s + 1) * 0.5 * face_size + 1) / (face_size + 2)
    v = ((t + 1) * 0.5 * face_size + 1) / (face_size + 2)
    return u, v, layer


_CUBES = {}
#: The image array last resampled and its cube: a scene passes the same array at every change of the atmosphere, and
#: hashing its bytes to find the cube took 10-20 ms of the frame after the change.
_LAST = [None, None]


def surface_cube(image):
    """The equirectangular sRGB ``image`` resampled onto the six faces of a cube: (6, n + 2, n + 2, 3) uint8 sRGB,
    layer order :data:`CUBE_FACES`, each face a gnomonic projection with a one-texel border holding what lies just
    beyond its edge, so bilinear filtering at an edge blends the right neighbours. The shaders read it with
    ``cube_face_uv``: no trigonometry per pixel (atan and asin cost 0.05 ms of a 1.26 ms frame on the H100). The
    default n is 1.25 w / 4, a little finer than the map along the equator, where a face spans a quarter of it.
    The same array object gets the same cube at once (change a map by passing a new array, not in place)."""
    if image is _LAST[0]:
        return _LAST[1]
    original = image
    image = np.ascontiguousarray(image, dtype=np.uint8)
    h, w, _ = image.shape
    n = max(4, round(1.25 * w / 4))
    key = (hashlib.blake2b(image.data, digest_size=16).digest(), image.shape, n)
    if key not in _CUBES:
        if len(_CUBES) >= 4:                                 # a few maps are kept: building one takes ~0.7 s
            _CUBES.pop(next(iter(_CUBES)))
        _CUBES[key] = _build_cube(image, n)
    _LAST[:] = [original, _CUBES[key]]
    return _CUBES[key]


#: The cube of a uniform surface (no map): one black texel a face, its border included.
NO_MAP_CUBE = np.zeros((6, 3, 3, 3), np.uint8)
NO_MAP_CUBE.setflags(write=False)


def surface_cube_or_black(image):
    """:func:`surface_cube` of ``image``, or :data:`NO_MAP_CUBE` where there is no map (None)."""
    return NO_MAP_CUBE if image is None else surface_cube(image)


class SurfaceTexture:
    """A cube of :func:`surface_cube` on the GPU (a 2D array texture of its six faces, sRGB), uploaded once for a
    render window and a cube. The actors of one scene share one: each change of the atmosphere makes new actors (the
    quick view, the draft tables, the final tables), and uploading Earth's 6 x 642 x 642 texels again cost about
    10 ms of each one's first frame on llvmpipe. Actors made without one own theirs.

    Example::

        texture = SurfaceTexture()
        faces = texture.get(render_window, surface_cube(image))   # a vtkTextureObject
        texture.release()                                          # before the window closes
    """

    def __init__(self):
        self._window = self._cube = self._texture = None

    def get(self, render_window, cube):
        """The texture of ``cube`` (the same array object as the last call's: no upload) in ``render_window``."""
        if self._texture is None or self._window is not render_window or self._cube is not cube:
            self.release()
            self._texture = upload(render_window, cube, srgb=True, layers=True)
            self._window, self._cube = render_window, cube
        return self._texture

    def release(self):
        """Free the texture on the GPU."""
        if self._texture is not None:
            self._texture.ReleaseGraphicsResources(self._window)
        self._window = self._cube = self._texture = None


def _build_cube(image, n):
    c = ((np.arange(n + 2) - 0.5) / n * 2 - 1).astype(np.float32)   # texel centres in face coordinates, border too
    t, s = np.meshgrid(c, c, indexing="ij")                        # rows along t, columns along s
    linear = _linear_rows(image)
    faces = []
    for major, sign, s_axis, t_axis in CUBE_FACES:
        d = np.zeros(s.shape + (3,), np.float32)
        d[..., major], d[..., s_axis], d[..., t_axis] = sign, s, t
        d /= np.linalg.norm(d, axis=-1, keepdims=True)
        faces.append(_bilinear(linear, d))
    return np.rint(255 * srgb_encode(np.stack(faces))).astype(np.uint8)
