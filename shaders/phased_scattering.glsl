// The in-scattered radiance of one ray from the tables and the quadratures (after horizon.glsl): the GLSL twin of
// planetviz/tables/evaluator.py's phased_scattering. No uniforms of its own.

// In-scattered radiance of group g in its parts (the evaluator's phased_scattering before the phases): single
// scattering from the tables or, for ground rays from near the ground, near_ground_single_scattering, and next to the
// horizon or with the sun low along the ray blended with horizon_single_scattering (quadrature_share); multiple
// scattering with its tables' ground_row_factor and top tables (get_multiple_scattering). The four tables' reads
// share the ray's opacity.
ScatteringParts get_scattering_parts(float a, float mu, float mu_s, float nu, bool intersects_ground, int g) {
    vec4 s_r, s_m;
    vec4 opacity = ray_opacity(a, mu, intersects_ground, g);
    if (near_ground_rays(a, intersects_ground)) {
        near_ground_single_scattering(a, mu, mu_s, nu, g, s_r, s_m);
    } else {
        s_r = get_scattering(single_rayleigh_texture, single_size, a, mu, mu_s, nu, intersects_ground, opacity, g);
        s_m = get_scattering(single_mie_texture, single_size, a, mu, mu_s, nu, intersects_ground, opacity, g);
        float share = quadrature_share(a, mu, mu_s, nu, intersects_ground);
        if (share > 0.0) {
            vec4 q_r, q_m;
            horizon_single_scattering(a, mu, mu_s, nu, intersects_ground, g, q_r, q_m);
            s_r += share * (q_r - s_r);
            s_m += share * (q_m - s_m);
        }
    }
    vec4 row = ground_row_factor(a, mu, intersects_ground, multiple_size.w, multiple_row_1_rho, g);
    return ScatteringParts(s_r, s_m,
        get_multiple_scattering(multiple_texture, top_multiple_texture, multiple_size, a, mu, mu_s, nu,
                                intersects_ground, opacity, g) * row,
        get_multiple_scattering(multiple_mie_texture, top_multiple_mie_texture, multiple_size, a, mu, mu_s, nu,
                                intersects_ground, opacity, g) * row);
}

// get_scattering_parts at a ground point (a = 0) for a ray to the ground, which has length 0 there: no single
// scattering (near_ground_single_scattering's integral over no length), the multiple-scattering tables with their
// opacity and ground_row_factor both 1. Written apart because a software renderer runs both sides of every branch:
// the general function would run the near-ground quadrature and the single-scattering tables for nothing.
ScatteringParts get_ground_point_parts(float mu, float mu_s, float nu, int g) {
    vec4 one = vec4(1.0);
    return ScatteringParts(vec4(0.0), vec4(0.0),
        get_scattering(multiple_texture, multiple_size, 0.0, mu, mu_s, nu, true, one, g),
        get_scattering(multiple_mie_texture, multiple_size, 0.0, mu, mu_s, nu, true, one, g));
}

// In-scattered radiance of group g (the evaluator's phased_scattering): get_scattering_parts with their phases.
vec4 get_phased_scattering(float a, float mu, float mu_s, float nu, bool intersects_ground, int g) {
    return phased_sum(get_scattering_parts(a, mu, mu_s, nu, intersects_ground, g), nu, g);
}
