"""The quick view as one VTK actor (plain ``vtkmodules``): Keller and Bohn's single scattering computed per vertex of
the direction mesh around the camera (planetviz/render/direction_mesh.py; shaders/quick_view_vertex.glsl, the twin of
planetviz/quick_view/single_scattering.py), with no 4D tables, so every atmosphere parameter takes effect at the next
frame; with ``orders="all"`` (the default) also the orders above the first and the sky's light on the ground from a
2D table of the mean radiance of the light scattered at least once (planetviz/quick_view/multiple_scattering.py),
solved in NumPy in a background job that the scene starts after the actor's first frame
(planetviz/render/background.py): that frame shows single scattering, the frames after the table is ready
(:meth:`QuickViewActor.collect`, about 0.5 s later) all orders. The inscatter (geometrically:
shaders/interpolation.glsl) and the ground's light per unit of the surface colour are interpolated over the triangles
and completed per fragment (shaders/quick_view_fragment.glsl) with the surface texture (or the file's uniform albedo)
and the sun's cosine at the pixel's ground point, as the per-vertex table renderer does; no sun disc.
"""
from __future__ import annotations

import numpy as np
from vtkmodules.vtkCommonCore import vtkCommand

from ..quick_view.multiple_scattering import GROUND_SKY_COLUMNS, LOG_FLOOR, MS_SIZE, ORDERS, quick_view_tables
from ..quick_view.single_scattering import (DEFAULT_SAMPLES, GAUSS_OFFSET, MAX_SAMPLES, SAMPLING, check_settings,
                                           coefficients, ground_sample_edges, sample_edges)
from .background import BACKGROUND_NICENESS, BackgroundJob
from .direction_mesh import DirectionMeshActor
from .shaders import shader_code
from ..model.color import albedo_matrix
from .surface import SurfaceTexture, surface_cube_or_black
from .textures import MAX_GROUPS, group_count, pack_2d, pad_groups, upload
from .uniforms import atmosphere_uniforms, draw_uniforms, groups_array

MAX_COMPONENTS = 6
PROFILE_TABLE_SIZE = 64
#: The shader's constants for the kinds of density profile (component_kinds): any profile but the exponential and
#: the tent is read from a table.
EXPONENTIAL_PROFILE, TENT_PROFILE, TABULATED_PROFILE = 0, 1, 2


def profile_kind(profile):
    """The shader's kind of a density profile."""
    return {"ExponentialProfile": EXPONENTIAL_PROFILE, "TentProfile": TENT_PROFILE}.get(type(profile).__name__,
                                                                                         TABULATED_PROFILE)


def shader_constants(extinction):
    """The constants of shaders/quick_view_vertex.glsl for the extinction components [(coefficients, profile), ...]:
    the arrays' sizes, the profile kinds, the components' count and the kind of each one's profile, so that the
    shader's loops over the components unroll and each evaluates its own profile only."""
    kinds = [profile_kind(profile) for _, profile in extinction]
    kinds += [EXPONENTIAL_PROFILE] * (MAX_COMPONENTS - len(kinds))
    defines = {"MAX_COMPONENTS": MAX_COMPONENTS, "PROFILE_TABLE_SIZE": PROFILE_TABLE_SIZE,
               "MAX_SAMPLES": MAX_SAMPLES, "EXPONENTIAL_PROFILE": EXPONENTIAL_PROFILE, "TENT_PROFILE": TENT_PROFILE,
               "TABULATED_PROFILE": TABULATED_PROFILE, "GAUSS_OFFSET": repr(float(GAUSS_OFFSET))}
    return ("".join(f"#define {name} {value}\n" for name, value in defines.items())
            + f"const int component_count = {len(extinction)};\n"
            + f"const int component_kinds[MAX_COMPONENTS] = int[]({', '.join(map(str, kinds))});\n")


def packed(values):
    """A float array as the shaders' vec4 arrays hold it (quick_view_vertex.glsl): (ceil(n / 4), 4), zero-padded."""
    out = np.zeros(-(-len(values) // 4) * 4, np.float32)
    out[:len(values)] = values
    return out.reshape(-1, 4)


def edge_uniform(edges):
    """(MAX_SAMPLES + 1,) a path's n + 1 interval edges (single_scattering.sample_edges, ground_sample_edges), then
    zeros: the shaders' edge arrays."""
    out = np.zeros(MAX_SAMPLES + 1)
    out[:len(edges)] = edges
    return out


#: The textures of the orders above the first, replaced when their table is ready.
MULTIPLE_SCATTERING_TEXTURES = ("multiple_scattering_texture", "ground_sky_texture")


class QuickViewActor(DirectionMeshActor):
    """A VTK actor drawing the quick view of ``atmosphere`` for the renderer's active camera.

    ``samples`` / ``density_samples``: points n on each view path and m on each optical-depth path;
    ``sampling``: ``"power"`` or ``"equidistant"``; ``terms``: ``"physical"`` or ``"artistic"``; ``orders``:
    ``"all"`` or ``"single"`` (:data:`ORDERS`; the artistic terms are single scattering only); ``surface``: an
    (h, w, 3) uint8 sRGB equirectangular image used as the ground albedo, or None for the file's uniform albedo;
    ``surface_texture``: the scene's :class:`~planetviz.render.surface.SurfaceTexture` (None: the actor's own)."""

    def __init__(self, atmosphere, renderer, samples=DEFAULT_SAMPLES, density_samples=None, sampling="power",
                 terms="physical", settings=None, orders="all", surface=None, surface_texture=None):
        self.samples, self.density_samples = check_settings(samples, density_samples, sampling, terms)
        if orders not in ORDERS:
            raise ValueError(f"quick view orders: one of {', '.join(ORDERS)}, got {orders!r}")
        self.atmosphere, self.surface = atmosphere, surface
        self.sampling, self.terms = sampling, terms
        self.orders = orders if terms == "physical" else "single"
        self.multiple = self.ground_sky = None          # Psi and E_sky once shown
        self._textures, self._job = {}, None
        self._own_surface = surface_texture is None
        self._surface_texture = SurfaceTexture() if surface_texture is None else surface_texture
        if self.orders == "all":
            self._job = BackgroundJob(lambda: quick_view_tables(atmosphere), niceness=BACKGROUND_NICENESS)
        _, _, extinction = coefficients(atmosphere, terms)
        if len(extinction) > MAX_COMPONENTS:
            raise ValueError(f"absorption: the quick view takes at most {MAX_COMPONENTS - 2} absorbing layers, "
                             f"got {len(extinction) - 2}")
        vertex_code = (shader_constants(extinction)
                       + shader_code("common.glsl", "view.glsl", "interpolation.glsl", "quick_view_vertex.glsl"))
        super().__init__(atmosphere, renderer, vertex_code,
                         "quick_view_vertex", shader_code("common.glsl", "view.glsl", "interpolation.glsl",
                                                          "display.glsl", "pixel.glsl", "quick_view_fragment.glsl"),
                         "quick_view_fragment", split_at_limb=True, settings=settings)
        self._observers.append(renderer.AddObserver(vtkCommand.EndEvent, lambda *_: self.deactivate()))

    def static_uniforms(self):
        atm = self.atmosphere
        G = group_count(atm.n_wavelengths)
        b_r, b_m, extinction = coefficients(atm, self.terms)
        ext = np.zeros((MAX_COMPONENTS, MAX_GROUPS, 4), np.float32)
        prof = np.zeros((MAX_COMPONENTS, 3), np.float32)
        table = np.zeros((MAX_COMPONENTS, PROFILE_TABLE_SIZE), np.float32)
        for k, (e, profile) in enumerate(extinction):
            ext[k, :G] = pad_groups(e)
            kind = profile_kind(profile)
            if kind == EXPONENTIAL_PROFILE:
                prof[k] = (profile.scale_height_m, 0.0, 0.0)
            elif kind == TENT_PROFILE:
                prof[k] = (profile.center_m, profile.half_width_m, 0.0)
            else:
                prof[k] = (atm.thickness_m, 0.0, 0.0)
                table[k] = profile.density(np.linspace(0.0, atm.thickness_m, PROFILE_TABLE_SIZE))
        per_group = lambda values: groups_array(pad_groups(values))
        e_view, e_depth = SAMPLING[self.sampling]
        albedo_weights = np.zeros((MAX_GROUPS, 3, 4), np.float32)
        albedo_weights[:G] = np.moveaxis(pad_groups(albedo_matrix(atm.wavelengths_nm)), 0, 1)   # (3, W) -> (G, 3, 4)
        return {
            **atmosphere_uniforms(atm),
            "view_samples": ("i", self.samples), "density_samples": ("i", self.density_samples),
            "view_edges": ("4fv", packed(edge_uniform(sample_edges(self.samples, e_view)))),
            "ground_view_edges": ("4fv", packed(edge_uniform(ground_sample_edges(self.samples, e_view)))),
            "density_edges": ("4fv", packed(edge_uniform(sample_edges(self.density_samples, e_depth)))),
            "rayleigh_scattering": ("4fv", per_group(b_r)), "mie_scattering": ("4fv", per_group(b_m)),
            "component_extinction": ("4fv", ext.reshape(-1, 4)),
            "component_profile": ("3fv", prof), "component_table": ("4fv", packed(table.ravel())),
            "artistic_terms": ("i", int(self.terms == "artistic")),
            "multiple_scattering_size": ("2f", (MS_SIZE[1], MS_SIZE[0])),
            "albedo_weights": ("4fv", albedo_weights.reshape(-1, 4)),
            "use_surface_texture": ("i", int(self.surface is not None)),
            "surface_face_size": ("f", self._cube().shape[1] - 2),
        }

    def _cube(self):
        """The surface map on the faces of a cube (planetviz/render/surface.py), or a black 1-texel cube."""
        return surface_cube_or_black(self.surface)

    @property
    def pending(self):
        """True while the table of the orders above the first is computed or not yet shown."""
        return self._job is not None

    def collect(self, wait=False):
        """Show the orders above the first from the next frame on, if their table is ready (``wait``: wait for
        it). Returns True when this call switched them on."""
        if self._job is None or (not wait and not self._job.done):
            return False
        self._job.join()
        job, self._job = self._job, None
        if job.error is not None:                     # the computation failed: single scattering stays
            return False
        self.multiple, self.ground_sky = job.result
        self._release_textures(MULTIPLE_SCATTERING_TEXTURES)        # bind uploads the tables in their place
        self._frame_key = None                        # new frame uniforms (multiple_scattering) at the next frame
        return True

    def bind(self, program):
        """Upload the textures not yet on the GPU (the logarithms of Psi and E_sky, which the shader reads
        geometrically: zeros until their table is ready, or for single scattering alone, and unread then; the
        surface), activate them and point the samplers at them."""
        window = self.renderer.GetRenderWindow()
        if "surface_faces" not in self._textures:
            self._textures["surface_faces"] = self._surface_texture.get(window, self._cube())
        if "multiple_scattering_texture" not in self._textures:
            shape = (*MS_SIZE, self.atmosphere.n_wavelengths)
            log = lambda table: np.log(np.maximum(table, LOG_FLOOR)).astype(np.float32)
            psi = log(self.multiple) if self.multiple is not None else np.zeros(shape, np.float32)
            sky = (log(self.ground_sky) if self.ground_sky is not None
                   else np.zeros((GROUND_SKY_COLUMNS, self.atmosphere.n_wavelengths), np.float32))
            self._textures["multiple_scattering_texture"] = upload(window, pack_2d(psi))
            self._textures["ground_sky_texture"] = upload(window, pack_2d(sky[None]))
        for name, tex in self._textures.items():
            tex.Activate()
            program.SetUniformi(name, tex.GetTextureUnit())

    def start_job(self):
        """Start computing the table of the orders above the first, if it waits (the scene starts it after the
        actor's first frame, planetviz/render/background.py)."""
        if self._job is not None:
            self._job.start()

    def deactivate(self):
        for tex in self._textures.values():
            tex.Deactivate()

    def release(self):
        """Stop following the renderer and free the GPU textures (the surface's where it is the actor's own)."""
        super().release()
        self._release_textures([name for name in self._textures if name != "surface_faces"])
        self._textures.pop("surface_faces", None)
        if self._own_surface:
            self._surface_texture.release()

    def _release_textures(self, names):
        for name in names:
            tex = self._textures.pop(name, None)
            if tex is not None:
                tex.ReleaseGraphicsResources(self.renderer.GetRenderWindow())

    def frame_uniforms(self, view):
        return {**draw_uniforms(view, np.asarray(self.sun_direction), self.settings, self.atmosphere),
                "multiple_scattering": ("i", int(self.multiple is not None))}
