// Quick view, per fragment: the vertex shader's value (fallback_vertex.glsl), interpolated over the triangle, shown
// through display.glsl (output_mode 0) or written as it is (1: spectral radiance, 2: linear sRGB).
//
// Uniforms: output_mode (int, as in fallback_vertex.glsl); those of display.glsl.

uniform int output_mode;
in vec3 fallback_value;

vec4 fallback_fragment() {
    return output_mode == 0 ? vec4(display_colour(fallback_value), 1.0) : vec4(fallback_value, 1.0);
}
