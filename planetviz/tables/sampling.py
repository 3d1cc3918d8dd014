"""Texture sampling as OpenGL does it (GL_LINEAR, CLAMP_TO_EDGE), so NumPy and GLSL read the same values.

A texture coordinate u in [0, 1] over n texels has its texel centres at (i + 1/2) / n; a lookup blends
the two nearest centres linearly, clamping indices at the edges. :func:`cubic_rows` is the precompute's own
(the cubic through four texels; no shader reads a table so).
"""
from __future__ import annotations

import numpy as np


def texel_axis(u, n):
    s = np.asarray(u, dtype=float) * n - 0.5
    i0 = np.floor(s)
    f = s - i0
    i0 = i0.astype(np.int64)
    return np.clip(i0, 0, n - 1), np.clip(i0 + 1, 0, n - 1), f


def cubic_rows(u, n):
    """[(row index, weight)] of the cubic through the four texel centres around texture coordinate u on an axis
    of n >= 4 texels (Lagrange: exact for a cubic in the texel index, error O(h^4) in the texel spacing h where
    linear filtering's is O(h^2)); in the axis's first and last intervals the four rows shift inside it, and u is
    clamped to the outermost centres."""
    if n < 4:
        raise ValueError(f"cubic_rows: the axis needs at least 4 texels, got {n}")
    s = np.clip(np.asarray(u, dtype=float) * n - 0.5, 0.0, n - 1.0)
    first = np.clip(np.floor(s).astype(np.int64) - 1, 0, n - 4)
    t = s - first                                     # the position from the first of the four rows, in rows
    rows = []
    for j in range(4):
        w = np.ones_like(t)
        for m in range(4):
            if m != j:
                w = w * (t - m) / (j - m)
        rows.append((first + j, w))
    return rows


def texture2d(table, u, v):
    """Bilinear lookup of ``table`` (height n_v, width n_u, channels) at (u, v); returns (..., channels). The
    texels are gathered by flat index (``take``: half the time of indexing by row and column)."""
    nv, nu = table.shape[:2]
    u0, u1, fu = texel_axis(u, nu)
    v0, v1, fv = texel_axis(v, nv)
    flat = table.reshape((nv * nu,) + table.shape[2:])
    fu, fv = fu[..., None], fv[..., None]
    row0, row1 = v0 * nu, v1 * nu
    top = flat.take(row0 + u0, axis=0) * (1 - fu) + flat.take(row0 + u1, axis=0) * fu
    bottom = flat.take(row1 + u0, axis=0) * (1 - fu) + flat.take(row1 + u1, axis=0) * fu
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
