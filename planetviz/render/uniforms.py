"""Uniforms shared by the actors: display settings, the atmosphere's constants, the camera (in double precision)
and the store that hands them to VTK."""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..model.color import linear_srgb_matrix
from ..model.optics.phase import PENNDORF_A
from ..tables.validated import particle_scattering_share
from .textures import MAX_GROUPS, group_count, pad_groups

TONE_MAPPINGS = {"exponential": 0, "filmic": 1, "clamp": 2}
OUTPUT_MODES = {"display": 0, "spectral": 1, "linear_srgb": 2}

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


def atmosphere_uniforms(atm):
    """The uniforms both actors take from the atmosphere: common.glsl's (radii, groups, phases), the ground's
    albedo and the spectral -> linear sRGB weights (``rgb_weights``)."""
    G = group_count(atm.n_wavelengths)
    rgb_w = np.zeros((MAX_GROUPS, 3, 4), np.float32)
    rgb_w[:G] = np.moveaxis(pad_groups(linear_srgb_matrix(atm).T), 0, 1)          # (W, 3) -> (G, 3, 4)
    per_group = lambda values: groups_array(pad_groups(values))
    return {
        "bottom_radius": ("f", atm.bottom_radius_m), "top_radius": ("f", atm.top_radius_m),
        "group_count": ("i", G),
        "rayleigh_anisotropy": ("f", 1.0 if atm.rayleigh.phase == "rayleigh" else PENNDORF_A),
        "mie_g1": ("4fv", per_group(atm.mie.g1)), "mie_g2": ("4fv", per_group(atm.mie.g2)),
        "mie_alpha": ("4fv", per_group(atm.mie.alpha)),
        "mie_lobe_share": ("4fv", per_group(particle_scattering_share(atm))),
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
    return {"camera_position": ("3f", pos),
            "camera_forward": ("3f", forward), "camera_right": ("3f", right * tan_h),
            "camera_up": ("3f", up * tan_v), "viewport": ("4f", (x0 * w, y0 * h, vw, vh))}


def camera_altitude(view, bottom_radius):
    """The uniform ``camera_altitude``: the camera's height above the ground [m], computed in double (the shaders'
    float32 radius would be 0.5 m coarse at 6.4e6 m); ``view``: :func:`camera_uniforms`."""
    return {"camera_altitude": ("f", float(np.linalg.norm(view["camera_position"][1]) - bottom_radius))}


def draw_uniforms(view, sun_direction, settings, atm):
    """The per-frame uniforms of the table-based actors: the camera's (``view``, :func:`camera_uniforms`, and
    :func:`camera_altitude` above the ground), the sun (its disc as big as ``atm``'s star seen from the planet) and
    the display settings."""
    cos_radius = math.cos(math.radians(atm.star.angular_radius_deg()))
    return {
        **view, **camera_altitude(view, atm.bottom_radius_m),
        "sun_direction": ("3f", sun_direction / np.linalg.norm(sun_direction)),
        "sun_cos_radius": ("f", cos_radius), "sun_solid_angle": ("f", 2 * math.pi * (1 - cos_radius)),
        "show_sun": ("i", int(settings.show_sun)),
        "output_mode": ("i", OUTPUT_MODES[settings.output_mode]), "output_triple": ("i", settings.output_triple),
        "exposure": ("f", settings.exposure), "tone_mapping": ("i", TONE_MAPPINGS[settings.tone_mapping]),
    }


def groups_array(values):
    """(G, 4) per-group values padded to MAX_GROUPS rows, flat for SetUniform4fv."""
    out = np.zeros((MAX_GROUPS, 4), np.float32)
    out[:len(values)] = values
    return out


#: The vtkUniforms setter of each single-value kind.
SINGLE_SETTERS = {"f": "SetUniformf", "i": "SetUniformi", "2f": "SetUniform2f", "3f": "SetUniform3f",
                  "4f": "SetUniform4f"}


class UniformStore:
    """The uniforms of one actor's shader program, written from Python only when they change.

    Single values go to the shader property's custom uniforms (``vtkUniforms``), which VTK sets in C++ before
    each draw: the constants are written once, the camera and the sun once per frame. Arrays (kinds 1fv, 3fv,
    4fv) are kept as float32 buffers and set on the program by :meth:`set_arrays` at the first draw after they
    changed, because ``vtkUniforms``' Python wrapping cannot take arrays of vectors (the overloads of its generic setter
    are ambiguous from Python).

    The shader code (shaders/*.glsl) declares and documents every uniform itself, so VTK's own declarations
    (``//VTK::CustomUniforms::Dec``) are removed from both stages."""

    def __init__(self, shader_property):
        shader_property.AddVertexShaderReplacement("//VTK::CustomUniforms::Dec", True, "", False)
        shader_property.AddFragmentShaderReplacement("//VTK::CustomUniforms::Dec", True, "", False)
        self.uniforms = shader_property.GetFragmentCustomUniforms()
        self._values = {}
        self._arrays = {}
        self._arrays_set_on = None

    def update(self, uniforms):
        """Take {name: (kind, value)} (kinds f, i, 2f, 3f, 4f, 1fv, 3fv, 4fv), writing the values that changed."""
        for name, (kind, value) in uniforms.items():
            if kind.endswith("fv"):
                self._arrays[name] = (kind, np.ascontiguousarray(value, dtype=np.float32).ravel())
                self._arrays_set_on = None
                continue
            value = float(value) if kind == "f" else int(value) if kind == "i" else tuple(map(float, value))
            if self._values.get(name) == value:
                continue
            self._values[name] = value
            getattr(self.uniforms, SINGLE_SETTERS[kind])(name, value)

    def set_arrays(self, program):
        """Set the array uniforms on ``program`` (a ``vtkShaderProgram`` about to draw), unless they were set on
        this program since it was last linked (a relinked or new program has a new handle and modification time)."""
        key = (program.GetHandle(), program.GetMTime())
        if key == self._arrays_set_on:
            return
        for name, (kind, values) in self._arrays.items():
            width = int(kind[0])
            getattr(program, f"SetUniform{kind}")(name, values.size // width, values)
        self._arrays_set_on = key


def frame_key(renderer, sun_direction, settings):
    """What the per-frame uniforms depend on, read without NumPy: the camera, the viewport's size in pixels, the
    sun and the display settings. The actors recompute their frame (camera uniforms, direction mesh) only when it
    changes."""
    cam = renderer.GetActiveCamera()
    return (cam.GetPosition(), cam.GetFocalPoint(), cam.GetViewUp(), cam.GetViewAngle(),
            cam.GetUseHorizontalViewAngle(), renderer.GetViewport(), renderer.GetRenderWindow().GetActualSize(),
            tuple(sun_direction), tuple(vars(settings).values()))
