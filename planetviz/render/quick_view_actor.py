"""The quick view as one VTK actor (plain ``vtkmodules``): Keller and Bohn's single scattering computed per vertex
of the direction mesh around the camera (planetviz/render/direction_mesh.py; shaders/quick_view_vertex.glsl, the
twin of planetviz/quick_view/single_scattering.py), with no 4D tables, so every atmosphere parameter takes effect at
the next frame; with ``orders="all"`` (the default) also the orders above the first and the sky's light on the
ground from Hillaire's 2D table (planetviz/quick_view/multiple_scattering.py), computed in NumPy in a background
thread when the actor is made: the first frame shows single scattering, the frames after the table is ready
(:meth:`QuickViewActor.collect`, about 0.1 s later) all orders. Colours are interpolated over the triangles and tone-mapped per fragment; the surface is the atmosphere
file's uniform albedo.
"""
from __future__ import annotations

import threading

import numpy as np
from vtkmodules.vtkCommonCore import vtkCommand

from ..quick_view.multiple_scattering import MS_SIZE, ORDERS, quick_view_tables
from ..quick_view.single_scattering import SAMPLING, coefficients, check_settings
from .direction_mesh import DirectionMeshActor
from .shaders import shader_code
from .textures import MAX_GROUPS, group_count, pack_2d, pad_groups, upload
from .uniforms import OUTPUT_MODES, TONE_MAPPINGS, atmosphere_uniforms, camera_altitude, groups_array

MAX_COMPONENTS = 6
PROFILE_TABLE_SIZE = 64


class QuickViewActor(DirectionMeshActor):
    """A VTK actor drawing the quick view of ``atmosphere`` for the renderer's active camera.

    ``samples`` / ``density_samples``: points n on each view path and m on each optical-depth path;
    ``sampling``: ``"power"`` or ``"equidistant"``; ``terms``: ``"physical"`` or ``"artistic"``; ``orders``:
    ``"all"`` or ``"single"`` (:data:`ORDERS`; the artistic terms are single scattering only)."""

    def __init__(self, atmosphere, renderer, samples=8, density_samples=None, sampling="power", terms="physical",
                 settings=None, orders="all"):
        self.samples, self.density_samples = check_settings(samples, density_samples, sampling, terms)
        if orders not in ORDERS:
            raise ValueError(f"quick view orders: one of {', '.join(ORDERS)}, got {orders!r}")
        self.atmosphere = atmosphere
        self.sampling, self.terms = sampling, terms
        self.orders = orders if terms == "physical" else "single"
        self.multiple = self.ground_sky = None          # Psi_ms and E_sky once shown
        self._textures = self._job = None
        self._tables = []
        if self.orders == "all":
            self._job = threading.Thread(target=lambda: self._tables.append(quick_view_tables(atmosphere)),
                                         daemon=True)
            self._job.start()
        super().__init__(atmosphere, renderer, shader_code("common.glsl", "quick_view_vertex.glsl"),
                         "quick_view_vertex", shader_code("display.glsl", "quick_view_fragment.glsl"),
                         "quick_view_fragment", settings=settings)
        self._observers.append(renderer.AddObserver(vtkCommand.EndEvent, lambda *_: self.deactivate()))

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
            "multiple_scattering_size": ("2f", (MS_SIZE[1], MS_SIZE[0])),
        }

    @property
    def pending(self):
        """True while the table of the orders above the first is computed or not yet shown."""
        return self._job is not None

    def collect(self, wait=False):
        """Show the orders above the first from the next frame on, if their table is ready (``wait``: wait for
        it). Returns True when this call switched them on."""
        if self._job is None or (not wait and self._job.is_alive()):
            return False
        self._job.join()
        self._job = None
        if not self._tables:                          # the computation failed: single scattering stays
            return False
        self.multiple, self.ground_sky = self._tables[0]
        self._release_textures()
        self._frame_key = None                        # new frame uniforms (multiple_scattering) at the next frame
        return True

    def bind(self, program):
        """Upload Psi_ms and E_sky on first use (zeros for single scattering alone), activate them and point the
        samplers at them."""
        if self._textures is None:
            window = self.renderer.GetRenderWindow()
            shape = (*MS_SIZE, self.atmosphere.n_wavelengths)
            psi = self.multiple if self.multiple is not None else np.zeros(shape, np.float32)
            sky = self.ground_sky if self.ground_sky is not None else np.zeros(shape[1:], np.float32)
            self._textures = {"multiple_scattering_texture": upload(window, pack_2d(psi.astype(np.float32))),
                              "ground_sky_texture": upload(window, pack_2d(sky[None].astype(np.float32)))}
        for name, tex in self._textures.items():
            tex.Activate()
            program.SetUniformi(name, tex.GetTextureUnit())

    def deactivate(self):
        for tex in (self._textures or {}).values():
            tex.Deactivate()

    def release(self):
        """Stop following the renderer and free the GPU textures."""
        super().release()
        self._release_textures()

    def _release_textures(self):
        for tex in (self._textures or {}).values():
            tex.ReleaseGraphicsResources(self.renderer.GetRenderWindow())
        self._textures = None

    def frame_uniforms(self, view):
        s = self.settings
        return {"camera_position": view["camera_position"], **camera_altitude(view, self.atmosphere.bottom_radius_m),
                "sun_direction": ("3f", self.sun_direction / np.linalg.norm(self.sun_direction)),
                "output_mode": ("i", OUTPUT_MODES[s.output_mode]), "output_triple": ("i", s.output_triple),
                "exposure": ("f", s.exposure), "tone_mapping": ("i", TONE_MAPPINGS[s.tone_mapping]),
                "multiple_scattering": ("i", int(self.multiple is not None))}
