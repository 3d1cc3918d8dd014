// The per-vertex renderer's fragments (after atmosphere_ray.glsl, inscatter_factor.glsl, interpolation.glsl,
// display.glsl and pixel.glsl): the inscatter (geometrically, interpolation.glsl), the sun disc's radiance and the
// ground's light of atmosphere_vertex.glsl interpolated over the triangle, completed per pixel with what changes
// faster across the screen: the ray's inscatter_factor (the inscatter is multiplied by the pixel's over the
// interpolated one), the surface texture's colour at the pixel's ground point and the sun's cosine there (the
// terminator); no 4D table is read per pixel. Shown through display.glsl (output_mode 0) or written as it is (1:
// spectral radiance, 2: linear sRGB).
//
// Uniforms: those of the files before it. The constant sky_part (planetviz/render/direction_mesh.py) is true in the
// part of the mesh whose rays all miss the ground, where the ground's code is left out.

in vec3 mesh_inscatter;
in vec4 mesh_phase_weights;
in float mesh_factor;
in float mesh_magnitude;
in float mesh_log_magnitude;
in float mesh_log_factor;
in vec2 mesh_ground_factors;
in vec3 mesh_sun;
in mat3 mesh_ground_sky;
in mat3 mesh_ground_sun;

// The largest correction of an interpolated value by a factor of ray_factors (the pixel's over the interpolated
// one). Where the mesh does not resolve the atmosphere at all (a halo thinner than the sagitta of the sectors'
// chords, a thin atmosphere seen from far) a pixel's factor can exceed its vertices' by orders of magnitude while
// their inscatter does not follow; the correction is then a guess, and bounded.
const float MAX_FACTOR_CORRECTION = 4.0;

float correction(float pixel, float interpolated) {
    return interpolated > 0.0 ? min(pixel / interpolated, MAX_FACTOR_CORRECTION) : 1.0;
}

// The inscatter: its colour times its magnitude interpolated geometrically (interpolation.glsl) and multiplied by
// the pixel's factor over the geometric interpolant of the vertices' factors, so that where the inscatter and its
// factor fall together by orders of magnitude across a triangle (a halo narrower than a pixel, the ground's twilight
// band) their ratio is what is interpolated. Two bounds, each relative to a linear interpolant (which bounds a value
// by its vertices'): the pixel's factor at most MAX_FACTOR_CORRECTION times the vertices' factors' (relative to the
// geometric interpolant, which inside such a triangle is many times below the linear one, the bound would cut the
// pixels to a fraction of their value), and the result at most MAX_FACTOR_CORRECTION times the vertices' magnitudes'
// (where a vertex's factor is 0, its sun below the factor's table, and its inscatter is not, the ratio alone would
// be unbounded).
vec3 corrected_inscatter(float pixel_factor) {
    float geometric_factor = geometric_scalar(mesh_factor, mesh_log_factor);
    float magnitude = geometric_scalar(mesh_magnitude, mesh_log_magnitude);
    if (geometric_factor > 0.0) {
        magnitude *= min(pixel_factor, MAX_FACTOR_CORRECTION * mesh_factor) / geometric_factor;
    }
    return mesh_inscatter * min(magnitude, MAX_FACTOR_CORRECTION * mesh_magnitude);
}

vec4 atmosphere_interpolated() {
    vec3 v = pixel_direction();
    ViewRay ray = view_ray(v);
    RayFactors f = ray_factors(ray, mesh_phase_weights, !sky_part);
    vec3 value = corrected_inscatter(f.inscatter);
    bool ground = false;
    if (!sky_part) {
        ground = ray_hits_ground(ray);
        if (ground) {
            vec3 n = normalize(ground_point(ray));
            mat3 light = mesh_ground_sky * correction(f.irradiance, mesh_ground_factors.y)
                + max(dot(n, sun_direction), 0.0) * mesh_ground_sun;
            value += light * surface_colour_or_unit(n) * correction(f.transmittance, mesh_ground_factors.x);
        }
    }
    if (!ground && in_sun_disc(v)) value += mesh_sun;
    // Spectral radiance is interpolated from non-negative vertices, but the rasteriser's barycentric weights can be
    // slightly negative on the slivers straddling a limb, which would extrapolate below 0 (linear sRGB may be
    // negative out of gamut and stays as it is; the display clamps).
    if (output_mode == 1) value = max(value, 0.0);
    return output_mode == 0 ? vec4(display_colour(value), 1.0) : vec4(value, 1.0);
}
