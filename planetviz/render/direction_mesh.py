"""The adaptive sphere of view directions around the camera, and the base of the actors that evaluate a model at
its vertices (the quick view, shaders/quick_view_vertex.glsl, and the per-vertex table renderer,
shaders/atmosphere_vertex.glsl).

The mesh is a sphere of directions around the camera: rings of constant angle from the nadir, dense just inside
and outside the planet's limb (the horizon seen from the ground) with a pair of rings straddling it, so the
horizon's step in brightness is sharp; extra rings and sectors around the sun, where the forward-scattering peak
needs them (the paper's "adaptive dome tessellated around the sun"; from space only where the sun is near the
atmosphere); and, from space, extra sectors where the planet's shadow meets the halo. Its vertices hold their
ring's and sector's indices, and shaders/direction_mesh.glsl makes their directions from the rings' and sectors'
angles and the mesh's axes, uniforms: when the camera or the sun moves, NumPy recomputes those angles and which
quads are drawn (1-3 ms), and the vertex buffer stays as it is. Each vertex is drawn at infinity along its
direction (the camera's translation drops out of the projection, so no float32 rounding of positions 6.4e6 m from
the planet's centre) and at mid-depth (at a true distance a 16-bit depth buffer, as in the float read-back, rounds
it onto the far plane and drops fragments).
"""
from __future__ import annotations

import functools
import math

import numpy as np
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401
from vtkmodules.util.misc import calldata_type
from vtkmodules.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray
from vtkmodules.vtkCommonCore import VTK_OBJECT, vtkCommand, vtkPoints
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData
from vtkmodules.vtkRenderingCore import vtkActor, vtkAssembly, vtkPolyDataMapper

from .shaders import shader_code
from .uniforms import DisplaySettings, UniformStore, camera_uniforms, frame_key

#: Degrees around the sun and around the limb where the mesh is refined.
SUN_REFINEMENT_DEG = (0.3, 0.7, 1.5, 3.0, 6.0, 12.0)
#: The angle [rad] of the two rings either side of the limb from it: a pixel's centre between them takes a blend of a
#: ray to the ground and a ray past it, which where the planet's shadow meets the limb reads several times either
#: (from 4 radii a pixel of a 720-pixel-high 30 deg view spans 7.4e-4 rad).
LIMB_STRADDLE = 2e-5
#: Rings on each side of the limb and sectors around the nadir of the actors' meshes (before the refinements).
RINGS = 40
SECTORS = 72


#: Rings between the planet's limb and the top of the atmosphere's, seen from above the top where that halo is
#: wider than HALO_PIXELS pixels: at the tangent altitudes k / n of the atmosphere's thickness, k = 1 .. n - 1,
#: n twice the halo's width in pixels, at least 4 and at most LIMB_RINGS. The radiance of the rays through the
#: limb falls by e about every scale height of tangent altitude (from 4 Earth radii, by 100 times across the
#: halo's 3 pixels); its ratio to the inscatter factor (shaders/inscatter_factor.glsl) changes where the tangent
#: path's optical depth passes 1, an altitude that depends on the wavelength and the atmosphere, hence even steps.
LIMB_RINGS = 16
HALO_PIXELS = 1
#: Sectors on each side of the sun where the planet's shadow meets the halo, seen from space (one per tangent
#: altitude, :func:`_shadow_limb_azimuths`): at the ends of the lit crescent the halo falls from lit to dark within a
#: few degrees of azimuth along the limb, which the SECTORS' 5 degrees do not resolve. Any other sector within a
#: quarter of the SECTORS' spacing of one of them is left out.
SHADOW_LIMB_SECTORS = 9
#: The most rings and sectors a mesh of RINGS and SECTORS has (every refinement distinct): the lengths of the
#: shader's ring_theta and sector_phi arrays (shaders/direction_mesh.glsl).
MESH_RINGS = 2 * RINGS + 4 + 3 + (LIMB_RINGS - 1) + 2 * len(SUN_REFINEMENT_DEG) + 1
MESH_SECTORS = SECTORS + 2 * len(SUN_REFINEMENT_DEG) + 1 + 2 * SHADOW_LIMB_SECTORS

#: The order of the triangles handed to OpenGL and the vertex buffer's layout, for a software renderer's vertex
#: reuse: llvmpipe shades the vertices of each run of 1024 indices once each (those of the next run again), telling
#: them apart by a direct-mapped table of 256 entries (the index modulo 256), on one thread. Quad after quad along
#: whole rings, a run spans two rings of quads and shades three rings of vertices. In strips of STRIP_SECTORS
#: sectors, ring after ring within a strip, a run spans about 11 rings of 16 quads; vertex (i, j) at index
#: i VERTEX_STRIDE + j, VERTEX_STRIDE = STRIP_SECTORS + 1 modulo 256, puts the rows of a strip on consecutive
#: entries of the table, 15 rows without a collision. Measured in docs/benchmarks.md ("Frame time on llvmpipe").
STRIP_SECTORS = 16
VERTEX_STRIDE = 273


def _ring_angles(limb, top_limb, rings, bottom, top, r, pixel):
    """Angles from the nadir [rad] of the rings of a camera at ``r`` from the centre of a planet of radius
    ``bottom`` under an atmosphere to ``top``: dense toward the limb from both sides, two rings
    :data:`LIMB_STRADDLE` either side of it, and, from above the top (``top_limb``, the top's limb,
    not None), the top's limb and, where the halo between the two limbs is wider than :data:`HALO_PIXELS` pixels
    of ``pixel`` [rad] (always for None), rings of tangent altitudes across it (:data:`LIMB_RINGS`)."""
    k = np.arange(1, rings + 1) / (rings + 1)
    inside = limb * (1 - (1 - k) ** 2)
    outside = limb + (math.pi - limb) * k ** 2
    extra = [limb - LIMB_STRADDLE, limb + LIMB_STRADDLE, 0.0, math.pi]
    if top_limb is not None:
        extra += [top_limb - 1e-3, top_limb - 1e-5, top_limb + 1e-3]
        if pixel is None or top_limb - limb > HALO_PIXELS * pixel:
            n = LIMB_RINGS if pixel is None else int(np.clip(np.ceil(2.0 * (top_limb - limb) / pixel), 4, LIMB_RINGS))
            tangent = bottom + (top - bottom) * (np.arange(1, n) / n)
            extra += list(np.arcsin(tangent / r))
    return np.unique(np.clip(np.concatenate([inside, outside, extra]), 0.0, math.pi))


class DirectionMesh:
    """The adaptive sphere of directions of :func:`direction_mesh`: ``theta`` (n_t,) rings' angles from the nadir
    ``down`` and ``phi`` (n_p,) sectors' azimuths from ``e1`` toward ``e2`` (about ``down``), both increasing.
    Quad (i, j) joins rings i and i + 1 and sectors j and j + 1 (the last sector to the first); its two triangles
    are rows 2 q and 2 q + 1 of :attr:`triangles`, q = i n_p + j. The culling tests work quad by quad on the rings'
    and sectors' angles (a few NumPy operations on small arrays: they run on every frame of a moving camera) and
    return (n_quads,) bools; :meth:`triangles_of` turns such a mask into triangles."""

    def __init__(self, theta, phi, down, e1, e2):
        self.theta, self.phi = theta, phi
        self.down, self.e1, self.e2 = down, e1, e2
        self._sin_theta, self._cos_theta = np.sin(theta), np.cos(theta)
        self._sin_phi, self._cos_phi = np.sin(phi), np.cos(phi)
        self.triangles = ring_triangles(len(theta), len(phi))
        self.longest_edges = self._longest_edges()

    @property
    def directions(self):
        """(n_t n_p, 3) the vertices' unit directions, ring after ring (the shader's mesh_direction)."""
        return np.moveaxis(self.dots(np.eye(3)), 0, -1).reshape(-1, 3)

    def dots(self, vectors):
        """(k, n_t, n_p) each vertex's direction dotted with each of ``vectors`` (k, 3):
        cos(theta) (down . v) + sin(theta) (cos(phi) (e1 . v) + sin(phi) (e2 . v))."""
        v = np.asarray(vectors, dtype=float).reshape(-1, 3)
        around = (self._cos_phi[None, None, :] * (v @ self.e1)[:, None, None]
                  + self._sin_phi[None, None, :] * (v @ self.e2)[:, None, None])
        return self._cos_theta[None, :, None] * (v @ self.down)[:, None, None] + self._sin_theta[None, :, None] * around

    def _longest_edges(self):
        """(n_t - 1, n_p) the longest chord between two corners of each quad (its sides and its diagonal, an
        upper bound on the longest edge of its two triangles), from chord^2 = 2 - 2 cos."""
        t0, t1 = self.theta[:-1, None], self.theta[1:, None]
        d_phi = (np.roll(self.phi, -1) - self.phi) % (2 * math.pi)
        half = np.sin(0.5 * d_phi)[None, :]
        rings = 2.0 * np.maximum(np.sin(t0), np.sin(t1)) * half
        sides = np.broadcast_to(2.0 * np.sin(0.5 * (t1 - t0)), rings.shape)
        cos_diagonal = np.cos(t0) * np.cos(t1) + np.sin(t0) * np.sin(t1) * np.cos(d_phi)[None, :]
        diagonal = np.sqrt(np.maximum(2.0 - 2.0 * cos_diagonal, 0.0))
        return np.maximum(np.maximum(rings, sides), diagonal)

    def _corners(self, values):
        """The four corners' ``values`` (..., n_t, n_p) of each quad: (a, b, c, d) each (..., n_t - 1, n_p)."""
        ahead = np.roll(values, -1, axis=-1)
        return values[..., :-1, :], ahead[..., :-1, :], values[..., 1:, :], ahead[..., 1:, :]

    def uniforms(self):
        """{name: (kind, value)} of shaders/direction_mesh.glsl for this mesh (the arrays padded with their last
        value to MESH_RINGS and MESH_SECTORS; a mesh made with more rings or sectors than RINGS and SECTORS does not
        fit)."""
        return {"mesh_from_grid": ("i", 1), "mesh_down": ("3f", self.down), "mesh_e1": ("3f", self.e1),
                "mesh_e2": ("3f", self.e2),
                "ring_theta": ("1fv", np.pad(self.theta, (0, MESH_RINGS - len(self.theta)), mode="edge")),
                "sector_phi": ("1fv", np.pad(self.phi, (0, MESH_SECTORS - len(self.phi)), mode="edge"))}

    def triangles_of(self, quads):
        """(m, 3) the triangles of the quads where the (n_quads,) bool ``quads`` is true."""
        return self.triangles.reshape(-1, 2, 3)[np.asarray(quads).ravel()].reshape(-1, 3)

    def buffer_triangles_of(self, quads):
        """(m, 3) the triangles of the quads where the (n_quads,) bool ``quads`` is true as OpenGL draws them:
        indices into :func:`grid_points`' vertex buffer, in strips of :data:`STRIP_SECTORS` sectors."""
        order, triangles = strip_triangles(len(self.theta), len(self.phi))
        return triangles[np.asarray(quads).ravel()[order]].reshape(-1, 3)

    def in_view(self, forward, right, up):
        """The quads not wholly outside one side of the view frustum (``right`` and ``up`` scaled by the tangents
        of the half fields of view, as in :func:`camera_uniforms`). The sides are planes through the camera, so a
        flat quad with its four corners beyond one of them is beyond it whole."""
        forward = np.asarray(forward, dtype=float)
        sides = [np.asarray(v, dtype=float) for v in (right, up)]
        normals = np.stack([side / np.dot(side, side) - forward for v in sides for side in (v, -v)], axis=1)
        # A quad is out when its four corners are all beyond one of the four sides.
        beyond = self._corners(self.dots(normals.T) > 0.0)
        return ~np.any(beyond[0] & beyond[1] & beyond[2] & beyond[3], axis=0).ravel()

    def may_meet_sphere(self, camera, radius):
        """The quads that may contain rays from ``camera`` meeting the sphere of ``radius`` about the planet's
        centre (the ground, or the top of the atmosphere): a corner inside the sphere's cone, or within the
        largest distance [rad] by which an edge between two corners outside the cone can dip inside it (the edges
        are great-circle arcs, the cone's edge a small circle), plus 1e-3 rad. ``camera`` must lie on the mesh's
        nadir axis."""
        r = np.linalg.norm(np.asarray(camera, dtype=float))
        if r <= radius:
            return np.ones(self.longest_edges.size, bool)
        limb = math.asin(radius / r)
        # The longest edge of each ring of quads as half an azimuthal span on the cone's circle, then the dip of an
        # arc of that span: tan(theta_mid) = tan(limb) cos(half span). A quad's least nadir angle is its first
        # ring's, so the test holds for whole rings of quads.
        half = np.arcsin(np.clip(self.longest_edges.max(axis=1) / (2 * math.sin(limb)), 0.0, 1.0))
        dip = limb - np.arctan(math.tan(min(limb, math.pi / 2 - 1e-9)) * np.cos(half))
        return np.repeat(self.theta[:-1] <= limb + dip + 1e-3, len(self.phi))

    def may_meet_disc(self, direction, radius):
        """The quads that may contain directions within ``radius`` [rad] of the unit ``direction`` (the sun's
        disc): any point of a quad's triangles lies within the quad's longest chord of a corner, so a quad meeting
        the disc has a corner within ``radius`` + that chord (as angles, plus 1e-3 rad)."""
        cos_to = np.clip(self.dots(direction)[0], -1.0, 1.0)
        a, b, c, d = self._corners(cos_to)
        nearest = np.maximum(np.maximum(a, b), np.maximum(c, d))
        reach = radius + 2.0 * np.arcsin(np.minimum(self.longest_edges / 2.0, 1.0)) + 1e-3
        return (np.arccos(nearest) <= reach).ravel()


def direction_mesh(camera, sun, bottom, top, rings=RINGS, sectors=SECTORS, pixel=None):
    """The adaptive sphere of directions around ``camera`` (:class:`DirectionMesh`); ``pixel``: the angle [rad] a
    pixel spans at the centre of the view (None: as if it were small)."""
    camera = np.asarray(camera, dtype=float)
    r = np.linalg.norm(camera)
    down = -camera / r
    limb = math.asin(min(bottom / r, 1.0)) if r > bottom else math.pi / 2
    top_limb = math.asin(top / r) if r > top else None
    theta = _ring_angles(limb, top_limb, rings, bottom, top, r, pixel)
    # Azimuth about the nadir axis, zero toward the sun's azimuth.
    e1 = np.asarray(sun, dtype=float) - np.dot(sun, down) * down
    if np.linalg.norm(e1) < 1e-9:
        e1 = np.cross(down, [1.0, 0.0, 0.0] if abs(down[0]) < 0.9 else [0.0, 1.0, 0.0])
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(down, e1)
    theta_sun = math.acos(np.clip(np.dot(sun, down), -1.0, 1.0))
    refine = np.radians(SUN_REFINEMENT_DEG)
    if top_limb is not None and theta_sun > top_limb + refine[-1]:
        refine = refine[:0]                 # from space, no ray near the sun meets the atmosphere
    theta = np.unique(np.clip(np.concatenate([theta, theta_sun + refine, theta_sun - refine, [theta_sun]]),
                              0.0, math.pi))
    ring_radius = max(math.sin(theta_sun), 1e-3)
    phi = np.concatenate([np.linspace(-math.pi, math.pi, sectors, endpoint=False),
                          np.clip(refine / ring_radius, 0, math.pi), -np.clip(refine / ring_radius, 0, math.pi), [0.0]])
    if top_limb is not None:
        # The shadow's sectors take the place of the others within a quarter of their spacing of one.
        shadow = _shadow_limb_azimuths(r, bottom, top, np.dot(sun, down), np.dot(sun, e1))
        if shadow.size:
            gap = np.abs(np.angle(np.exp(1j * (phi[:, None] - shadow[None, :])))).min(axis=1)
            phi = np.concatenate([phi[gap > 0.5 * math.pi / sectors], shadow])
    phi = np.unique(np.mod(phi + math.pi, 2 * math.pi) - math.pi)
    return DirectionMesh(theta, phi, down, e1, e2)


def _shadow_limb_azimuths(r, bottom, top, s_down, s_e1, n=SHADOW_LIMB_SECTORS):
    """Azimuths [rad] about the nadir (zero toward the sun's) where the planet's shadow meets the halo seen from
    ``r`` > ``top``: for tangent radii r_h = bottom + (top - bottom) (k / (n - 1))^2, k = 0 .. n - 1, the two
    azimuths where the ray tangent at r_h has its tangent point on the shadow cylinder's edge (on the terminator
    for r_h = bottom). The tangent point is r sin(theta) (-sin(theta) down + cos(theta) u(phi)), sin(theta) =
    r_h / r, u(phi) = cos(phi) e1 + sin(phi) e2, and the sun s = s_down down + s_e1 e1 (s_e1 >= 0); it lies on
    the shadow's edge where its dot with s is -sqrt(r_h^2 - bottom^2):
    cos(phi) = (sin(theta) s_down - sqrt(r_h^2 - bottom^2) / r_h) / (cos(theta) s_e1). Empty where the shadow
    does not meet the halo."""
    r_h = bottom + (top - bottom) * np.linspace(0.0, 1.0, n) ** 2
    sin_t = r_h / r
    cos_t = np.sqrt(1.0 - sin_t * sin_t)
    cos_phi = (sin_t * s_down - np.sqrt(np.maximum(r_h * r_h - bottom * bottom, 0.0)) / r_h) / np.maximum(
        cos_t * s_e1, 1e-12)
    phi = np.arccos(cos_phi[np.abs(cos_phi) <= 1.0])
    return np.concatenate([phi, -phi])


@functools.lru_cache(maxsize=8)
def ring_triangles(n_t, n_p):
    """(m, 3) the triangles between ``n_t`` rings of ``n_p`` vertices each, vertex (i, j) numbered i n_p + j (as
    :attr:`DirectionMesh.directions` lists them): the two triangles of each quad side by side, quad after quad
    along the rings (kept: the same for every mesh with as many rings and sectors). OpenGL gets them in the order
    and numbering of :func:`strip_triangles`."""
    i, j = np.meshgrid(np.arange(n_t - 1), np.arange(n_p), indexing="ij")
    a, b = i * n_p + j, i * n_p + (j + 1) % n_p
    c, d = a + n_p, b + n_p
    tris = np.stack([np.stack([a, b, d], -1), np.stack([a, d, c], -1)], axis=2).reshape(-1, 3)
    tris.flags.writeable = False
    return tris


@functools.lru_cache(maxsize=8)
def strip_triangles(n_t, n_p):
    """(order (n_quads,), triangles (n_quads, 2, 3)): the quads of :func:`ring_triangles` in strips of
    :data:`STRIP_SECTORS` sectors (ring after ring within a strip, sector after sector within a ring) and their two
    triangles, as indices into :func:`grid_points`' vertex buffer (vertex (i, j) at i VERTEX_STRIDE + j)."""
    if n_p > VERTEX_STRIDE:
        raise ValueError(f"sectors: at most {VERTEX_STRIDE} in a mesh, got {n_p}")
    i, j = np.meshgrid(np.arange(n_t - 1), np.arange(n_p), indexing="ij")
    order = np.lexsort((j.ravel(), i.ravel(), j.ravel() // STRIP_SECTORS))
    tris = ring_triangles(n_t, n_p).reshape(-1, 2, 3)[order]
    tris = (tris // n_p) * VERTEX_STRIDE + tris % n_p
    order.flags.writeable = tris.flags.writeable = False
    return order, tris


def _points(points):
    pts = vtkPoints()
    pts.SetData(numpy_to_vtk(np.ascontiguousarray(points, dtype=np.float32), deep=True))
    return pts


@functools.lru_cache(maxsize=4)
def grid_points(n_t):
    """vtkPoints of the vertices (i, j, 0) of a mesh of ``n_t`` rings, vertex (i, j) at index i VERTEX_STRIDE + j
    (:func:`strip_triangles`; the entries past a mesh's sectors are never drawn). Kept: the same object, hence the
    same vertex buffer, for every frame with as many rings."""
    i, j = np.meshgrid(np.arange(n_t), np.arange(VERTEX_STRIDE), indexing="ij")
    return _points(np.stack([i, j, np.zeros_like(i)], axis=-1).reshape(-1, 3))


def _cell_array(cells):
    """vtkCellArray of ``cells`` (m, k), each of k point ids."""
    arr = vtkCellArray()
    arr.SetData(cells.shape[1], numpy_to_vtkIdTypeArray(np.ascontiguousarray(cells, dtype=np.int64).ravel(), deep=True))
    return arr


def _set_cells(poly, points, cells, kind):
    """Make ``poly`` ``cells`` (polygons or vertices) over ``points``; the same polydata from frame to frame, so
    that VTK keeps its vertex buffer while ``points`` stays the same object."""
    if poly.GetPoints() is not points:
        poly.SetPoints(points)
    setters = {"polys": (poly.GetPolys, poly.SetPolys), "verts": (poly.GetVerts, poly.SetVerts)}
    setters[kind][1](_cell_array(cells))
    get_other, set_other = setters["verts" if kind == "polys" else "polys"]
    if get_other() is not None and get_other().GetNumberOfCells():       # emptied once, when the kind changes
        set_other(vtkCellArray())


class DirectionMeshActor:
    """A VTK actor drawing the direction mesh around the renderer's active camera, its vertex shader calling
    ``vertex_call`` on each vertex's unit direction (``vertex_code`` declares it) and its fragment shader writing
    ``fragment_call`` (declared by ``fragment_code``).

    ``split_at_limb``: draw the triangles that may contain rays to the ground and the others (sky only) as two
    parts of a ``vtkAssembly``, each with its own shader program; ``fragment_code`` then sees the constant
    ``sky_part`` (true in the second), so the sky's fragments do not pay for the ground's code (a software
    renderer runs both sides of a branch). Subclasses give :meth:`static_uniforms` (set once) and
    :meth:`frame_uniforms` (set before each frame, where they changed) and may bind textures in :meth:`bind`
    (called for every draw). ``directions``: fixed unit directions (n, 3) drawn as points instead of the
    adaptive mesh (for tests that need one vertex per pixel)."""

    def __init__(self, atmosphere, renderer, vertex_code, vertex_call, fragment_code, fragment_call,
                 split_at_limb=False, settings=None):
        self.atmosphere = atmosphere
        self.renderer = renderer
        self.sun_direction = np.array([1.0, 0.0, 0.0])
        self.directions = None
        self.split_at_limb = split_at_limb
        self.settings = settings or DisplaySettings()
        self._mesh_key = self._frame_key = None
        self.mappers, actors, self._stores, self._polys, self._cells = [], [], [], [], []
        static = self.static_uniforms()
        mesh_code = (f"#define MESH_RINGS {MESH_RINGS}\n#define MESH_SECTORS {MESH_SECTORS}\n"
                     + shader_code("direction_mesh.glsl"))
        for prefix in (("const bool sky_part = false;\n", "const bool sky_part = true;\n") if split_at_limb
                       else ("",)):
            mapper = vtkPolyDataMapper()
            mapper.SetVBOShiftScaleMethod(0)
            poly = vtkPolyData()
            mapper.SetInputData(poly)
            self._polys.append(poly)
            self._cells.append(None)
            actor = vtkActor()
            actor.SetMapper(mapper)
            actor.GetProperty().SetPointSize(1)
            sp = actor.GetShaderProperty()
            sp.AddVertexShaderReplacement("//VTK::PositionVC::Dec", True,
                                          "//VTK::PositionVC::Dec\n" + prefix + mesh_code + vertex_code, False)
            sp.AddVertexShaderReplacement("//VTK::PositionVC::Impl", True,
                                          "//VTK::PositionVC::Impl\n  vec3 mesh_dir = mesh_direction(vertexMC.xyz);\n"
                                          f"  {vertex_call}(mesh_dir);\n"
                                          "  gl_Position = MCDCMatrix * vec4(mesh_dir, 0.0);\n"
                                          "  gl_Position.z = 0.0;  // mid-depth: no far-plane or depth-format "
                                          "quantisation\n", False)
            sp.AddFragmentShaderReplacement("//VTK::Light::Dec", True, prefix + fragment_code, False)
            sp.AddFragmentShaderReplacement("//VTK::Light::Impl", True, f"gl_FragData[0] = {fragment_call}();\n",
                                            False)
            store = UniformStore(sp)
            store.update(static)
            mapper.AddObserver(vtkCommand.UpdateShaderEvent, self._shader_observer(store))
            self._stores.append(store)
            self.mappers.append(mapper)
            actors.append(actor)
        self.mapper = self.mappers[0]
        if split_at_limb:
            self.actor = vtkAssembly()
            for actor in actors:
                self.actor.AddPart(actor)
        else:
            self.actor = actors[0]
        # The vertices hold ring and sector indices, not positions: their bounds mean nothing, so the actor takes
        # no part in the clipping range, and the renderer's frustum culler, which judges props by their bounds,
        # is removed (it would drop the mesh whenever the planet's centre is out of view).
        self.actor.SetUseBounds(False)
        renderer.GetCullers().RemoveAllItems()
        self._observers = [renderer.AddObserver(vtkCommand.StartEvent, self._start_frame)]

    def release(self):
        """Stop following the renderer (call when the actor is taken out of the scene)."""
        for tag in self._observers:
            self.renderer.RemoveObserver(tag)
        self._observers = []

    def static_uniforms(self):
        """{name: (kind, value)} of the uniforms that stay as they are for the actor's life."""
        raise NotImplementedError

    def frame_uniforms(self, view):
        """{name: (kind, value)} of the uniforms of the next frame; ``view``: :func:`camera_uniforms`."""
        raise NotImplementedError

    def bind(self, program):
        """Activate textures and set their sampler uniforms (none here)."""

    def _start_frame(self, caller=None, event=None):
        key = (frame_key(self.renderer, self.sun_direction, self.settings), id(self.directions))
        if key == self._frame_key:
            return
        self._frame_key = key
        view = camera_uniforms(self.renderer)
        frame = {**self._update_mesh(view), **self.frame_uniforms(view)}
        for store in self._stores:
            store.update(frame)

    def _update_mesh(self, view):
        """Hand the mappers the triangles (or points) of the next frame; return the mesh's uniforms (none where
        the mesh is as it was)."""
        cam = view["camera_position"][1]
        key = (tuple(cam), tuple(self.sun_direction), None if self.directions is None else id(self.directions),
               tuple(np.concatenate([view[name][1] for name in ("camera_forward", "camera_right", "camera_up")])))
        if key == self._mesh_key:
            return {}
        self._mesh_key = key
        if self.directions is not None:
            points = _points(self.directions)
            parts = [(np.arange(len(self.directions))[:, None], "verts"), (np.zeros((0, 3), np.int64), "polys")]
            uniforms = {"mesh_from_grid": ("i", 0)}
        else:
            bottom = self.atmosphere.bottom_radius_m
            tan_up, height = np.linalg.norm(view["camera_up"][1]), view["viewport"][1][3]
            mesh = direction_mesh(cam, self.sun_direction, bottom, self.atmosphere.top_radius_m,
                                  pixel=2.0 * math.atan(tan_up) / max(height, 1.0))
            drawn = mesh.in_view(*(view[name][1] for name in ("camera_forward", "camera_right", "camera_up")))
            if np.linalg.norm(cam) > self.atmosphere.top_radius_m:
                # From space, rays that miss the atmosphere and the sun's disc stay black, the background's
                # colour: their quads are not drawn (most of the frame).
                sun_radius = math.radians(self.atmosphere.star.angular_radius_deg())
                drawn &= (mesh.may_meet_sphere(cam, self.atmosphere.top_radius_m)
                          | mesh.may_meet_disc(self.sun_direction / np.linalg.norm(self.sun_direction), sun_radius))
            points = grid_points(len(mesh.theta))
            if self.split_at_limb:
                ground = mesh.may_meet_sphere(cam, bottom)
                parts = [(mesh.buffer_triangles_of(drawn & ground), "polys"),
                         (mesh.buffer_triangles_of(drawn & ~ground), "polys")]
            else:
                parts = [(mesh.buffer_triangles_of(drawn), "polys")]
            uniforms = mesh.uniforms()
        for k, (poly, (cells, kind)) in enumerate(zip(self._polys, parts)):
            last = self._cells[k]
            if (poly.GetPoints() is not points or last is None or last[1] != kind
                    or not np.array_equal(last[0], cells)):
                _set_cells(poly, points, cells, kind)      # VTK uploads the part's index buffer again
                self._cells[k] = (cells, kind)
        return uniforms

    def _shader_observer(self, store):
        """The observer of one part's UpdateShaderEvent: its array uniforms and the textures, for each draw."""
        @calldata_type(VTK_OBJECT)
        def update_shader(caller, event, program=None):
            if program is not None:
                store.set_arrays(program)
                self.bind(program)
        return update_shader
