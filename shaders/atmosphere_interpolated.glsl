// The per-vertex renderer's fragments (after atmosphere_ray.glsl, display.glsl and pixel.glsl): the inscatter and
// the sun disc's radiance of atmosphere_vertex.glsl interpolated over the triangle, plus the lit ground per pixel,
// because it changes faster across the screen (the surface texture, the terminator) and reads only 2D tables
// (sun and sky irradiance, transmittance to the camera); shown through display.glsl (output_mode 0) or written as
// it is (1: spectral radiance, 2: linear sRGB).
//
// Uniforms: those of the files before it. The constant sky_part (planetviz/render/direction_mesh.py) is true in the
// part of the mesh whose rays all miss the ground, where the ground's code is left out.

in vec3 mesh_inscatter;
in vec3 mesh_sun;

vec4 atmosphere_interpolated() {
    vec3 v = pixel_direction();
    // Spectral radiance is interpolated from non-negative vertices, but the rasteriser's barycentric weights can be
    // slightly negative on the slivers straddling a limb, which would extrapolate below 0 (linear sRGB may be
    // negative out of gamut and stays as it is; the display clamps).
    vec3 value = output_mode == 1 ? max(mesh_inscatter, 0.0) : mesh_inscatter;
    bool ground = false;
    if (!sky_part) {
        ViewRay ray = view_ray(v);
        ground = ray_hits_ground(ray);
        if (ground) {
            vec3 c = use_surface_texture == 1 ? surface_colour(ground_point(ray)) : vec3(0.0);
            for (int g = first_group(); g <= last_group(); ++g) {
                value += to_channels(albedo_from_colour(c, g) * get_ground_light(ray, g), g);
            }
        }
    }
    if (!ground && in_sun_disc(v)) value += output_mode == 1 ? max(mesh_sun, 0.0) : mesh_sun;
    return output_mode == 0 ? vec4(display_colour(value), 1.0) : vec4(value, 1.0);
}
