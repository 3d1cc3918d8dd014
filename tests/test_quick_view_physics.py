"""The quick-view integrator (Keller and Bohn) in NumPy: against the deterministic single-scattering integral."""
import subprocess
import sys

import numpy as np
import pytest

from planetviz import load_atmosphere
from planetviz.quick_view.single_scattering import ground_sample_edges, quick_view_radiance, sample_fractions
from planetviz.reference import single_scattering

EARTH = load_atmosphere("earth")
R = EARTH.bottom_radius_m


def rays():
    """Ground, aircraft and space cameras; views up, along the horizon, down; sun 30 deg high."""
    cams = np.array([[0, 0, R + 2.0]] * 4 + [[0, 0, R + 1e4]] * 3 + [[0, 0, 3 * R]] * 3)
    views = np.array([[0, 0, 1], [0.8, 0, 0.6], [0, 1, 0.05], [-0.9, 0.3, 0.3], [1, 0, 0], [0, 1, -0.2],
                      [0.3, 0, -1], [0, 0, -1], [0.3, 0, -1], [0, 0.3, -1]], float)
    return cams, views / np.linalg.norm(views, axis=1, keepdims=True), np.array([0.5, 0.0, 0.866])


def test_sample_fractions_cover_the_path_and_crowd_its_start():
    mid, width = sample_fractions(4, 3.0)
    assert np.isclose(width.sum(), 1.0)
    assert np.allclose(mid, [(0 + 1 / 64) / 2, (1 / 64 + 8 / 64) / 2, (8 / 64 + 27 / 64) / 2, (27 / 64 + 1) / 2])


def test_converges_to_the_single_scattering_integral():
    # Independent check: reference.single_scattering integrates the same single-scattering equation with
    # 48-panel Gauss-Legendre quadrature and exact optical depths. With 32 points on every path the midpoint
    # rule on (i/n)^3 must agree to 1% (measured 0.2% RMS on the benchmark's rays) and with 4 points it must
    # not (measured 14%): the test fails for a wrong integrand and for a rule that does not converge.
    cams, views, sun = rays()
    a, g = single_scattering(EARTH, cams, views, sun, panels=48)
    ref = a + g
    fine, _ = quick_view_radiance(EARTH, cams, views, sun, samples=32, density_samples=32)
    coarse, _ = quick_view_radiance(EARTH, cams, views, sun, samples=4, density_samples=4)
    assert np.max(np.abs(fine - ref) / ref) < 0.01
    assert np.max(np.abs(coarse - ref) / ref) > 0.02


def test_ground_edges_cover_the_path_and_crowd_both_ends():
    edges = ground_sample_edges(4, 3.0)
    assert np.allclose(edges, [0, 0.5 / 8, 0.5, 1 - 0.5 / 8, 1])
    assert np.allclose(ground_sample_edges(1, 3.0), [0, 1])


def test_a_ray_from_space_into_a_thick_atmosphere_at_the_default_points():
    # The 10-bar planet (vertical optical depth 0.7 / 1.7 / 4.1) seen from 3 radii: the disc's centre and two rays
    # toward its edge. Independent check: reference.single_scattering (48-panel Gauss-Legendre, exact optical
    # depths; 96 panels change it by under 1e-5). The bound is the quick view's target in the Earth's views (5%):
    # points crowded at the top of the atmosphere alone, where a ray from space starts, read 6-14% high.
    atm = load_atmosphere("exo-co2-thick")
    r = atm.bottom_radius_m
    tilt = np.radians([0.0, 10.0, 17.0])
    cams = np.tile([0.0, 0.0, 3 * r], (3, 1))
    views = np.stack([np.sin(tilt), 0 * tilt, -np.cos(tilt)], -1)
    sun = np.array([0.5, 0.0, 0.866])
    a, g = single_scattering(atm, cams, views, sun, panels=48)
    got, _ = quick_view_radiance(atm, cams, views, sun)
    assert np.max(np.abs(got / (a + g) - 1.0)) < 0.05


def test_power_sampling_beats_equidistant_at_equal_cost():
    # The paper's claim (Sect. 6), measured here for 8 points on every path on the rays above.
    cams, views, sun = rays()
    a, g = single_scattering(EARTH, cams, views, sun, panels=48)
    ref = a + g
    err = {}
    for sampling in ("power", "equidistant"):
        L, _ = quick_view_radiance(EARTH, cams, views, sun, samples=8, density_samples=8, sampling=sampling)
        err[sampling] = np.sqrt(np.mean(((L - ref) / ref) ** 2))
    assert err["power"] < 0.5 * err["equidistant"], err


def test_transmittance_and_space():
    # A ray from space that misses the atmosphere sees nothing and keeps T = 1; one that crosses it has the
    # transmittance of the whole chord (exact for an exponential atmosphere through the centre: up and down).
    cams = np.array([[0, 0, 10 * R], [0, 0, 10 * R]])
    views = np.array([[1.0, 0, 0], [0, 0, -1.0]])
    L, T = quick_view_radiance(EARTH, cams, views, [0, 0, 1.0], samples=64, density_samples=64)
    assert np.all(L[0] == 0) and np.all(T[0] == 1)
    tau = EARTH.vertical_optical_depth()
    assert np.allclose(T[1], np.exp(-tau), rtol=2e-3)


def test_artistic_terms_follow_table_1():
    # Table 1 of Keller and Bohn: molecular scattering scaled by (lambda_red / lambda)^4 from the longest
    # wavelength, so the artistic and physical coefficients agree at the red end only.
    from planetviz.quick_view.single_scattering import coefficients
    b_r, b_m, _ = coefficients(EARTH, "artistic")
    wl = np.asarray(EARTH.wavelengths_nm)
    assert np.isclose(b_r[0], EARTH.rayleigh.scattering_m[0])
    assert np.allclose(b_r / b_r[0], (wl[0] / wl) ** 4)
    assert np.allclose(b_m / b_m[0], (wl[0] / wl) ** 2)
    cams, views, sun = rays()
    L, _ = quick_view_radiance(EARTH, cams, views, sun, samples=8, terms="artistic")
    assert np.all(np.isfinite(L)) and np.all(L >= 0)


@pytest.mark.parametrize("kwargs, word", [({"samples": 0}, "samples"), ({"sampling": "cubic"}, "sampling"),
                                          ({"terms": "pretty"}, "terms")])
def test_bad_settings_are_refused_by_name(kwargs, word):
    cams, views, sun = rays()
    with pytest.raises(ValueError, match=word):
        quick_view_radiance(EARTH, cams, views, sun, **kwargs)


def test_quick_view_command(tmp_path):
    cams, views, sun = rays()
    q, out = tmp_path / "q.npz", tmp_path / "o.npz"
    np.savez(q, camera_m=cams, view_dir=views, sun_dir=sun)
    proc = subprocess.run([sys.executable, "-m", "planetviz", "radiance", "--atmosphere", "earth", "--queries", q,
                           "--out", out, "--method", "quick", "--samples", "12"], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    with np.load(out) as f:
        # The command re-normalises the directions (a 1e-4 change); 12 points, not the default 20.
        assert np.allclose(f["radiance"], quick_view_radiance(EARTH, cams, views, sun, samples=12)[0], rtol=1e-3)
        assert not np.allclose(f["radiance"], quick_view_radiance(EARTH, cams, views, sun)[0], rtol=1e-3)
