"""Numerical stability under stress: generated cameras, views and suns anywhere the API
accepts them, plus the fixed worst cases, for the table evaluator, the quick-view integrator and the reference
solver.

Two hypothesis profiles: the default run draws ``FAST`` examples per property; ``pytest -m slow`` (CI runs it
too) repeats the properties with ``LONG`` examples. Counts and findings: docs/stability.md.
"""
import re

import numpy as np
import pytest
from conftest import check_finite_and_bounded, distances_along, draft_earth_tables, transmittance_along
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from planetviz import load_atmosphere
from planetviz.model.geometry import ray_sphere
from planetviz.quick_view.single_scattering import quick_view_radiance
from planetviz.reference import optical_depth, solve
from planetviz.reference.single import single_scattering
from planetviz.tables.evaluator import sky_radiance

EARTH = load_atmosphere("earth")
R, TOP = EARTH.bottom_radius_m, EARTH.top_radius_m
TABLES = draft_earth_tables()
FAST, LONG = 100, 3000

altitudes = st.floats(-3.0, 12.0).map(lambda e: 10.0 ** e)             # 1 mm above the ground to 1e12 m
unit = st.tuples(*[st.floats(-1.0, 1.0)] * 3).filter(lambda v: np.linalg.norm(v) > 1e-3) \
    .map(lambda v: np.asarray(v) / np.linalg.norm(v))


def _camera(alt, direction):
    return direction * (R + alt)


def _both(cams, views, sun):
    for f in (lambda: sky_radiance(TABLES, EARTH, cams, views, sun),
              lambda: quick_view_radiance(EARTH, cams, views, sun, samples=6)):
        yield f()


def random_rays(n_examples):
    @settings(max_examples=n_examples, deadline=None, suppress_health_check=[HealthCheck.too_slow])
    @given(alt=altitudes, up=unit, view=unit, sun=unit, special=st.sampled_from(["random", "sun", "anti-sun"]))
    def check(alt, up, view, sun, special):
        cam = _camera(alt, up)
        if special == "sun":
            sun = view
        elif special == "anti-sun":
            sun = -view
        for radiance, transmittance in _both(cam[None], view[None], sun):
            check_finite_and_bounded(radiance, transmittance)
    return check


test_random_rays_give_finite_non_negative_radiance = random_rays(FAST)
test_random_rays_long = pytest.mark.slow(random_rays(LONG))


def _aimed(r, up, other, kind):
    """A view from radius ``r`` (unit ``up``): along ``other`` (made unit), or exactly tangent to the ground or to
    the top of the atmosphere (where the camera is outside that sphere), or straight up or down."""
    if kind in ("up", "down"):
        return up if kind == "up" else -up
    side = other - (other @ up) * up
    if np.linalg.norm(side) < 1e-6:
        side = np.cross(up, [1.0, 0.0, 0.0] if abs(up[0]) < 0.9 else [0.0, 1.0, 0.0])
    side /= np.linalg.norm(side)
    radius = {"tangent to the ground": R, "tangent to the top": TOP}.get(kind)
    if radius is None or r <= radius:
        return other
    mu = -np.sqrt(1.0 - (radius / r) ** 2)
    return mu * up + np.sqrt(1.0 - mu * mu) * side


def reference_rays(n_examples):
    @settings(max_examples=n_examples, deadline=None, suppress_health_check=[HealthCheck.too_slow])
    @given(alt=altitudes, up=unit, view=unit, sun=unit,
           kind=st.sampled_from(["random", "tangent to the ground", "tangent to the top", "up", "down"]),
           special=st.sampled_from(["random", "sun", "anti-sun", "zenith", "horizon", "behind the planet"]))
    @example(alt=1.0, up=np.array([0.0, -1.0, 0.0]), view=np.array([1.0, 0.0, 0.0]),
             sun=np.array([0.9701425, 0.24253563, 0.0]), kind="random", special="random")
    # CI's long run: a ray tangent to the ground read as hitting it by the quadrature and as missing it by the
    # Monte Carlo solver (0.088 against 0.036 at 440 nm), which normalised the direction again and so changed
    # its last bit; both normalise alike now (1.4% of tangent rays flipped)
    @example(alt=1.0, up=np.array([-0.6873966272441575, -0.5950153185186051, 0.4164644613668252]),
             view=np.array([-0.10708092147336722, 2.914125888022547, 0.926342075423221]),
             sun=np.array([0.0, 0.0, 1.0]), kind="tangent to the ground", special="zenith")
    @example(alt=10.0 ** 6.25, up=np.array([2.0, 0.0, 1.0]) / np.sqrt(5.0), view=np.array([1.0, 0.0, 0.0]),
             sun=np.array([0.0, 0.0, -1.0]), kind="tangent to the ground", special="random")
    @example(alt=1.0, up=np.array([-0.29774567, 0.05954913, 0.95278613]), view=np.array([0.0, 1.0, 0.0]),
             sun=np.array([0.6, 0.8, 0.0]), kind="random", special="random")
    # A run of the default suite: a ray tangent to the top of the atmosphere from 908 km read 8.4e-5 by the Monte
    # Carlo solver against 1.1e-18 by the quadrature: from its entry point on the top sphere its exit was put 51,000
    # km away (model/geometry.ray_sphere's far root, c / q with q ~ 1e-10 m), through air above the top
    @example(alt=907520.7719057648, up=np.array([0.03289467664147788, 0.9837605262161956, 0.17644593309987777]),
             view=np.array([-0.4329923716276989, 0.0, -0.9013975849269958]), sun=np.array([0.0, 0.0, -1.0]),
             kind="tangent to the top", special="random")
    @example(alt=1641178.2339246783, up=np.array([0.70710325, 0.0, 0.70711032]), view=np.array([1.0, 0.0, 0.0]),
             sun=np.array([1.0, 0.0, 0.0]), kind="tangent to the ground", special="sun")
    def check(alt, up, view, sun, kind, special):
        # The reference solver anywhere: its Monte Carlo estimate (single scattering and the directly lit ground
        # only) against the deterministic single-scattering quadrature of reference/single.py, two independent
        # computations of the same integral. Bound: 5 standard errors of the estimate (a false alarm once in
        # ~1e6 draws per wavelength) plus 1e-3 relative (the quadratures' own errors, under 1e-4) plus 1e-5
        # absolute (1/1000 of a daylight sky): an estimate whose paths all scattered where the sun does not
        # reach has no variance to report; found by CI's long run (kept below): 1 m up along the horizon, the
        # sun 14 deg below it, single scattering 2.3e-6 from air lit hundreds of km away, and none of the 1024
        # paths scattered there. Radiance finite and >= 0, view transmittance in [0, 1].
        r = R + alt
        view = _aimed(r, up, view, kind)
        sun = {"sun": view, "anti-sun": -view, "zenith": up, "behind the planet": -up,
               "horizon": sun - (sun @ up) * up}.get(special, sun)
        if np.linalg.norm(sun) < 1e-6:
            return
        if kind == "tangent to the ground" and special in ("sun", "anti-sun"):
            # The sun along a tangent view is tangent at every point of the path, each point's shadow settled by
            # its own last bit (CI's long run: 337 km up, the estimate 0.041 between the lit 0.056 and the dark
            # 0). Tilted up by an angle a, the sun's ray from a point s before the tangent point clears it by
            # about a s, so a view that dips d below the tangent point leaves the last d / a of its path in shadow:
            # with a = 1e-6 rad the view tilted 1e-9 rad down (4 mm at 4400 km) lost 5 km of its densest air, 4%
            # of the radiance (CI's long run, 1641 km up: 0.02812 +- 0.00007 against 0.02696); with a = 1e-4 rad
            # that shadow is 50 m, under 0.1%.
            sun = sun + 1e-4 * up
        sun = sun / np.linalg.norm(sun)
        mc = solve(EARTH, [r * up], [view], sun, samples=1024, seed=1, max_order=1, single="paths")
        scatter, ground = single_scattering(EARTH, [r * up], [view], sun)
        exact = scatter + ground
        check_finite_and_bounded(mc.radiance, mc.transmittance)
        check_finite_and_bounded(exact, mc.transmittance)
        # A ray exactly tangent to the ground touches it or not by the last bit of the arithmetic, and the two
        # solvers' array shapes round differently (CI's long run: from 1.8e6 m, 0.223 against 0.183 at 680 nm,
        # the quadrature stopping at the tangent point): there the estimate must match the quadrature of the ray
        # 1e-9 rad above (5 mm clear of the ground) or below (into it), one side or the other.
        sides = [exact]
        if kind == "tangent to the ground" and r > R:
            sides += [sum(single_scattering(EARTH, [r * up], [view + tilt * up], sun)) for tilt in (1e-9, -1e-9)]
        # Compared where the estimate resolves its value (relative standard error under 25%): in twilight a few
        # of the 1024 paths carry all of it and the sample standard error itself is unreliable (CI's long run:
        # 1 m up, the sun 7.5 deg below the horizon, 1.8e-5 +- 0.6e-5 against 6.1e-5 at 550 nm).
        resolved = mc.stderr < 0.25 * mc.radiance
        assert any(np.all((np.abs(mc.radiance - e) <= 5 * mc.stderr + 1e-3 * e + 1e-5) | ~resolved) for e in sides), \
            (mc.radiance, mc.stderr, sides)
    return check


test_reference_solver_under_generated_input = reference_rays(20)
test_reference_solver_under_generated_input_long = pytest.mark.slow(reference_rays(300))


def worst_cases():
    """Cameras on the ground, 1 mm above it, exactly at the top, just inside and outside it, 1e12 m away; views
    up, down, along the horizon (tangent to the ground) and tangent to the top; the sun at the zenith, on the
    horizon, behind the planet, along the view and against it."""
    ez, ex = np.array([0.0, 0.0, 1.0]), np.array([1.0, 0.0, 0.0])
    cams, views, suns = [], [], []
    for alt in (0.0, 1e-3, 2.0, TOP - R - 1.0, TOP - R, TOP - R + 1.0, 1e7, 1e12):
        r = R + alt
        cam = r * ez
        dip = np.arccos(min(R / r, 1.0))
        top_dip = np.arccos(min(TOP / r, 1.0)) if r > TOP else 0.0
        for view in (ez, -ez, np.cos(dip) * ex - np.sin(dip) * ez, np.cos(top_dip) * ex - np.sin(top_dip) * ez, ex):
            for sun in (ez, ex, -ez, view, -view):
                cams.append(cam)
                views.append(view)
                suns.append(sun)
    return np.array(cams), np.array(views), np.array(suns)


def test_fixed_worst_cases():
    cams, views, suns = worst_cases()
    for radiance, transmittance in _both(cams, views, suns):
        check_finite_and_bounded(radiance, transmittance)


@settings(max_examples=FAST, deadline=None)
@given(up=unit, side=unit, radius=st.sampled_from([R, TOP, 1e9]))
def test_a_ray_tangent_to_a_sphere_from_a_point_on_it_stays_there(up, side, radius):
    # From a point on the sphere (its radius known to a few ulp) along the sphere's tangent plane, the chord is
    # 0 analytically: both roots within 1e-7 of the radius, the rounding of the half chord sqrt(disc) (disc =
    # R^2 - |perp|^2 carries a few ulp of R^2, 4 ulp giving 3e-8 R) and of the clip around it (1e-9 R); the
    # ray the reference solver traced 51,000 km past the top came from such a root.
    tangent = side - (side @ up) * up
    if np.linalg.norm(tangent) < 1e-3:
        return
    t0, t1 = ray_sphere(radius * up, tangent / np.linalg.norm(tangent), radius)
    assert not np.isfinite(t0) or (abs(t0) <= 1e-7 * radius and abs(t1) <= 1e-7 * radius), (t0, t1)


def continuity(n_examples):
    @settings(max_examples=n_examples, deadline=None)
    @given(up=unit, view=unit, sun=unit)
    def check(up, view, sun):
        # A camera crossing the top of the atmosphere along its view ray, 1 m outside then 1 m inside, sees the
        # same ray (less 1 m of the thinnest air): relative change under 0.1% (the bound; measured at
        # most 2.1e-4 over 9890 rays). Found on the first run: comparing cameras 1 m above and below the top with the same
        # direction moves oblique rays 2 m sideways, a real change of up to 0.2% (low aerosol, 1.2 km scale
        # height) and of 100% for rays grazing the top; only the camera's crossing is the renderer's business.
        if up @ view > -0.01:
            return                                   # a ray that does not enter the atmosphere here
        entry = up * TOP
        outside, inside = entry - view, entry + view
        a, _ = sky_radiance(TABLES, EARTH, np.array([outside, inside]), np.array([view, view]), sun)
        lit = a[0] > 1e-6
        assert np.all(np.abs(a[0] - a[1])[lit] <= 1e-3 * a[0][lit]), (a, up @ view)
    return check


test_radiance_is_continuous_across_the_top = continuity(FAST)
test_radiance_is_continuous_across_the_top_long = pytest.mark.slow(continuity(LONG))


@settings(max_examples=FAST, deadline=None)
@given(alt=st.one_of(st.just(0.0), st.floats(1e-3, 59e3)), mu=st.floats(-1.0, 1.0))
@example(alt=50406.0, mu=-0.125)
@example(alt=0.5, mu=-0.001953125)
def test_transmittance_never_increases_along_a_ray(alt, mu):
    # T(x, x + d v) from the tables for growing d, up to where the ray leaves the atmosphere or meets the ground.
    # Cameras on the ground or from 1 mm up: the radius of a point 1e-7 m above the Earth's ground is known to
    # ulp(R) = 9.3e-10 m, and the tables' coordinate rho = sqrt(2 R h) moves by 0.4% per ulp there (CI's
    # falsifying example, 1.2e-7 m up looking 6e-5 below the horizontal at the ground 2 mm away: T rose by 8e-10).
    # lookup.get_optical_depth reads rays that point up only (its docstring says why); the bound is float64
    # rounding of tau (< 1e-15 relative, tau < 40 here). Found by CI's run of the earlier form (50 km,
    # mu = -0.125, kept above as an example): Bruneton's tau(r, mu) - tau(r_d, mu_d) for rays that pass their
    # lowest point rose by up to 0.4% with these draft tables (0.15% at standard) on rays from 40-60 km looking
    # 2-7 deg down; it fails this test at 2e-3. With the new form a rise remains only within the tables' own error
    # against the exact optical depth (reference.optical_depth, relative error 1e-9 here): CI's falsifying
    # example 0.5 m up looking 0.11 deg down, where the last step to the ground read T 2.3e-5 higher at 550 nm
    # and the draft tables' T is 9.3e-4 off at those points (two readings of grazing rays from the ground whose
    # optical depths, 10-40, differ by the segment's 0.003). Bound: float64 rounding plus the larger of the two
    # points' errors against the exact T: a rise the tables' accuracy there does not explain fails.
    t = transmittance_along(TABLES, alt, mu)
    assert np.all((t >= 0) & (t <= 1))
    r, d = distances_along(TABLES, alt, mu, len(t))
    x = np.tile([0.0, 0.0, r], (len(d), 1))
    v = np.tile([np.sqrt(1.0 - mu * mu), 0.0, mu], (len(d), 1))
    error = np.abs(t - np.exp(-optical_depth(EARTH, x, v, d)))
    assert np.all(np.diff(t, axis=0) <= 1e-13 + np.maximum(error[1:], error[:-1]))


@pytest.mark.parametrize("camera, view, sun, word", [
    ([[0, 0, R + 2.0]], [[0, 0, 0.0]], [0, 0, 1.0], "view_dir[0]: zero vector"),
    ([[0, 0, R + 2.0]], [[np.nan, 0, 1.0]], [0, 0, 1.0], "view_dir[0]: contains NaN"),
    ([[0, 0, R - 10.0]], [[0, 0, 1.0]], [0, 0, 1.0], "camera_m[0]: 10 m below the ground"),
    ([[0, 0, R + 2.0], [0, 0, R + 3.0]], [[0, 0, 1.0]] * 3, [0, 0, 1.0], "view_dir: shape (3, 3)"),
    ([[0, 0, R + 2.0]], [[0, 0, 1.0]], [np.inf, 0, 0], "sun_dir[0]: contains NaN or inf"),
])
def test_bad_queries_are_refused_by_name(camera, view, sun, word):
    for f in (lambda: sky_radiance(TABLES, EARTH, camera, view, sun),
              lambda: quick_view_radiance(EARTH, camera, view, sun)):
        with pytest.raises(ValueError, match=re.escape(word)):
            f()
