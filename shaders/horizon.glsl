// Single scattering integrated along the rays next to the horizon's direction (after near_ground.glsl): the GLSL
// twin of planetviz/tables/horizon.py.
//
// Uniforms (set by planetviz/render/atmosphere_actor.py for every draw):
//   horizon_quadrature          int    1: the rays next to the horizon's direction are integrated (horizon_share),
//                                      0 for optically thick atmospheres (planetviz/tables/horizon.py)
uniform int horizon_quadrature;

// ------------------------------------------------------------------- next to the horizon (NumPy twin:
// planetviz/tables/horizon.py, whose docstring says why): single scattering of the rays within HORIZON_BAND of the
// horizon's direction by Gauss-Legendre nodes on each side of the closest approach of each lit part of the ray,
// blended into the tables' reading by horizon_share.
#define HORIZON_SAMPLES 8
const vec2 HORIZON_BAND = vec2(0.01, 0.03);
const float HORIZON_NODES[8] = float[8](0.019855072, 0.101666761, 0.237233795, 0.408282679, 0.591717321,
                                        0.762766205, 0.898333239, 0.980144928);
const float HORIZON_WEIGHTS[8] = float[8](0.050614268, 0.111190517, 0.156853323, 0.181341892, 0.181341892,
                                          0.156853323, 0.111190517, 0.050614268);
const float HORIZON_NODES_ONE_SIDE[16] = float[16](0.005299533, 0.027712488, 0.067184399, 0.122297796,
    0.191061878, 0.270991611, 0.359198225, 0.452493745, 0.547506255, 0.640801775, 0.729008389, 0.808938122,
    0.877702204, 0.932815601, 0.972287512, 0.994700467);
const float HORIZON_WEIGHTS_ONE_SIDE[16] = float[16](0.013576230, 0.031126762, 0.047579256, 0.062314486,
    0.074797994, 0.084578260, 0.091301708, 0.094725305, 0.094725305, 0.091301708, 0.084578260, 0.074797994,
    0.062314486, 0.047579256, 0.031126762, 0.013576230);

float horizon_share(float a, float mu) {
    if (horizon_quadrature == 0) return 0.0;
    float mu_h = -sqrt(a * (a + 2.0 * bottom_radius)) / radius_of(a);
    float x = clamp((HORIZON_BAND.y - abs(mu - mu_h)) / (HORIZON_BAND.y - HORIZON_BAND.x), 0.0, 1.0);
    return x * x * (3.0 - 2.0 * x);
}

// Node k (0 .. 2 HORIZON_SAMPLES - 1) of precompute.py's ray_nodes on [start, end] along (a, mu): t = t_c -+ span u^2
// on each side of the closest approach t_c, or all nodes on the one side there is where t_c is an end.
vec2 ray_node(float a, float mu, float start, float end, int k) {
    float t_c = clamp(-radius_of(a) * mu, start, end);
    if (t_c <= start || t_c >= end) {
        float span = end - start;
        float u = HORIZON_NODES_ONE_SIDE[k];
        float t = t_c <= start ? start + span * u * u : end - span * u * u;
        return vec2(t, 2.0 * span * u * HORIZON_WEIGHTS_ONE_SIDE[k]);
    }
    float u = HORIZON_NODES[k % HORIZON_SAMPLES];
    float span = k < HORIZON_SAMPLES ? t_c - start : end - t_c;
    float t = k < HORIZON_SAMPLES ? t_c - span * u * u : t_c + span * u * u;
    return vec2(t, 2.0 * span * u * HORIZON_WEIGHTS[k % HORIZON_SAMPLES]);
}

// (S_R,1, S_M,1) of group g without phase, per unit solar irradiance, of the ray (a, mu) to the ground or the top.
void horizon_single_scattering(float a, float mu, float mu_s, float nu, bool intersects_ground, int g,
                               out vec4 s_r, out vec4 s_m) {
    float d = intersects_ground ? distance_to_bottom_atmosphere_boundary(a, mu)
                                : distance_to_top_atmosphere_boundary(a, mu);
    vec2 shadow = shadow_interval(a, mu, mu_s, nu, d);
    mat2x4 readings = ray_readings(a, mu, d, g);                // get_transmittance's, taken once per ray
    s_r = vec4(0.0);
    s_m = vec4(0.0);
    for (int k = 0; k < 4 * HORIZON_SAMPLES; ++k) {
        bool lit_before = k < 2 * HORIZON_SAMPLES;
        vec2 node = ray_node(a, mu, lit_before ? 0.0 : shadow.y, lit_before ? shadow.x : d, k % (2 * HORIZON_SAMPLES));
        add_single_scattering_node(a, mu, mu_s, nu, node.x, node.y, readings, g, s_r, s_m);
    }
    s_r *= rayleigh_scattering[g];
    s_m *= mie_scattering[g];
}
