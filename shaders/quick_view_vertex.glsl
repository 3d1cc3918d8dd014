// Quick view: Keller and Bohn's single scattering computed per vertex, with no 4D tables (after common.glsl,
// view.glsl and interpolation.glsl).
// The GLSL twin of planetviz/quick_view/single_scattering.py (same sampling, same names): for the direction of a
// vertex of the direction mesh (direction_mesh.glsl), L = sum_i Delta_i J(p_i) exp(-tau(x, p_i) - tau(p_i, sun)) V_i
// plus the sunlit ground, with the midpoint rule on the intervals of view_edges (ground_view_edges on a ray that
// reaches the ground), tau(x, p_i) summed over them and
// each other optical depth on the intervals of density_edges from the path's lower end. With multiple_scattering = 1, the orders above the first from the table
// of the mean radiance Psi(h, mu_s) of the light scattered at least once (planetviz/quick_view/multiple_scattering.py):
// sum_i Delta_i beta_s(h_i) Psi exp(-tau(x, p_i)), and the sky's irradiance on the ground E_sky(mu_s) added to the
// sun's. The ground's light is output per unit of the surface colour and split by the sun's cosine, as
// atmosphere_vertex.glsl does, for quick_view_fragment.glsl to complete per pixel with the surface texture and the
// terminator.
//
// Uniforms: those of view.glsl (the camera, the sun, the output channels, the albedo), and
//   view_samples           int    n, points on the view path
//   density_samples        int    m, points on each optical-depth path
//   view_edges             vec4[EDGE_VECTORS]  the edges (i / n)^e of the view path's intervals, i = 0 .. n,
//                                 four to a vector (view_edge(i)); e = 3, the paper's power law, or 1, equidistant
//   ground_view_edges      vec4[EDGE_VECTORS]  the edges of a view path that reaches the ground: half the
//                                 intervals on the same law from the camera's end, half mirrored from the ground
//                                 (ground_sample_edges in NumPy; ground_view_edge(i))
//   density_edges          vec4[EDGE_VECTORS]  the same (j / m)^e of an optical-depth path (e = 2 or 1;
//                                 density_edge(j))
//   rayleigh_scattering    vec4[MAX_GROUPS]  beta_R^s at the ground [1/m]
//   mie_scattering         vec4[MAX_GROUPS]  beta_M^s at the ground [1/m]
//   component_extinction   vec4[MAX_COMPONENTS * MAX_GROUPS]  [k * MAX_GROUPS + g]: extinction of component k [1/m]
//   component_profile      vec3[MAX_COMPONENTS]  (scale height, 0, 0) exponential; (centre, half width, 0) tent;
//                                 (top altitude, 0, 0) tabulated in component_table[k] at PROFILE_TABLE_SIZE
//                                 altitudes from 0 to the top, read linearly
//   component_table        vec4[MAX_COMPONENTS * PROFILE_TABLE_SIZE / 4]  the tabulated profiles, four values to
//                                 a vector (component_value(k * PROFILE_TABLE_SIZE + i))
// The float arrays are packed four to a vec4: a GPU gives each element of a float array a whole vector register of
// the vertex stage's 1024 (NVIDIA's limit; unpacked, these three took 898 and the program did not link).
//   artistic_terms         int    1: Table 1's phases 1 + 0.5 nu^2 and HG without 1 / (4 pi) (coefficients are
//                                 uploaded already scaled, planetviz/quick_view/single_scattering.py _coefficients)
//   multiple_scattering    int    1: add the orders above the first and the sky's light on the ground; 0: single
//                                 scattering alone (Keller and Bohn)
//   multiple_scattering_texture  sampler2D  log Psi (Psi [1/sr per unit solar irradiance], at least LOG_FLOOR),
//                                 rows: altitudes H (i / (n_h - 1))^2 (H the thickness), columns: mu_s =
//                                 sign(x) x^2, x uniform in [-1, 1]; groups of four wavelengths stacked along y
//                                 (textures.py pack_2d)
//   ground_sky_texture     sampler2D  log E_sky (E_sky per unit solar irradiance, at least LOG_FLOOR) over mu_s =
//                                 sign(x) x^2, x uniform in [-1, 1] (GROUND_SKY_COLUMNS columns), one row per group
//   multiple_scattering_size  vec2  (n_mu_s, n_h) of multiple_scattering_texture
// Constants, defined before this file (planetviz/render/quick_view_actor.py shader_constants): MAX_COMPONENTS,
// PROFILE_TABLE_SIZE, MAX_SAMPLES, the profile kinds, GAUSS_OFFSET (the 2-point Gauss-Legendre nodes' offset from
// an interval's middle, in units of its width), and from the atmosphere, so that the loops over the
// components unroll and each evaluates its own profile only (a software renderer runs both sides of a branch, even
// one on a uniform):
//   component_count        int    extinction components (Rayleigh, Mie, then absorbers), at most MAX_COMPONENTS
//   component_kinds        int[MAX_COMPONENTS]  each component's profile: EXPONENTIAL_PROFILE, TENT_PROFILE or
//                                 TABULATED_PROFILE
// Outputs (output channels as output_mode says), interpolated over the triangles:
//   quick_view_value   vec3  the inscatter's colour (aerial perspective for ground rays): the inscatter over its
//                            largest channel (split_magnitude, interpolation.glsl)
//   quick_magnitude    float the inscatter's magnitude
//   quick_log_magnitude float its logarithm
//   quick_ground_sky   mat3  column k: the ground's radiance lit by the sky, T(x, y) albedo E_sky(y) / pi, for a
//                            unit of component k of the surface colour (surface_colour_or_unit, pixel.glsl)
//   quick_ground_sun   mat3  column k: the same lit by the sun, T(x, y) albedo T_sun(y) / pi, per unit of
//                            max(n . s, 0), which the pixel multiplies in
// For a ray that misses the ground the ground's terms are those of the grazing ray at the same azimuth, so a
// triangle straddling the limb interpolates toward the ground's value at the horizon. The constant sky_part
// (planetviz/render/direction_mesh.py) is true in the part of the mesh whose rays all miss the ground, where the
// ground's terms are left out.

uniform int view_samples;
uniform int density_samples;
#define EDGE_VECTORS ((MAX_SAMPLES + 4) / 4)
uniform vec4 view_edges[EDGE_VECTORS];
uniform vec4 ground_view_edges[EDGE_VECTORS];
uniform vec4 density_edges[EDGE_VECTORS];
uniform vec4 rayleigh_scattering[MAX_GROUPS];
uniform vec4 mie_scattering[MAX_GROUPS];
uniform vec4 component_extinction[MAX_COMPONENTS * MAX_GROUPS];
uniform vec3 component_profile[MAX_COMPONENTS];
uniform vec4 component_table[MAX_COMPONENTS * PROFILE_TABLE_SIZE / 4];
uniform int artistic_terms;
uniform int multiple_scattering;
uniform sampler2D multiple_scattering_texture;
uniform sampler2D ground_sky_texture;
uniform vec2 multiple_scattering_size;

// Element i of the packed float arrays (four to a vec4).
float view_edge(int i) { return view_edges[i / 4][i % 4]; }
float ground_view_edge(int i) { return ground_view_edges[i / 4][i % 4]; }
float density_edge(int j) { return density_edges[j / 4][j % 4]; }
float component_value(int i) { return component_table[i / 4][i % 4]; }

out vec3 quick_view_value;
out float quick_magnitude;
out float quick_log_magnitude;
out mat3 quick_ground_sky;
out mat3 quick_ground_sun;

// Density of component k at altitude h (its profile, 1 at its reference altitude).
float profile_density(int k, float h) {
    vec3 p = component_profile[k];
    h = max(h, 0.0);
    if (component_kinds[k] == EXPONENTIAL_PROFILE) return exp(-h / p.x);
    if (component_kinds[k] == TENT_PROFILE) return max(0.0, 1.0 - abs(h - p.x) / p.y);
    float x = clamp(h / p.x, 0.0, 1.0) * float(PROFILE_TABLE_SIZE - 1);
    int i = min(int(x), PROFILE_TABLE_SIZE - 2);
    float f = x - float(i);
    return mix(component_value(k * PROFILE_TABLE_SIZE + i), component_value(k * PROFILE_TABLE_SIZE + i + 1), f);
}

// Column coordinate in [0, 1] of a cosine on the tables' grid sign(x) x^2 (cosine_grid in NumPy).
float cosine_coordinate(float mu) {
    mu = clamp(mu, -1.0, 1.0);
    return (sign(mu) * sqrt(abs(mu)) + 1.0) / 2.0;
}

// Psi of group g at altitude h and sun zenith cosine mu_s: bilinear in its logarithm between texel centres, as
// read_table(geometric=True) in NumPy.
vec4 multiple_scattering_at(float h, float mu_s, int g) {
    vec2 n = multiple_scattering_size;
    float x = cosine_coordinate(mu_s) * (n.x - 1.0);
    float y = sqrt(clamp(h / (top_radius - bottom_radius), 0.0, 1.0)) * (n.y - 1.0);
    vec2 uv = vec2((x + 0.5) / n.x, (float(g) * n.y + y + 0.5) / (float(group_count) * n.y));
    return exp(texture(multiple_scattering_texture, uv));
}

// E_sky of group g on the ground where the sun's zenith cosine is mu_s (its texture has columns of its own), read
// geometrically as Psi.
vec4 ground_sky_irradiance(float mu_s, int g) {
    float n = float(textureSize(ground_sky_texture, 0).x);
    float x = cosine_coordinate(mu_s) * (n - 1.0);
    return exp(texture(ground_sky_texture, vec2((x + 0.5) / n, (float(g) + 0.5) / float(group_count))));
}

// beta_ext of group g at p [1/m].
vec4 extinction_at(vec3 p, int g) {
    float h = length(p) - bottom_radius;
    vec4 ext = vec4(0.0);
    for (int k = 0; k < component_count; ++k) {
        ext += component_extinction[k * MAX_GROUPS + g] * profile_density(k, h);
    }
    return ext;
}

// tau of group g along start + t direction, 0 <= t <= len, midpoint rule on density_edges from the path's lower end
// (where the density is highest: the start, or the end where it is nearer the planet's centre).
vec4 path_optical_depth(vec3 start, vec3 direction, float len, int g) {
    vec4 tau = vec4(0.0);
    bool from_end = length(start + len * direction) < length(start);
    for (int j = 0; j < density_samples; ++j) {
        float a = density_edge(j), b = density_edge(j + 1);
        float f = 0.5 * (a + b);
        tau += (b - a) * extinction_at(start + ((from_end ? 1.0 - f : f) * len) * direction, g);
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

// Where the ray along v from the camera starts in the atmosphere: x and its altitude a (the camera, or where the
// ray enters from space: closest approach as a vector, no cancellation); false if it misses the atmosphere.
bool enter_atmosphere(vec3 v, out vec3 x, out float a) {
    x = camera_position;
    a = camera_altitude;
    if (a <= top_radius - bottom_radius) return true;
    float b = dot(x, v);
    vec3 q = x - b * v;
    float p2 = dot(q, q);
    if (b >= 0.0 || p2 >= top_radius * top_radius) return false;
    x = q - sqrt(top_radius * top_radius - p2) * v;
    a = top_radius - bottom_radius;
    return true;
}

// The inscattered radiance of group g along v from the camera, per unit solar irradiance [1/sr]: single
// scattering and, with multiple_scattering = 1, the orders above it (the ground's light is quick_view_ground's).
// tau(x, p_i) is summed over the view path's intervals, 2-point Gauss-Legendre each, and half of the interval
// of p_i at its first node.
vec4 quick_view_inscatter(vec3 v, int g) {
    vec3 x;
    float a;
    if (!enter_atmosphere(v, x, a)) return vec4(0.0);
    float mu = dot(x, v) / radius_of(a);
    bool ground = ray_intersects_ground(a, mu);
    float path = ground ? distance_to_bottom_atmosphere_boundary(a, mu) : distance_to_top_exit(x, v);
    float nu = dot(v, sun_direction);
    float p_r;
    vec4 p_m;
    if (artistic_terms == 1) {
        p_r = 1.0 + 0.5 * nu * nu;
        p_m = 4.0 * PI * henyey_greenstein(nu, mie_g1[g]);
    } else {
        p_r = rayleigh_like_phase(nu);
        p_m = double_henyey_greenstein(nu, mie_g1[g], mie_g2[g], mie_alpha[g]);
    }
    vec4 l = vec4(0.0);
    vec4 tau_before = vec4(0.0);            // tau from x to the interval's start (view_optical_depth in NumPy)
    for (int i = 0; i < view_samples; ++i) {
        float a = ground ? ground_view_edge(i) : view_edge(i);
        float b = ground ? ground_view_edge(i + 1) : view_edge(i + 1);
        float t = 0.5 * (a + b) * path;
        vec3 p = x + t * v;
        float h = length(p) - bottom_radius;
        float rho_r = profile_density(0, h), rho_m = profile_density(1, h);
        float w = (b - a) * path;
        vec4 first = extinction_at(x + (a * path + (0.5 - GAUSS_OFFSET) * w) * v, g);
        vec4 second = extinction_at(x + (a * path + (0.5 + GAUSS_OFFSET) * w) * v, g);
        vec4 tau_view = tau_before + 0.5 * w * first;
        tau_before += 0.5 * w * (first + second);
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
    return l;
}

// The ground's light of group g toward the camera along v per unit albedo: lit by the sky, T(x, y) E_sky / pi,
// and by the sun, T(x, y) T_sun(y) / pi per unit max(n . s, 0). A ray that misses the ground takes the grazing
// ray in the plane of v and the nadir.
void quick_view_ground(vec3 v, int g, out vec4 sky, out vec4 sun) {
    sky = vec4(0.0);
    sun = vec4(0.0);
    vec3 x;
    float a;
    vec3 u = v;
    float r = radius_of(camera_altitude);
    if (!ray_intersects_ground(camera_altitude, dot(camera_position, v) / r)) {
        vec3 down = -camera_position / r;
        vec3 side = v - dot(v, down) * down;
        float s = length(side);
        if (s == 0.0) return;
        u = down * (rho_of(camera_altitude) / r) + side * (bottom_radius / (r * s));
    }
    if (!enter_atmosphere(u, x, a)) return;
    float d = distance_to_bottom_atmosphere_boundary(a, dot(x, u) / radius_of(a));
    vec3 y = x + d * u;
    float mu_s = dot(normalize(y), sun_direction);
    vec4 t_view = exp(-path_optical_depth(x, u, d, g)) / PI;
    if (mu_s > 0.0) {
        sun = t_view * exp(-path_optical_depth(y, sun_direction, distance_to_top_exit(y, sun_direction), g));
    }
    if (multiple_scattering == 1) sky = t_view * ground_sky_irradiance(mu_s, g);
}

void quick_view_vertex(vec3 v) {
    quick_view_value = vec3(0.0);
    quick_ground_sky = mat3(0.0);
    quick_ground_sun = mat3(0.0);
    for (int g = first_group(); g <= last_group(); ++g) {
        quick_view_value += to_channels(quick_view_inscatter(v, g), g);
        if (sky_part) continue;
        vec4 sky, sun;
        quick_view_ground(v, g, sky, sun);
        for (int k = 0; k < 3; ++k) {
            quick_ground_sky[k] += to_channels(albedo_column(k, g) * sky, g);
            quick_ground_sun[k] += to_channels(albedo_column(k, g) * sun, g);
        }
    }
    split_magnitude(quick_view_value, quick_view_value, quick_magnitude, quick_log_magnitude);
}
