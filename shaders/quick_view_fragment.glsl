// Quick view, per fragment: the vertex shader's value (quick_view_vertex.glsl), interpolated over the triangle, shown
// through display.glsl (output_mode 0) or written as it is (1: spectral radiance, 2: linear sRGB).
//
// Uniforms: output_mode (int, as in quick_view_vertex.glsl); those of display.glsl.

uniform int output_mode;
in vec3 quick_view_value;

vec4 quick_view_fragment() {
    // Spectral radiance is interpolated from non-negative vertices, but the rasteriser's barycentric weights can be
    // slightly negative on the slivers straddling a limb, which would extrapolate below 0 (linear sRGB may be
    // negative out of gamut and stays as it is; the display clamps).
    vec3 value = output_mode == 1 ? max(quick_view_value, 0.0) : quick_view_value;
    return output_mode == 0 ? vec4(display_colour(value), 1.0) : vec4(value, 1.0);
}
