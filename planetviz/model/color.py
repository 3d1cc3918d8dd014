"""Colour from spectra: radiance at the atmosphere's wavelengths -> CIE XYZ -> sRGB (colour-science).

Spectral radiance L(lambda) = radiance per unit irradiance x the star's E(lambda) at the
atmosphere's wavelengths. Between them the spectrum is taken as piecewise linear (held
constant beyond the end samples), so XYZ = k int L(lambda) cmf(lambda) d lambda over the CMF
range is a fixed linear map of the samples (a flat spectrum stays white, with 3 wavelengths
or 64); with k = 683 lm/W, Y is luminance in cd/m^2.
"""
from __future__ import annotations

import numpy as np

LUMINOUS_EFFICACY = 683.0


def xyz_matrix(wavelengths_nm):
    """(W, 3) matrix M with XYZ = L_spectral @ M, for a piecewise-linear spectrum through the samples."""
    import colour
    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
    wl = np.asarray(wavelengths_nm, dtype=float)
    order = np.argsort(wl)
    grid = cmfs.wavelengths
    step = np.gradient(grid)
    hats = np.stack([np.interp(grid, wl[order], np.eye(len(wl))[i][order]) for i in range(len(wl))])
    return LUMINOUS_EFFICACY * (hats * step) @ cmfs.values


def radiance_to_xyz(radiance, atm):
    """CIE XYZ of radiance per unit irradiance (..., W) lit by the atmosphere's star."""
    from .optics.light import star_irradiance
    spectral = np.asarray(radiance, dtype=float) * star_irradiance(atm.star, atm.wavelengths_nm)
    return spectral @ xyz_matrix(atm.wavelengths_nm)


def radiance_to_srgb(radiance, atm, exposure=None):
    """8-bit sRGB; ``exposure`` multiplies linear sRGB (default: brightest channel at 0.8)."""
    import colour
    rgb = colour.XYZ_to_sRGB(radiance_to_xyz(radiance, atm), apply_cctf_encoding=False)
    rgb = np.maximum(rgb, 0.0)
    if exposure is None:
        peak = rgb.max()
        exposure = 0.8 / peak if peak > 0 else 1.0
    encoded = colour.cctf_encoding(np.clip(rgb * exposure, 0.0, 1.0), function="sRGB")
    return np.round(encoded * 255).astype(int)


def linear_srgb_matrix(atm):
    """(W, 3) matrix M with linear sRGB = L @ M for radiance L per unit irradiance (..., W) lit by the
    atmosphere's star: the star's spectrum, the CIE 1931 functions (683 lm/W, so the luminance is in cd/m^2)
    and colour-science's XYZ -> sRGB matrix (linear in XYZ, so applied to the rows)."""
    import colour
    from .optics.light import star_irradiance
    xyz = star_irradiance(atm.star, atm.wavelengths_nm)[:, None] * xyz_matrix(atm.wavelengths_nm)
    return colour.XYZ_to_sRGB(xyz, apply_cctf_encoding=False)


def linear_srgb(radiance, atm):
    """Linear sRGB (..., 3), float32, luminance in cd/m^2, of radiance per unit irradiance (..., W)."""
    return (np.asarray(radiance) @ linear_srgb_matrix(atm)).astype(np.float32)


def albedo_matrix(wavelengths_nm):
    """(3, W) matrix A with albedo(lambda) = linear sRGB colour @ A: a colour texture read as a reflectance
    spectrum, piecewise linear through the sRGB primaries' dominant wavelengths (B 465 nm, G 549 nm, R 612 nm)
    and held constant beyond them, so a grey texel reflects every wavelength equally."""
    wl = np.asarray(wavelengths_nm, dtype=float)
    centres = np.array([612.0, 549.0, 465.0])
    order = np.argsort(centres)
    return np.stack([np.interp(wl, centres[order], np.eye(3)[c][order]) for c in range(3)])


def tone_map(x, tone_mapping="exponential"):
    """The twin of shaders/display.glsl tone_map: ``exponential`` 1 - exp(-x) (the paper), ``filmic``
    (Narkowicz's fit of the ACES curve) or ``clamp``; in x's float precision (float64 for other input)."""
    x = np.asarray(x)
    x = x if np.issubdtype(x.dtype, np.floating) else x.astype(float)
    if tone_mapping == "exponential":
        return 1.0 - np.exp(-x)
    if tone_mapping == "filmic":
        return np.clip(x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0)
    if tone_mapping == "clamp":
        return np.clip(x, 0.0, 1.0)
    raise ValueError(f"tone_mapping: exponential, filmic or clamp, got {tone_mapping!r}")


def srgb_encode(c):
    """The twin of shaders/display.glsl srgb_encode: the sRGB transfer function (IEC 61966-2-1) of linear values
    in [0, 1], 12.92 c below 0.0031308, 1.055 c^(1 / 2.4) - 0.055 above (colour-science's cctf_encoding "sRGB";
    tests/test_light_color.py compares them), in c's float precision."""
    c = np.asarray(c)
    return np.where(c > 0.0031308, 1.055 * np.power(c, 1.0 / 2.4) - 0.055, 12.92 * c)


def display_colour(rgb, exposure, tone_mapping="exponential"):
    """The twin of shaders/display.glsl display_colour: linear sRGB (cd/m^2) -> sRGB-encoded values in [0, 1], in
    float32 as the shader is."""
    mapped = tone_map(np.maximum(np.asarray(rgb, dtype=np.float32), 0.0) * np.float32(exposure), tone_mapping)
    return srgb_encode(np.clip(mapped, 0.0, 1.0))
