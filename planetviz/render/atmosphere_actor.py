"""The planet and its atmosphere as one VTK actor (plain ``vtkmodules``, no PyVista, so it also runs where only
VTK's rendering modules are installed, e.g. the GPU timing bundle), evaluated per pixel.

The actor is a sphere mesh just outside the top of the atmosphere with its front faces culled: it covers exactly
the pixels whose view rays can meet the atmosphere, from space (a planet a few pixels wide costs a few pixels) and
from inside (the whole screen). Its fragment shader (shaders/atmosphere_ray.glsl, shaders/pixel.glsl and
shaders/atmosphere_fragment.glsl) traces each pixel's ray analytically and reads the tables; the mesh's vertices
only decide coverage, so their float precision at planetary scale does not matter (and their depth is set to
the middle of the depth range). All uniforms and textures are
set in the mapper's ``UpdateShaderEvent``, once per draw, from the current camera (computed in double precision).
"""
from __future__ import annotations

import math

import numpy as np
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401  (registers the OpenGL implementations)
from vtkmodules.util.misc import calldata_type
from vtkmodules.vtkCommonCore import VTK_OBJECT, vtkCommand
from vtkmodules.vtkFiltersSources import vtkSphereSource
from vtkmodules.vtkRenderingCore import vtkActor, vtkPolyDataMapper

from ..model.color import albedo_matrix
from ..tables.compact import CompactTables
from ..tables.lookup import first_row_rho
from ..tables.near_ground import near_ground_altitude
from ..tables.parameterization import MU_S_MIN
from .shaders import shader_code
from .surface import SurfaceTexture, surface_cube_or_black
from .textures import MAX_GROUPS, group_count, pack_2d, pack_3d, pad_groups, upload
from .uniforms import (DisplaySettings, UniformStore, atmosphere_uniforms, camera_uniforms, draw_uniforms,
                       frame_key, groups_array)

#: The GLSL both table-based actors share, in order (each file declares what the later ones use): for the 4D
#: tables, and for the compact tables (planetviz/tables/compact.py), read without the quadratures along rays.
TABLE_SHADERS = ("common.glsl", "table_lookup.glsl", "near_ground.glsl", "horizon.glsl", "phased_scattering.glsl",
                 "view.glsl", "atmosphere_ray.glsl")
COMPACT_TABLE_SHADERS = ("common.glsl", "table_lookup.glsl", "compact_scattering.glsl", "view.glsl",
                         "atmosphere_ray.glsl")


#: Altitudes at which the shaders get the density profiles (density_texture, read by density_at in GLSL).
DENSITY_TABLE = 1024


def ray_quadrature_uniforms(atm, tables):
    """What shaders/near_ground.glsl's and shaders/horizon.glsl's quadratures along rays (near_ground_single_scattering,
    horizon_single_scattering) take besides :func:`density_image`: the scattering coefficients and the altitude
    below which ground rays are integrated."""
    per_group = lambda values: groups_array(pad_groups(values))
    return {"rayleigh_scattering": ("4fv", per_group(atm.rayleigh.scattering_m)),
            "mie_scattering": ("4fv", per_group(atm.mie.scattering_m)),
            "near_ground_altitude": ("f", near_ground_altitude(tables))}


def density_image(atm, n=DENSITY_TABLE):
    """density_texture: (1, n, 4) float32, the Rayleigh and the Mie density profiles (r, g) at the altitudes
    (i / (n - 1))^2 (R_t - R_b), dense near the ground. Read linearly between them, the Earth's Mie profile
    (1.2 km scale height) is within 1.9e-5 of its value below standard's near-ground altitude (1.57 km), and
    3.2e-4 wherever it is above 1e-6 of its value at the ground (Rayleigh: 1.8e-6 and 2.5e-5)."""
    h = (np.arange(n) / (n - 1)) ** 2 * atm.thickness_m
    image = np.zeros((1, n, 4), np.float32)
    image[0, :, 0] = atm.rayleigh.profile.density(h)
    image[0, :, 1] = atm.mie.profile.density(h)
    return image


class TableTextures:
    """The precomputed tables (and the surface texture) as GPU textures, with the uniforms that describe them:
    what the per-pixel and the per-vertex actors share. ``tables``: the 4D set (:class:`~planetviz.tables.Tables`)
    or the compact one (:class:`~planetviz.tables.compact.CompactTables`); :attr:`shaders` lists the GLSL that
    reads it.

    ``surface``: an (h, w, 3) uint8 sRGB equirectangular image used as the ground albedo, or None for the
    atmosphere file's uniform ``ground_albedo``. ``half_float``: 16-bit float tables (only for measuring what that
    costs; the default 32-bit is what the accuracy tests cover). ``surface_texture``: a
    :class:`~planetviz.render.surface.SurfaceTexture` shared with the scene's other actors, or None for one of
    its own."""

    def __init__(self, atmosphere, tables, surface=None, half_float=False, surface_texture=None):
        self.atmosphere, self.tables, self.surface, self.half_float = atmosphere, tables, surface, half_float
        self.compact = isinstance(tables, CompactTables)
        self.shaders = COMPACT_TABLE_SHADERS if self.compact else TABLE_SHADERS
        self._textures = None
        self._own_surface = surface_texture is None
        self._surface_texture = SurfaceTexture() if surface_texture is None else surface_texture

    def static_uniforms(self):
        atm, t = self.atmosphere, self.tables
        G = group_count(atm.n_wavelengths)
        alb_w = np.zeros((MAX_GROUPS, 3, 4), np.float32)
        alb_w[:G] = np.moveaxis(pad_groups(albedo_matrix(atm.wavelengths_nm)), 0, 1)   # (3, W) -> (G, 3, 4)
        n_r_t, n_mu_t = t.optical_depth.shape[:2]
        n_r_e, n_mu_s_e = t.irradiance.shape[:2]
        shared = {
            **atmosphere_uniforms(atm), "mu_s_min": ("f", MU_S_MIN),
            "transmittance_size": ("2f", (n_mu_t, n_r_t)), "irradiance_size": ("2f", (n_mu_s_e, n_r_e)),
            "albedo_weights": ("4fv", alb_w.reshape(-1, 4)),
            "use_surface_texture": ("i", int(self.surface is not None)),
            "surface_face_size": ("f", self._cube().shape[1] - 2),
        }
        if self.compact:
            n_h, n_mu, n_mu_s = t.rayleigh.shape[:3]
            return {**shared, "compact_size": ("3f", (n_mu_s, n_mu, n_h))}
        s1, sm = t.rayleigh.shape, t.multiple.shape
        return {**shared, "single_size": ("4f", (s1[2], s1[3], s1[1], s1[0])),
                "multiple_size": ("4f", (sm[2], sm[3], sm[1], sm[0])), "r_axis": ("1fv", t.r_axis),
                "multiple_row_1_rho": ("f", first_row_rho(t, sm[0])), **ray_quadrature_uniforms(atm, t)}

    def _cube(self):
        """The surface map on the faces of a cube (planetviz/render/surface.py), or a black 1-texel cube."""
        return surface_cube_or_black(self.surface)

    def bind(self, program, render_window):
        """Upload the textures on first use, activate them and point the samplers at them."""
        if self._textures is None:
            t, half = self.tables, self.half_float
            self._textures = {
                "optical_depth_texture": upload(render_window, pack_2d(t.optical_depth), half_float=half),
                "irradiance_texture": upload(render_window, pack_2d(t.irradiance), half_float=half)}
            if self.compact:                # (n_h, n_mu, n_mu_s, W) as a 4D table of one nu slice
                self._textures.update({
                    f"compact_{name}_texture": upload(render_window, pack_3d(getattr(t, name)[:, :, None]),
                                                      half_float=half)
                    for name in ("rayleigh", "mie", "multiple")})
            else:
                self._textures.update({
                    **{f"{name}_texture": upload(render_window, pack_3d(table, odd_width=True), half_float=half)
                       for name, table in (("single_rayleigh", t.rayleigh), ("single_mie", t.mie),
                                           ("multiple", t.multiple), ("multiple_mie", t.multiple_mie))},
                    **{f"top_{name}_texture": upload(render_window, pack_3d(table[None], odd_width=True),
                                                     half_float=half)
                       for name, table in (("multiple", t.top_multiple), ("multiple_mie", t.top_multiple_mie))},
                    "scattering_share_texture": upload(render_window, pack_2d(t.scattering_share), half_float=half),
                    "density_texture": upload(render_window, density_image(self.atmosphere))})
            self._textures["surface_faces"] = self._surface_texture.get(render_window, self._cube())
        for name, tex in self._textures.items():
            tex.Activate()
            program.SetUniformi(name, tex.GetTextureUnit())

    def deactivate(self):
        for tex in (self._textures or {}).values():
            tex.Deactivate()

    def release(self, render_window):
        """Free the tables' textures, and the surface's where it is the actor's own."""
        for name, tex in (self._textures or {}).items():
            if name != "surface_faces":
                tex.ReleaseGraphicsResources(render_window)
        if self._own_surface:
            self._surface_texture.release()
        self._textures = None


class AtmosphereActor:
    """A VTK actor drawing the planet, its atmosphere and the sun from precomputed tables, per pixel.

    ``surface``: an (h, w, 3) uint8 sRGB equirectangular image used as the ground albedo, or None for the
    atmosphere file's uniform ``ground_albedo``. ``half_float_tables`` stores the tables as 16-bit floats on
    the GPU (only for measuring what that costs; the default 32-bit is what the accuracy tests cover).
    ``surface_texture``: the scene's :class:`~planetviz.render.surface.SurfaceTexture` (None: the actor's own).
    """

    def __init__(self, atmosphere, tables, renderer, surface=None, settings=None, shell_resolution=96,
                 half_float_tables=False, surface_texture=None):
        self.atmosphere = atmosphere
        self.tables = tables
        self.renderer = renderer
        self.settings = settings or DisplaySettings()
        self.sun_direction = np.array([1.0, 0.0, 0.0])
        self.textures = TableTextures(atmosphere, tables, surface, half_float_tables, surface_texture)

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
        code = shader_code(*self.textures.shaders, "display.glsl", "pixel.glsl", "atmosphere_fragment.glsl")
        # The shell's depth means nothing (each fragment traces its ray), but computed from float32 vertices at
        # 6.4e6 m with a near plane centimetres away it can land beyond the far plane and drop the whole view:
        # drawn at mid-depth, as the direction mesh is.
        sp.AddVertexShaderReplacement("//VTK::PositionVC::Impl", True,
                                      "//VTK::PositionVC::Impl\n  gl_Position.z = 0.0;\n", False)
        sp.AddFragmentShaderReplacement("//VTK::Light::Dec", True, code, False)
        sp.AddFragmentShaderReplacement("//VTK::Light::Impl", True,
                                        "gl_FragData[0] = atmosphere_fragment();\n", False)
        self._store = UniformStore(sp)
        self._frame_key = None
        self._store.update(self.static_uniforms())
        self.mapper.AddObserver(vtkCommand.UpdateShaderEvent, self._update_shader)
        self._observers = [renderer.AddObserver(vtkCommand.StartEvent, self._start_frame),
                           renderer.AddObserver(vtkCommand.EndEvent, self._deactivate)]

    def static_uniforms(self):
        return self.textures.static_uniforms()

    def _start_frame(self, caller=None, event=None):
        key = frame_key(self.renderer, self.sun_direction, self.settings)
        if key != self._frame_key:
            self._frame_key = key
            self._store.update(draw_uniforms(camera_uniforms(self.renderer), self.sun_direction, self.settings,
                                             self.atmosphere))

    @calldata_type(VTK_OBJECT)
    def _update_shader(self, caller, event, program=None):
        if program is not None:
            self._store.set_arrays(program)
            self.textures.bind(program, self.renderer.GetRenderWindow())

    def _deactivate(self, caller=None, event=None):
        self.textures.deactivate()

    def release(self):
        """Stop following the renderer and free the GPU textures (call before the window closes)."""
        for tag in self._observers:
            self.renderer.RemoveObserver(tag)
        self._observers = []
        self.textures.release(self.renderer.GetRenderWindow())
