"""Texture sampling as OpenGL does it (GL_LINEAR, CLAMP_TO_EDGE), so NumPy and GLSL read the same values.

A texture coordinate u in [0, 1] over n texels has its texel centres at (i + 1/2) / n; a lookup blends
the two nearest centres linearly, clamping indices at the edges.
"""
from __future__ import annotations

import numpy as np


def texel_axis(u, n):
    s = np.asarray(u, dtype=float) * n - 0.5
    i0 = np.floor(s)
    f = s - i0
    i0 = i0.astype(np.int64)
    return np.clip(i0, 0, n - 1), np.clip(i0 + 1, 0, n - 1), f


def texture2d(table, u, v):
    """Bilinear lookup of ``table`` (height n_v, width n_u, channels) at (u, v); returns (..., channels)."""
    nv, nu = table.shape[:2]
    u0, u1, fu = texel_axis(u, nu)
    v0, v1, fv = texel_axis(v, nv)
    fu, fv = fu[..., None], fv[..., None]
    top = table[v0, u0] * (1 - fu) + table[v0, u1] * fu
    bottom = table[v1, u0] * (1 - fu) + table[v1, u1] * fu
    return top * (1 - fv) + bottom * fv


def texture3d(table, u, v, w):
    """Trilinear lookup of ``table`` (depth n_w, height n_v, width n_u, channels) at (u, v, w)."""
    nw = table.shape[0]
    w0, w1, fw = texel_axis(w, nw)
    fw = fw[..., None]
    return texture2d_slices(table, w0, u, v) * (1 - fw) + texture2d_slices(table, w1, u, v) * fw


def texture2d_slices(table, slice_index, u, v):
    """Bilinear lookup in the slices ``table[slice_index]`` (one slice per query)."""
    nv, nu = table.shape[1:3]
    u0, u1, fu = texel_axis(u, nu)
    v0, v1, fv = texel_axis(v, nv)
    fu, fv = fu[..., None], fv[..., None]
    top = table[slice_index, v0, u0] * (1 - fu) + table[slice_index, v0, u1] * fu
    bottom = table[slice_index, v1, u0] * (1 - fu) + table[slice_index, v1, u1] * fu
    return top * (1 - fv) + bottom * fv
