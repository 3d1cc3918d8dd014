// The table-based renderer per vertex (after atmosphere_ray.glsl, inscatter_factor.glsl and interpolation.glsl): for
// the direction of a vertex of the direction mesh around the camera (direction_mesh.glsl), the inscatter of
// atmosphere_ray.glsl (the 4D tables), the sun disc's radiance and the light the ground sends toward the camera,
// summed over the wavelength groups into the three output channels, for atmosphere_interpolated.glsl to interpolate
// over the triangles and complete per pixel.
//
// Uniforms: those of the files before it, and
//   sun_solid_angle        float  solid angle of the sun's disc [sr]
// The constant sky_part (planetviz/render/direction_mesh.py) is true in the part of the mesh whose rays all miss
// the ground, where the ground's light is left out.
// Outputs (output channels as output_mode says):
//   mesh_inscatter     vec3  the inscatter's colour: the inscatter (aerial perspective for ground rays) over its
//                            largest channel (its magnitude; split_magnitude, interpolation.glsl)
//   mesh_magnitude     float the inscatter's magnitude
//   mesh_phase_weights vec4  phase_weights of the inscatter's parts (inscatter_factor.glsl)
//   mesh_factor        float the ray's inscatter factor (inscatter_factor.glsl ray_factors)
//   mesh_log_magnitude float the logarithm of the inscatter's magnitude
//   mesh_log_factor    float the logarithm of mesh_factor
//   mesh_ground_factors vec2 the transmittance and the sky irradiance of ray_factors for the ground's light
//   mesh_sun           vec3  the disc's radiance T / sun_solid_angle along this direction
//   mesh_ground_sky    mat3  column k: the ground's radiance lit by the sky, T(x, y) albedo E_sky(y) / pi, for a
//                            unit of component k of the surface colour (surface_colour_or_unit)
//   mesh_ground_sun    mat3  column k: the same lit by the sun, T(x, y) albedo T_sun(y) / pi, per unit of
//                            max(n . s, 0), which the pixel multiplies in (the terminator stays sharp)
// For a ray that misses the ground the ground's terms are those of the grazing ray at the same azimuth, so a
// triangle straddling the limb interpolates toward the ground's value at the horizon.

uniform float sun_solid_angle;

out vec3 mesh_inscatter;
out vec4 mesh_phase_weights;
out float mesh_factor;
out float mesh_magnitude;
out float mesh_log_magnitude;
out float mesh_log_factor;
out vec2 mesh_ground_factors;
out vec3 mesh_sun;
out mat3 mesh_ground_sky;
out mat3 mesh_ground_sun;

// The ray itself where it meets the ground; otherwise the ray tangent to the ground in the plane of its direction
// and the nadir (the ray itself straight up, where that plane is undefined).
ViewRay ground_or_grazing(ViewRay ray) {
    if (ray_hits_ground(ray)) return ray;
    vec3 down = -normalize(camera_position);
    vec3 side = ray.v - dot(ray.v, down) * down;
    float s = length(side);
    if (s == 0.0) return ray;
    float r = radius_of(camera_altitude);
    return view_ray(down * (rho_of(camera_altitude) / r) + side * (bottom_radius / (r * s)));
}

void ground_light_columns(ViewRay ray) {
    mesh_ground_sky = mat3(0.0);
    mesh_ground_sun = mat3(0.0);
    mesh_ground_factors = vec2(1.0);
    if (sky_part) return;
    ViewRay grazing = ground_or_grazing(ray);
    RayFactors f = ray_factors(grazing, mesh_phase_weights, true);
    mesh_ground_factors = vec2(f.transmittance, f.irradiance);
    GroundHit h = ground_hit(grazing);
    for (int g = first_group(); g <= last_group(); ++g) {
        vec4 t = get_transmittance(grazing.a, grazing.mu, h.d, g) / PI;
        vec4 sky = t * get_irradiance(0.0, h.mu_s, g);
        vec4 sun = t * get_transmittance_to_top_atmosphere_boundary(0.0, max(h.mu_s, 0.0), g);
        for (int k = 0; k < 3; ++k) {
            mesh_ground_sky[k] += to_channels(albedo_column(k, g) * sky, g);
            mesh_ground_sun[k] += to_channels(albedo_column(k, g) * sun, g);
        }
    }
}

// The inscatter's parts (get_inscatter_parts); in the sky part, whose rays all miss the ground, read at the camera
// only: the constant folds the ground point's reading away, which a software renderer would otherwise run for every
// vertex (it runs both sides of a branch).
ScatteringParts vertex_inscatter_parts(ViewRay ray, int g) {
    if (!sky_part) return get_inscatter_parts(ray, g);
    if (!ray.visible) return ScatteringParts(vec4(0.0), vec4(0.0), vec4(0.0), vec4(0.0));
    return get_scattering_parts(ray.a, ray.mu, ray.mu_s, ray.nu, false, g);
}

void atmosphere_vertex(vec3 direction) {
    ViewRay ray = view_ray(direction);
    mesh_inscatter = vec3(0.0);
    mesh_phase_weights = vec4(0.0, 0.0, 1.0, 0.0);
    mesh_factor = 0.0;
    mesh_sun = vec3(0.0);
    for (int g = first_group(); g <= last_group(); ++g) {
        ScatteringParts parts = vertex_inscatter_parts(ray, g);
        if (g == first_group()) mesh_phase_weights = phase_weights(parts);
        mesh_inscatter += to_channels(max(phased_sum(parts, ray.nu, g), 0.0), g);
        mesh_sun += to_channels(get_sun_transmittance(ray, g), g) / sun_solid_angle;
    }
    mesh_factor = ray_factors(ray, mesh_phase_weights, !sky_part).inscatter;
    split_magnitude(mesh_inscatter, mesh_inscatter, mesh_magnitude, mesh_log_magnitude);
    mesh_log_factor = floored_log(mesh_factor);
    ground_light_columns(ray);
}
