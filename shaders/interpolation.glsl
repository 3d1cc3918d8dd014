// Geometric interpolation over the direction mesh's triangles (after common.glsl; in the vertex and the fragment
// shaders of the per-vertex renderer and of the quick view). Across the twilight band of the ground, the night side
// of the limb and the terminator seen from space the inscatter falls by orders of magnitude within a triangle,
// about exponentially, which a linear interpolant reads many times too high toward the dark vertices. A vertex
// splits such a value into its colour (over its largest channel), that magnitude and the magnitude's logarithm
// (split_magnitude); the rasteriser interpolates the three linearly, and the fragment takes the colour times
// exp(interpolated logarithm) (geometric_value). The smaller of that and the linearly interpolated magnitude is
// taken: for barycentric weights in [0, 1] it is the geometric one, and on the slivers straddling a limb, where the
// rasteriser's weights go slightly negative, a negative weight on a dark vertex's logarithm would multiply the
// geometric one many times.
//
// No uniforms.

// The least magnitude whose logarithm is taken (a black vertex reads as it).
const float LOG_MAGNITUDE_FLOOR = 1e-37;

// log(max(x, LOG_MAGNITUDE_FLOOR)), for a vertex to pass beside x.
float floored_log(float x) {
    return log(max(x, LOG_MAGNITUDE_FLOOR));
}

// value = colour * magnitude, magnitude its largest channel (by absolute value), colour 0 for a black value.
void split_magnitude(vec3 value, out vec3 colour, out float magnitude, out float log_magnitude) {
    magnitude = max(max(abs(value.r), abs(value.g)), abs(value.b));
    log_magnitude = floored_log(magnitude);
    colour = magnitude > 0.0 ? value / magnitude : vec3(0.0);
}

// The geometric interpolant of a positive scalar from its interpolated value and logarithm.
float geometric_scalar(float value, float log_value) {
    return min(exp(log_value), value);
}

// The geometric interpolant of a value split by split_magnitude, from the interpolated colour, magnitude and
// logarithm.
vec3 geometric_value(vec3 colour, float magnitude, float log_magnitude) {
    return colour * geometric_scalar(magnitude, log_magnitude);
}
