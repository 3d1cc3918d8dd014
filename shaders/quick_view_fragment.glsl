// Quick view, per fragment (after common.glsl, view.glsl, interpolation.glsl, display.glsl and pixel.glsl): the
// vertex shader's inscatter (geometrically, interpolation.glsl) and ground light (quick_view_vertex.glsl)
// interpolated over the triangle, completed per pixel with the surface texture's colour at the pixel's ground point
// and the sun's cosine there (the terminator), as atmosphere_interpolated.glsl completes the per-vertex tables; no
// sun disc. Shown through display.glsl (output_mode 0) or written as it is (1: spectral radiance, 2: linear sRGB).
//
// Uniforms: those of the files before it. The constant sky_part (planetviz/render/direction_mesh.py) is true in the
// part of the mesh whose rays all miss the ground.

in vec3 quick_view_value;
in float quick_magnitude;
in float quick_log_magnitude;
in mat3 quick_ground_sky;
in mat3 quick_ground_sun;

vec4 quick_view_fragment() {
    vec3 v = pixel_direction();
    vec3 value = geometric_value(quick_view_value, quick_magnitude, quick_log_magnitude);
    float mu = dot(camera_position, v) / radius_of(camera_altitude);
    if (!sky_part && ray_intersects_ground(camera_altitude, mu)) {
        vec3 n = normalize(camera_position + distance_to_bottom_atmosphere_boundary(camera_altitude, mu) * v);
        value += (quick_ground_sky + max(dot(n, sun_direction), 0.0) * quick_ground_sun) * surface_colour_or_unit(n);
    }
    // Spectral radiance is interpolated from non-negative vertices, but the rasteriser's barycentric weights can be
    // slightly negative on the slivers straddling a limb, which would extrapolate below 0 (linear sRGB may be
    // negative out of gamut and stays as it is; the display clamps).
    if (output_mode == 1) value = max(value, 0.0);
    return output_mode == 0 ? vec4(display_colour(value), 1.0) : vec4(value, 1.0);
}
