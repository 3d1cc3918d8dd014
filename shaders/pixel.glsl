// What both fragment shaders of the table-based renderer compute per pixel (after atmosphere_ray.glsl and
// display.glsl): the pixel's view direction, the sun disc test and the surface texture's colour.
//
// Uniforms:
//   camera_forward         vec3   unit view direction at the centre of the viewport
//   camera_right           vec3   right vector scaled by tan(horizontal half field of view)
//   camera_up              vec3   up vector scaled by tan(vertical half field of view)
//   viewport               vec4   viewport origin and size in pixels (x0, y0, width, height)
//   sun_cos_radius         float  cos of the sun's angular radius (the disc: nu > sun_cos_radius)
//   sun_solid_angle        float  solid angle of the disc [sr]: its radiance is T / sun_solid_angle per unit irradiance
//   show_sun               int    1: draw the sun disc
//   surface_texture        sampler2D  the planet's surface colour (equirectangular, 8-bit sRGB stored as GL_SRGB8:
//                                     the GPU returns it decoded to linear, filtered in linear)

uniform vec3 camera_forward;
uniform vec3 camera_right;
uniform vec3 camera_up;
uniform vec4 viewport;
uniform float sun_cos_radius;
uniform float sun_solid_angle;
uniform int show_sun;
uniform sampler2D surface_texture;

// The unit view direction through this pixel's centre (Scene.pixel_directions is its NumPy twin).
vec3 pixel_direction() {
    vec2 ndc = (gl_FragCoord.xy - viewport.xy) / viewport.zw * 2.0 - 1.0;
    return normalize(camera_forward + ndc.x * camera_right + ndc.y * camera_up);
}

bool in_sun_disc(vec3 v) { return show_sun == 1 && dot(v, sun_direction) > sun_cos_radius; }

// Linear colour of the surface texture at the ground point p (planet-centred [m]).
vec3 surface_colour(vec3 p) {
    vec3 n = normalize(p);
    vec2 uv = vec2(atan(n.y, n.x) / (2.0 * PI) + 0.5, asin(clamp(n.z, -1.0, 1.0)) / PI + 0.5);
    return texture(surface_texture, uv).rgb;
}
