"""The quick view's orders above the first (the table of the mean radiance Psi solved in
planetviz/quick_view/multiple_scattering.py): its quadratures against closed forms and the reference's optical
depth, Psi against DISORT where its isotropic model is exact, and the quick view's pictures against the per-pixel
4D tables on Earth."""
import os

import numpy as np
import pytest

os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkOSOpenGLRenderWindow")

from planetviz import load_atmosphere  # noqa: E402
from planetviz.quick_view.multiple_scattering import (altitude_grid, cosine_coordinate, cosine_grid,  # noqa: E402
                                                      direction_set, fibonacci_sphere, multiple_scattering_table,
                                                      read_table, step_weights, transmittance_table,
                                                      transport_scaled)
from planetviz.reference.optical_depth import optical_depth  # noqa: E402
from planetviz.validation.pictures import VIEWS, floored_difference, view_luminance  # noqa: E402

from conftest import hold_to_targets  # noqa: E402

#: Earth's daylight views (planetviz.validation.pictures) bounded at the quick view's 5% target.
DAYLIGHT_VIEWS = ["orbit, day", "aircraft, 10 km", "ground, noon", "ground, sunset"]

EARTH = load_atmosphere("earth")


def test_step_weights_integrate_a_constant_medium_exactly():
    # int_0^L beta_s exp(-beta_t t) dt = beta_s / beta_t (1 - exp(-beta_t L)), cut into steps of any optical
    # thickness (0.01 to 50 per step): the sum of the steps is the closed form to rounding.
    beta_s, beta_t = 0.7, 1.0
    for length, steps in ((0.05, 5), (10.0, 4), (200.0, 4)):
        dt = np.full((1, steps), length / steps)
        weights = step_weights(np.full((1, steps, 1), beta_s), dt, beta_t * dt[..., None])
        assert weights.sum() == pytest.approx(beta_s / beta_t * -np.expm1(-beta_t * length), rel=1e-12)


def test_read_table_is_bilinear_between_the_nodes():
    # A table linear in the grid coordinates (sqrt(h / H), the cosine's coordinate) is read back exactly anywhere.
    n_h, n_mu = 8, 12
    u = np.sqrt(altitude_grid(EARTH, n_h) / EARTH.thickness_m)[:, None, None]
    v = cosine_coordinate(cosine_grid(n_mu))[None, :, None]
    table = 3.0 * u - 2.0 * v + np.array([0.0, 1.0, 2.0])
    rng = np.random.default_rng(5)
    h = rng.uniform(0.0, EARTH.thickness_m, 50)
    mu = rng.uniform(-1.0, 1.0, 50)
    want = 3.0 * np.sqrt(h / EARTH.thickness_m)[:, None] - 2.0 * cosine_coordinate(mu)[:, None] + [0.0, 1.0, 2.0]
    assert np.allclose(read_table(table, EARTH, h, mu), want, atol=1e-12)
    assert np.allclose(cosine_coordinate(cosine_grid(9)), np.linspace(-1, 1, 9))


def test_a_geometric_read_is_exact_for_a_table_exponential_in_the_grid_coordinates():
    # Psi and E_sky fall exponentially with the sun's depression in twilight; read geometrically (as the shader reads
    # its log textures), a table exp(a u + b v) is read back exactly anywhere, where a linear read is not.
    n_h, n_mu = 8, 12
    u = np.sqrt(altitude_grid(EARTH, n_h) / EARTH.thickness_m)[:, None, None]
    v = cosine_coordinate(cosine_grid(n_mu))[None, :, None]
    table = np.exp(-4.0 * u + 9.0 * v + np.array([0.0, -1.0]))
    rng = np.random.default_rng(6)
    h, mu = rng.uniform(0.0, EARTH.thickness_m, 50), rng.uniform(-1.0, 1.0, 50)
    want = np.exp(-4.0 * np.sqrt(h / EARTH.thickness_m)[:, None] + 9.0 * cosine_coordinate(mu)[:, None]
                  + [0.0, -1.0])
    assert np.allclose(read_table(table, EARTH, h, mu, geometric=True), want, rtol=1e-12)
    assert not np.allclose(read_table(table, EARTH, h, mu), want, rtol=1e-2)


def test_the_direction_set_averages_polynomials_to_their_sphere_means():
    # Gauss-Legendre on each hemisphere is exact in mu for degree 2 n - 1; the azimuths' midpoints over [0, pi]
    # average cos^2 phi to 1/2. Sphere means: mu^2 1/3, mu^4 1/5, |mu| 1/2, x^2 = (1 - mu^2) cos^2 phi 1/3.
    d, w = direction_set()
    assert w.sum() == pytest.approx(1.0, abs=1e-14)
    for f, mean in ((d[:, 2] ** 2, 1 / 3), (d[:, 2] ** 4, 1 / 5), (np.abs(d[:, 2]), 1 / 2), (d[:, 0] ** 2, 1 / 3)):
        assert np.dot(w, f) == pytest.approx(mean, rel=1e-12)


@pytest.mark.slow
def test_psi_is_the_mean_radiance_disort_computes_for_isotropic_scatterers():
    # With isotropic phase functions the table's model is exact: Psi is the mean over directions of the diffuse
    # radiance, which DISORT gives as (1/2) int u0 dmu (planetviz/validation/disort.py; its error at 64 streams is
    # below 0.3%, the planet's curvature 1e-4 at 1e9 m). What is left is the table's quadrature (directions, steps,
    # nodes). The bound, 3%, is what the table may spend of the quick view's 5% RMS target in Earth's views;
    # optical depths 0.1-2 (Earth's and Mars's skies), sun 17 and 72 deg from the zenith, the ground and three
    # altitudes.
    from planetviz.validation.disort import disort_mean_radiance, isotropic_atmosphere
    atm = isotropic_atmosphere((0.1, 1.0, 2.0), 0.95)
    psi = multiple_scattering_table(atm)
    heights = np.array([0.0, 2000.0, 10000.0, 30000.0])
    for mu_s in (0.95, 0.3):
        got = read_table(psi, atm, heights, np.full(heights.shape, mu_s), geometric=True)
        for w in range(3):
            want = disort_mean_radiance(atm, w, mu_s, heights)
            assert np.allclose(got[:, w], want, rtol=0.03), (mu_s, w, got[:, w] / want)


def test_transmittance_table_against_the_reference_optical_depth():
    # The reference integrates the optical depth with adaptive Gauss-Legendre (relative error < 5e-5). The table's
    # midpoint rule errs by O(1 / m^2): about 1e-3 of tau with 40 points where the ozone layer's tent puts kinks
    # in the integrand, so the bound is 3e-3, and doubling the points must cut the error about fourfold.
    def errors(steps):
        table = transmittance_table(EARTH, steps=steps)
        n_h, n_mu = table.shape[:2]
        heights, cosines = altitude_grid(EARTH, n_h), cosine_grid(n_mu)
        out = []
        for i in (0, 5, 20, n_h - 2):
            for j in (n_mu // 2 + 1, 3 * n_mu // 4, n_mu - 1):
                point = np.array([[0.0, 0.0, EARTH.bottom_radius_m + heights[i]]])
                direction = np.array([[np.sqrt(1 - cosines[j] ** 2), 0.0, cosines[j]]])
                tau = optical_depth(EARTH, point, direction, np.inf)[0]
                out.append(np.abs(-np.log(table[i, j]) / tau - 1.0))
        return np.array(out), table
    coarse, table = errors(40)
    assert coarse.max() < 3e-3
    assert errors(80)[0].max() < coarse.max() / 3.0
    # Rays that meet the ground are in the planet's shadow.
    assert np.all(table[0, : table.shape[1] // 2 - 1] == 0.0)


def test_fibonacci_directions_average_a_linear_and_a_quadratic_function_to_their_sphere_means():
    # Mean over the sphere: of z, 0; of z^2, 1/3 (the even spread the table's mean over directions relies on).
    d = fibonacci_sphere(64)
    assert np.allclose(np.linalg.norm(d, axis=1), 1.0)
    assert abs(d[:, 2].mean()) < 1e-12 and d[:, 2].var() == pytest.approx(1 / 3, rel=2e-3)


def test_transport_scaling_keeps_the_absorption_and_removes_the_forward_share():
    atm = load_atmosphere("mars")
    scaled = transport_scaled(atm)
    g = np.asarray(atm.mie.alpha) * atm.mie.g1 + (1 - np.asarray(atm.mie.alpha)) * atm.mie.g2
    absorption = np.subtract(atm.mie.extinction_m, atm.mie.scattering_m)
    assert np.allclose(np.subtract(scaled.mie.extinction_m, scaled.mie.scattering_m), absorption)
    assert np.allclose(scaled.mie.scattering_m, np.multiply(atm.mie.scattering_m, 1 - g))


@pytest.fixture(scope="module")
def earth_pictures():
    """CIE Y of Earth's views drawn by the per-pixel standard tables and by the quick view (all orders; single
    scattering alone), the sun's disc left out, the atmosphere's uniform albedo on both sides."""
    from planetviz.render import Scene
    kinds = {"tables": dict(method="tables"), "all": dict(method="quick", quick_orders="all"),
             "single": dict(method="quick", quick_orders="single")}
    scenes = {k: Scene("earth", quality="standard", surface=None, off_screen=True, window_size=(160, 100),
                       shading="pixel", **kw) for k, kw in kinds.items()}
    out = {}
    try:
        for view in DAYLIGHT_VIEWS:
            for kind, scene in scenes.items():
                out[view, kind] = view_luminance(scene, VIEWS[view])
    finally:
        for scene in scenes.values():
            scene.close()
    return out


@pytest.mark.parametrize("view", DAYLIGHT_VIEWS)
def test_the_quick_view_of_earth_by_day_is_within_5_percent_of_the_tables(earth_pictures, view):
    # The target for the quick view in Earth's views: 5% RMS of the per-pixel tables, the difference floored at 1%
    # of the frame's 99th percentile. The standard tables are 0.3% from the reference on Earth's daylight rays
    # (docs/benchmarks.md), so the bound tests the quick view. Single scattering alone misses 14-57% here.
    def rms(kind):
        return np.sqrt(np.mean(floored_difference(earth_pictures[view, kind], earth_pictures[view, "tables"]) ** 2))
    assert rms("all") < 0.05 and rms("single") > 0.1, (rms("all"), rms("single"))


def test_the_quick_view_draws_the_surface_texture():
    # Earth from orbit by day with its surface texture, quick view against the per-pixel tables: the texture and the
    # terminator completed per pixel bring the quick view within its own model error of the tables (by day 1-4.5%
    # with a uniform albedo, docs/benchmarks.md; bound 10%), where the quick view with the file's uniform albedo
    # is about 50% off the textured picture (bound 30%: the texture is what closes the gap).
    from planetviz.render import Scene
    kinds = {"tables": dict(method="tables", surface="texture"), "quick": dict(method="quick", surface="texture"),
             "uniform": dict(method="quick", surface=None)}
    y = {}
    for kind, keywords in kinds.items():
        scene = Scene("earth", quality="standard", off_screen=True, window_size=(160, 100), shading="pixel",
                      **keywords)
        try:
            y[kind] = view_luminance(scene, VIEWS["orbit, day"])
        finally:
            scene.close()

    def rms(kind):
        return np.sqrt(np.mean(floored_difference(y[kind], y["tables"]) ** 2))
    assert rms("quick") < 0.1 and rms("uniform") > 0.3, (rms("quick"), rms("uniform"))


#: The views of docs/benchmarks.md's quick-view table (320x200, uniform albedo) that miss the issue's targets, and
#: which figures they miss. What limits them is written there: on Mars the isotropic model of the orders above the
#: first, with the similarity scaling, does not follow the dust's forward lobe (g = 0.86-0.91), and the sky near the
#: horizon and at low sun reads 30-45% dark (on the night side from orbit, the lit crescent along the limb about a
#: third dark), and its terminator from orbit reads 25.3% at the 99th percentile (target 25%; 23.5% with every point
#: of the view paths that reach the ground crowded at the camera's end, which took the random atmospheres' discs
#: from space to 16-27% RMS); in the thick planet's twilight the table's mean radiance near the ground reads above
#: the tables' 4-6 deg after sunset, the most at the bluest wavelength (docs/benchmarks.md).
QUICK_VIEW_MISSES = {("mars", view): {"rms", "p99"} for view in VIEWS if view not in ("orbit, day", "orbit, terminator")}
QUICK_VIEW_MISSES |= {("mars", "orbit, terminator"): {"p99"}, ("exo-co2-thick", "ground, twilight"): {"rms"}}
#: The issue's targets for the quick view against the per-pixel tables: Earth 5% RMS and 15% at the 99th percentile,
#: dusty or thick atmospheres 10% and 25%.
QUICK_VIEW_TARGETS = {"earth": {"rms": 0.05, "p99": 0.15}, "mars": {"rms": 0.10, "p99": 0.25},
                      "exo-co2-thick": {"rms": 0.10, "p99": 0.25}}


@pytest.mark.slow
@pytest.mark.parametrize("preset", list(QUICK_VIEW_TARGETS))
@pytest.mark.parametrize("view", list(VIEWS))
def test_every_view_class_of_the_quick_view_against_the_tables(scene_pairs, preset, view):
    # The targets, in the frames of docs/benchmarks.md's quick-view table (320x200, CIE Y, the difference
    # floored at 1% of the frame's 99th percentile, uniform albedo). The standard tables are within 1% of the
    # reference by day on these presets (docs/benchmarks.md), a tenth of the bounds, so the bounds test the quick
    # view. Every figure a view meets is held to its target; a figure in QUICK_VIEW_MISSES that misses it marks the
    # test as an expected failure, and one that meets it fails the test, so that the docs and the list are brought
    # up to date. A known miss must still beat single scattering alone in the same frame (the quick view without
    # the orders above the first, an independent picture of the same view): a table of Psi that adds nothing, or
    # too much, fails there.
    from planetviz.render import Scene
    if preset not in scene_pairs:
        scene_pairs[preset] = tuple(
            Scene(preset, quality="standard", surface=None, off_screen=True, window_size=(320, 200), **keywords)
            for keywords in (dict(shading="pixel"), dict(method="quick"),
                             dict(method="quick", quick_orders="single")))
    tables, quick, single = (view_luminance(scene, VIEWS[view]) for scene in scene_pairs[preset])

    def figures_of(picture):
        difference = floored_difference(picture, tables)
        return {"rms": np.sqrt(np.mean(difference ** 2)), "p99": np.percentile(difference, 99)}
    hold_to_targets(figures_of(quick), QUICK_VIEW_TARGETS[preset], QUICK_VIEW_MISSES.get((preset, view), set()),
                    "docs/benchmarks.md 'Quick view'", ceilings=figures_of(single))
