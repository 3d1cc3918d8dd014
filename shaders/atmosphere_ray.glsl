// The table-based model along one view ray, in either stage (after phased_scattering.glsl and view.glsl): where the
// ray enters the atmosphere, and the three terms whose sum is its radiance, as the NumPy evaluator computes it
// (planetviz/tables/evaluator.py, sky_radiance):
//   L = inscatter + albedo * ground_light + [the ray is in the sun's disc] sun_transmittance / sun_solid_angle
// The per-pixel renderer (atmosphere_fragment.glsl) evaluates all three for every pixel. The per-vertex renderer
// evaluates them at the vertices of a direction mesh (atmosphere_vertex.glsl: the 4D tables, most of the cost, and
// the ground's light split by the sun's cosine) and completes per pixel (atmosphere_interpolated.glsl) what
// changes faster across the screen: the surface texture, the sun's cosine at the ground point (the terminator),
// the disc, inscatter_factor (below); no 4D table is read per pixel there.
//
// Uniforms: those of view.glsl (before it).

// The view ray along v where it enters the atmosphere: (a, mu, mu_s, nu) with a = r - R_b (common.glsl), the start
// point x and whether the ray meets the atmosphere at all.
struct ViewRay { vec3 v; vec3 x; float a; float mu; float mu_s; float nu; bool visible; };

ViewRay view_ray(vec3 v) {
    ViewRay ray;
    ray.v = v;
    ray.x = camera_position;
    ray.a = camera_altitude;
    ray.mu = dot(camera_position, ray.v) / radius_of(camera_altitude);
    ray.visible = true;
    if (camera_altitude > top_radius - bottom_radius) {
        // Closest approach of the planet centre, |x - (x.v) v|^2, computed as a vector (no cancellation).
        float b = dot(camera_position, ray.v);
        vec3 q = camera_position - b * ray.v;
        float p2 = dot(q, q);
        if (b >= 0.0 || p2 >= top_radius * top_radius) {
            ray.visible = false;
        } else {
            float half_chord = sqrt(top_radius * top_radius - p2);
            ray.x = q - half_chord * ray.v;
            ray.a = top_radius - bottom_radius;
            ray.mu = -half_chord / top_radius;
        }
    }
    ray.mu = clamp_cosine(ray.mu);
    ray.mu_s = clamp_cosine(dot(normalize(ray.x), sun_direction));
    ray.nu = clamp_cosine(dot(ray.v, sun_direction));
    return ray;
}

bool ray_hits_ground(ViewRay ray) { return ray.visible && ray_intersects_ground(ray.a, ray.mu); }

// Where the ray meets the ground (planet-centred, [m]); only meaningful where ray_hits_ground.
vec3 ground_point(ViewRay ray) { return ray.x + distance_to_bottom_atmosphere_boundary(ray.a, ray.mu) * ray.v; }

// Where a ground ray ends: its length d and (mu, mu_s) at the ground point (altitude 0).
struct GroundHit { float d; float mu; float mu_s; };

GroundHit ground_hit(ViewRay ray) {
    GroundHit h;
    float r = radius_of(ray.a);
    h.d = distance_to_bottom_atmosphere_boundary(ray.a, ray.mu);
    h.mu = clamp_cosine((r * ray.mu + h.d) / bottom_radius);
    h.mu_s = clamp_cosine((r * ray.mu_s + h.d * ray.nu) / bottom_radius);
    return h;
}

// Light scattered toward the camera along the ray, of group g per unit solar irradiance, in its parts before their
// phases (phased_sum); for ground rays S(x) - T(x, y) S(y) (aerial perspective), part by part.
ScatteringParts get_inscatter_parts(ViewRay ray, int g) {
    if (!ray.visible) return ScatteringParts(vec4(0.0), vec4(0.0), vec4(0.0), vec4(0.0));
    bool ground = ray_intersects_ground(ray.a, ray.mu);
    ScatteringParts x = get_scattering_parts(ray.a, ray.mu, ray.mu_s, ray.nu, ground, g);
    if (!ground) return x;
    GroundHit h = ground_hit(ray);
    vec4 t_xy = get_transmittance(ray.a, ray.mu, h.d, g);
    ScatteringParts y = get_scattering_parts(0.0, h.mu, h.mu_s, ray.nu, true, g);
    return ScatteringParts(x.rayleigh - t_xy * y.rayleigh, x.mie - t_xy * y.mie, x.multiple - t_xy * y.multiple,
                           x.multiple_mie - t_xy * y.multiple_mie);
}

// Light scattered toward the camera along the ray, of group g per unit solar irradiance [1/sr].
vec4 get_inscatter(ViewRay ray, int g) { return max(phased_sum(get_inscatter_parts(ray, g), ray.nu, g), 0.0); }

// The radiance of a ground of albedo 1 at the end of a ground ray, seen through the atmosphere, of group g per
// unit solar irradiance: T(x, y) (T_sun max(n . s, 0) + E_sky) / pi [1/sr]; 0 for rays that miss the ground.
vec4 get_ground_light(ViewRay ray, int g) {
    if (!ray_hits_ground(ray)) return vec4(0.0);
    GroundHit h = ground_hit(ray);
    vec4 sun = get_transmittance_to_sun(0.0, h.mu_s, g) * max(h.mu_s, 0.0);
    return get_transmittance(ray.a, ray.mu, h.d, g) / PI * (sun + get_irradiance(0.0, h.mu_s, g));
}

// Transmittance from the camera to space along the ray, of group g (1 for rays that miss the atmosphere, 0 for
// rays that hit the ground): the sun disc's radiance is this over sun_solid_angle.
vec4 get_sun_transmittance(ViewRay ray, int g) {
    if (!ray.visible) return vec4(1.0);
    if (ray_intersects_ground(ray.a, ray.mu)) return vec4(0.0);
    return get_transmittance_to_top_atmosphere_boundary(ray.a, ray.mu, g);
}

// The per-vertex renderer's factor of the inscatter, F = path_opacity x twilight_factor x phase_factor: what makes
// the inscatter change across the screen faster than the direction mesh resolves, computed per pixel from the 2D
// tables and the phase functions. atmosphere_vertex.glsl passes each vertex's F beside its inscatter, and
// atmosphere_interpolated.glsl multiplies the interpolated inscatter by F at the pixel over the interpolated F: the
// interpolation then only has to follow the inscatter's ratio to F, which changes slowly.
// - path_opacity: the opacity 1 - T of the ray from x to where it leaves the atmosphere or meets the ground
//   (averaged over the first output group's wavelengths; 0 for a ray that misses the atmosphere): along the limb's
//   halo, the horizon and the aerial perspective the inscatter grows with the ray's optical depth (the tables' sky
//   half holds S / (1 - T) for the same reason, table_lookup.glsl ray_opacity);
// - twilight_factor: E(0, mu_s), the sky's irradiance on the ground for the sun's cosine mu_s at the ray's ground
//   point, or at its point nearest the planet's centre, held at its value with the sun on the horizon where the sun
//   is above that point's horizon and at mu_s_min below the tables' range: over the ground's twilight band seen
//   from space and along the limb over the terminator the inscatter falls with the sun's depression as this
//   irradiance does (only ratios of F matter, so no normalisation);
// - phase_factor: the phase functions at nu (the first output group's, averaged over its wavelengths) of a mix w
//   of the inscatter's parts before their phases (get_inscatter_parts; phase_weights: that group's parts averaged
//   over its wavelengths, normalised), w interpolated: around the sun a strong forward lobe changes the inscatter
//   faster than the mesh resolves, while the parts change slowly. Magnitudes |w| keep it positive where the aerial
//   perspective's parts cancel.
float path_opacity(ViewRay ray) {
    if (!ray.visible) return 0.0;
    int g = first_group();
    vec4 tau = ray_intersects_ground(ray.a, ray.mu)
        ? get_optical_depth(ray.a, ray.mu, distance_to_bottom_atmosphere_boundary(ray.a, ray.mu), g)
        : get_optical_depth_to_top_atmosphere_boundary(ray.a, ray.mu, g);
    return dot(one_minus_exp(tau), vec4(0.25));
}

float twilight_factor(ViewRay ray) {
    if (!ray.visible) return 1.0;
    vec3 p = ray_intersects_ground(ray.a, ray.mu) ? ground_point(ray)
                                                  : ray.x + max(-dot(ray.x, ray.v), 0.0) * ray.v;
    float mu_s = clamp(dot(normalize(p), sun_direction), mu_s_min, 0.0);
    return dot(get_irradiance(0.0, mu_s, first_group()), vec4(0.25));
}

vec4 phase_weights(ScatteringParts s) {
    vec4 w = vec4(dot(s.rayleigh, vec4(0.25)), dot(s.mie, vec4(0.25)), dot(s.multiple, vec4(0.25)),
                  dot(s.multiple_mie, vec4(0.25)));
    float total = dot(abs(w), vec4(1.0));
    return total > 0.0 ? w / total : vec4(0.0, 0.0, 1.0, 0.0);
}

float phase_factor(vec4 w, float nu) {
    int g = first_group();
    vec4 phases = vec4(rayleigh_like_phase(nu),
                       dot(double_henyey_greenstein(nu, mie_g1[g], mie_g2[g], mie_alpha[g]), vec4(0.25)), 1.0,
                       dot(forward_factor(nu, g), vec4(0.25)));
    return dot(abs(w), phases);
}

float inscatter_factor(ViewRay ray, vec4 w) {
    return path_opacity(ray) * twilight_factor(ray) * phase_factor(w, ray.nu);
}
