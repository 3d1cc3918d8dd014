// Quick view: Keller and Bohn's single scattering computed per vertex, with no 4D tables (after common.glsl).
// The GLSL twin of planetviz/quick_view/single_scattering.py (same sampling, same names): for the direction from the
// camera to the vertex, L = sum_i Delta_i J(p_i) exp(-tau(x, p_i) - tau(p_i, sun)) V_i plus the sunlit ground, with
// the midpoint rule on (i / n)^view_exponent and each optical depth on (j / m)^density_exponent. With
// multiple_scattering = 1, the orders above the first from Hillaire's table Psi_ms(h, mu_s)
// (planetviz/quick_view/multiple_scattering.py): sum_i Delta_i beta_s(h_i) Psi_ms exp(-tau(x, p_i)), and the sky's
// irradiance on the ground E_sky(mu_s) added to the sun's.
//
// Uniforms:
//   camera_position        vec3   planet-centred camera position [m]
//   camera_altitude        float  |camera_position| - bottom_radius [m], computed in double on the CPU
//   sun_direction          vec3   unit vector toward the sun
//   view_samples           int    n, points on the view path
//   density_samples        int    m, points on each optical-depth path
//   view_exponent          float  3 (the paper's power law) or 1 (equidistant)
//   density_exponent       float  2 (the paper's power law) or 1 (equidistant)
//   rayleigh_scattering    vec4[MAX_GROUPS]  beta_R^s at the ground [1/m]
//   mie_scattering         vec4[MAX_GROUPS]  beta_M^s at the ground [1/m]
//   component_count        int    extinction components (Rayleigh, Mie, then absorbers), at most MAX_COMPONENTS
//   component_extinction   vec4[MAX_COMPONENTS * MAX_GROUPS]  [k * MAX_GROUPS + g]: extinction of component k [1/m]
//   component_profile      vec3[MAX_COMPONENTS]  (0, scale height, 0) exponential; (1, centre, half width) tent;
//                                 (2, top altitude, 0) tabulated in component_table[k] at PROFILE_TABLE_SIZE
//                                 altitudes from 0 to the top, read linearly
//   component_table        float[MAX_COMPONENTS * PROFILE_TABLE_SIZE]
//   artistic_terms         int    1: Table 1's phases 1 + 0.5 nu^2 and HG without 1 / (4 pi) (coefficients are
//                                 uploaded already scaled, planetviz/quick_view/single_scattering.py _coefficients)
//   surface_albedo         vec4[MAX_GROUPS]  ground albedo per wavelength
//   rgb_weights            vec4[3 MAX_GROUPS]  linear sRGB of group g = dot(rgb_weights[3g + c], L_g) (as in
//                                 atmosphere_fragment.glsl)
//   output_mode            int    0 and 2: linear sRGB; 1: the radiance at wavelengths 3k .. 3k + 2
//                                 (k = output_triple) per unit solar irradiance [1/sr]
//   output_triple          int    k of output_mode 1
//   multiple_scattering    int    1: add the orders above the first and the sky's light on the ground; 0: single
//                                 scattering alone (Keller and Bohn)
//   multiple_scattering_texture  sampler2D  Psi_ms [1/sr per unit solar irradiance], rows: altitudes
//                                 H (i / (n_h - 1))^2 (H the thickness), columns: mu_s = sign(x) x^2, x uniform in
//                                 [-1, 1]; groups of four wavelengths stacked along y (textures.py pack_2d)
//   ground_sky_texture     sampler2D  E_sky [per unit solar irradiance] over the same mu_s, one row per group
//   multiple_scattering_size  vec2  (n_mu_s, n_h) of multiple_scattering_texture
// Output: quick_view_value (vec3), interpolated over the triangles.

#define MAX_COMPONENTS 6
#define PROFILE_TABLE_SIZE 64

uniform vec3 camera_position;
uniform float camera_altitude;
uniform vec3 sun_direction;
uniform int view_samples;
uniform int density_samples;
uniform float view_exponent;
uniform float density_exponent;
uniform vec4 rayleigh_scattering[MAX_GROUPS];
uniform vec4 mie_scattering[MAX_GROUPS];
uniform int component_count;
uniform vec4 component_extinction[MAX_COMPONENTS * MAX_GROUPS];
uniform vec3 component_profile[MAX_COMPONENTS];
uniform float component_table[MAX_COMPONENTS * PROFILE_TABLE_SIZE];
uniform int artistic_terms;
uniform vec4 surface_albedo[MAX_GROUPS];
uniform vec4 rgb_weights[3 * MAX_GROUPS];
uniform int output_mode;
uniform int output_triple;
uniform int multiple_scattering;
uniform sampler2D multiple_scattering_texture;
uniform sampler2D ground_sky_texture;
uniform vec2 multiple_scattering_size;

out vec3 quick_view_value;

// Density of component k at altitude h (its profile, 1 at its reference altitude).
float profile_density(int k, float h) {
    vec3 p = component_profile[k];
    h = max(h, 0.0);
    if (p.x == 0.0) return exp(-h / p.y);
    if (p.x == 1.0) return max(0.0, 1.0 - abs(h - p.y) / p.z);
    float x = clamp(h / p.y, 0.0, 1.0) * float(PROFILE_TABLE_SIZE - 1);
    int i = min(int(x), PROFILE_TABLE_SIZE - 2);
    float f = x - float(i);
    return mix(component_table[k * PROFILE_TABLE_SIZE + i], component_table[k * PROFILE_TABLE_SIZE + i + 1], f);
}

// Column coordinate in [0, 1] of a cosine on the tables' grid sign(x) x^2 (cosine_grid in NumPy).
float cosine_coordinate(float mu) {
    mu = clamp(mu, -1.0, 1.0);
    return (sign(mu) * sqrt(abs(mu)) + 1.0) / 2.0;
}

// Psi_ms of group g at altitude h and sun zenith cosine mu_s: bilinear between texel centres, as read_table in NumPy.
vec4 multiple_scattering_at(float h, float mu_s, int g) {
    vec2 n = multiple_scattering_size;
    float x = cosine_coordinate(mu_s) * (n.x - 1.0);
    float y = sqrt(clamp(h / (top_radius - bottom_radius), 0.0, 1.0)) * (n.y - 1.0);
    vec2 uv = vec2((x + 0.5) / n.x, (float(g) * n.y + y + 0.5) / (float(group_count) * n.y));
    return texture(multiple_scattering_texture, uv);
}

// E_sky of group g on the ground where the sun's zenith cosine is mu_s.
vec4 ground_sky_irradiance(float mu_s, int g) {
    float n = multiple_scattering_size.x;
    float x = cosine_coordinate(mu_s) * (n - 1.0);
    return texture(ground_sky_texture, vec2((x + 0.5) / n, (float(g) + 0.5) / float(group_count)));
}

// Edges (i / n)^e of the midpoint rule.
float sample_edge(int i, int n, float e) { return pow(float(i) / float(n), e); }

// tau of group g along start + t direction, 0 <= t <= len, midpoint rule at (j / m)^density_exponent.
vec4 path_optical_depth(vec3 start, vec3 direction, float len, int g) {
    vec4 tau = vec4(0.0);
    for (int j = 0; j < density_samples; ++j) {
        float a = sample_edge(j, density_samples, density_exponent);
        float b = sample_edge(j + 1, density_samples, density_exponent);
        float h = length(start + (0.5 * (a + b) * len) * direction) - bottom_radius;
        vec4 ext = vec4(0.0);
        for (int k = 0; k < component_count; ++k) {
            ext += component_extinction[k * MAX_GROUPS + g] * profile_density(k, h);
        }
        tau += (b - a) * ext;
    }
    return tau * len;
}

// Distance from p (|p| <= top) to where the ray leaves the top of the atmosphere.
float distance_to_top_exit(vec3 p, vec3 d) {
    float b = dot(p, d);
    vec3 q = p - b * d;
    return max(-b + safe_sqrt(top_radius * top_radius - dot(q, q)), 0.0);
}

// True where the planet hides the sun from p.
bool in_shadow(vec3 p) {
    float r = length(p);
    return ray_intersects_ground(r - bottom_radius, dot(p, sun_direction) / r);
}

// Single-scattered radiance of group g along v from the camera, per unit solar irradiance [1/sr].
vec4 quick_view_radiance(vec3 v, int g) {
    vec3 x = camera_position;
    float a = camera_altitude;
    float mu = dot(x, v) / radius_of(a);
    // Enter the atmosphere first when the camera is in space (closest approach as a vector: no cancellation).
    if (a > top_radius - bottom_radius) {
        float b = dot(x, v);
        vec3 q = x - b * v;
        float p2 = dot(q, q);
        if (b >= 0.0 || p2 >= top_radius * top_radius) return vec4(0.0);
        x = q - sqrt(top_radius * top_radius - p2) * v;
        a = top_radius - bottom_radius;
        mu = dot(x, v) / top_radius;
    }
    bool ground = ray_intersects_ground(a, mu);
    float path = ground ? distance_to_bottom_atmosphere_boundary(a, mu) : distance_to_top_exit(x, v);
    float nu = dot(v, sun_direction);
    float p_r, p_m_norm;
    vec4 p_m;
    if (artistic_terms == 1) {
        p_r = 1.0 + 0.5 * nu * nu;
        p_m = 4.0 * PI * henyey_greenstein(nu, mie_g1[g]);
    } else {
        p_r = rayleigh_like_phase(nu);
        p_m = double_henyey_greenstein(nu, mie_g1[g], mie_g2[g], mie_alpha[g]);
    }
    vec4 l = vec4(0.0);
    for (int i = 0; i < view_samples; ++i) {
        float a = sample_edge(i, view_samples, view_exponent);
        float b = sample_edge(i + 1, view_samples, view_exponent);
        float t = 0.5 * (a + b) * path;
        vec3 p = x + t * v;
        float h = length(p) - bottom_radius;
        float rho_r = profile_density(0, h), rho_m = profile_density(1, h);
        vec4 tau_view = path_optical_depth(x, v, t, g);
        if (multiple_scattering == 1) {
            vec4 beta_s = rayleigh_scattering[g] * rho_r + mie_scattering[g] * rho_m;
            l += (b - a) * path * beta_s * multiple_scattering_at(h, dot(p, sun_direction) / length(p), g)
               * exp(-tau_view);
        }
        if (in_shadow(p)) continue;
        vec4 j = rayleigh_scattering[g] * rho_r * p_r + mie_scattering[g] * rho_m * p_m;
        vec4 tau = tau_view + path_optical_depth(p, sun_direction, distance_to_top_exit(p, sun_direction), g);
        l += (b - a) * path * j * exp(-tau);
    }
    if (ground) {
        vec3 y = x + path * v;
        vec3 n = normalize(y);
        float mu_s = dot(n, sun_direction);
        float cos_s = max(mu_s, 0.0);
        vec4 irradiance = vec4(0.0);
        if (cos_s > 0.0) {
            irradiance = cos_s * exp(-path_optical_depth(y, sun_direction, distance_to_top_exit(y, sun_direction), g));
        }
        if (multiple_scattering == 1) irradiance += ground_sky_irradiance(mu_s, g);
        if (any(greaterThan(irradiance, vec4(0.0)))) {
            l += exp(-path_optical_depth(x, v, path, g)) * surface_albedo[g] / PI * irradiance;
        }
    }
    return l;
}

void quick_view_vertex(vec3 vertex_position) {
    vec3 v = normalize(vertex_position - camera_position);
    if (output_mode == 1) {
        int first = 3 * output_triple;
        for (int k = 0; k < 3; ++k) {
            int i = first + k;
            quick_view_value[k] = quick_view_radiance(v, i / 4)[i % 4];
        }
        return;
    }
    vec3 rgb = vec3(0.0);
    for (int g = 0; g < group_count; ++g) {
        vec4 l = quick_view_radiance(v, g);
        rgb += vec3(dot(rgb_weights[3 * g], l), dot(rgb_weights[3 * g + 1], l), dot(rgb_weights[3 * g + 2], l));
    }
    quick_view_value = rgb;
}
