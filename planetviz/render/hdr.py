"""Float read-back of what the atmosphere actor computes (the window's framebuffer holds 8 bits per channel):
the spectral radiance per unit solar irradiance, one pass per three wavelengths (R, G, B), through a
``vtkFramebufferPass`` with a 32-bit float colour buffer; and OpenEXR output."""
from __future__ import annotations

import json

import numpy as np
from vtkmodules.vtkCommonCore import VTK_FLOAT
from vtkmodules.vtkRenderingOpenGL2 import vtkFramebufferPass, vtkRenderStepsPass, vtkTextureObject



def read_float_image(renderer, render_window):
    """Render once into a float framebuffer and return its RGBA (h, w, 4) float32, top row first."""
    fbp = vtkFramebufferPass()
    fbp.SetColorFormat(vtkTextureObject.Float32)
    fbp.SetDelegatePass(vtkRenderStepsPass())
    previous = renderer.GetPass()
    renderer.SetPass(fbp)
    try:
        render_window.Render()
        render_window.MakeCurrent()
        tex = fbp.GetColorTexture()
        w, h = tex.GetWidth(), tex.GetHeight()
        out = np.empty((h, w, 4), np.float32)
        tex.Download().Download2D(VTK_FLOAT, out, [w, h], 4, [0, 0])
    finally:
        fbp.ReleaseGraphicsResources(render_window)
        renderer.SetPass(previous)
    return out[::-1].copy()


def render_spectral(atmosphere_actor, render_window):
    """(h, w, W) float32 radiance per unit solar irradiance [1/sr] at the atmosphere's wavelengths."""
    s = atmosphere_actor.settings
    saved = (s.output_mode, s.output_triple)
    W = atmosphere_actor.atmosphere.n_wavelengths
    planes = []
    try:
        s.output_mode = "spectral"
        for k in range(-(-W // 3)):
            s.output_triple = k
            planes.append(read_float_image(atmosphere_actor.renderer, render_window)[..., :3])
    finally:
        s.output_mode, s.output_triple = saved
    return np.concatenate(planes, axis=-1)[..., :W]


def write_exr(path, linear_srgb, spectral_radiance, wavelengths_nm, metadata):
    """OpenEXR (float32, ZIP): R, G, B = linear sRGB (luminance in cd/m^2) and one channel per wavelength,
    ``L.<nm>nm``, with the spectral radiance [W m^-2 sr^-1 nm^-1]; ``metadata`` (JSON) in the header."""
    import OpenEXR
    channels = {"R": linear_srgb[..., 0], "G": linear_srgb[..., 1], "B": linear_srgb[..., 2]}
    for i, wl in enumerate(wavelengths_nm):
        channels[f"L.{wl:g}nm"] = spectral_radiance[..., i]
    channels = {k: np.ascontiguousarray(v, dtype=np.float32) for k, v in channels.items()}
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage,
              "planetviz": json.dumps(metadata)}
    OpenEXR.File(header, channels).write(str(path))
