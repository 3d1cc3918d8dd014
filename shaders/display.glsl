// From linear sRGB to the screen: exposure, tone mapping and sRGB encoding.
//
// Uniforms:
//   exposure               float  multiplies linear sRGB (luminance in cd/m^2) before tone mapping [m^2 / cd]
//   tone_mapping           int    0: the paper's exponential 1 - exp(-x); 1: filmic (Narkowicz's ACES fit); 2: clamp

uniform float exposure;
uniform int tone_mapping;

vec3 srgb_encode(vec3 c) {
    c = clamp(c, 0.0, 1.0);
    return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, greaterThan(c, vec3(0.0031308)));
}

vec3 tone_map(vec3 x) {
    if (tone_mapping == 0) return 1.0 - exp(-x);
    if (tone_mapping == 1) return clamp((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
    return clamp(x, 0.0, 1.0);
}

// The displayed colour of linear sRGB radiance.
vec3 display_colour(vec3 rgb) { return srgb_encode(tone_map(max(rgb, 0.0) * exposure)); }
