// What the per-vertex renderer reads per pixel (after atmosphere_ray.glsl), from small tables: the factor of the
// inscatter F = path opacity x sky irradiance x phase, what makes the inscatter change across the screen faster
// than the direction mesh resolves, and the factors of the ground's light (ray_factors). atmosphere_vertex.glsl
// passes each vertex's F beside its inscatter, and atmosphere_interpolated.glsl multiplies the interpolated
// inscatter by F at the pixel over the interpolated F: the interpolation then only has to follow the inscatter's
// ratio to F, which changes slowly.
// - path opacity: the scattering opacity of the ray from x to where it leaves the atmosphere or meets the ground,
//   the integral of beta_scat T along it (its opacity 1 - T times the share of that opacity which scatters; averaged
//   over the first output group's wavelengths): along the limb's halo, the horizon and the aerial perspective the
//   inscatter grows with it (the tables' sky half holds S over it for the same reason, table_lookup.glsl
//   ray_opacity), while an absorbing layer (ozone) raises 1 - T and not the inscatter. Every ray of the frame starts
//   at the same altitude, so it is read from a 1D table of mu made for that altitude on the CPU
//   (planetviz/tables/inscatter_factor.py), beside the ray's opacity 1 - T for the ground's light: one fetch
//   instead of the 2D optical-depth table's two for a ground ray;
// - sky irradiance: E(0, mu_s), the sky's irradiance on the ground for the sun's cosine mu_s at the ray's ground
//   point, or at its point nearest the planet's centre (held at mu_s_min below the tables' range): over the
//   ground's twilight band seen from space and along the limb over the terminator the inscatter falls with the
//   sun's depression as this irradiance does, and the ground's light from the sky is this irradiance (only ratios
//   of F matter, so no normalisation);
// - phase: the phase functions at nu of a mix w of the inscatter's parts before their phases
//   (get_inscatter_parts; phase_weights: the first output group's parts averaged over its wavelengths,
//   normalised), w interpolated: around the sun a strong forward lobe changes the inscatter faster than the mesh
//   resolves, while the parts change slowly. Magnitudes |w| keep it positive where the aerial perspective's parts
//   cancel.
// The sky irradiance and the phases come in one fetch of a table of their products (phase_irradiance).
// may_meet_ground: false where no ray can meet the ground (the mesh's sky part), which leaves the ground's code out
// (a software renderer runs both sides of a branch).
//
// Uniforms:
//   path_opacity_texture     sampler2D  one row 2 path_opacity_texels wide (the rays to the ground, then the
//                                       others) at the frame's ray altitude: the first group's means of
//                                       path_opacity_table (x) and path_scattering_table (y)
//                                       (planetviz/tables/inscatter_factor.py, planetviz/render/vertex_actor.py
//                                       path_opacity_image)
//   path_opacity_texels      float      texels of each half of path_opacity_texture
//   phase_irradiance_texture sampler2D  per group (blocks stacked along y) the outer product of the phases of the
//                                       inscatter's four parts along x (phase_factor_table, at phase_factor_u) and
//                                       the sky's irradiance on the ground along y (sky_irradiance_rows, on the
//                                       rows of irradiance_rows), each averaged over the group's wavelengths
//                                       (planetviz/tables/inscatter_factor.py)
//   phase_factor_texels      float      texels of phase_irradiance_texture along x
//   irradiance_rows          vec4       (mu_s of the first row, mu_s of the knee, the rows' step in mu_s below the
//                                       knee, above it) of the rows of a group's block (irradiance_rows)

uniform sampler2D path_opacity_texture;
uniform float path_opacity_texels;
uniform sampler2D phase_irradiance_texture;
uniform float phase_factor_texels;
uniform vec4 irradiance_rows;

// The coordinate of path_opacity_texture of the ray (a, mu) (inscatter_factor.py's path_opacity_u): each half
// uniform in the ray's length, to the ground or to the top.
float path_opacity_u(float a, float mu, bool intersects_ground) {
    float rho = rho_of(a);
    float x;
    if (intersects_ground) {
        float d = distance_to_bottom_atmosphere_boundary(a, mu);
        x = rho > a ? (d - a) / (rho - a) : 0.0;
    } else {
        float h = sqrt(top_radius * top_radius - bottom_radius * bottom_radius);
        float d_min = (top_radius - bottom_radius) - a;
        x = (distance_to_top_atmosphere_boundary(a, mu) - d_min) / (rho + h - d_min);
    }
    float half_u = 0.5 * texcoord_from_unit_range(clamp(x, 0.0, 1.0), path_opacity_texels);
    return intersects_ground ? 0.5 - half_u : 0.5 + half_u;
}

// (opacity 1 - T, scattering opacity) of the ray.
vec2 path_opacity(ViewRay ray, bool may_meet_ground) {
    bool ground = may_meet_ground && ray_intersects_ground(ray.a, ray.mu);
    return texture(path_opacity_texture, vec2(path_opacity_u(ray.a, ray.mu, ground), 0.5)).xy;
}

vec4 phase_weights(ScatteringParts s) {
    vec4 w = vec4(dot(s.rayleigh, vec4(0.25)), dot(s.mie, vec4(0.25)), dot(s.multiple, vec4(0.25)),
                  dot(s.multiple_mie, vec4(0.25)));
    float total = dot(abs(w), vec4(1.0));
    return total > 0.0 ? w / total : vec4(0.0, 0.0, 1.0, 0.0);
}

// The x coordinate of phase_irradiance_texture of the view-sun cosine nu (inscatter_factor.py's phase_factor_u):
// sin(theta / 2) / sqrt(2) toward the sun, 1 - cos(theta / 2) / sqrt(2) away from it.
float phase_factor_u(float nu) {
    float t = sqrt(clamp(0.5 - 0.5 * abs(nu), 0.0, 0.5)) * 0.70710678;
    return texcoord_from_unit_range(nu >= 0.0 ? t : 1.0 - t, phase_factor_texels);
}

// The y coordinate in a group's block of phase_irradiance_texture of the sun's cosine mu_s >= mu_s_min: its row
// (inscatter_factor.py's irradiance_row_index) over the block's rows.
float irradiance_v(float mu_s) {
    vec4 rows = irradiance_rows;
    float index = (min(mu_s, rows.y) - rows.x) / rows.z + max(mu_s - rows.y, 0.0) / rows.w;
    float block = float(textureSize(phase_irradiance_texture, 0).y) / float(group_count);
    return (index + 0.5) / block;
}

// The texel of phase_irradiance_texture for the ray: its view-sun angle, and the sun's cosine at its ground point or
// its point nearest the planet's centre.
vec4 phase_irradiance(ViewRay ray, bool may_meet_ground) {
    vec3 p = ray.x + max(-dot(ray.x, ray.v), 0.0) * ray.v;
    if (may_meet_ground && ray_intersects_ground(ray.a, ray.mu)) p = ground_point(ray);
    float mu_s = max(dot(normalize(p), sun_direction), mu_s_min);
    vec2 uv = vec2(phase_factor_u(ray.nu), irradiance_v(mu_s));
    return texture_group(phase_irradiance_texture, uv, first_group());
}

// What the per-vertex renderer reads per pixel for the ray (w: the interpolated phase_weights): the inscatter's
// factor F; and for the ground's light, which the vertices pass on as matrices, the ray's transmittance T (1 - its
// path opacity) and the sky's irradiance E at its ground point (the texel's third component, whose phase is 1), by
// which the pixel corrects them as it corrects the inscatter by F: along the limb T changes, across the terminator
// E changes, faster than the mesh resolves.
struct RayFactors { float inscatter; float transmittance; float irradiance; };

RayFactors ray_factors(ViewRay ray, vec4 w, bool may_meet_ground) {
    if (!ray.visible) return RayFactors(0.0, 1.0, 1.0);
    vec2 opacity = path_opacity(ray, may_meet_ground);
    vec4 phases = phase_irradiance(ray, may_meet_ground);
    return RayFactors(opacity.y * dot(abs(w), phases), 1.0 - opacity.x, phases.z);
}
