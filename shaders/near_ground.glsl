// Single scattering integrated along ground rays from cameras near the ground (after table_lookup.glsl): the GLSL
// twin of planetviz/tables/near_ground.py.
//
// Uniforms (set by planetviz/render/atmosphere_actor.py for every draw):
//   rayleigh_scattering         vec4[MAX_GROUPS]  beta_R^s at the ground [1/m] (here and in horizon.glsl)
//   mie_scattering              vec4[MAX_GROUPS]  beta_M^s at the ground [1/m]
//   near_ground_altitude        float  altitude [m] of the single-scattering tables' row NEAR_GROUND_ROWS (5): ground
//                                      rays from cameras below it are integrated (planetviz/tables/near_ground.py)
//   density_texture             sampler2D  one row of n texels: the Rayleigh (r) and Mie (g) density profiles at the
//                                      altitudes (i / (n - 1))^2 (R_t - R_b), i = 0 .. n - 1, read linearly
//                                      (density_at; planetviz/render/atmosphere_actor.py's density_image)
uniform vec4 rayleigh_scattering[MAX_GROUPS];
uniform vec4 mie_scattering[MAX_GROUPS];
uniform float near_ground_altitude;
uniform sampler2D density_texture;

// ------------------------------------------------------------------------------- near the ground (NumPy twin:
// planetviz/tables/near_ground.py, whose docstring says why): single scattering of ground rays from cameras below
// near_ground_altitude by a 4-node Gauss-Legendre rule on each lit part of the ray, before and after the part in
// the planet's shadow (each half of the ray where there is none), with the tables' transmittances.
const float NEAR_GROUND_NODES[4] = float[4](0.069431844, 0.330009478, 0.669990522, 0.930568156);
const float NEAR_GROUND_WEIGHTS[4] = float[4](0.173927423, 0.326072577, 0.326072577, 0.173927423);

bool near_ground_rays(float a, bool intersects_ground) { return intersects_ground && a < near_ground_altitude; }

// Densities of the Rayleigh (x) and the Mie (y) component at altitude a [m], linear between density_texture's
// texels (at altitudes (i / (n - 1))^2 (R_t - R_b)).
vec2 density_at(float a) {
    int n = textureSize(density_texture, 0).x;
    float x = sqrt(clamp(a / (top_radius - bottom_radius), 0.0, 1.0)) * float(n - 1);
    int i = min(int(x), n - 2);
    return mix(texelFetch(density_texture, ivec2(i, 0), 0).xy, texelFetch(density_texture, ivec2(i + 1, 0), 0).xy,
               x - float(i));
}

// [t_0, t_1] within [0, d]: the part of the ray (a, mu) where the planet hides the sun, t_0 = t_1 where it hides
// it nowhere, at the point where a shadow would appear first (near_ground.py's shadow_interval, whose docstring has
// the derivation: f(t) = A t^2 + 2 B t + C < 0 on [lo, hi], A = 1 - nu^2, B = r (mu - mu_s nu), C = r^2 - R_b^2 -
// r^2 mu_s^2, roots q / A and C / q, or lo = hi = -B / A without roots; the shadow is where p(t) = r mu_s + t nu
// < 0 within [lo, hi]).
vec2 shadow_interval(float a, float mu, float mu_s, float nu, float d) {
    float r = radius_of(a);
    float A = max(1.0 - nu * nu, 1e-12);
    float B = r * (mu - mu_s * nu);
    float C = a * (a + 2.0 * bottom_radius) - r * r * mu_s * mu_s;
    float disc = B * B - A * C;
    float q = disc > 0.0 ? -(B + (B < 0.0 ? -1.0 : 1.0) * sqrt(disc)) : 1.0;   // |q| >= sqrt(disc) > 0
    float lo = disc > 0.0 ? min(q / A, C / q) : -B / A;
    float hi = disc > 0.0 ? max(q / A, C / q) : -B / A;
    lo = clamp(lo, 0.0, d);
    hi = clamp(hi, 0.0, d);
    float p_lo = r * mu_s + lo * nu;
    float p_hi = r * mu_s + hi * nu;
    if (p_lo >= 0.0 && p_hi >= 0.0) {
        float total = p_lo + p_hi;
        return vec2(total > 0.0 ? (lo * p_hi + hi * p_lo) / total : lo);
    }
    if (p_lo < 0.0 && p_hi < 0.0) return vec2(lo, hi);
    float t_p = lo + (hi - lo) * p_lo / (p_lo - p_hi);
    return p_lo < 0.0 ? vec2(lo, t_p) : vec2(t_p, hi);
}

// One node's term of tables/single.py's single_scattering_integral, for both quadratures along rays: w T(x, x_t)
// T_sun(x_t) times the Rayleigh and the Mie density at x_t = x + t v, added to s_r and s_m (the callers multiply by
// the scattering coefficients once). readings: ray_readings of the ray.
void add_single_scattering_node(float a, float mu, float mu_s, float nu, float t, float w, mat2x4 readings, int g,
                                inout vec4 s_r, inout vec4 s_m) {
    float a_t = altitude_along_ray(a, mu, t);
    float mu_s_t = clamp_cosine((radius_of(a) * mu_s + t * nu) / radius_of(a_t));
    vec4 view = exp(-get_optical_depth_from_readings(a, mu, t, readings, g));
    vec4 path = w * view * get_transmittance_to_sun(a_t, mu_s_t, g);
    vec2 density = density_at(a_t);
    s_r += path * density.x;
    s_m += path * density.y;
}

// (S_R,1, S_M,1) of group g without phase, per unit solar irradiance, for a ground ray at (a, mu, mu_s, nu).
void near_ground_single_scattering(float a, float mu, float mu_s, float nu, int g, out vec4 s_r, out vec4 s_m) {
    float d = distance_to_bottom_atmosphere_boundary(a, mu);
    s_r = vec4(0.0);
    s_m = vec4(0.0);
    if (d <= 0.0) return;                                    // a ray from the ground (the ground point's reading)
    vec2 shadow = shadow_interval(a, mu, mu_s, nu, d);
    mat2x4 readings = ray_readings(a, mu, d, g);                // get_transmittance's, taken once per ray
    for (int i = 0; i < 8; ++i) {
        float start = i < 4 ? 0.0 : shadow.y;
        float span = i < 4 ? shadow.x : d - shadow.y;
        add_single_scattering_node(a, mu, mu_s, nu, start + span * NEAR_GROUND_NODES[i % 4],
                                   span * NEAR_GROUND_WEIGHTS[i % 4], readings, g, s_r, s_m);
    }
    s_r *= rayleigh_scattering[g];
    s_m *= mie_scattering[g];
}
