"""The standard tables against DISORT (PythonicDISORT, ../shared/notes/disort.md) in the plane-parallel limit,
where its 64 streams are exact within 0.3%: large planets and an optically thick, forward-lobed random atmosphere.
A module of its own so that the slow run's two workers can share the tables' slow tests."""
import functools

import numpy as np
import pytest

from planetviz.tables.evaluator import sky_radiance
from planetviz.tables.precompute import QUALITY, precompute


@pytest.mark.parametrize("seed", [1, 4, 5, 8, 100005, 100006, 100014, 100680])
def test_a_random_atmospheres_twin_is_plane_parallel(seed):
    # DISORT's sky is that of a plane-parallel slab; the tables' twin is a sphere of 1e9 m. Its single scattering
    # (reference/single.py, on the sphere, within 1e-11 of 4x its panels) against the same integral over the slab
    # (validation.disort.plane_parallel_single_scattering, checked here against twice its layers), on
    # ground_and_top_views' rays with the sun 30 and 70 deg from the zenith (validation.disort.curvature_error):
    # their difference is the planet's curvature, held to 0.1%, a third of DISORT's own 0.3%, so that the
    # comparison with DISORT does not resolve it. Atmospheres from both splits, the thickest and most opaque among
    # the first of each (random-1 5200 km thick, 100006 13,500 km, 100680 1260 km with an optical depth of 9.9;
    # 100014 a 770 m shell). Kept at their own thickness, 100006's twin read 16.6% off, random-1's 6.8%.
    from planetviz.validation import random_atmosphere
    from planetviz.validation.disort import (curvature_error, ground_and_top_views, plane_parallel_single_scattering,
                                            plane_parallel_twin)
    atm = plane_parallel_twin(random_atmosphere(seed))
    views, _, _ = ground_and_top_views(atm)
    for w in range(atm.n_wavelengths):
        slab = plane_parallel_single_scattering(atm, w, 0.5, views)
        assert np.allclose(plane_parallel_single_scattering(atm, w, 0.5, views, panels=800), slab, rtol=1e-9)
    assert np.max(np.abs(curvature_error(atm))) < 1e-3


@pytest.mark.slow
@pytest.mark.parametrize("aerosol", [False, True])
def test_a_large_planets_sky_meets_the_daylight_target_against_disort(aerosol):
    # Issue 25's daylight target (RMS 1%, p95 3%) for the standard tables of Earth's Rayleigh layer (60 km, ground
    # albedo 0.3), alone and with an absorbing aerosol of g1 = 0.85 (validation.disort.plane_parallel_atmosphere), on
    # a planet of 1e9 m, against DISORT (PythonicDISORT, 64 streams), which is exact here within its own 0.3% (64
    # against 128 streams, ../shared/notes/disort.md) and the planet's curvature (validation.disort.curvature_error:
    # 0.08% at 1e9 m for these views): at the ground looking up and at the top looking down, view zenith 20, 55 and
    # 78 deg x 3 azimuths, the sun 30 and 70 deg from the zenith, 3 wavelengths. With the view-zenith axis on the
    # planet's own geometry (no distance_warp) the Rayleigh sky from the ground reads 2.8% RMS off and from the top
    # 4.5%; with the particles' orders above the first stored over their lobe alone (multiple.forward_factor with
    # s = 1) the aerosol's sky from the ground reads 1.7% RMS, 5.2% at most.
    from planetviz.validation.disort import plane_parallel_atmosphere
    atm = plane_parallel_atmosphere(aerosol, 1e9)
    errors = np.abs(_against_disort(atm)[0])
    assert np.sqrt(np.mean(errors ** 2)) < 0.01
    assert np.percentile(errors, 95) < 0.03


@functools.lru_cache(maxsize=None)
def _random_4_twin(keep=(0, 1, 2), quality="standard"):
    """(atmosphere, its tables at ``quality``): random atmosphere 4 of the tuning split in its plane-parallel limit
    (validation.disort.plane_parallel_twin) with the wavelengths of index in ``keep``. Its 3-wavelength standard
    tables take about 3.5 minutes on one core; the module's tests share them (a module runs on one worker)."""
    from planetviz.validation import random_atmosphere
    from planetviz.validation.disort import only_wavelengths, plane_parallel_twin
    atm = only_wavelengths(plane_parallel_twin(random_atmosphere(4)), list(keep))
    return atm, precompute(atm, QUALITY[quality])


def _against_disort(atm, other=None, tables=None):
    """(the standard tables' relative difference from DISORT's sky of ``atm``, a plane-parallel planet, and that of
    DISORT's sky of the atmosphere ``other`` or None) (2, W, views): the sun 30 and 70 deg from the zenith, the
    wavelengths, the views of ``ground_and_top_views``; ``tables`` are ``atm``'s standard tables (None: computed)."""
    from planetviz.validation.disort import disort_radiance, ground_and_top_views
    tables = precompute(atm, QUALITY["standard"]) if tables is None else tables
    views, cams, dirs = ground_and_top_views(atm)
    errors, others = [], []
    for zenith in (30.0, 70.0):
        theta0 = np.radians(zenith)
        got, _ = sky_radiance(tables, atm, cams, dirs, [np.sin(theta0), 0.0, np.cos(theta0)])
        for w in range(atm.n_wavelengths):
            want = disort_radiance(atm, w, np.cos(theta0), views)
            errors.append(got[:, w] / want - 1.0)
            if other is not None:
                others.append(disort_radiance(other, w, np.cos(theta0), views) / want - 1.0)
    shape = (2, atm.n_wavelengths, -1)
    return np.reshape(errors, shape), np.reshape(others, shape) if others else None


@functools.lru_cache(maxsize=None)
def _random_4_against_disort():
    """:func:`_against_disort` of :func:`_random_4_twin`'s three-wavelength standard tables, with ``other`` the
    same atmosphere with its particles' phase function isotropic: (errors, theirs), each (2, 3, views), computed
    once for the module's tests (about 70 DISORT solves)."""
    atm, tables = _random_4_twin()
    d = atm.to_dict()
    d["mie"] = dict(d["mie"], phase={"g1": [0.0] * 3, "g2": [0.0] * 3, "alpha": [1.0] * 3})
    return _against_disort(atm, type(atm).from_dict(d), tables)


@pytest.mark.slow
def test_an_optically_thick_forward_lobed_sky_against_disort():
    # The daylight target (RMS 1%, p95 3%) on random atmosphere 4 of the tuning split without its absorbing layer,
    # on a planet of 1e9 m: optical depth 1.6 / 2.8 / 4.9 at 680 / 550 / 440 nm, particles that scatter backward at
    # 680 nm and forward (g 0.56-0.65) at the others, ground albedo 0.74-0.94; a 20 km slab. DISORT (64 streams,
    # exact here within its own 0.3%, ../shared/notes/disort.md) at the ground looking up and at the top looking
    # down, the views of ground_and_top_views, the sun 30 and 70 deg from the zenith. With the rays through the
    # thick air split at the 440 nm depth alone (nodes.split_ray_nodes), every view at 550 and 440 nm read 1-2% low
    # (1.22% RMS; the twin then at its own 2300 km). Its independent ceiling: DISORT's own sky with the particles'
    # phase made isotropic, which differs from the lobed one by 12.4% RMS (p95 23%): tables that read further off
    # than dropping the lobes altogether have regressed.
    from conftest import hold_to_targets
    errors, lobe = (np.abs(e) for e in _random_4_against_disort())
    figures = {"rms": np.sqrt(np.mean(errors ** 2)), "p95": np.percentile(errors, 95)}
    ceilings = {"rms": np.sqrt(np.mean(lobe ** 2)), "p95": np.percentile(lobe, 95)}
    hold_to_targets(figures, {"rms": 0.01, "p95": 0.03}, [], "docs/benchmarks.md (random atmosphere 4)", ceilings)


@pytest.mark.slow
def test_a_forward_lobe_in_optically_thick_air_meets_the_daylight_target_against_disort():
    # The daylight target (RMS 1%, p95 3%) where a moderate forward lobe shapes the multiply scattered light though
    # the particles hold under half the scattering: random atmosphere 4's 440 nm channel in its plane-parallel
    # limit (optical depth 4.9; the particles' scattering optical depth 2.4, their share 0.47, g1 = 0.56 with weight
    # 0.52), against DISORT (exact within its own 0.3%), the views and suns of _against_disort. With the
    # multiple-scattering tables' 4 nu and 32 mu_s texels (precompute.sizes_for without its thick_forward_lobe
    # rule) it read 3.4% RMS (p95 6.2%), every view low, from the ground 5-7% with the sun 70 deg from the zenith
    # (the twin then at its own 2300 km).
    errors = np.abs(_random_4_against_disort()[0][:, 2])
    assert np.sqrt(np.mean(errors ** 2)) < 0.01
    assert np.percentile(errors, 95) < 0.03


@pytest.mark.slow
def test_a_wavelengths_sky_does_not_depend_on_the_other_wavelengths():
    # The wavelengths of a table scatter independently: random atmosphere 4's plane-parallel sky at 550 nm (optical
    # depth 2.8) computed with its 680 nm (1.6) and 440 nm (4.9) channels must read as computed alone, the views of
    # ground_and_top_views with the sun 30 and 70 deg from the zenith; draft tables, since what couples the
    # channels does not depend on the level: where the rays through the optically thick air are split
    # (nodes.split_ray_nodes). The bound is the tables' own quadrature error along the rays: computed alone, the
    # sky moves by at most 0.36% with 4 times the nodes at the standard level, 0.04% at draft. Split at the 440 nm
    # depth alone (two segments of as many nodes), it read 1.3% low on average at standard, up to 1.7%, and 1.2%
    # low, up to 1.6%, at draft; on the five segments of thick atmospheres, at most 0.075% at draft (the twin then
    # at its own 2300 km).
    from planetviz.validation.disort import ground_and_top_views

    def sky(atm, tables, w):
        _, cams, dirs = ground_and_top_views(atm)
        return np.array([sky_radiance(tables, atm, cams, dirs, [np.sin(z), 0.0, np.cos(z)])[0][:, w]
                         for z in np.radians([30.0, 70.0])])

    alone, with_others = sky(*_random_4_twin((1,), "draft"), 0), sky(*_random_4_twin(quality="draft"), 1)
    assert np.max(np.abs(with_others / alone - 1.0)) < 0.005


@pytest.mark.slow
def test_the_sky_under_an_optical_depth_of_ten_meets_the_daylight_target_from_the_ground():
    # Random atmosphere 942 of the tuning split, its 440 nm channel in the plane-parallel limit: optical depth 9.8
    # (Rayleigh 6.7, particles 3.1), single-scattering albedo 0.95, so about twenty orders make the light seen from
    # the ground and each is read from the last one's scattering density. Against DISORT (exact within its own 0.3%,
    # ../shared/notes/disort.md; the twin's curvature under 0.1%), the views and suns of _against_disort: the mean
    # difference from the ground looking up within 0.7%, the daylight target (1%) less DISORT's error, and the
    # target's RMS over every view. With the density read linearly between its own rows (multiple.density_read_rows
    # returning them) it read +1.21% from the ground, geometrically -1.01%: the interpolation's error, compounded
    # over the orders.
    from planetviz.validation import random_atmosphere
    from planetviz.validation.disort import only_wavelengths, plane_parallel_twin
    atm = only_wavelengths(plane_parallel_twin(random_atmosphere(942)), [2])
    errors = _against_disort(atm)[0]
    assert abs(np.mean(errors[..., 0::2])) < 0.007
    assert np.sqrt(np.mean(errors ** 2)) < 0.01


@pytest.mark.slow
def test_a_forward_lobe_under_thick_molecular_scattering_meets_the_daylight_target_against_disort():
    # The daylight target (RMS 1%, p95 3%) where molecules hold most of a thick scattering and a forward lobe in
    # the rest still shapes the multiply scattered light: random atmosphere 809's 440 nm channel in its
    # plane-parallel limit (scattering optical depth 3.4, the particles' forward factor F(1) / F(-1) = 5.7; neither
    # the particles' share nor their own depth reaches the other clauses of precompute.sizes_for), against DISORT
    # (exact within its own 0.3%, ../shared/notes/disort.md; the twin's curvature under 0.1%), the views and suns
    # of _against_disort. With the multiple-scattering tables' 4 nu and 32 mu_s texels (sizes_for without its
    # thick_forward_range rule) it read 3.61% RMS, low from the ground, to -6.6% with the sun 70 deg from the zenith.
    from planetviz.validation import random_atmosphere
    from planetviz.validation.disort import only_wavelengths, plane_parallel_twin
    atm = only_wavelengths(plane_parallel_twin(random_atmosphere(809)), [2])
    errors = np.abs(_against_disort(atm)[0])
    assert np.sqrt(np.mean(errors ** 2)) < 0.01
    assert np.percentile(errors, 95) < 0.03
