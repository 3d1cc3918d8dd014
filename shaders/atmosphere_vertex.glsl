// The table-based renderer per vertex (after atmosphere_ray.glsl): for the direction from the camera to a vertex
// of the direction mesh around the camera, the inscatter of atmosphere_ray.glsl (the 4D tables) and the sun
// disc's radiance, summed over the wavelength groups into the three output channels, for
// atmosphere_interpolated.glsl to interpolate over the triangles and complete per pixel.
//
// Uniforms: those of the files before it, and
//   sun_solid_angle        float  solid angle of the sun's disc [sr]
// Outputs (output channels as output_mode says): mesh_inscatter (vec3), mesh_sun (vec3: the disc's radiance
// T / sun_solid_angle along this direction).

uniform float sun_solid_angle;

out vec3 mesh_inscatter;
out vec3 mesh_sun;

void atmosphere_vertex(vec3 vertex_position) {
    ViewRay ray = view_ray(normalize(vertex_position - camera_position));
    mesh_inscatter = vec3(0.0);
    mesh_sun = vec3(0.0);
    for (int g = first_group(); g <= last_group(); ++g) {
        mesh_inscatter += to_channels(get_inscatter(ray, g), g);
        mesh_sun += to_channels(get_sun_transmittance(ray, g), g) / sun_solid_angle;
    }
}
