"""The quick view as one VTK actor (plain ``vtkmodules``): Keller and Bohn's single scattering computed per vertex
of the direction mesh around the camera (planetviz/render/direction_mesh.py; shaders/quick_view_vertex.glsl, the twin
of planetviz/quick_view/single_scattering.py), with no tables, so every atmosphere parameter takes effect at the next frame. Colours
are interpolated over the triangles and tone-mapped per fragment; the surface is the atmosphere file's uniform
albedo.
"""
from __future__ import annotations

import numpy as np

from ..quick_view.single_scattering import SAMPLING, coefficients, check_settings
from .direction_mesh import DirectionMeshActor
from .shaders import shader_code
from .textures import MAX_GROUPS, group_count, pad_groups
from .uniforms import OUTPUT_MODES, TONE_MAPPINGS, atmosphere_uniforms, camera_altitude, groups_array

MAX_COMPONENTS = 6
PROFILE_TABLE_SIZE = 64


class QuickViewActor(DirectionMeshActor):
    """A VTK actor drawing the quick view of ``atmosphere`` for the renderer's active camera.

    ``samples`` / ``density_samples``: points n on each view path and m on each optical-depth path;
    ``sampling``: ``"power"`` or ``"equidistant"``; ``terms``: ``"physical"`` or ``"artistic"``."""

    def __init__(self, atmosphere, renderer, samples=8, density_samples=None, sampling="power", terms="physical",
                 settings=None):
        self.samples, self.density_samples = check_settings(samples, density_samples, sampling, terms)
        self.atmosphere = atmosphere
        self.sampling, self.terms = sampling, terms
        super().__init__(atmosphere, renderer, shader_code("common.glsl", "quick_view_vertex.glsl"), "quick_view_vertex",
                         shader_code("display.glsl", "quick_view_fragment.glsl"), "quick_view_fragment", settings=settings)

    def static_uniforms(self):
        atm = self.atmosphere
        G = group_count(atm.n_wavelengths)
        b_r, b_m, extinction = coefficients(atm, self.terms)
        if len(extinction) > MAX_COMPONENTS:
            raise ValueError(f"absorption: the quick view takes at most {MAX_COMPONENTS - 2} absorbing layers, "
                             f"got {len(extinction) - 2}")
        ext = np.zeros((MAX_COMPONENTS, MAX_GROUPS, 4), np.float32)
        prof = np.zeros((MAX_COMPONENTS, 3), np.float32)
        table = np.zeros((MAX_COMPONENTS, PROFILE_TABLE_SIZE), np.float32)
        for k, (e, profile) in enumerate(extinction):
            ext[k, :G] = pad_groups(e)
            kind = type(profile).__name__
            if kind == "ExponentialProfile":
                prof[k] = (0.0, profile.scale_height_m, 0.0)
            elif kind == "TentProfile":
                prof[k] = (1.0, profile.center_m, profile.half_width_m)
            else:
                prof[k] = (2.0, atm.thickness_m, 0.0)
                table[k] = profile.density(np.linspace(0.0, atm.thickness_m, PROFILE_TABLE_SIZE))
        per_group = lambda values: groups_array(pad_groups(values))
        e_view, e_depth = SAMPLING[self.sampling]
        return {
            **atmosphere_uniforms(atm),
            "view_samples": ("i", self.samples), "density_samples": ("i", self.density_samples),
            "view_exponent": ("f", e_view), "density_exponent": ("f", e_depth),
            "rayleigh_scattering": ("4fv", per_group(b_r)), "mie_scattering": ("4fv", per_group(b_m)),
            "component_count": ("i", len(extinction)),
            "component_extinction": ("4fv", ext.reshape(-1, 4)),
            "component_profile": ("3fv", prof), "component_table": ("1fv", table.ravel()),
            "artistic_terms": ("i", int(self.terms == "artistic")),
        }

    def frame_uniforms(self, view):
        s = self.settings
        return {"camera_position": view["camera_position"], **camera_altitude(view, self.atmosphere.bottom_radius_m),
                "sun_direction": ("3f", self.sun_direction / np.linalg.norm(self.sun_direction)),
                "output_mode": ("i", OUTPUT_MODES[s.output_mode]), "output_triple": ("i", s.output_triple),
                "exposure": ("f", s.exposure), "tone_mapping": ("i", TONE_MAPPINGS[s.tone_mapping])}
