// Shared by every planetviz shader: constants, the planet's radii, stable ray-sphere distances and the phase
// functions, each with the name of its NumPy twin (planetviz/tables/parameterization.py, planetviz/model/optics/phase.py,
// planetviz/tables/multiple.py forward_factor).
//
// Uniforms:
//   bottom_radius, top_radius   float  planet and top-of-atmosphere radii [m]
//   group_count                 int    number of wavelength groups G (1 .. MAX_GROUPS); group g holds wavelengths
//                                      4g .. 4g + 3, one per component of a vec4
//   rayleigh_anisotropy         float  A in P_R = (1 + A nu^2) / (4 pi (1 + A / 3)): 1 Rayleigh, 0.932 Penndorf
//   mie_g1, mie_g2, mie_alpha   vec4[MAX_GROUPS]  the double Henyey-Greenstein parameters per wavelength
//   mie_lobe_share              vec4[MAX_GROUPS]  the particles' share of the vertical scattering optical depth per
//                                      wavelength (forward_factor)

#define MAX_GROUPS 16
const float PI = 3.14159265358979;

uniform float bottom_radius;
uniform float top_radius;
uniform int group_count;
uniform float rayleigh_anisotropy;
uniform vec4 mie_g1[MAX_GROUPS];
uniform vec4 mie_g2[MAX_GROUPS];
uniform vec4 mie_alpha[MAX_GROUPS];
uniform vec4 mie_lobe_share[MAX_GROUPS];

float safe_sqrt(float a) { return sqrt(max(a, 0.0)); }
float clamp_cosine(float mu) { return clamp(mu, -1.0, 1.0); }

// Points are given to these functions by their altitude a = r - R_b [m] where the NumPy twins take r: a float r
// is 0.5 m coarse at 6.4e6 m (a camera 1.7 m up would be drawn from 1.5 m), a float a is not. r = R_b + a is
// formed only where a relative precision of 6e-8 suffices (products with cosines, distances to the top), and
// r^2 - R_b^2 is always a (a + 2 R_b).
float radius_of(float a) { return bottom_radius + a; }

// rho = sqrt(r^2 - R_b^2), the distance to the horizon.
float rho_of(float a) { return safe_sqrt(a * (a + 2.0 * bottom_radius)); }

// d >= 0 along (a, mu) to the top of the atmosphere, r <= top, in the stable form of the two roots: -r mu +
// sqrt(disc) for mu < 0, c / (r mu + sqrt(disc)) for mu >= 0, with c = R_t^2 - r^2 = (R_t - R_b - a)(R_t + r) and
// disc = (r mu)^2 + c. The difference -r mu + sqrt(disc) of two numbers near r loses float32's 0.5 m at 6.4e6 m,
// 0.5% of the ray's length looking up from 100 m under the top.
float distance_to_top_atmosphere_boundary(float a, float mu) {
    float r = radius_of(a);
    float c = max((top_radius - bottom_radius) - a, 0.0) * (top_radius + r);
    float root = safe_sqrt(r * mu * r * mu + c);
    return mu < 0.0 ? root - r * mu : c / max(r * mu + root, 1e-30);
}

// d >= 0 along (a, mu) to the ground, in the stable form c / q with c = r^2 - R_b^2 = a (a + 2 R_b).
float distance_to_bottom_atmosphere_boundary(float a, float mu) {
    float r = radius_of(a);
    float c = a * (a + 2.0 * bottom_radius);
    float disc = r * r * mu * mu - c;
    float q = -r * mu + safe_sqrt(disc);
    return q > 0.0 ? max(c / q, 0.0) : 0.0;
}

bool ray_intersects_ground(float a, float mu) {
    float r = radius_of(a);
    return mu < 0.0 && r * r * mu * mu - a * (a + 2.0 * bottom_radius) >= 0.0;
}

// --------------------------------------------------------------------------------------------------- phases
// The molecules' phase with the atmosphere's anisotropy A: the NumPy twins rayleigh_phase (A = 1) and
// penndorf_phase (A = PENNDORF_A = 0.932) of planetviz/model/optics/phase.py.
float rayleigh_like_phase(float nu) {
    float a = rayleigh_anisotropy;
    return (1.0 + a * nu * nu) / (4.0 * PI * (1.0 + a / 3.0));
}

// x^1.5 as x sqrt(x): a software renderer evaluates pow as exp2(1.5 log2(x)), several times the cost.
vec4 henyey_greenstein(float nu, vec4 g) {
    vec4 x = 1.0 + g * g - 2.0 * g * nu;
    return (1.0 - g * g) / (4.0 * PI * x * sqrt(x));
}

vec4 double_henyey_greenstein(float nu, vec4 g1, vec4 g2, vec4 alpha) {
    return alpha * henyey_greenstein(nu, g1) + (1.0 - alpha) * henyey_greenstein(nu, g2);
}

// The shape of the light the particles scatter the second time, F(nu) = s DHG(nu; g1+^2, g2+^2, alpha) +
// (1 - s) / (4 pi) of group g, s = mie_lobe_share, g+ = max(g, 0) (a backward lobe counts as isotropic;
// planetviz/tables/multiple.py forward_factor says why).
vec4 forward_factor(float nu, int g) {
    vec4 g1 = max(mie_g1[g], 0.0), g2 = max(mie_g2[g], 0.0);
    vec4 s = mie_lobe_share[g];
    return s * double_henyey_greenstein(nu, g1 * g1, g2 * g2, mie_alpha[g]) + (1.0 - s) / (4.0 * PI);
}

// The in-scattered radiance of group g in four parts, each without the phase function that phased_sum applies
// (per unit solar irradiance): single scattering by molecules (times rayleigh_like_phase) and by particles (times
// the double Henyey-Greenstein phase), the orders above the first last scattered by molecules (phase included: times
// 1) and by particles (times forward_factor).
struct ScatteringParts { vec4 rayleigh; vec4 mie; vec4 multiple; vec4 multiple_mie; };

vec4 phased_sum(ScatteringParts s, float nu, int g) {
    return s.rayleigh * rayleigh_like_phase(nu)
        + s.mie * double_henyey_greenstein(nu, mie_g1[g], mie_g2[g], mie_alpha[g])
        + s.multiple + forward_factor(nu, g) * s.multiple_mie;
}

