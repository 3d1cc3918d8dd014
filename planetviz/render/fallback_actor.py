"""The quick view as one VTK actor (plain ``vtkmodules``): Keller and Bohn's single scattering computed per vertex
of a direction mesh around the camera (shaders/fallback_vertex.glsl, the twin of planetviz/fallback.py), with
no tables, so every atmosphere parameter takes effect at the next frame.

The mesh is a sphere of directions centred on the camera (drawn at mid-depth: at its true distance a 16-bit
depth buffer, as in the float read-back, rounds it onto the far plane and drops fragments), rebuilt (in NumPy, a few milliseconds) whenever the
camera or the sun moves: rings of constant angle from the nadir, dense just inside and outside the planet's limb
(the horizon seen from the ground) with a pair of rings straddling it, so the horizon's step in brightness is
sharp; and extra rings and sectors around the sun, where the forward-scattering peak needs them (the paper's
"adaptive dome tessellated around the sun"). Colours are interpolated over the triangles and tone-mapped per
fragment; the surface is the atmosphere file's uniform albedo (a per-vertex method cannot show a texture).
"""
from __future__ import annotations

import math

import numpy as np
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401
from vtkmodules.util.misc import calldata_type
from vtkmodules.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray
from vtkmodules.vtkCommonCore import VTK_OBJECT, vtkCommand, vtkPoints
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData
from vtkmodules.vtkRenderingCore import vtkActor, vtkPolyDataMapper

from ..fallback import SAMPLING, _coefficients, check_settings
from .atmosphere_actor import (OUTPUT_MODES, TONE_MAPPINGS, DisplaySettings, _groups_array, _set_uniform,
                               atmosphere_uniforms)
from .shaders import shader_code
from .textures import MAX_GROUPS, group_count, pad_groups

MAX_COMPONENTS = 6
PROFILE_TABLE_SIZE = 64

#: Degrees around the sun and around the limb where the mesh is refined.
SUN_REFINEMENT_DEG = (0.3, 0.7, 1.5, 3.0, 6.0, 12.0)


def _ring_angles(limb, top_limb, rings):
    """Angles from the nadir [rad] of the rings: dense toward the limb from both sides, two rings 1e-4 rad
    either side of it, and the top of the atmosphere's limb seen from space."""
    k = np.arange(1, rings + 1) / (rings + 1)
    inside = limb * (1 - (1 - k) ** 2)
    outside = limb + (math.pi - limb) * k ** 2
    extra = [limb - 1e-4, limb + 1e-4, 0.0, math.pi]
    if top_limb is not None:
        extra += [top_limb - 1e-3, top_limb, top_limb + 1e-3]
    return np.unique(np.clip(np.concatenate([inside, outside, extra]), 0.0, math.pi))


def direction_mesh(camera, sun, bottom, top, rings=40, sectors=72):
    """(unit directions (n, 3), triangles (m, 3)) of the adaptive sphere of directions around ``camera``."""
    camera = np.asarray(camera, dtype=float)
    r = np.linalg.norm(camera)
    down = -camera / r
    limb = math.asin(min(bottom / r, 1.0)) if r > bottom else math.pi / 2
    top_limb = math.asin(top / r) if r > top else None
    theta = _ring_angles(limb, top_limb, rings)
    # Azimuth about the nadir axis, zero toward the sun's azimuth.
    e1 = np.asarray(sun, dtype=float) - np.dot(sun, down) * down
    if np.linalg.norm(e1) < 1e-9:
        e1 = np.cross(down, [1.0, 0.0, 0.0] if abs(down[0]) < 0.9 else [0.0, 1.0, 0.0])
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(down, e1)
    theta_sun = math.acos(np.clip(np.dot(sun, down), -1.0, 1.0))
    refine = np.radians(SUN_REFINEMENT_DEG)
    theta = np.unique(np.clip(np.concatenate([theta, theta_sun + refine, theta_sun - refine, [theta_sun]]),
                              0.0, math.pi))
    ring_radius = max(math.sin(theta_sun), 1e-3)
    phi = np.concatenate([np.linspace(-math.pi, math.pi, sectors, endpoint=False),
                          np.clip(refine / ring_radius, 0, math.pi), -np.clip(refine / ring_radius, 0, math.pi), [0.0]])
    phi = np.unique(np.mod(phi + math.pi, 2 * math.pi) - math.pi)
    st, ct = np.sin(theta)[:, None], np.cos(theta)[:, None]
    dirs = (ct[..., None] * down + st[..., None] * (np.cos(phi)[None, :, None] * e1 + np.sin(phi)[None, :, None] * e2))
    n_t, n_p = len(theta), len(phi)
    i, j = np.meshgrid(np.arange(n_t - 1), np.arange(n_p), indexing="ij")
    a, b = i * n_p + j, i * n_p + (j + 1) % n_p
    c, d = a + n_p, b + n_p
    tris = np.concatenate([np.stack([a, b, d], -1).reshape(-1, 3), np.stack([a, d, c], -1).reshape(-1, 3)])
    return dirs.reshape(-1, 3), tris


def _polydata(points, cells, kind):
    poly = vtkPolyData()
    pts = vtkPoints()
    pts.SetData(numpy_to_vtk(np.ascontiguousarray(points, dtype=np.float64), deep=True))
    poly.SetPoints(pts)
    offsets = np.arange(len(cells) + 1, dtype=np.int64) * cells.shape[1]
    arr = vtkCellArray()
    arr.SetData(numpy_to_vtkIdTypeArray(offsets, deep=True),
                numpy_to_vtkIdTypeArray(np.ascontiguousarray(cells, dtype=np.int64).ravel(), deep=True))
    (poly.SetPolys if kind == "polys" else poly.SetVerts)(arr)
    return poly


class FallbackActor:
    """A VTK actor drawing the quick view of ``atmosphere`` for the renderer's active camera.

    ``samples`` / ``density_samples``: points n on each view path and m on each optical-depth path;
    ``sampling``: ``"power"`` or ``"equidistant"``; ``terms``: ``"physical"`` or ``"artistic"``."""

    def __init__(self, atmosphere, renderer, samples=8, density_samples=None, sampling="power", terms="physical",
                 settings=None):
        self.samples, self.density_samples = check_settings(samples, density_samples, sampling, terms)
        self.atmosphere = atmosphere
        self.renderer = renderer
        self.settings = settings or DisplaySettings()
        self.sampling, self.terms = sampling, terms
        self.sun_direction = np.array([1.0, 0.0, 0.0])
        self.directions = None                       # fixed directions (points) instead of the adaptive mesh
        self._static = self._static_uniforms()
        self._mesh_key = None
        self.mapper = vtkPolyDataMapper()
        self.mapper.SetVBOShiftScaleMethod(0)
        self.actor = vtkActor()
        self.actor.SetMapper(self.mapper)
        self.actor.GetProperty().SetPointSize(1)
        sp = self.actor.GetShaderProperty()
        sp.AddVertexShaderReplacement("//VTK::PositionVC::Dec", True,
                                      "//VTK::PositionVC::Dec\n" + shader_code("common.glsl", "fallback_vertex.glsl"),
                                      False)
        sp.AddVertexShaderReplacement("//VTK::PositionVC::Impl", True,
                                      "//VTK::PositionVC::Impl\n  fallback_vertex(vertexMC.xyz);\n"
                                      "  gl_Position.z = 0.0;  // mid-depth: no far-plane or depth-format quantisation\n",
                                      False)
        sp.AddFragmentShaderReplacement("//VTK::Light::Dec", True,
                                        shader_code("display.glsl", "fallback_fragment.glsl"), False)
        sp.AddFragmentShaderReplacement("//VTK::Light::Impl", True,
                                        "gl_FragData[0] = fallback_fragment();\n", False)
        self.mapper.AddObserver(vtkCommand.UpdateShaderEvent, self._update_shader)
        renderer.AddObserver(vtkCommand.StartEvent, self._update_mesh)

    def _static_uniforms(self):
        atm = self.atmosphere
        G = group_count(atm.n_wavelengths)
        b_r, b_m, extinction = _coefficients(atm, self.terms)
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
        per_group = lambda values: _groups_array(pad_groups(values))
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

    def _update_mesh(self, caller=None, event=None):
        cam = np.array(self.renderer.GetActiveCamera().GetPosition())
        key = (tuple(cam), tuple(self.sun_direction), None if self.directions is None else id(self.directions))
        if key == self._mesh_key:
            return
        self._mesh_key = key
        distance = max(1e6, 1e-2 * np.linalg.norm(cam))
        if self.directions is not None:
            dirs = self.directions
            poly = _polydata(cam + distance * dirs, np.arange(len(dirs))[:, None], "verts")
        else:
            dirs, tris = direction_mesh(cam, self.sun_direction, self.atmosphere.bottom_radius_m,
                                        self.atmosphere.top_radius_m)
            poly = _polydata(cam + distance * dirs, tris, "polys")
        self.mapper.SetInputData(poly)
        self.renderer.ResetCameraClippingRange()

    @calldata_type(VTK_OBJECT)
    def _update_shader(self, caller, event, program=None):
        if program is None:
            return
        s = self.settings
        cam = np.array(self.renderer.GetActiveCamera().GetPosition())
        dynamic = {"camera_position": ("3f", cam),
                   "sun_direction": ("3f", self.sun_direction / np.linalg.norm(self.sun_direction)),
                   "output_mode": ("i", OUTPUT_MODES[s.output_mode]), "output_triple": ("i", s.output_triple),
                   "exposure": ("f", s.exposure), "tone_mapping": ("i", TONE_MAPPINGS[s.tone_mapping])}
        for name, (kind, value) in {**self._static, **dynamic}.items():
            _set_uniform(program, name, kind, value)
