// The in-scattered radiance of one ray from the tables and the quadratures (after horizon.glsl): the GLSL twin of
// planetviz/tables/evaluator.py's phased_scattering. No uniforms of its own.

// In-scattered radiance of group g (the evaluator's phased_scattering): single scattering with its phases, from the tables
// or, for ground rays from near the ground, near_ground_single_scattering, and next to the horizon blended with
// horizon_single_scattering; plus multiple scattering with its tables' ground_row_factor. The four tables' reads share
// the ray's opacity.
vec4 get_phased_scattering(float a, float mu, float mu_s, float nu, bool intersects_ground, int g) {
    vec4 s_r, s_m;
    vec4 opacity = ray_opacity(a, mu, intersects_ground, g);
    if (near_ground_rays(a, intersects_ground)) {
        near_ground_single_scattering(a, mu, mu_s, nu, g, s_r, s_m);
    } else {
        s_r = get_scattering(single_rayleigh_texture, single_size, a, mu, mu_s, nu, intersects_ground, opacity, g);
        s_m = get_scattering(single_mie_texture, single_size, a, mu, mu_s, nu, intersects_ground, opacity, g);
        float share = horizon_share(a, mu);
        if (share > 0.0) {
            vec4 q_r, q_m;
            horizon_single_scattering(a, mu, mu_s, nu, intersects_ground, g, q_r, q_m);
            s_r += share * (q_r - s_r);
            s_m += share * (q_m - s_m);
        }
    }
    vec4 s_ms = get_scattering(multiple_texture, multiple_size, a, mu, mu_s, nu, intersects_ground, opacity, g);
    vec4 s_ms_mie = get_scattering(multiple_mie_texture, multiple_size, a, mu, mu_s, nu, intersects_ground, opacity, g);
    return s_r * rayleigh_like_phase(nu) + s_m * double_henyey_greenstein(nu, mie_g1[g], mie_g2[g], mie_alpha[g])
        + (s_ms + forward_factor(nu, g) * s_ms_mie) * ground_row_factor(a, mu, intersects_ground, multiple_size.w, g);
}
