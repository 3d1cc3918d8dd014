"""The tables as GPU textures: NumPy packing (no VTK) and upload through ``vtkTextureObject``.

Wavelengths go four to a texel (RGBA) in groups; group g holds wavelengths 4g .. 4g + 3 and the groups are
stacked along the r axis (y of the 2D tables, z of the 3D ones). The shaders read a group only between its own
texel centres (``texture_group`` and ``get_scattering`` in shaders/table_lookup.glsl), so filtering never
mixes two groups. Float tables stay 32-bit (GL_RGBA32F): half floats would cost up to 2^-11 = 0.05% per texel,
which the 1% agreement test could absorb, but the textures are 40 MB at standard quality, so nothing is gained.
"""
from __future__ import annotations

import numpy as np

MAX_GROUPS = 16


def group_count(n_wavelengths: int) -> int:
    """Number of RGBA groups for ``n_wavelengths`` (at most 64 wavelengths)."""
    g = -(-n_wavelengths // 4)
    if g > MAX_GROUPS:
        raise ValueError(f"wavelengths: at most {4 * MAX_GROUPS} can be rendered, got {n_wavelengths}")
    return g


def pad_groups(values, fill=0.0):
    """(..., W) -> (..., G, 4): the last axis padded to whole groups of four."""
    v = np.asarray(values, dtype=np.float32)
    g = group_count(v.shape[-1])
    out = np.full(v.shape[:-1] + (4 * g,), fill, np.float32)
    out[..., :v.shape[-1]] = v
    return out.reshape(v.shape[:-1] + (g, 4))


def pack_2d(table):
    """A 2D table (n_r, n_x, W) as an RGBA image (G n_r, n_x, 4), the groups stacked along y."""
    t = pad_groups(table)                                   # (n_r, n_x, G, 4)
    return np.ascontiguousarray(np.moveaxis(t, 2, 0).reshape(-1, t.shape[1], 4))


def pack_3d(table, odd_width=False):
    """A 4D table (n_r, n_mu, n_nu, n_mu_s, W) as an RGBA volume (G n_r, n_mu, X, 4), X = n_nu n_mu_s: x runs
    over the nu slices of mu_s, y over mu, z over r, the groups stacked along z. ``odd_width``: where X is a power
    of two, one column of zeros is appended, never read (the shader divides by the texture's own width), so that
    the width never is one: llvmpipe compiles a shader variant per power-of-two-ness of the textures it samples,
    and the draft level's 4 x 16 slices (64) would otherwise draw with another program than the standard level's
    8 x 48 (384), compiled the first time a machine shows draft tables (1.6-1.9 s)."""
    n_r, n_mu, n_nu, n_mu_s = table.shape[:4]
    x = n_nu * n_mu_s
    t = pad_groups(np.asarray(table).reshape(n_r, n_mu, x, -1))               # (n_r, n_mu, X, G, 4)
    volume = np.moveaxis(t, 3, 0).reshape(-1, n_mu, x, 4)
    if odd_width and x > 1 and x & (x - 1) == 0:
        volume = np.concatenate([volume, np.zeros_like(volume[:, :, :1])], axis=2)
    return np.ascontiguousarray(volume)


#: OpenGL internal format of half-float RGBA textures (for the precision and speed comparison only).
GL_RGBA16F = 0x881A
#: OpenGL internal format of sRGB-encoded 8-bit RGB textures, decoded to linear by the GPU before filtering.
GL_SRGB8 = 0x8C41


def upload(render_window, image, half_float=False, srgb=False, layers=False):
    """A ``vtkTextureObject`` holding ``image``: (h, w, c) -> 2D, (d, h, w, c) -> 3D, or with ``layers`` a 2D
    array texture of d layers (each filtered on its own); float32 or uint8 data;
    linear filtering, clamped to the edge. ``half_float``
    stores float data as 16-bit floats on the GPU (benchmarks/gpu_render_timing.py compares the two); ``srgb``:
    (h, w, 3) uint8 sRGB-encoded colours, which the GPU decodes to linear (exactly, from the 8-bit values) before
    it filters them."""
    from vtkmodules.vtkCommonCore import VTK_FLOAT, VTK_UNSIGNED_CHAR
    from vtkmodules.vtkRenderingOpenGL2 import vtkTextureObject
    data = np.ascontiguousarray(image)
    kind = {np.dtype(np.float32): VTK_FLOAT, np.dtype(np.uint8): VTK_UNSIGNED_CHAR}[data.dtype]
    tex = vtkTextureObject()
    tex.SetContext(render_window)
    if half_float:
        tex.SetInternalFormat(GL_RGBA16F)
    if srgb:
        tex.SetInternalFormat(GL_SRGB8)
    if data.ndim == 3:
        h, w, c = data.shape
        ok = tex.Create2DFromRaw(w, h, c, kind, data)
    elif layers:
        d, h, w, c = data.shape
        ok = tex.Create2DArrayFromRaw(w, h, c, kind, d, data)
    else:
        d, h, w, c = data.shape
        ok = tex.Create3DFromRaw(w, h, d, c, kind, data)
    if not ok:
        raise RuntimeError(f"could not create a {data.ndim - 1}D texture of shape {data.shape}")
    tex.SetMinificationFilter(vtkTextureObject.Linear)
    tex.SetMagnificationFilter(vtkTextureObject.Linear)
    tex.SetWrapS(vtkTextureObject.ClampToEdge)
    tex.SetWrapT(vtkTextureObject.ClampToEdge)
    tex.SetWrapR(vtkTextureObject.ClampToEdge)
    return tex
