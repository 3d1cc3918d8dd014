// Single scattering integrated along the rays next to the horizon's direction and the rays along which the sun is
// low somewhere (after near_ground.glsl): the GLSL twin of planetviz/tables/horizon.py, whose docstring says why.
// No uniforms of its own.
//
// The rays within HORIZON_BAND of the horizon's direction (horizon_share) and those along which the sun's elevation
// falls below TWILIGHT_BAND (twilight_share) take their single scattering from Gauss-Legendre nodes on each side of
// the closest approach of each lit part of the ray, blended into the tables' reading by the larger share
// (quadrature_share).
#define HORIZON_SAMPLES 12
const vec2 HORIZON_BAND = vec2(0.01, 0.03);
const vec2 TWILIGHT_BAND = vec2(0.0, 0.034899497);          // sin(0 deg), sin(2 deg)
const float HORIZON_NODES[12] = float[12](0.009219683, 0.047941372, 0.115048663, 0.206341023, 0.316084251,
    0.437383296, 0.562616704, 0.683915749, 0.793658977, 0.884951337, 0.952058628, 0.990780317);
const float HORIZON_WEIGHTS[12] = float[12](0.023587668, 0.053469663, 0.080039164, 0.101583713, 0.116746268,
    0.124573523, 0.124573523, 0.116746268, 0.101583713, 0.080039164, 0.053469663, 0.023587668);
const float HORIZON_NODES_ONE_SIDE[24] = float[24](0.002406390, 0.012635722, 0.030862724, 0.056792236, 0.089999007,
    0.129937904, 0.175953174, 0.227289264, 0.283103246, 0.342478660, 0.404440566, 0.467971554, 0.532028446,
    0.595559434, 0.657521340, 0.716896754, 0.772710736, 0.824046826, 0.870062096, 0.910000993, 0.943207764,
    0.969137276, 0.987364278, 0.997593610);
const float HORIZON_WEIGHTS_ONE_SIDE[24] = float[24](0.006170615, 0.014265694, 0.022138719, 0.029649292, 0.036673241,
    0.043095081, 0.048809326, 0.053722135, 0.057752834, 0.060835236, 0.062918728, 0.063969098, 0.063969098,
    0.062918728, 0.060835236, 0.057752834, 0.053722135, 0.048809326, 0.043095081, 0.036673241, 0.029649292,
    0.022138719, 0.014265694, 0.006170615);

float horizon_share(float a, float mu) {
    float mu_h = -sqrt(a * (a + 2.0 * bottom_radius)) / radius_of(a);
    float x = clamp((HORIZON_BAND.y - abs(mu - mu_h)) / (HORIZON_BAND.y - HORIZON_BAND.x), 0.0, 1.0);
    return x * x * (3.0 - 2.0 * x);
}

// The least cos(sun zenith) at the points of the ray (a, mu) from 0 to d: at an end, or where the point's direction,
// which turns by theta_d in the plane of the camera's and the view's, points most away from the sun.
float lowest_mu_s(float a, float mu, float mu_s, float nu, float d) {
    float sin_v = sqrt(max(1.0 - mu * mu, 0.0));
    float theta_d = atan(d * sin_v, radius_of(a) + d * mu);
    float b_max = sqrt(max(1.0 - mu_s * mu_s, 0.0));
    float b = sin_v > 0.0 ? clamp((nu - mu * mu_s) / sin_v, -b_max, b_max) : 0.0;
    float low = min(mu_s, mu_s * cos(theta_d) + b * sin(theta_d));
    bool between = mod(atan(b, mu_s) + PI, 2.0 * PI) <= theta_d;
    return between ? min(low, -sqrt(mu_s * mu_s + b * b)) : low;
}

float twilight_share(float a, float mu, float mu_s, float nu, bool intersects_ground) {
    float d = intersects_ground ? distance_to_bottom_atmosphere_boundary(a, mu)
                                : distance_to_top_atmosphere_boundary(a, mu);
    float low = lowest_mu_s(a, mu, mu_s, nu, d);
    float x = clamp((TWILIGHT_BAND.y - low) / (TWILIGHT_BAND.y - TWILIGHT_BAND.x), 0.0, 1.0);
    return x * x * (3.0 - 2.0 * x);
}

float quadrature_share(float a, float mu, float mu_s, float nu, bool intersects_ground) {
    return max(horizon_share(a, mu), twilight_share(a, mu, mu_s, nu, intersects_ground));
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
