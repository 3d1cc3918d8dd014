// The in-scattered radiance of one ray from the compact tables (after table_lookup.glsl, in place of near_ground.glsl,
// horizon.glsl and phased_scattering.glsl): the GLSL twin of planetviz/tables/compact.py's compact_uvw_from_r_mu_mu_s
// and get_compact_scattering, and of planetviz/tables/evaluator.py's phased_scattering for compact tables. The
// transmittance and irradiance tables are the 4D set's (table_lookup.glsl).
//
// Uniforms (set by planetviz/render/atmosphere_actor.py for every draw):
//   compact_size                vec3       compact tables (n_mu_s, n_mu, n_h)
//   compact_rayleigh_texture    sampler3D  single scattering by molecules without phase, averaged over the sun-view
//                                          azimuth; x: mu_s, y: mu, z: altitude, the G groups stacked along z
//   compact_mie_texture         sampler3D  the same for particles
//   compact_multiple_texture    sampler3D  orders >= 2 (radiance, phase included), the same layout
uniform vec3 compact_size;
uniform sampler3D compact_rayleigh_texture;
uniform sampler3D compact_mie_texture;
uniform sampler3D compact_multiple_texture;

// Atmosphere Plus's zenith-cosine coordinate in [0, 1]: (1 + sign(c) |c|^(1/3)) / 2.
float compact_x_from_cosine(float c) {
    return 0.5 * (1.0 + sign(c) * pow(abs(c), 1.0 / 3.0));
}

// (u_mu_s, u_mu, u_h) of the compact tables: x_h = sqrt(h / (R_t - R_b)), the cosines through compact_x_from_cosine.
vec3 compact_uvw_from_r_mu_mu_s(float a, float mu, float mu_s) {
    float x_h = sqrt(clamp(a / (top_radius - bottom_radius), 0.0, 1.0));
    return vec3(texcoord_from_unit_range(compact_x_from_cosine(mu_s), compact_size.x),
                texcoord_from_unit_range(compact_x_from_cosine(mu), compact_size.y),
                texcoord_from_unit_range(x_h, compact_size.z));
}

// A compact table of group g at uvw, trilinear (the hardware's).
vec4 get_compact_scattering(sampler3D table, vec3 uvw, int g) {
    return texture(table, vec3(uvw.x, uvw.y, (float(g) + uvw.z) / float(group_count)));
}

// In-scattered radiance of group g in its parts (the evaluator's phased_scattering for compact tables before the
// phases): the single-scattering tables, and multiple scattering with its phase included (no particle part).
ScatteringParts get_scattering_parts(float a, float mu, float mu_s, float nu, bool intersects_ground, int g) {
    vec3 uvw = compact_uvw_from_r_mu_mu_s(a, mu, mu_s);
    return ScatteringParts(get_compact_scattering(compact_rayleigh_texture, uvw, g),
                           get_compact_scattering(compact_mie_texture, uvw, g),
                           get_compact_scattering(compact_multiple_texture, uvw, g), vec4(0.0));
}

// get_scattering_parts at a ground point (a = 0), for a ray to the ground.
ScatteringParts get_ground_point_parts(float mu, float mu_s, float nu, int g) {
    return get_scattering_parts(0.0, mu, mu_s, nu, true, g);
}

// In-scattered radiance of group g: the single-scattering tables times their phase functions at the true nu, plus
// multiple scattering.
vec4 get_phased_scattering(float a, float mu, float mu_s, float nu, bool intersects_ground, int g) {
    return phased_sum(get_scattering_parts(a, mu, mu_s, nu, intersects_ground, g), nu, g);
}
