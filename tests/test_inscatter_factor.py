"""The small tables of the per-vertex renderer's inscatter factor (planetviz/tables/inscatter_factor.py, read by
shaders/inscatter_factor.glsl): read as the GPU reads them (linear interpolation between texel centres), each
against the function it tabulates, computed directly.

The factor multiplies every pixel of the per-vertex picture, whose target is 1% RMS from the per-pixel picture
(docs/rendering.md); the tables are bounded at 0.3%, a third of that. A wrong mapping between a ray and its texel
reads another ray's value: tens of percent near the horizon or the sun."""
import dataclasses

import numpy as np
import pytest

from conftest import draft_earth_tables
from planetviz import load_atmosphere
from planetviz.reference.optical_depth import optical_depth
from planetviz.tables import QUALITY, precompute
from planetviz.tables.inscatter_factor import (IRRADIANCE_SUBROWS, PATH_OPACITY_TEXELS, PHASE_FACTOR_TEXELS,
                                               SCATTERING_SHARE_NODES, SHARE_ALTITUDE_STEP,
                                               irradiance_row_index, irradiance_rows, path_opacity_altitude,
                                               path_opacity_rays, path_opacity_table, path_opacity_u,
                                               path_scattering_share, phase_factor_table, phase_factor_u,
                                               share_holds, sky_irradiance_rows)
from planetviz.tables.lookup import (get_irradiance, get_optical_depth, get_optical_depth_to_top_atmosphere_boundary,
                                     one_minus_exp, ray_opacity)
from planetviz.tables.parameterization import MU_S_MIN
from planetviz.tables.multiple import forward_factor
from planetviz.tables.nodes import altitude, ray_nodes, scattering_share
from planetviz.tables.precompute import transmittance_rays
from planetviz.tables.parameterization import (distance_to_bottom_atmosphere_boundary,
                                               distance_to_top_atmosphere_boundary, ray_intersects_ground)
from planetviz.validation.random_suite import random_atmosphere

TOLERANCE = 3e-3


def read_linear(table, u):
    """``table`` (n, ...) read at coordinates u in [0, 1] with linear filtering between texel centres, clamped."""
    x = np.asarray(u) * len(table) - 0.5
    i = np.clip(np.floor(x).astype(int), 0, len(table) - 2)
    f = np.clip(x - i, 0.0, 1.0).reshape(x.shape + (1,) * (table.ndim - 1))
    return table[i] * (1.0 - f) + table[i + 1] * f


def direct_opacity(t, a, mu):
    """1 - T of the rays (a, mu) to the ground or the top from the 2D optical-depth table (what the shaders read
    before this table), and whether each meets the ground."""
    r = np.full(mu.shape, t.bottom + a)
    ground = ray_intersects_ground(r, mu, t.bottom)
    d = distance_to_bottom_atmosphere_boundary(r, mu, t.bottom)
    tau = np.where(ground[:, None], get_optical_depth(t, r, mu, d),
                   get_optical_depth_to_top_atmosphere_boundary(t, r, np.where(ground, 0.0, mu)))
    return one_minus_exp(tau), ground


def integrated_opacity(atm, a, mu, ground):
    """1 - T of the same rays by the reference's quadrature of the extinction along them (relative error of tau
    1e-9 to 3.5e-5, planetviz/reference/optical_depth.py)."""
    r = atm.bottom_radius_m + a
    origin = np.broadcast_to([0.0, 0.0, r], mu.shape + (3,))
    direction = np.stack([np.sqrt(1.0 - mu * mu), np.zeros_like(mu), mu], axis=-1)
    length = np.where(ground, distance_to_bottom_atmosphere_boundary(r, mu, atm.bottom_radius_m), np.inf)
    return one_minus_exp(optical_depth(atm, origin, direction, length, panels=16))


def opacity_tables():
    atm = load_atmosphere("earth")
    yield "earth", atm, draft_earth_tables()
    for seed in (3, 100_004):        # one atmosphere of each split of the random suite
        atm = random_atmosphere(seed)
        yield f"random-{seed}", atm, precompute(atm, QUALITY["draft"], multiple=False)


@pytest.mark.parametrize("fraction", [0.0, 1e-4, 0.02, 0.3, 0.999, 1.0, 3.0])
def test_the_path_opacity_table_reads_as_the_opacity_of_each_ray(fraction):
    # From the ground, 1e-4 of the thickness (6 m for the Earth), 2%, 30%, just under the top, at the top and from
    # space (the rays start at the top), over every mu, with 4000 more next to the horizon where it changes
    # fastest. At its texel centres the table holds the 2D table's readings (path_opacity_u is the inverse of
    # path_opacity_rays); between them it interpolates, which against the quadrature of the extinction along each
    # ray can be off by no more than the readings at the two neighbouring centres are, plus the interpolation's own
    # error (TOLERANCE). The 2D table's readings themselves are off by up to 2.5x for rays metres long from metres
    # up (get_optical_depth's docstring), which the table inherits but does not add to.
    for name, atm, t in opacity_tables():
        a = path_opacity_altitude(fraction * (t.top - t.bottom), t.bottom, t.top)
        table = path_opacity_table(t, a)
        n = PATH_OPACITY_TEXELS
        assert table.shape == (2 * n, t.optical_depth.shape[-1])
        centre_mu, _, centre_ground = path_opacity_rays(a, t.bottom, t.top)
        u = path_opacity_u(a, centre_mu, centre_ground, t.bottom, t.top)
        # (from the ground itself, a = 0, every ray down has length 0: the ground half is one value; the ray
        # tangent to the ground, texel 0, has a length ill-conditioned in mu: 1/50 of a texel)
        half = slice(n if a == 0 else 0, 2 * n)
        np.testing.assert_allclose((u * 2 * n - 0.5)[half], np.arange(2 * n)[half], atol=0.02)
        centre_error = np.abs(table - integrated_opacity(atm, a, centre_mu, centre_ground))

        horizon = -np.sqrt(a * (a + 2 * t.bottom)) / (t.bottom + a)
        mu = np.clip(np.concatenate([np.linspace(-1, 1, 4001), horizon + np.linspace(-0.02, 0.02, 4001)]), -1, 1)
        _, ground = direct_opacity(t, a, mu)
        truth = integrated_opacity(atm, a, mu, ground)
        u = path_opacity_u(a, mu, ground, t.bottom, t.top)
        got = read_linear(table, u)
        i = np.clip(np.floor(u * 2 * n - 0.5).astype(int), 0, 2 * n - 2)
        bound = np.maximum(centre_error[i], centre_error[i + 1]) + TOLERANCE * truth
        worst = np.argmax(np.abs(got - truth) - bound) // truth.shape[1]
        assert np.all(np.abs(got - truth) <= bound), (name, a, mu[worst], got[worst], truth[worst], bound[worst])


def test_the_halves_of_the_path_opacity_table_meet_at_the_horizon():
    # Rays just below the horizon read the ground half, just above it the sky half: u falls on either side of 1/2,
    # and the two readings differ (a ray to the ground against one that grazes it and goes on).
    t = draft_earth_tables()
    a = 1e4
    horizon = -np.sqrt(a * (a + 2 * t.bottom)) / (t.bottom + a)
    mu = np.array([horizon - 1e-6, horizon + 1e-6])
    r = np.full(2, t.bottom + a)
    ground = ray_intersects_ground(r, mu, t.bottom)
    assert ground.tolist() == [True, False]
    u = path_opacity_u(a, mu, ground, t.bottom, t.top)
    assert u[0] < 0.5 < u[1]
    table = path_opacity_table(t, a)
    assert not np.allclose(read_linear(table, u)[0], read_linear(table, u)[1], rtol=0.1)


@pytest.mark.parametrize("g1, g2, alpha", [(0.95, 0.0, 1.0), (0.2, 0.95, 0.1), (-0.95, 0.6, 0.5), (0.0, 0.0, 1.0),
                                           (0.86, -0.71, 0.95)])
def test_the_phase_table_reads_as_the_phase_functions(g1, g2, alpha):
    # The format's strongest lobes (|g| up to 0.95) in either component, backward, isotropic, Mars's dust; the
    # molecules' phase and 1 (the orders above the first by molecules) beside them.
    earth = load_atmosphere("earth")
    w = earth.n_wavelengths
    atm = dataclasses.replace(earth, mie=dataclasses.replace(earth.mie, g1=(g1,) * w, g2=(g2,) * w,
                                                              alpha=(alpha,) * w))
    table = phase_factor_table(atm)
    assert table.shape == (PHASE_FACTOR_TEXELS, w, 4)
    nu = np.cos(np.linspace(0.0, np.pi, 100001))
    got = read_linear(table, phase_factor_u(nu))
    mie = atm.mie.phase_function(nu)
    want = np.stack([np.broadcast_to(atm.rayleigh.phase_function(nu)[:, None], mie.shape), mie, np.ones_like(mie),
                     forward_factor(atm, nu)], axis=-1)
    err = np.abs(got / want - 1.0)
    assert err.max() < TOLERANCE, err.max()


@pytest.mark.parametrize("quality", ["draft", "standard"])
def test_the_sky_irradiance_rows_read_as_the_irradiance_table(quality):
    # The rows of the factor texture read linearly (the GPU's filtering) against get_irradiance, which the
    # vertices' ground light uses. Above the first texel with the sun up both are the table's linear reading
    # (the rows are its texels): equal. Below, the table is read geometrically, an exponential between two texels
    # changing by q, and linear interpolation between rows 1/IRRADIANCE_SUBROWS of a texel apart, an exponential
    # step of a = ln q / SUBROWS, overestimates it by at most (e^a - 1) / a e^(-a x) - 1 at x = 1/a - 1/(e^a - 1),
    # q the steepest step of the table's texels there. Relative, floored at 1e-9 of the largest irradiance (the
    # table falls to 0 deep in the night).
    atm = load_atmosphere("earth") if quality == "standard" else random_atmosphere(100_004)
    t = precompute(atm, QUALITY[quality], cache=None)
    rows = irradiance_rows(t.irradiance.shape[1])
    table = sky_irradiance_rows(t)
    mu_s = np.linspace(MU_S_MIN, 1.0, 20001)
    index = irradiance_row_index(mu_s, rows)
    got = read_linear(table, (index + 0.5) / len(table))
    want = get_irradiance(t, np.full(mu_s.shape, t.bottom), mu_s)
    rel = np.abs(got - want) / np.maximum(want, 1e-9 * want.max())
    first, knee, _, step = rows
    texels = t.irradiance[0, int(round((first + 1.0) / step)):int(round((knee + 1.0) / step)) + 1]
    q = np.max(np.maximum(texels[1:], 1e-300) / np.maximum(texels[:-1], 1e-300))
    a = np.log(float(q)) / IRRADIANCE_SUBROWS
    x = 1.0 / a - 1.0 / np.expm1(a)
    bound = np.expm1(a) / a * np.exp(-a * x) - 1.0
    assert np.max(rel[mu_s >= knee]) < 1e-6
    assert np.max(rel[mu_s < knee]) < bound + 1e-6, (np.max(rel), bound)


def integrated_scattering_share(atm, r, mu, d, points=20_001):
    """The integral of beta_scat T(0, t) dt over each ray (r, mu) of length d, over its opacity 1 - T(0, d), by
    the trapezoidal rule on ``points`` even steps (T from the trapezoidal optical depth on the same steps): steps
    of at most 60 m on Earth's longest ray (3,600 km), against scale heights of 1.2 km and more, a relative error
    below 1e-4."""
    t = np.linspace(0.0, 1.0, points)[None, :] * d[:, None]
    h = altitude(r[:, None], mu[:, None], t, atm.bottom_radius_m)
    extinction = atm.extinction(h)
    rayleigh, mie = atm.scattering(h)
    step = (d / (points - 1))[:, None, None]
    tau = np.concatenate([np.zeros_like(extinction[:, :1]),
                          np.cumsum(0.5 * (extinction[:, 1:] + extinction[:, :-1]) * step, axis=1)], axis=1)
    f = (rayleigh + mie) * np.exp(-tau)
    return np.sum(0.5 * (f[:, 1:] + f[:, :-1]) * step, axis=1) / one_minus_exp(tau[:, -1])


def share_rays(atm, a):
    """Every 7th ray of the path-opacity table from altitude a [m]: (r, mu, d)."""
    top = atm.top_radius_m - atm.bottom_radius_m
    mu, d, _ = path_opacity_rays(min(a, top), atm.bottom_radius_m, atm.top_radius_m)
    return np.full(mu[::7].shape, atm.bottom_radius_m + min(a, top)), mu[::7], d[::7]


def test_ascending_ray_nodes_are_the_nodes_in_the_order_of_t():
    # The share sums its cells in the order of t along each ray; ray_nodes(..., ascending=True) must give the same
    # nodes and weights as the default, sorted: on rays up, down to the ground, ending before or past their closest
    # approach, and segments from a start beyond 0.
    earth = load_atmosphere("earth")
    rng = np.random.default_rng(6)
    r = rng.uniform(earth.bottom_radius_m, earth.top_radius_m, 2000)
    mu = rng.uniform(-1.0, 1.0, 2000)
    start = rng.choice([0.0, 5e3], 2000) * rng.uniform(0.0, 1.0, 2000)
    d = start + rng.uniform(0.0, 2e6, 2000)
    t, w = ray_nodes(r, mu, d, 8, start=start)
    got_t, got_w = ray_nodes(r, mu, d, 8, start=start, ascending=True)
    order = np.argsort(t, axis=-1, kind="stable")
    assert np.all(np.diff(got_t, axis=-1) >= 0.0)
    np.testing.assert_array_equal(got_t, np.take_along_axis(t, order, -1))
    np.testing.assert_array_equal(got_w, np.take_along_axis(w, order, -1))


@pytest.mark.parametrize("a", [2.0, 1e4, 1e9])
def test_the_scattering_share_is_one_where_nothing_absorbs(a):
    # Where beta_scat = beta_ext everywhere, the integral of beta_scat T dt is 1 - T exactly, and so is the sum of
    # the quadrature's cells, whatever the nodes (their transmittance steps telescope): a share of 1 to rounding.
    earth = load_atmosphere("earth")
    atm = earth.replace(absorption=(), mie=dataclasses.replace(earth.mie, extinction_m=earth.mie.scattering_m))
    share = scattering_share(atm, *share_rays(atm, a), SCATTERING_SHARE_NODES)
    np.testing.assert_allclose(share, 1.0, rtol=0.0, atol=1e-12)


SHARE_TOLERANCE = 0.03


@pytest.mark.parametrize("name", ["earth", "random-0", "random-2", "random-100004"])
@pytest.mark.parametrize("a", [2.0, 1e4, 1e9])
def test_the_scattering_share_is_the_integral_of_the_scattering_along_the_ray(name, a):
    # Against the trapezoidal integral of beta_scat T along the ray (error below 1e-4). The share enters a pixel only
    # as the ratio of its factor to its vertices' (shaders/atmosphere_interpolated.glsl), so no error of it can move
    # a pixel by more than its own size: bounded at 3%, the per-vertex picture's target at the 99th percentile.
    # Absorbers (Earth's ozone, the random atmospheres' layers and absorbing particles) lower the share by 20-80%
    # on the rays through them; an albedo taken from the wrong component or a transmittance from the wrong end of
    # the ray misses by that much.
    atm = load_atmosphere("earth") if name == "earth" else random_atmosphere(int(name.split("-")[1]))
    rays = share_rays(atm, a)
    np.testing.assert_allclose(scattering_share(atm, *rays, SCATTERING_SHARE_NODES),
                               integrated_scattering_share(atm, *rays), rtol=SHARE_TOLERANCE)


@pytest.mark.parametrize("name", ["earth", "random-0", "random-2"])
def test_ray_opacity_is_the_scattering_opacity_of_the_ray_to_the_top(name):
    # The 4D tables' sky half holds S over the ray's scattering opacity, the integral of beta_scat T along the ray
    # to the top (lookup.ray_opacity): at the texel centres of the scattering-share table (standard sizes), where
    # the read is the stored value, against the trapezoidal integral (error below 1e-4), within the same 3% (the
    # quadrature's cells hold one albedo each). The opacity 1 - T in its place reads the rays through Earth's ozone
    # up to 5 times high and those through the random atmospheres' absorbing layers up to 4e5 times, which the last
    # line checks the test would see.
    atm = load_atmosphere("earth") if name == "earth" else random_atmosphere(int(name.split("-")[1]))
    sizes = QUALITY["standard"]
    t = precompute(atm, dataclasses.replace(sizes, scattering=(2, 4, 8, 4)), multiple=False)
    r, mu, d = (a.ravel()[::97] for a in transmittance_rays(atm, sizes))          # 169 of the 16,384 texels
    full = np.abs(d - distance_to_top_atmosphere_boundary(r, mu, atm.top_radius_m)) < 1e-6 * d
    r, mu, d = r[full], mu[full], d[full]
    tau = get_optical_depth_to_top_atmosphere_boundary(t, r, mu)
    exact = integrated_scattering_share(atm, r, mu, d) * one_minus_exp(tau)
    np.testing.assert_allclose(ray_opacity(t, r, mu, np.zeros(r.shape, bool)), exact, rtol=SHARE_TOLERANCE)
    assert np.max(one_minus_exp(tau) / exact) > 1.2


def test_the_path_scattering_share_reads_as_the_share_of_each_texel():
    # The table computes the share on every few texels and reads it linearly between them: against the share of
    # every texel's own ray, within the same 3% (the share changes over the absorbing layers' kilometres, a texel
    # is 0.2 km of tangent altitude from the top of the Earth's atmosphere). A slice of the wavelengths reads as
    # those wavelengths of the whole.
    atm, t = load_atmosphere("earth"), draft_earth_tables()
    for a in (2.0, 3e4, t.top - t.bottom):
        mu, d, _ = path_opacity_rays(a, t.bottom, t.top)
        share = scattering_share(atm, np.full(mu.shape, t.bottom + a), mu, d, SCATTERING_SHARE_NODES)
        table = path_scattering_share(t, atm, a)
        np.testing.assert_allclose(table, share, rtol=SHARE_TOLERANCE)
        np.testing.assert_allclose(path_scattering_share(t, atm, a, wavelengths=slice(1, 3)), table[:, 1:3],
                                   rtol=1e-12)


@pytest.mark.parametrize("name", ["earth", "random-7", "random-100003"])
def test_a_scattering_share_stands_for_the_altitudes_it_holds_for(name):
    # The renderer keeps a share while share_holds says so (a camera turning moves it by millimetres): within that
    # step the share of every texel stays within the share's own tolerance. The two random atmospheres are the
    # ones whose share moved most with the altitude among 16 (thin atmospheres, where a texel's ray moves fastest
    # near the top).
    atm = load_atmosphere("earth") if name == "earth" else random_atmosphere(int(name.split("-")[1]))
    t = draft_earth_tables() if name == "earth" else precompute(atm, QUALITY["draft"], multiple=False)
    step = SHARE_ALTITUDE_STEP * atm.thickness_m
    assert share_holds(100.0, 100.0 + step, atm) and not share_holds(100.0, 100.0 + 1.01 * step, atm)
    for a in np.concatenate([[0.0, 2.0], np.geomspace(100.0, 0.999 * atm.thickness_m, 8)]):
        np.testing.assert_allclose(path_scattering_share(t, atm, a + step), path_scattering_share(t, atm, a),
                                   rtol=0.0, atol=SHARE_TOLERANCE)
