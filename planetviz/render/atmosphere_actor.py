"""The planet and its atmosphere as one VTK actor (plain ``vtkmodules``, no PyVista, so it also runs where only
VTK's rendering modules are installed, e.g. the GPU timing bundle).

The actor is a sphere mesh just outside the top of the atmosphere with its front faces culled: it covers exactly
the pixels whose view rays can meet the atmosphere, from space (a planet a few pixels wide costs a few pixels) and
from inside (the whole screen). Its fragment shader (shaders/atmosphere_functions.glsl and
shaders/atmosphere_fragment.glsl) traces each pixel's ray analytically and reads the tables; the mesh's vertices
only decide coverage, so their float precision at planetary scale does not matter. All uniforms and textures are
set in the mapper's ``UpdateShaderEvent``, once per draw, from the current camera (computed in double precision).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401  (registers the OpenGL implementations)
from vtkmodules.util.misc import calldata_type
from vtkmodules.vtkCommonCore import VTK_OBJECT, vtkCommand
from vtkmodules.vtkFiltersSources import vtkSphereSource
from vtkmodules.vtkRenderingCore import vtkActor, vtkPolyDataMapper

from ..color import albedo_matrix, linear_srgb_matrix
from ..tables.parameterization import MU_S_MIN
from .shaders import fragment_code
from .textures import MAX_GROUPS, group_count, pack_2d, pack_3d, pad_groups, upload

TONE_MAPPINGS = {"exponential": 0, "filmic": 1, "clamp": 2}
OUTPUT_MODES = {"display": 0, "spectral": 1, "linear_srgb": 2}

#: Angular radius of the Sun seen from the Earth [deg].
SUN_ANGULAR_RADIUS_DEG = 0.2666


@dataclass
class DisplaySettings:
    """What the fragment shader writes: ``output_mode`` (display / spectral / linear_srgb), the three wavelengths
    of the spectral mode (``output_triple`` k: wavelengths 3k .. 3k + 2), exposure [m^2/cd] and tone mapping
    (exponential / filmic / clamp)."""

    output_mode: str = "display"
    output_triple: int = 0
    exposure: float = 1e-4
    tone_mapping: str = "exponential"
    show_sun: bool = True
    sun_angular_radius_deg: float = SUN_ANGULAR_RADIUS_DEG


class AtmosphereActor:
    """A VTK actor drawing the planet, its atmosphere and the sun from precomputed tables.

    ``surface``: an (h, w, 3) uint8 sRGB equirectangular image used as the ground albedo, or None for the
    atmosphere file's uniform ``ground_albedo``. ``half_float_tables`` stores the tables as 16-bit floats on
    the GPU (only for measuring what that costs; the default 32-bit is what the accuracy tests cover).
    """

    def __init__(self, atmosphere, tables, renderer, surface=None, settings=None, shell_resolution=96,
                 half_float_tables=False):
        self.atmosphere = atmosphere
        self.tables = tables
        self.renderer = renderer
        self.surface = surface
        self.settings = settings or DisplaySettings()
        self.sun_direction = np.array([1.0, 0.0, 0.0])
        self.half_float_tables = half_float_tables
        self._textures = None
        self._static = self._static_uniforms()

        # The shell: vertices at radius top / cos(edge angle) keep every flat triangle outside the top sphere.
        sphere = vtkSphereSource()
        sphere.SetThetaResolution(2 * shell_resolution)
        sphere.SetPhiResolution(shell_resolution)
        edge = math.pi / shell_resolution
        sphere.SetRadius(tables.top / math.cos(edge) ** 2)
        self.mapper = vtkPolyDataMapper()
        self.mapper.SetInputConnection(sphere.GetOutputPort())
        self.mapper.SetVBOShiftScaleMethod(0)
        self.actor = vtkActor()
        self.actor.SetMapper(self.mapper)
        self.actor.GetProperty().FrontfaceCullingOn()
        sp = self.actor.GetShaderProperty()
        sp.AddFragmentShaderReplacement("//VTK::Light::Dec", True, fragment_code(), False)
        sp.AddFragmentShaderReplacement("//VTK::Light::Impl", True,
                                        "gl_FragData[0] = atmosphere_fragment();\n", False)
        self.mapper.AddObserver(vtkCommand.UpdateShaderEvent, self._update_shader)
        self._end_observer = renderer.AddObserver(vtkCommand.EndEvent, self._deactivate)

    # ------------------------------------------------------------------------------------------ uniforms
    def _static_uniforms(self):
        atm, t = self.atmosphere, self.tables
        G = group_count(atm.n_wavelengths)
        alb_w = np.zeros((MAX_GROUPS, 3, 4), np.float32)
        alb_w[:G] = np.moveaxis(pad_groups(albedo_matrix(atm.wavelengths_nm)), 0, 1)   # (3, W) -> (G, 3, 4)
        n_r_t, n_mu_t = t.optical_depth.shape[:2]
        n_r_e, n_mu_s_e = t.irradiance.shape[:2]
        s1, sm = t.rayleigh.shape, t.multiple.shape
        return {
            **atmosphere_uniforms(atm), "mu_s_min": ("f", MU_S_MIN),
            "transmittance_size": ("2f", (n_mu_t, n_r_t)), "irradiance_size": ("2f", (n_mu_s_e, n_r_e)),
            "single_size": ("4f", (s1[2], s1[3], s1[1], s1[0])),
            "multiple_size": ("4f", (sm[2], sm[3], sm[1], sm[0])),
            "albedo_weights": ("4fv", alb_w.reshape(-1, 4)),
            "use_surface_texture": ("i", int(self.surface is not None)),
        }

    def camera_uniforms(self):
        """The per-draw uniforms: the camera's (double precision), the sun and the display settings."""
        s = self.settings
        cos_radius = math.cos(math.radians(s.sun_angular_radius_deg))
        return {
            **camera_uniforms(self.renderer),
            "sun_direction": ("3f", self.sun_direction / np.linalg.norm(self.sun_direction)),
            "sun_cos_radius": ("f", cos_radius), "sun_solid_angle": ("f", 2 * math.pi * (1 - cos_radius)),
            "show_sun": ("i", int(s.show_sun)),
            "output_mode": ("i", OUTPUT_MODES[s.output_mode]), "output_triple": ("i", s.output_triple),
            "exposure": ("f", s.exposure), "tone_mapping": ("i", TONE_MAPPINGS[s.tone_mapping]),
        }

    # ---------------------------------------------------------------------------------------- VTK events
    def _create_textures(self, render_window):
        t, half = self.tables, self.half_float_tables
        tex = {"optical_depth_texture": upload(render_window, pack_2d(t.optical_depth), half_float=half),
               "irradiance_texture": upload(render_window, pack_2d(t.irradiance), half_float=half),
               "single_rayleigh_texture": upload(render_window, pack_3d(t.rayleigh), half_float=half),
               "single_mie_texture": upload(render_window, pack_3d(t.mie), half_float=half),
               "multiple_texture": upload(render_window, pack_3d(t.multiple), half_float=half),
               "multiple_mie_texture": upload(render_window, pack_3d(t.multiple_mie), half_float=half)}
        surface = self.surface if self.surface is not None else np.zeros((1, 1, 3), np.uint8)
        tex["surface_texture"] = upload(render_window, np.ascontiguousarray(surface[::-1]), repeat_x=True)
        return tex

    @calldata_type(VTK_OBJECT)
    def _update_shader(self, caller, event, program=None):
        if program is None:
            return
        if self._textures is None:
            self._textures = self._create_textures(self.renderer.GetRenderWindow())
        for name, tex in self._textures.items():
            tex.Activate()
            program.SetUniformi(name, tex.GetTextureUnit())
        for name, (kind, value) in {**self._static, **self.camera_uniforms()}.items():
            _set_uniform(program, name, kind, value)

    def _deactivate(self, caller=None, event=None):
        for tex in (self._textures or {}).values():
            tex.Deactivate()

    def release(self):
        """Free the GPU textures (call before the window closes)."""
        for tex in (self._textures or {}).values():
            tex.ReleaseGraphicsResources(self.renderer.GetRenderWindow())
        self._textures = None


def atmosphere_uniforms(atm):
    """The uniforms both actors take from the atmosphere: common.glsl's (radii, groups, phases), the ground's
    albedo and the spectral -> linear sRGB weights (``rgb_weights``)."""
    G = group_count(atm.n_wavelengths)
    rgb_w = np.zeros((MAX_GROUPS, 3, 4), np.float32)
    rgb_w[:G] = np.moveaxis(pad_groups(linear_srgb_matrix(atm).T), 0, 1)          # (W, 3) -> (G, 3, 4)
    per_group = lambda values: _groups_array(pad_groups(values))
    return {
        "bottom_radius": ("f", atm.bottom_radius_m), "top_radius": ("f", atm.top_radius_m),
        "group_count": ("i", G),
        "rayleigh_anisotropy": ("f", 1.0 if atm.rayleigh.phase == "rayleigh" else 0.932),
        "mie_g1": ("4fv", per_group(atm.mie.g1)), "mie_g2": ("4fv", per_group(atm.mie.g2)),
        "mie_alpha": ("4fv", per_group(atm.mie.alpha)),
        "surface_albedo": ("4fv", per_group(atm.ground_albedo)),
        "rgb_weights": ("4fv", rgb_w.reshape(-1, 4)),
    }


def camera_uniforms(renderer):
    """The camera's uniforms, computed in double precision from the renderer's active camera: position, its
    distance from the centre, the view basis scaled by the half fields of view, and the viewport in pixels."""
    cam = renderer.GetActiveCamera()
    pos = np.array(cam.GetPosition(), dtype=float)
    forward = np.array(cam.GetFocalPoint(), dtype=float) - pos
    forward /= np.linalg.norm(forward)
    up = np.array(cam.GetViewUp(), dtype=float)
    right = np.cross(forward, up)
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    x0, y0, x1, y1 = renderer.GetViewport()
    w, h = renderer.GetRenderWindow().GetActualSize()
    vw, vh = (x1 - x0) * w, (y1 - y0) * h
    tan_v = math.tan(math.radians(cam.GetViewAngle()) / 2)
    if cam.GetUseHorizontalViewAngle():
        tan_h, tan_v = tan_v, tan_v * vh / vw
    else:
        tan_h = tan_v * vw / vh
    return {"camera_position": ("3f", pos), "camera_radius": ("f", float(np.linalg.norm(pos))),
            "camera_forward": ("3f", forward), "camera_right": ("3f", right * tan_h),
            "camera_up": ("3f", up * tan_v), "viewport": ("4f", (x0 * w, y0 * h, vw, vh))}


def _groups_array(values):
    """(G, 4) per-group values padded to MAX_GROUPS rows, flat for SetUniform4fv."""
    out = np.zeros((MAX_GROUPS, 4), np.float32)
    out[:len(values)] = values
    return out


def _set_uniform(program, name, kind, value):
    if kind == "f":
        program.SetUniformf(name, float(value))
    elif kind == "i":
        program.SetUniformi(name, int(value))
    elif kind == "2f":
        program.SetUniform2f(name, [float(v) for v in value])
    elif kind == "3f":
        program.SetUniform3f(name, [float(v) for v in value])
    elif kind == "4f":
        program.SetUniform4f(name, [float(v) for v in value])
    elif kind == "1fv":
        arr = np.ascontiguousarray(value, dtype=np.float32)
        program.SetUniform1fv(name, len(arr), arr)
    elif kind == "3fv":
        arr = np.ascontiguousarray(value, dtype=np.float32)
        program.SetUniform3fv(name, len(arr), arr.ravel())
    else:
        arr = np.ascontiguousarray(value, dtype=np.float32)
        program.SetUniform4fv(name, len(arr), arr.ravel())
