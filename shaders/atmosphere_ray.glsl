// The table-based model along one view ray, in either stage (after phased_scattering.glsl and view.glsl): where the
// ray enters the atmosphere, and the three terms whose sum is its radiance, as the NumPy evaluator computes it
// (planetviz/tables/evaluator.py, sky_radiance):
//   L = inscatter + albedo * ground_light + [the ray is in the sun's disc] sun_transmittance / sun_solid_angle
// The per-pixel renderer (atmosphere_fragment.glsl) evaluates all three for every pixel. The per-vertex renderer
// evaluates them at the vertices of a direction mesh (atmosphere_vertex.glsl: the 4D tables, most of the cost, and
// the ground's light split by the sun's cosine) and completes per pixel (atmosphere_interpolated.glsl) what
// changes faster across the screen: the surface texture, the sun's cosine at the ground point (the terminator),
// the disc, inscatter_factor (inscatter_factor.glsl); no 4D table is read per pixel there.
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
    ScatteringParts y = get_ground_point_parts(h.mu, h.mu_s, ray.nu, g);
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
