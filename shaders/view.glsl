// The camera, the sun and the output channels, which the table-based shaders (atmosphere_ray.glsl and after) and
// the quick view's (quick_view_vertex.glsl, quick_view_fragment.glsl) share (after common.glsl): the wavelength
// groups an output mode needs, their weights in the three output channels, and the ground's albedo per unit of
// the surface colour.
//
// Uniforms:
//   camera_position        vec3   planet-centred camera position [m] (float: for directions and the ground point's
//                                 texture coordinates, never for the camera's height)
//   camera_altitude        float  |camera_position| - bottom_radius [m], computed in double on the CPU
//   sun_direction          vec3   unit vector toward the sun
//   use_surface_texture    int    1: albedo from the surface texture, 0: surface_albedo
//   albedo_weights         vec4[3 MAX_GROUPS]  albedo of group g = sum_c albedo_weights[3g + c] * linear texture[c]
//   surface_albedo         vec4[MAX_GROUPS]  the atmosphere file's ground albedo per wavelength
//   rgb_weights            vec4[3 MAX_GROUPS]  linear sRGB of group g = dot(rgb_weights[3g + c], L_g): the star's
//                                 spectral irradiance, the CIE 1931 functions, 683 lm/W and colour-science's
//                                 XYZ -> sRGB matrix folded in (planetviz/model/color.py; luminance in cd/m^2)
//   output_mode            int    0: display colour (exposure, tone mapping, sRGB encoding); 1: the radiance at
//                                 wavelengths 3 k .. 3 k + 2 (k = output_triple) per unit solar irradiance [1/sr]
//                                 in R, G, B (alpha stays 1: VTK blends by alpha); 2: linear sRGB (CIE Y in
//                                 cd/m^2), not tone-mapped
//   output_triple          int    k of output_mode 1

uniform vec3 camera_position;
uniform float camera_altitude;
uniform vec3 sun_direction;
uniform int use_surface_texture;
uniform vec4 albedo_weights[3 * MAX_GROUPS];
uniform vec4 surface_albedo[MAX_GROUPS];
uniform vec4 rgb_weights[3 * MAX_GROUPS];
uniform int output_mode;
uniform int output_triple;

// The wavelength groups output_mode needs: first_group() .. last_group().
int first_group() { return output_mode == 1 ? 3 * output_triple / 4 : 0; }
int last_group() { return output_mode == 1 ? (3 * output_triple + 2) / 4 : group_count - 1; }

// Weights of group g's four wavelengths in output channel k.
vec4 channel_weights(int k, int g) {
    if (output_mode != 1) return rgb_weights[3 * g + k];
    return vec4(equal(ivec4(4 * g) + ivec4(0, 1, 2, 3), ivec4(3 * output_triple + k)));
}

// Group g's radiance l added to the output channels.
vec3 to_channels(vec4 l, int g) {
    return vec3(dot(channel_weights(0, g), l), dot(channel_weights(1, g), l), dot(channel_weights(2, g), l));
}

// Group g's albedo for each unit of component k (0, 1, 2) of the surface colour: the albedo is linear in the
// texture's linear colour c (albedo_from_colour); with no texture, the file's albedo is component 0 of the colour
// (1, 0, 0) (surface_colour_or_unit).
vec4 albedo_column(int k, int g) {
    if (use_surface_texture == 1) return albedo_weights[3 * g + k];
    return k == 0 ? surface_albedo[g] : vec4(0.0);
}

// The ground's albedo of group g for the colour c: the linear colour of the surface texture at the ground point,
// or (1, 0, 0) with no texture.
vec4 albedo_from_colour(vec3 c, int g) {
    return albedo_column(0, g) * c.r + albedo_column(1, g) * c.g + albedo_column(2, g) * c.b;
}
