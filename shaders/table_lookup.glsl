// Table parameterisations and lookups: the GLSL twins of planetviz/tables/parameterization.py and
// planetviz/tables/lookup.py (after common.glsl). Every function carries the name of its NumPy twin;
// tests/test_render.py checks that the shader and the NumPy evaluator agree.
//
// Notation as in the NumPy code, except that a point is given by its altitude a = r - R_b [m] where NumPy takes
// its distance r to the planet centre (common.glsl: a float r is 0.5 m coarse at 6.4e6 m); mu = cos(view zenith),
// mu_s = cos(sun zenith), nu = cos(view-sun angle). Radiance is per unit solar irradiance [1/sr], one vec4 per
// group of four wavelengths (group g holds wavelengths 4g .. 4g + 3).
//
// Uniforms (set by planetviz/render/atmosphere_actor.py for every draw):
//   mu_s_min                    float  cos(108 deg): the lowest sun the tables cover (18 deg below the horizon)
//   transmittance_size          vec2   optical-depth table (n_mu, n_r)
//   irradiance_size             vec2   irradiance table (n_mu_s, n_r)
//   single_size                 vec4   single-scattering tables (n_nu, n_mu_s, n_mu, n_r)
//   multiple_size               vec4   multiple-scattering tables (n_nu, n_mu_s, n_mu, n_r)
//   r_axis                      float[R_AXIS_KNOTS]  the 4D tables' r coordinate x_r at rho / H = k / (R_AXIS_KNOTS
//                                          - 1) (NumPy: the tables' r_axis, planetviz/tables/parameterization.py)
//   multiple_row_1_rho          float  rho [m] of the multiple-scattering tables' first row above the ground
//   optical_depth_texture       sampler2D  tau(r, mu) to the top; x: mu, y: r, the G groups stacked along y
//   scattering_share_texture    sampler2D  the share of 1 - T(r, mu) to the top that scatters; the same layout
//   irradiance_texture          sampler2D  indirect irradiance E(r, mu_s); x: mu_s, y: r, groups along y
//   single_rayleigh_texture     sampler3D  S_R(r, mu, mu_s, nu); x: nu slices of mu_s, y: mu, z: r, groups along z
//                                          (x one column wider, unread, where n_nu n_mu_s is a power of two:
//                                          planetviz/render/textures.py pack_3d)
//   single_mie_texture          sampler3D  S_M, same layout
//   multiple_texture            sampler3D  multiple scattering last scattered by molecules (phase included)
//   multiple_mie_texture        sampler3D  multiple scattering last scattered by particles, divided by forward_factor
//   top_multiple_texture        sampler3D  multiple_texture's top tables (NumPy: multiple.top_source): upward views at
//                                          the top of the atmosphere; x: nu slices of mu_s as in multiple_texture, y:
//                                          theta / (pi / 2) (theta the view zenith angle), z: the groups
//   top_multiple_mie_texture    sampler3D  multiple_mie_texture's top tables, the same layout
uniform float mu_s_min;
uniform vec2 transmittance_size;
uniform vec2 irradiance_size;
uniform vec4 single_size;
uniform vec4 multiple_size;
#define R_AXIS_KNOTS 65
uniform float r_axis[R_AXIS_KNOTS];
uniform float multiple_row_1_rho;
uniform sampler2D optical_depth_texture;
uniform sampler2D scattering_share_texture;
uniform sampler2D irradiance_texture;
uniform sampler3D single_rayleigh_texture;
uniform sampler3D single_mie_texture;
uniform sampler3D multiple_texture;
uniform sampler3D multiple_mie_texture;
uniform sampler3D top_multiple_texture;
uniform sampler3D top_multiple_mie_texture;

float texcoord_from_unit_range(float x, float n) { return 0.5 / n + x * (1.0 - 1.0 / n); }

// ------------------------------------------------------------------------------------------- transmittance
vec2 transmittance_uv_from_r_mu(float a, float mu) {
    float h = sqrt(top_radius * top_radius - bottom_radius * bottom_radius);
    float rho = rho_of(a);
    float d = distance_to_top_atmosphere_boundary(a, mu);
    float d_min = (top_radius - bottom_radius) - a;
    float d_max = rho + h;
    float x_mu = d_max > d_min ? (d - d_min) / (d_max - d_min) : 0.0;
    return vec2(texcoord_from_unit_range(x_mu, transmittance_size.x),
                texcoord_from_unit_range(rho / h, transmittance_size.y));
}

// A 2D table's texel of group g: the groups are stacked along y, and v never leaves its group's texel centres.
vec4 texture_group(sampler2D table, vec2 uv, int g) {
    return texture(table, vec2(uv.x, (float(g) + uv.y) / float(group_count)));
}

// The table holds the mean extinction tau / d along the ray (NumPy's docstring says why): times the ray's length d.
vec4 get_optical_depth_to_top_atmosphere_boundary(float a, float mu, int g) {
    return texture_group(optical_depth_texture, transmittance_uv_from_r_mu(a, mu), g)
        * distance_to_top_atmosphere_boundary(a, mu);
}

vec4 get_transmittance_to_top_atmosphere_boundary(float a, float mu, int g) {
    return exp(-get_optical_depth_to_top_atmosphere_boundary(a, mu, g));
}

// Altitude of the point at distance d along (a, mu), from r_d^2 - R_b^2 = d (d + 2 r mu) + a (a + 2 R_b): no
// cancellation against R_b^2.
float altitude_along_ray(float a, float mu, float d) {
    float c_d = max(d * (d + 2.0 * radius_of(a) * mu) + a * (a + 2.0 * bottom_radius), 0.0);
    return min(c_d / (sqrt(c_d + bottom_radius * bottom_radius) + bottom_radius), top_radius - bottom_radius);
}

// tau between (a, mu) and the point at distance d along the ray: NumPy's get_optical_depth with all its branches,
// from readings of rays that point up only (its docstring says why), for the quadratures along whole rays below:
// on the ray's descending part (d <= -r mu) the reversed ray, tau(a_d, -mu_d) -
// tau(a, -mu); past its lowest point a_l, tau(a_l, 0) - tau(a, -mu) to it plus tau(a_l, 0) - tau(a_d, mu_d) from
// it; rays up, tau(a, mu) - tau(a_d, mu_d). The readings at the camera and at the lowest point depend on the ray
// only (ray_readings, for points up to d_end along it: [0] the camera's, [1] the lowest point's where d_end is past
// it), so that a quadrature along one ray takes them once.
mat2x4 ray_readings(float a, float mu, float d_end, int g) {
    vec4 camera = get_optical_depth_to_top_atmosphere_boundary(a, abs(mu), g);
    float d_l = -radius_of(a) * mu;
    if (mu >= 0.0 || d_end <= d_l) return mat2x4(camera, vec4(0.0));
    return mat2x4(camera, get_optical_depth_to_top_atmosphere_boundary(altitude_along_ray(a, mu, d_l), 0.0, g));
}

vec4 get_optical_depth_from_readings(float a, float mu, float d, mat2x4 readings, int g) {
    float a_d = altitude_along_ray(a, mu, d);
    float mu_d = clamp_cosine((radius_of(a) * mu + d) / radius_of(a_d));
    bool descending = mu < 0.0 && d <= -radius_of(a) * mu;
    // One reading at the point, its direction chosen per branch (a software renderer runs every branch's fetch).
    vec4 point = get_optical_depth_to_top_atmosphere_boundary(a_d, descending ? -mu_d : max(mu_d, 0.0), g);
    if (mu >= 0.0) return max(readings[0] - point, 0.0);
    if (descending) return max(point - readings[0], 0.0);
    return max(readings[1] - point, 0.0) + max(readings[1] - readings[0], 0.0);
}

// The same on the ray's descending part only (d <= -r mu), where every segment of the ray set-up ends (on the
// ground or before it); the branches it leaves out slowed every pixel on llvmpipe by 18% (720p, from orbit).
vec4 get_optical_depth(float a, float mu, float d, int g) {
    float a_d = altitude_along_ray(a, mu, d);
    float mu_d = clamp_cosine((radius_of(a) * mu + d) / radius_of(a_d));
    return max(get_optical_depth_to_top_atmosphere_boundary(a_d, -mu_d, g)
               - get_optical_depth_to_top_atmosphere_boundary(a, -mu, g), 0.0);
}

vec4 get_transmittance(float a, float mu, float d, int g) {
    return exp(-get_optical_depth(a, mu, d, g));
}

vec4 get_transmittance_to_sun(float a, float mu_s, int g) {
    return ray_intersects_ground(a, mu_s) ? vec4(0.0) : get_transmittance_to_top_atmosphere_boundary(a, mu_s, g);
}

// a^(1 - f) b^f, a zero neighbour raised to ZERO_FLOOR times the other (0 where both are 0); f < 0 continues a
// decay beyond a, never above a.
const float ZERO_FLOOR = 1e-3;
vec4 geometric_blend(vec4 a, vec4 b, float f) {
    bvec4 lit = bvec4(vec4(greaterThan(a, vec4(0.0))) + vec4(greaterThan(b, vec4(0.0))));
    // mix with a bvec selects; with 0/1 float weights it is x + w (y - x), which NVIDIA's compiler evaluates as
    // such: 1 + (1e-6 - 1) keeps 1e-6 to 6%, 1 + (1e-37 - 1) is 0, and a 0 here made log(0 / 0) NaN (twilight
    // rays from space read 0 or NaN on an H100, benchmarks/gpu_agreement.py; llvmpipe computes it exactly).
    vec4 a_f = mix(vec4(1.0), max(max(a, ZERO_FLOOR * b), 1e-37), lit);
    vec4 b_f = mix(vec4(1.0), max(max(b, ZERO_FLOOR * a), 1e-37), lit);
    vec4 ratio = b_f / a_f;                          // within [ZERO_FLOOR, 1 / ZERO_FLOOR]: no overflow below
    if (f < 0.0) ratio = max(ratio, vec4(1.0));
    return a_f * exp(f * log(ratio)) * vec4(lit);
}

// ---------------------------------------------------------------------------------------------- irradiance
vec2 irradiance_uv_from_r_mu_s(float a, float mu_s) {
    float x_r = a / (top_radius - bottom_radius);
    float x_mu_s = mu_s * 0.5 + 0.5;
    return vec2(texcoord_from_unit_range(x_mu_s, irradiance_size.x), texcoord_from_unit_range(x_r, irradiance_size.y));
}

// E(a, mu_s) of group g as the NumPy get_irradiance reads it: the hardware interpolates r at two exact mu_s texel
// centres, blended linearly where the upper one is above the horizon and geometrically where it is not.
vec4 get_irradiance(float a, float mu_s, int g) {
    vec2 uv = irradiance_uv_from_r_mu_s(a, mu_s);
    float n = irradiance_size.x;
    float s = uv.x * n - 0.5;
    float s0 = clamp(floor(s), 0.0, n - 1.0);
    float s1 = clamp(floor(s) + 1.0, 0.0, n - 1.0);
    float f = s - floor(s);
    vec4 low = texture_group(irradiance_texture, vec2((s0 + 0.5) / n, uv.y), g);
    vec4 high = texture_group(irradiance_texture, vec2((s1 + 0.5) / n, uv.y), g);
    return 2.0 * s1 / (n - 1.0) - 1.0 <= 0.0 ? geometric_blend(low, high, f) : mix(low, high, f);
}

// ---------------------------------------------------------------------------------------------- scattering
// The radius of parameterization.py's limited_geometry: the planet's, or that of a smaller planet under the same
// thickness whose H / (R_t - R_b) is RATIO_LIMIT.
const float RATIO_LIMIT = 16.0;

float limited_bottom_radius() {
    return min(bottom_radius, (top_radius - bottom_radius) * (RATIO_LIMIT * RATIO_LIMIT - 1.0) / 2.0);
}

// The sun's zenith angle's share in the sun-zenith coordinate (parameterization.py's SUN_ANGLE_SHARE).
const float SUN_ANGLE_SHARE = 0.2;

// The sun's zenith angle acos(mu_s) down to mu_s_min, continued below it along its tangent, linear in mu_s
// (parameterization.py's sun_zenith_angle: acos's infinite slope at mu_s = -1 turned float32's rounding of mu_s
// into 0.6% of the extrapolated night sky).
float sun_zenith_angle(float mu_s) {
    float theta_max = acos(mu_s_min);
    mu_s = clamp(mu_s, -1.0, 1.0);
    return mu_s >= mu_s_min ? acos(mu_s) : theta_max + (mu_s_min - mu_s) / sqrt(1.0 - mu_s_min * mu_s_min);
}

// The sun-zenith coordinate in [0, 1], unclamped below mu_s_min (for the twilight extrapolation): Bruneton's on the
// geometry of limited_bottom_radius, (1 - SUN_ANGLE_SHARE) of it, plus SUN_ANGLE_SHARE of the sun's zenith angle
// (sun_zenith_angle) from its largest, acos(mu_s_min) (parameterization.py's x_mu_s_from_mu_s).
float x_mu_s_from_mu_s(float mu_s) {
    float thickness = top_radius - bottom_radius;
    float r = limited_bottom_radius();
    float top = r + thickness;
    float d_min = thickness;
    float d_max = sqrt(thickness * (top + r));
    float disc = r * r * (mu_s * mu_s - 1.0) + top * top;
    float disc_min = r * r * (mu_s_min * mu_s_min - 1.0) + top * top;
    float a = (max(-r * mu_s + safe_sqrt(disc), 0.0) - d_min) / (d_max - d_min);
    float big_a = (max(-r * mu_s_min + safe_sqrt(disc_min), 0.0) - d_min) / (d_max - d_min);
    float theta_max = acos(mu_s_min);
    return (1.0 - SUN_ANGLE_SHARE) * (1.0 - a / big_a) / (1.0 + a)
        + SUN_ANGLE_SHARE * (theta_max - sun_zenith_angle(mu_s)) / theta_max;
}

// k [1/m] of the view-zenith axis's distance coordinate for a camera at altitude a, in the ground half or the sky
// half: 1 / d_max' - 1 / d_max, the longest ray of that half on limited_bottom_radius's planet and on this one;
// 0 where they are one (parameterization.py's distance_warp says why).
float distance_warp(float a, bool ground) {
    float small = limited_bottom_radius();
    if (small >= bottom_radius) return 0.0;
    float rho_small = sqrt(max(a, 0.0) * (2.0 * small + max(a, 0.0)));
    float rho = rho_of(a);
    if (ground) return rho_small > 0.0 ? max(1.0 / rho_small - 1.0 / rho, 0.0) : 0.0;
    float thickness = top_radius - bottom_radius;
    float h = sqrt(top_radius * top_radius - bottom_radius * bottom_radius);
    return max(1.0 / (rho_small + sqrt(thickness * (2.0 * small + thickness))) - 1.0 / (rho + h), 0.0);
}

// The angle's share in the view-zenith coordinate (parameterization.py's VIEW_ANGLE_SHARE).
const float VIEW_ANGLE_SHARE = 0.5;

// The offset e of the coordinate's angle-like part in the ground half and at the top (parameterization.py's
// VIEW_ANGLE_OFFSET).
const float VIEW_ANGLE_OFFSET = 1.5e-3;

// e of the sky half's distance_coordinate for a camera at altitude a: VIEW_ANGLE_OFFSET times a over the thickness
// (parameterization.py's sky_angle_offset).
float sky_angle_offset(float a) {
    return VIEW_ANGLE_OFFSET * clamp(a / (top_radius - bottom_radius), 0.0, 1.0);
}

// x in [0, 1] of a ray of length d in a half of the view-zenith axis from d_min to d_max:
// (1 - c) y + c (sqrt(y + e) - sqrt(e)) / (sqrt(1 + e) - sqrt(e)), c = VIEW_ANGLE_SHARE, e the half's offset
// (VIEW_ANGLE_OFFSET, or sky_angle_offset), the square roots' difference written without cancellation; y linear in
// d / (1 + k d) (parameterization.py's distance_coordinate); 0 where the half is a single ray.
float distance_coordinate(float d, float d_min, float d_max, float k, float e) {
    float low = d_min / (1.0 + k * d_min);
    float span = d_max / (1.0 + k * d_max) - low;
    float y = span > 0.0 ? clamp((d / (1.0 + k * d) - low) / span, 0.0, 1.0) : 0.0;
    return (1.0 - VIEW_ANGLE_SHARE) * y
        + VIEW_ANGLE_SHARE * y * (sqrt(1.0 + e) + sqrt(e)) / max(sqrt(y + e) + sqrt(e), 1e-30);
}

// Its inverse: the length of the ray at x (the positive root s = sqrt(y + e) of a quadratic).
float distance_from_coordinate(float x, float d_min, float d_max, float k, float e) {
    float c = VIEW_ANGLE_SHARE;
    float big_d = sqrt(1.0 + e) - sqrt(e);
    float a = 1.0 - c;
    float b = c / big_d;
    float q = a * e + c * sqrt(e) / big_d + clamp(x, 0.0, 1.0);
    float s = 2.0 * q / (b + sqrt(b * b + 4.0 * a * q));
    float y = clamp(s * s - e, 0.0, 1.0);
    float low = d_min / (1.0 + k * d_min);
    float w = low + y * (d_max / (1.0 + k * d_max) - low);
    return w / (1.0 - k * w);
}

// The sky half's refinement of the rays that dip below the horizontal, past the pivot x_p:
// x_p + (1 - x_p)(1 - G(t)), t = (1 - x) / (1 - x_p), G(t) = (1 - w) t + w (a S_e(t) + (1 - a) t^2), a = SQRT_SHARE,
// S_e(t) = (sqrt(t + e) - sqrt(e)) / (sqrt(1 + e) - sqrt(e)) written without cancellation, e = LINEAR_ALTITUDE
// (R_t - R_b) / a; parameterization.py's dipping_pivot_and_weight and refine_dipping_rays say how x_p, w and e
// follow the camera's altitude a, and why.
// h, d_min, d_max and k are the caller's (scattering_uvwz_from_r_mu_mu_s_nu's sky half), not recomputed per call.
const float PIVOT_SMOOTHING = 0.03;
const float REFINEMENT_ALTITUDE = 0.1;
const float SQRT_SHARE = 5.0 / 6.0;
const float LINEAR_ALTITUDE = 0.005;
float refine_dipping_rays(float x, float a, float h, float d_min, float d_max, float k) {
    float c = PIVOT_SMOOTHING * h;
    float s = max(d_min * (top_radius + radius_of(a)), 0.0);
    float x_p = clamp(distance_coordinate(s / sqrt(s + c * c), d_min, d_max, k, sky_angle_offset(a)), 0.0, 1.0);
    if (x <= x_p) return x;
    float w = 1.0 - exp(-max(a, 0.0) / (REFINEMENT_ALTITUDE * (top_radius - bottom_radius)));
    float t = clamp((1.0 - x) / max(1.0 - x_p, 1e-30), 0.0, 1.0);
    float e = LINEAR_ALTITUDE * (top_radius - bottom_radius) / max(a, 1e-9);
    float softened_sqrt = t * (sqrt(1.0 + e) + sqrt(e)) / (sqrt(t + e) + sqrt(e));
    float g = (1.0 - w) * t + w * (SQRT_SHARE * softened_sqrt + (1.0 - SQRT_SHARE) * t * t);
    return x_p + (1.0 - x_p) * (1.0 - g);
}

// The view-sun coordinate: linear in nu over the range that (mu, mu_s) allow (x_nu_from_nu in NumPy).
const float NU_RANGE_FLOOR = 1e-2;
float x_nu_from_nu(float mu, float mu_s, float nu) {
    float root = max(safe_sqrt((1.0 - mu * mu) * (1.0 - mu_s * mu_s)), NU_RANGE_FLOOR);
    return clamp(0.5 + 0.5 * (nu - mu * mu_s) / root, 0.0, 1.0);
}

// The 4D tables' r coordinate x_r in [0, 1] of rho [m]: r_axis read linearly at q = rho / H.
float x_r_from_rho(float rho, float h) {
    float k = clamp(rho / h, 0.0, 1.0) * float(R_AXIS_KNOTS - 1);
    int i = min(int(k), R_AXIS_KNOTS - 2);
    return mix(r_axis[i], r_axis[i + 1], k - float(i));
}

// (u_nu, u_mu_s, u_mu, u_r) of a table of size (n_nu, n_mu_s, n_mu, n_r); u_mu_s clamped as in NumPy.
vec4 scattering_uvwz_from_r_mu_mu_s_nu(float a, float mu, float mu_s, float nu, bool intersects_ground, vec4 size) {
    float h = sqrt(top_radius * top_radius - bottom_radius * bottom_radius);
    float rho = rho_of(a);
    float u_r = texcoord_from_unit_range(x_r_from_rho(rho, h), size.w);
    float r_mu = radius_of(a) * mu;
    float disc = r_mu * r_mu - rho * rho;
    float u_mu;
    if (intersects_ground) {
        float d = distance_to_bottom_atmosphere_boundary(a, mu);
        float x = distance_coordinate(d, a, rho, distance_warp(a, true), VIEW_ANGLE_OFFSET);
        u_mu = 0.5 - 0.5 * texcoord_from_unit_range(x, size.z / 2.0);
    } else {
        float d = -r_mu + safe_sqrt(disc + h * h);
        float d_min = (top_radius - bottom_radius) - a;
        float d_max = rho + h;
        float k = distance_warp(a, false);
        float x = refine_dipping_rays(distance_coordinate(d, d_min, d_max, k, sky_angle_offset(a)), a, h, d_min,
                                     d_max, k);
        u_mu = 0.5 + 0.5 * texcoord_from_unit_range(x, size.z / 2.0);
    }
    float u_mu_s = texcoord_from_unit_range(max(x_mu_s_from_mu_s(mu_s), 0.0), size.y);
    return vec4(x_nu_from_nu(mu, mu_s, nu), u_mu_s, u_mu, u_r);
}

// 1 - exp(-x) for x >= 0 without cancellation for small x (NumPy: -expm1(-x)); the series' error below 1e-2 is
// x^3 / 24 < 5e-8 relative.
vec4 one_minus_exp(vec4 x) {
    return mix(1.0 - exp(-x), x * (1.0 - x * (0.5 - x / 6.0)), lessThan(x, vec4(1e-2)));
}

// The factor on what get_scattering reads from a 4D table of n_r rows at (a, mu), for ground rays from below its
// first row above the ground (at rho_1 [m]):
// (1 - exp(-k tau_1)) / (f (1 - exp(-tau_1))), k / f where tau_1 = 0; 1 for every other ray. f: the camera's
// fraction of the way to row 1; k = d / d_1 and tau_1: the ratio of the ray's length to that of row 1's ray at
// the same u_mu, and that ray's optical depth (planetviz/tables/lookup.py ground_row_factor says why).
vec4 ground_row_factor(float a, float mu, bool intersects_ground, float n_r, float rho_1, int g) {
    float h = sqrt(top_radius * top_radius - bottom_radius * bottom_radius);
    float rho = rho_of(a);
    float f = x_r_from_rho(rho, h) * (n_r - 1.0);
    if (!intersects_ground || f <= 0.0 || f >= 1.0) return vec4(1.0);
    float d = distance_to_bottom_atmosphere_boundary(a, mu);
    float x = distance_coordinate(d, a, rho, distance_warp(a, true), VIEW_ANGLE_OFFSET);
    float a_1 = rho_1 * rho_1 / (sqrt(rho_1 * rho_1 + bottom_radius * bottom_radius) + bottom_radius);
    float d_1 = distance_from_coordinate(x, a_1, rho_1, distance_warp(a_1, true), VIEW_ANGLE_OFFSET);
    float mu_1 = clamp_cosine(-(rho_1 * rho_1 + d_1 * d_1) / (2.0 * radius_of(a_1) * d_1));
    vec4 tau_1 = get_optical_depth(a_1, mu_1, d_1, g);
    float k = d / d_1;
    vec4 ratio = one_minus_exp(k * tau_1) / max(one_minus_exp(tau_1), vec4(1e-37));
    return mix(ratio, vec4(k), lessThanEqual(tau_1, vec4(0.0))) / f;
}

// The scattering opacity int beta_scat T dt = s (1 - T) of a ray (a, mu) that leaves through the top of the
// atmosphere, 1 for a ray to the ground: the tables' sky half holds S over it and get_scattering multiplies it back
// (NumPy: ray_opacity, whose docstring says why).
vec4 ray_opacity(float a, float mu, bool intersects_ground, int g) {
    if (intersects_ground) return vec4(1.0);
    vec2 uv = transmittance_uv_from_r_mu(a, mu);
    vec4 tau = texture_group(optical_depth_texture, uv, g) * distance_to_top_atmosphere_boundary(a, mu);
    return texture_group(scattering_share_texture, uv, g) * one_minus_exp(tau);
}

// The 4D table in a 3D texture read as the NumPy get_scattering reads it, before the opacity: four fetches at exact
// mu_s texel centres (the hardware interpolates r and mu) blended geometrically along mu_s and nu. With with_top, a
// ray upward within the top row interval reads top_table in the top row's place: each fetch is the row under the top
// blended with top_table's texel at theta / (pi / 2) by top_share, the texel coordinate's fraction of the way up.
vec4 read_scattering(sampler3D table, sampler3D top_table, bool with_top, vec4 size, float a, float mu, float mu_s,
                     float nu, bool intersects_ground, int g) {
    float n_nu = size.x, n_mu_s = size.y, n_r = size.w;
    vec4 uvwz = scattering_uvwz_from_r_mu_mu_s_nu(a, mu, mu_s, nu, intersects_ground, size);
    float top_share = (with_top && !intersects_ground && mu >= 0.0)
        ? clamp(uvwz.w * n_r - 0.5 - (n_r - 2.0), 0.0, 1.0) : 0.0;
    float coord = uvwz.x * (n_nu - 1.0);
    float tex_nu = clamp(floor(coord), 0.0, max(n_nu - 2.0, 0.0));
    float lerp_nu = coord - tex_nu;
    float coord_s = texcoord_from_unit_range(x_mu_s_from_mu_s(mu_s), n_mu_s) * n_mu_s - 0.5;
    float s0 = clamp(floor(coord_s), 0.0, n_mu_s - 2.0);
    float fs = min(coord_s - s0, 1.0);
    float u_r = top_share > 0.0 ? (n_r - 1.5) / n_r : uvwz.w;
    float z = (float(g) + u_r) / float(group_count);
    float u_top = acos(clamp(mu, 0.0, 1.0)) / (0.5 * PI);
    float z_top = (float(g) + 0.5) / float(group_count);
    float width = float(textureSize(table, 0).x);        // n_nu n_mu_s, or one more (textures.py pack_3d)
    vec4 slices[2];
    for (int dn = 0; dn < 2; ++dn) {
        float base = (tex_nu + float(dn)) * n_mu_s;
        vec4 ab[2];
        for (int ds = 0; ds < 2; ++ds) {
            float x = (base + s0 + 0.5 + float(ds)) / width;
            ab[ds] = texture(table, vec3(x, uvwz.z, z));
            if (top_share > 0.0) ab[ds] = mix(ab[ds], texture(top_table, vec3(x, u_top, z_top)), top_share);
        }
        slices[dn] = geometric_blend(ab[0], ab[1], fs);
    }
    return n_nu > 1.0 ? geometric_blend(slices[0], slices[1], lerp_nu) : slices[0];
}

// The 4D table read as the NumPy get_scattering reads it (read_scattering), times the ray's opacity (ray_opacity, the
// caller's: one per ray for the four tables).
vec4 get_scattering(sampler3D table, vec4 size, float a, float mu, float mu_s, float nu, bool intersects_ground,
                    vec4 opacity, int g) {
    return read_scattering(table, table, false, size, a, mu, mu_s, nu, intersects_ground, g) * opacity;
}

// get_scattering of a multiple-scattering table with its top tables (NumPy: get_scattering with top): a ray upward
// from within the top row interval reads top_table in the top row's place, at theta / (pi / 2).
vec4 get_multiple_scattering(sampler3D table, sampler3D top_table, vec4 size, float a, float mu, float mu_s,
                             float nu, bool intersects_ground, vec4 opacity, int g) {
    return read_scattering(table, top_table, true, size, a, mu, mu_s, nu, intersects_ground, g) * opacity;
}
