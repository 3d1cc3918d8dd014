// The direction of a vertex of the direction mesh around the camera (planetviz/render/direction_mesh.py,
// DirectionMesh). A vertex holds the indices of its ring i and its sector j, and its direction is
//   cos(theta_i) mesh_down + sin(theta_i) (cos(phi_j) mesh_e1 + sin(phi_j) mesh_e2)
// so a camera in motion changes these uniforms while the vertex buffer stays as it is. The vertex is drawn at
// infinity along that direction (w = 0: the camera's translation drops out of the projection) and at mid-depth.
//
// Uniforms (MESH_RINGS and MESH_SECTORS are defined before this file, from direction_mesh.py):
//   mesh_from_grid               int    1: vertexMC is (i, j, 0); 0: vertexMC is the unit direction itself (fixed
//                                       directions drawn as points, DirectionMeshActor.directions)
//   mesh_down, mesh_e1, mesh_e2  vec3   the mesh's nadir, and the azimuth's zero (toward the sun) and quarter
//   ring_theta[MESH_RINGS]       float  the rings' angles from mesh_down [rad], in order
//   sector_phi[MESH_SECTORS]     float  the sectors' azimuths [rad], in order

uniform int mesh_from_grid;
uniform vec3 mesh_down;
uniform vec3 mesh_e1;
uniform vec3 mesh_e2;
uniform float ring_theta[MESH_RINGS];
uniform float sector_phi[MESH_SECTORS];

vec3 mesh_direction(vec3 vertex) {
    if (mesh_from_grid == 0) return normalize(vertex);
    float theta = ring_theta[int(vertex.x + 0.5)];
    float phi = sector_phi[int(vertex.y + 0.5)];
    return cos(theta) * mesh_down + sin(theta) * (cos(phi) * mesh_e1 + sin(phi) * mesh_e2);
}
