"""The table-based renderer evaluated per vertex: the same model as :class:`AtmosphereActor`
(shaders/atmosphere_ray.glsl) at the vertices of the adaptive direction mesh around the camera
(planetviz/render/direction_mesh.py, shaders/atmosphere_vertex.glsl), interpolated over the triangles and
completed per pixel with the surface texture and the sun disc (shaders/atmosphere_interpolated.glsl).

8,000-9,400 vertices read the tables instead of every pixel: the interactive renderer where the GPU is slow (a
software renderer such as llvmpipe) or the frame is large; its difference from the per-pixel actor is the
interpolation error between vertices, measured in docs/benchmarks.md.
"""
from __future__ import annotations

import numpy as np
from vtkmodules.vtkCommonCore import vtkCommand

from ..tables.inscatter_factor import (PATH_OPACITY_TEXELS, PHASE_FACTOR_TEXELS, irradiance_rows,
                                       path_opacity_altitude, path_opacity_table, path_scattering_share,
                                       phase_factor_table, share_holds, sky_irradiance_rows)
from .atmosphere_actor import TableTextures
from .direction_mesh import DirectionMeshActor
from .shaders import shader_code
from .textures import pad_groups, upload
from .uniforms import draw_uniforms


class InscatterFactorTextures:
    """The textures of shaders/inscatter_factor.glsl (planetviz/tables/inscatter_factor.py):
    ``phase_irradiance_texture``, made once, and ``path_opacity_texture``, the opacity and the scattering opacity of
    every view ray from the frame's ray altitude, made on the CPU and uploaded again when that altitude changes
    (never while the camera stays above the atmosphere, where the rays start at its top): the opacity in about 1 ms,
    the share of it that scatters in 3-5 ms, only when the altitude moved by more than ``share_holds`` allows (not
    while the camera turns)."""

    def __init__(self, atmosphere, tables):
        self.atmosphere, self.tables = atmosphere, tables
        self.altitude = 0.0
        self.irradiance = sky_irradiance_rows(tables)
        self._phase_irradiance = self._opacity = self._opacity_altitude = None
        self._share = self._share_altitude = None

    def uniforms(self):
        return {"path_opacity_texels": ("f", PATH_OPACITY_TEXELS), "phase_factor_texels": ("f", PHASE_FACTOR_TEXELS),
                "irradiance_rows": ("4f", irradiance_rows(self.tables.irradiance.shape[1]))}

    def set_camera_altitude(self, camera_altitude):
        """Follow the camera's altitude [m] (the uniform ``camera_altitude``)."""
        self.altitude = path_opacity_altitude(camera_altitude, self.tables.bottom, self.tables.top)

    def bind(self, program, render_window):
        """Upload what is missing or stale, activate the textures and point the samplers at them."""
        if self._phase_irradiance is None:
            self._phase_irradiance = upload(render_window, phase_irradiance_image(self.atmosphere, self.irradiance))
        if self._opacity_altitude != self.altitude:
            if self._opacity is not None:
                self._opacity.ReleaseGraphicsResources(render_window)
            first = slice(0, min(4, self.atmosphere.n_wavelengths))
            if self._share is None or not share_holds(self._share_altitude, self.altitude, self.atmosphere):
                self._share = path_scattering_share(self.tables, self.atmosphere, self.altitude,
                                                    PATH_OPACITY_TEXELS, first)
                self._share_altitude = self.altitude
            opacity = path_opacity_table(self.tables, self.altitude, PATH_OPACITY_TEXELS)[:, first]
            self._opacity = upload(render_window, path_opacity_image(opacity, self._share))
            self._opacity_altitude = self.altitude
        for name, tex in (("phase_irradiance_texture", self._phase_irradiance), ("path_opacity_texture", self._opacity)):
            tex.Activate()
            program.SetUniformi(name, tex.GetTextureUnit())

    def deactivate(self):
        for tex in (self._phase_irradiance, self._opacity):
            if tex is not None:
                tex.Deactivate()

    def release(self, render_window):
        for tex in (self._phase_irradiance, self._opacity):
            if tex is not None:
                tex.ReleaseGraphicsResources(render_window)
        self._phase_irradiance = self._opacity = self._opacity_altitude = None


def group_means(values):
    """(..., W) -> (..., G): the mean over each group's wavelengths (the padding of the last group left out)."""
    return np.nanmean(pad_groups(values, fill=np.nan), axis=-1)


def path_opacity_image(opacity, share):
    """``path_opacity_texture``, (1, 2n, 4): per texel the means over the first group's wavelengths of the rays'
    opacity (2n, W'; :func:`path_opacity_table`) and of their scattering opacity, that times the ``share``
    (:func:`path_scattering_share`), then 0, 0."""
    image = np.zeros((1, len(opacity), 4), np.float32)
    image[0, :, 0] = opacity.mean(-1)
    image[0, :, 1] = (opacity * share).mean(-1)
    return image


def phase_irradiance_image(atmosphere, rows):
    """``phase_irradiance_texture``, (G n_rows, n, 4): per group, the sky's irradiance on the ground ``rows``
    (rows, W; :func:`sky_irradiance_rows`) times the phases of :func:`phase_factor_table` (n, W, 4), each averaged
    over the group's wavelengths."""
    phases = group_means(np.moveaxis(phase_factor_table(atmosphere, PHASE_FACTOR_TEXELS), 1, -1))   # (n, 4, G)
    irradiance = group_means(rows)                                                                  # (rows, G)
    image = irradiance.T[:, :, None, None] * np.moveaxis(phases, -1, 0)[:, None]                   # (G, rows, n, 4)
    return np.ascontiguousarray(image.reshape(-1, *image.shape[2:]), dtype=np.float32)


class VertexAtmosphereActor(DirectionMeshActor):
    """A VTK actor drawing the planet, its atmosphere and the sun from precomputed tables, per vertex of the
    direction mesh (arguments as :class:`AtmosphereActor`)."""

    def __init__(self, atmosphere, tables, renderer, surface=None, settings=None, half_float_tables=False,
                 surface_texture=None):
        self.tables = tables
        self.textures = TableTextures(atmosphere, tables, surface, half_float_tables, surface_texture)
        self.factor_textures = InscatterFactorTextures(atmosphere, tables)
        shaders = (*self.textures.shaders, "inscatter_factor.glsl", "interpolation.glsl")
        super().__init__(atmosphere, renderer, shader_code(*shaders, "atmosphere_vertex.glsl"), "atmosphere_vertex",
                         shader_code(*shaders, "display.glsl", "pixel.glsl", "atmosphere_interpolated.glsl"),
                         "atmosphere_interpolated", split_at_limb=True, settings=settings)
        self._observers.append(renderer.AddObserver(vtkCommand.EndEvent, lambda *_: self._deactivate()))

    def static_uniforms(self):
        return {**self.textures.static_uniforms(), **self.factor_textures.uniforms()}

    def bind(self, program):
        window = self.renderer.GetRenderWindow()
        self.textures.bind(program, window)
        self.factor_textures.bind(program, window)

    def _deactivate(self):
        self.textures.deactivate()
        self.factor_textures.deactivate()

    def frame_uniforms(self, view):
        uniforms = draw_uniforms(view, np.asarray(self.sun_direction), self.settings, self.atmosphere)
        self.factor_textures.set_camera_altitude(uniforms["camera_altitude"][1])
        return uniforms

    def release(self):
        """Stop following the renderer and free the GPU textures (call before the window closes)."""
        super().release()
        window = self.renderer.GetRenderWindow()
        self.textures.release(window)
        self.factor_textures.release(window)
