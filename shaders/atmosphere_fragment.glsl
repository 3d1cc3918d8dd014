// The planet and its atmosphere for one pixel: the paper's Algorithm 1 (Sect. 5.2), read from the tables.
// Inserted after atmosphere_functions.glsl in the fragment shader of a shell enclosing the atmosphere (front
// faces culled, so it covers exactly the pixels whose rays may meet the atmosphere, from space and from inside).
// The view ray comes from gl_FragCoord and the camera uniforms, computed in double precision on the CPU, never
// from the shell's vertices; intersections use the stable forms (planetviz/geometry.py).
//
// Same formulas as the NumPy evaluator (planetviz/tables/evaluator.py, sky_radiance):
//   rays to space   L = S_R P_R + S_M P_M + S_ms + F S_ms_mie, plus the sun disc T / Omega_sun
//   rays to ground  L = S(x) - T(x, y) S(y) + T(x, y) (albedo / pi) (T_sun(y) max(n . s, 0) + E_sky(y))
//
// Uniforms:
//   camera_position        vec3   planet-centred camera position [m] (float; used for the ground point's texture)
//   camera_radius          float  |camera_position| [m], computed in double on the CPU
//   camera_forward         vec3   unit view direction at the centre of the viewport
//   camera_right           vec3   right vector scaled by tan(horizontal half field of view)
//   camera_up              vec3   up vector scaled by tan(vertical half field of view)
//   viewport               vec4   viewport origin and size in pixels (x0, y0, width, height)
//   sun_direction          vec3   unit vector toward the sun
//   sun_cos_radius         float  cos of the sun's angular radius (the disc: nu > sun_cos_radius)
//   sun_solid_angle        float  solid angle of the disc [sr]: its radiance is T / sun_solid_angle per unit irradiance
//   show_sun               int    1: draw the sun disc
//   rgb_weights            vec4[3 MAX_GROUPS]  linear sRGB of group g = dot(rgb_weights[3g + c], L_g): the star's
//                                 spectral irradiance, the CIE 1931 functions, 683 lm/W and colour-science's
//                                 XYZ -> sRGB matrix folded in (planetviz/color.py; luminance in cd/m^2)
//   surface_texture        sampler2D  the planet's surface colour (equirectangular, sRGB-encoded, 8 bit)
//   use_surface_texture    int    1: albedo from surface_texture, 0: surface_albedo
//   albedo_weights         vec4[3 MAX_GROUPS]  albedo of group g = sum_c albedo_weights[3g + c] * linear texture[c]
//   surface_albedo         vec4[MAX_GROUPS]  the atmosphere file's ground albedo per wavelength
//   output_mode            int    0: display colour (exposure, tone mapping, sRGB encoding); 1: the radiance at
//                                 wavelengths 3 k .. 3 k + 2 (k = output_triple) per unit solar irradiance [1/sr]
//                                 in R, G, B (alpha stays 1: VTK blends by alpha); 2: linear sRGB (CIE Y in
//                                 cd/m^2), not tone-mapped
//   output_triple          int    k of output_mode 1

uniform vec3 camera_position;
uniform float camera_radius;
uniform vec3 camera_forward;
uniform vec3 camera_right;
uniform vec3 camera_up;
uniform vec4 viewport;
uniform vec3 sun_direction;
uniform float sun_cos_radius;
uniform float sun_solid_angle;
uniform int show_sun;
uniform vec4 rgb_weights[3 * MAX_GROUPS];
uniform sampler2D surface_texture;
uniform int use_surface_texture;
uniform vec4 albedo_weights[3 * MAX_GROUPS];
uniform vec4 surface_albedo[MAX_GROUPS];
uniform int output_mode;
uniform int output_triple;

// The view ray of this pixel where it enters the atmosphere: (r, mu, mu_s, nu), the start point x and whether
// the ray meets the atmosphere at all.
struct ViewRay { vec3 v; vec3 x; float r; float mu; float mu_s; float nu; bool visible; };

ViewRay view_ray() {
    ViewRay ray;
    vec2 ndc = (gl_FragCoord.xy - viewport.xy) / viewport.zw * 2.0 - 1.0;
    ray.v = normalize(camera_forward + ndc.x * camera_right + ndc.y * camera_up);
    ray.x = camera_position;
    ray.r = camera_radius;
    ray.mu = dot(camera_position, ray.v) / camera_radius;
    ray.visible = true;
    if (camera_radius > top_radius) {
        // Closest approach of the planet centre, |x - (x.v) v|^2, computed as a vector (no cancellation).
        float b = dot(camera_position, ray.v);
        vec3 q = camera_position - b * ray.v;
        float p2 = dot(q, q);
        if (b >= 0.0 || p2 >= top_radius * top_radius) {
            ray.visible = false;
        } else {
            float half_chord = sqrt(top_radius * top_radius - p2);
            ray.x = q - half_chord * ray.v;
            ray.r = top_radius;
            ray.mu = -half_chord / top_radius;
        }
    }
    ray.mu = clamp_cosine(ray.mu);
    ray.mu_s = clamp_cosine(dot(normalize(ray.x), sun_direction));
    ray.nu = clamp_cosine(dot(ray.v, sun_direction));
    return ray;
}

// Albedo of group g at the ground point p.
vec4 ground_albedo(vec3 p, int g) {
    if (use_surface_texture == 0) return surface_albedo[g];
    vec3 n = normalize(p);
    vec2 uv = vec2(atan(n.y, n.x) / (2.0 * PI) + 0.5, asin(clamp(n.z, -1.0, 1.0)) / PI + 0.5);
    vec3 c = srgb_decode(texture(surface_texture, uv).rgb);
    return albedo_weights[3 * g] * c.r + albedo_weights[3 * g + 1] * c.g + albedo_weights[3 * g + 2] * c.b;
}

// Radiance of group g along the ray, per unit solar irradiance [1/sr].
vec4 radiance(ViewRay ray, int g) {
    if (!ray.visible) {
        return (show_sun == 1 && ray.nu > sun_cos_radius) ? vec4(1.0 / sun_solid_angle) : vec4(0.0);
    }
    bool ground = ray_intersects_ground(ray.r, ray.mu);
    vec4 l = get_phased_scattering(ray.r, ray.mu, ray.mu_s, ray.nu, ground, g);
    if (ground) {
        float d = distance_to_bottom_atmosphere_boundary(ray.r, ray.mu);
        float r_d = max(sqrt(max(d * d + 2.0 * ray.r * ray.mu * d + ray.r * ray.r, 0.0)), bottom_radius);
        float mu_d = clamp_cosine((ray.r * ray.mu + d) / r_d);
        float mu_s_d = clamp_cosine((ray.r * ray.mu_s + d * ray.nu) / r_d);
        vec4 t_xy = get_transmittance(ray.r, ray.mu, d, true, g);
        vec4 far_l = get_phased_scattering(r_d, mu_d, mu_s_d, ray.nu, true, g);
        vec4 sun_ground = get_transmittance_to_sun(bottom_radius, mu_s_d, g) * max(mu_s_d, 0.0);
        vec4 sky_ground = get_irradiance(bottom_radius, mu_s_d, g);
        vec4 albedo = ground_albedo(ray.x + d * ray.v, g);
        l = max(l - t_xy * far_l, 0.0) + t_xy * albedo / PI * (sun_ground + sky_ground);
    } else if (show_sun == 1 && ray.nu > sun_cos_radius) {
        l += get_transmittance_to_top_atmosphere_boundary(ray.r, ray.mu, g) / sun_solid_angle;
    }
    return l;
}

vec4 atmosphere_fragment() {
    ViewRay ray = view_ray();
    if (output_mode == 1) {
        int first = 3 * output_triple;
        vec4 l0 = radiance(ray, first / 4);
        vec4 l1 = (first + 2) / 4 != first / 4 ? radiance(ray, first / 4 + 1) : l0;
        vec3 out_l;
        for (int k = 0; k < 3; ++k) {
            int i = first + k;
            out_l[k] = i / 4 == first / 4 ? l0[i % 4] : l1[i % 4];
        }
        return vec4(out_l, 1.0);
    }
    vec3 rgb = vec3(0.0);
    for (int g = 0; g < group_count; ++g) {
        vec4 l = radiance(ray, g);
        rgb += vec3(dot(rgb_weights[3 * g], l), dot(rgb_weights[3 * g + 1], l), dot(rgb_weights[3 * g + 2], l));
    }
    if (output_mode == 2) return vec4(rgb, 1.0);
    return vec4(display_colour(rgb), 1.0);
}
