// What both fragment shaders of the table-based renderer compute per pixel (after atmosphere_ray.glsl and
// display.glsl): the pixel's view direction, the sun disc test and the surface texture's colour.
//
// Uniforms:
//   camera_forward         vec3   unit view direction at the centre of the viewport
//   camera_right           vec3   right vector scaled by tan(horizontal half field of view)
//   camera_up              vec3   up vector scaled by tan(vertical half field of view)
//   viewport               vec4   viewport origin and size in pixels (x0, y0, width, height)
//   sun_cos_radius         float  cos of the star disc's angular radius seen from the planet (Star.angular_radius_deg;
//                                 the disc: nu > sun_cos_radius)
//   sun_solid_angle        float  solid angle of the disc [sr]: its radiance is T / sun_solid_angle per unit irradiance
//   show_sun               int    1: draw the sun disc
//   surface_faces          sampler2DArray  the planet's surface colour on the six faces of a cube, one layer each
//                                     (planetviz/render/surface.py surface_cube: gnomonic faces with a one-texel
//                                     border; 8-bit sRGB stored as GL_SRGB8: the GPU returns it decoded to linear,
//                                     filtered in linear)
//   surface_face_size      float  texels along a face's side, border excluded

uniform vec3 camera_forward;
uniform vec3 camera_right;
uniform vec3 camera_up;
uniform vec4 viewport;
uniform float sun_cos_radius;
uniform float sun_solid_angle;
uniform int show_sun;
uniform sampler2DArray surface_faces;
uniform float surface_face_size;

// The unit view direction through this pixel's centre (Scene.pixel_directions is its NumPy twin).
vec3 pixel_direction() {
    vec2 ndc = (gl_FragCoord.xy - viewport.xy) / viewport.zw * 2.0 - 1.0;
    return normalize(camera_forward + ndc.x * camera_right + ndc.y * camera_up);
}

bool in_sun_disc(vec3 v) { return show_sun == 1 && dot(v, sun_direction) > sun_cos_radius; }

// (u, v, layer) in surface_faces of the unit direction n: the face of the largest component (x before y before z
// on ties), the other two divided by it, past the texel border (surface.py cube_face_uv is the NumPy twin). No
// trigonometry: an equirectangular map's atan and asin cost the H100 0.05 ms of a 1.26 ms per-vertex frame at 1080p.
vec3 cube_face_uv(vec3 n) {
    vec3 a = abs(n);
    vec3 st_layer;
    if (a.x >= a.y && a.x >= a.z) st_layer = vec3(n.yz / a.x, n.x > 0.0 ? 0.0 : 1.0);
    else if (a.y >= a.z) st_layer = vec3(n.xz / a.y, n.y > 0.0 ? 2.0 : 3.0);
    else st_layer = vec3(n.xy / a.z, n.z > 0.0 ? 4.0 : 5.0);
    return vec3(((st_layer.xy + 1.0) * 0.5 * surface_face_size + 1.0) / (surface_face_size + 2.0), st_layer.z);
}

// Linear colour of the surface texture at the ground point of unit normal n.
vec3 surface_colour(vec3 n) { return texture(surface_faces, cube_face_uv(n)).rgb; }

// The colour albedo_from_colour takes at the ground point of unit normal n: the surface texture's, or (1, 0, 0).
vec3 surface_colour_or_unit(vec3 n) { return use_surface_texture == 1 ? surface_colour(n) : vec3(1.0, 0.0, 0.0); }
