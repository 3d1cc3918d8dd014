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

from .atmosphere_actor import TableTextures
from .direction_mesh import DirectionMeshActor
from .shaders import shader_code
from .uniforms import draw_uniforms


class VertexAtmosphereActor(DirectionMeshActor):
    """A VTK actor drawing the planet, its atmosphere and the sun from precomputed tables, per vertex of the
    direction mesh (arguments as :class:`AtmosphereActor`)."""

    def __init__(self, atmosphere, tables, renderer, surface=None, settings=None, half_float_tables=False):
        self.tables = tables
        self.textures = TableTextures(atmosphere, tables, surface, half_float_tables)
        shaders = self.textures.shaders
        super().__init__(atmosphere, renderer, shader_code(*shaders, "atmosphere_vertex.glsl"), "atmosphere_vertex",
                         shader_code(*shaders, "display.glsl", "pixel.glsl", "atmosphere_interpolated.glsl"),
                         "atmosphere_interpolated", split_at_limb=True, settings=settings)
        self._observers.append(renderer.AddObserver(vtkCommand.EndEvent, lambda *_: self.textures.deactivate()))

    def static_uniforms(self):
        return self.textures.static_uniforms()

    def bind(self, program):
        self.textures.bind(program, self.renderer.GetRenderWindow())

    def frame_uniforms(self, view):
        return draw_uniforms(view, np.asarray(self.sun_direction), self.settings, self.atmosphere)

    def release(self):
        """Stop following the renderer and free the GPU textures (call before the window closes)."""
        super().release()
        self.textures.release(self.renderer.GetRenderWindow())
