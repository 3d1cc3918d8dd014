// The planet and its atmosphere for one pixel: the paper's Algorithm 1 (Sect. 5.2), read from the tables
// (after atmosphere_ray.glsl, display.glsl and pixel.glsl). Inserted into the fragment shader of a shell
// enclosing the atmosphere (front faces culled, so it covers exactly the pixels whose rays may meet the
// atmosphere, from space and from inside). The view ray comes from gl_FragCoord and the camera uniforms,
// computed in double precision on the CPU, never from the shell's vertices; intersections use the stable forms
// (planetviz/model/geometry.py).
//
// Uniforms: those of the files before it (output_mode and output_triple in atmosphere_ray.glsl).

// Radiance of group g along the ray, per unit solar irradiance [1/sr].
vec4 radiance(ViewRay ray, int g) {
    vec4 l = get_inscatter(ray, g);
    if (ray_hits_ground(ray)) {
        l += albedo_from_colour(surface_colour_or_unit(normalize(ground_point(ray))), g) * get_ground_light(ray, g);
    } else if (in_sun_disc(ray.v)) {
        l += get_sun_transmittance(ray, g) / sun_solid_angle;
    }
    return l;
}

vec4 atmosphere_fragment() {
    ViewRay ray = view_ray(pixel_direction());
    vec3 value = vec3(0.0);
    for (int g = first_group(); g <= last_group(); ++g) value += to_channels(radiance(ray, g), g);
    return output_mode == 0 ? vec4(display_colour(value), 1.0) : vec4(value, 1.0);
}
