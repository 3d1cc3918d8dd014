"""The first two orders of scattering along one of the suite's rays by brute force, against the stored Monte Carlo
reference of benchmarks/tables_orders.py and the tables' first two orders with each direction quadrature.

    python benchmarks/order2_brute_force.py [--atmosphere random-0] [--light twilight] [--camera aircraft]
                                            [--ray 0] [--grid 60 72 12] [--directions 10 10 20 10 40 10]
                                            [--collisions extinction]
    python benchmarks/order2_brute_force.py --sample N [--seed 1] [--grid ...]
    python benchmarks/order2_brute_force.py --limb [--grid 60 72 24]

Order 1 is reference/single.py's deterministic quadrature (the in-scattered light and the directly lit ground,
no noise). Order 2 is that light seen from Gauss-Legendre points along the view ray (``--grid``'s third number),
integrated over the directions at each point with the atmosphere's phase functions: cosines split at the point's
horizon, the sky's side clustered toward it (x^3 on the midpoint rule, where the only lit air lies when the point
is in the planet's shadow), azimuths all round on the midpoint rule (the grid's first two numbers), times the
scattering coefficients at the point and the view transmittance to it (a 20,001-point trapezoid); for a ray to
the ground, plus the ground's reflection of the sky's light of order 1 (the same directions at the ground point).
Nothing is
shared with the tables or the Monte Carlo solver but the atmosphere. The same sum on a grid with half the cosines,
half the azimuths and two thirds of the points is printed beside it: their difference is the brute force's own
error. About 30 s per point of the view ray at the default grid, on one core.

The Monte Carlo reference is the stored one of ``tables_orders.py`` (``max_order=2``, 16384 paths, its standard
error beside it; ``--collisions``: the one whose collisions were drawn so); the tables' first two orders are
``multiple.first_two_orders`` with each ``--directions`` pair of each kind of ``multiple.QUADRATURES``.
``--sample N`` checks N rays drawn at random (``--seed``) from the tuning split's twilight and deep-twilight classes
instead, one line each. ``--limb``: Earth's limb from 1000 km instead
(:func:`limb_ray`), order 2 alone against the tables' (their first two orders less their first), no Monte Carlo.
"""
import argparse

import numpy as np

from planetviz import load_atmosphere
from planetviz.quick_view.single_scattering import coefficients
from planetviz.reference.single import single_scattering
from planetviz.reference.montecarlo import COLLISIONS, DEFAULT_COLLISIONS
from planetviz.tables import QUALITY, TableCache, precompute
from planetviz.tables.evaluator import sky_radiance
from planetviz.tables.multiple import QUADRATURES, first_two_orders
from planetviz.tables.precompute import sizes_for
from planetviz.validation import CAMERAS, suite_atmosphere
from planetviz.validation.single_scattering import single_scattering_only
from tables_orders import reference_orders


def view_transmittance(atm, x, v, t):
    """T from x to the points x + t v (n,) -> (n, W), by a 20,001-point trapezoid of the extinction to the last."""
    _, _, extinction = coefficients(atm, "physical")
    fine = np.linspace(0.0, t.max(), 20001)
    h = np.maximum(np.linalg.norm(x + fine[:, None] * v, axis=1) - atm.bottom_radius_m, 0.0)
    beta = sum(profile.density(h)[:, None] * np.asarray(e) for e, profile in extinction)
    tau = np.concatenate([np.zeros((1, beta.shape[1])),
                          np.cumsum(0.5 * (beta[1:] + beta[:-1]) * np.diff(fine)[:, None], axis=0)])
    return np.exp(-np.stack([np.interp(t, fine, tau[:, w]) for w in range(beta.shape[1])], -1))


def local_directions(atm, y, s, n_cos, n_phi):
    """(directions (K, 3), weights (K,)) over the sphere at y: cosines split at y's horizon, n_cos / 6 on the
    ground's side uniform, the rest on the sky's at mu_h + (1 - mu_h) x^3 (x on the midpoint rule), azimuths on the
    midpoint rule all round from the sun's."""
    r = np.linalg.norm(y)
    up = y / r
    mu_h = -np.sqrt(max(1.0 - (atm.bottom_radius_m / r) ** 2, 0.0))
    n_ground = max(n_cos // 6, 2)
    x = (np.arange(n_cos - n_ground) + 0.5) / (n_cos - n_ground)
    xg = (np.arange(n_ground) + 0.5) / n_ground
    mu = np.concatenate([-1.0 + (mu_h + 1.0) * xg, mu_h + (1.0 - mu_h) * x ** 3])
    w_mu = np.concatenate([np.full(n_ground, (mu_h + 1.0) / n_ground), 3.0 * (1.0 - mu_h) * x ** 2 / x.size])
    toward_sun = s - (s @ up) * up
    norm = np.linalg.norm(toward_sun)
    ex = toward_sun / norm if norm > 1e-9 else np.cross(up, [0.0, 1.0, 0.0] if abs(up[1]) < 0.9 else [1.0, 0, 0])
    ey = np.cross(up, ex)
    phi = (np.arange(n_phi) + 0.5) * 2.0 * np.pi / n_phi
    m, p = (a.ravel() for a in np.meshgrid(mu, phi, indexing="ij"))
    sin = np.sqrt(np.maximum(1.0 - m * m, 0.0))
    dirs = (sin * np.cos(p))[:, None] * ex + (sin * np.sin(p))[:, None] * ey + m[:, None] * up
    return dirs, np.repeat(w_mu, n_phi) * 2.0 * np.pi / n_phi


def brute_force(atm, x, v, s, n_cos, n_phi, n_points):
    """(order 1, order 2) (W,) [1/sr per unit solar irradiance] of the ray from x along v, the sun toward s."""
    sky, ground = single_scattering(atm, x[None], v[None], s)
    b = x @ v
    top = -b + np.sqrt(b * b - (x @ x - atm.top_radius_m ** 2))
    c = x @ x - atm.bottom_radius_m ** 2
    hits = b < 0 and b * b - c >= 0
    length = -b - np.sqrt(b * b - c) if hits else top
    g, wg = np.polynomial.legendre.leggauss(n_points)
    t, wt = 0.5 * length * (g + 1.0), 0.5 * length * wg
    T = view_transmittance(atm, x, v, t)
    b_r, b_m, _ = coefficients(atm, "physical")
    order2 = np.zeros(atm.n_wavelengths)
    for i in range(n_points):
        y = x + t[i] * v
        h = np.array(np.linalg.norm(y) - atm.bottom_radius_m)
        dirs, w = local_directions(atm, y, s, n_cos, n_phi)
        lit_sky, lit_ground = single_scattering(atm, np.tile(y, (len(dirs), 1)), dirs, s, panels=4)
        light = (lit_sky + lit_ground) * w[:, None]
        c_angle = dirs @ v                      # light arriving along -dirs leaves along -v
        j = (atm.rayleigh.profile.density(h) * np.asarray(b_r) * (atm.rayleigh.phase_function(c_angle)[:, None]
                                                                  * light).sum(0)
             + atm.mie.profile.density(h) * np.asarray(b_m) * (atm.mie.phase_function(c_angle) * light).sum(0))
        order2 += wt[i] * T[i] * j
    if hits:                                    # the ground reflects the sky's light of order 1
        g = x + length * v
        dirs, w = local_directions(atm, g * (1.0 + 1e-9), s, n_cos, n_phi)
        up = g / np.linalg.norm(g)
        cos = dirs @ up
        sky_dirs = cos > 0.0
        lit_sky, lit_ground = single_scattering(atm, np.tile(g * (1.0 + 1e-9), (sky_dirs.sum(), 1)), dirs[sky_dirs],
                                                s, panels=4)
        irradiance = ((lit_sky + lit_ground) * (w * cos)[sky_dirs, None]).sum(0)
        order2 += view_transmittance(atm, x, v, np.array([length]))[0] * np.asarray(atm.ground_albedo) / np.pi \
            * irradiance
    return sky[0] + ground[0], order2


def suite_ray(atmosphere, light, camera, ray, collisions=DEFAULT_COLLISIONS):
    """(atmosphere, the ray's camera, view and sun directions, the stored reference's result for it and its index
    there) of the suite's ray ``ray`` of ``camera`` in ``light`` on ``atmosphere`` (a preset or random-N); the
    reference's collisions drawn as ``collisions`` says."""
    atm, seed = suite_atmosphere(atmosphere)
    cams, views, suns, ref = reference_orders(atmosphere, atm, seed, light, 16384, collisions)
    k = 2 * CAMERAS.index(camera) + ray
    return atm, cams[k], views[k] / np.linalg.norm(views[k]), suns[k] / np.linalg.norm(suns[k]), ref, k


def tables_first_two_orders(atm, x, v, s, directions, kinds):
    """{(kind, (n_theta, n_phi)): the standard tables' first two orders (W,) of the ray} for each kind of
    ``multiple.QUADRATURES`` in ``kinds`` and each pair in ``directions``."""
    sizes = sizes_for(atm, QUALITY["standard"])
    tables = precompute(atm, QUALITY["standard"], cache=TableCache())
    return {(kind, pair): sky_radiance(first_two_orders(tables, atm, sizes, pair, quadrature=kind), atm, x[None],
                                       v[None], s[None])[0][0]
            for kind in kinds for pair in directions}


def sample(args):
    """``--sample N``: N rays drawn at random (``--seed``) from the tuning split's twilight and deep-twilight classes,
    one line each: the brute force's own change from the coarser grid, the reference's ratio to it and its z (the
    difference over the reference's standard error and the brute force's change from the coarser grid combined),
    the tables' ratio to it with ``hemispheres`` and with ``lit-band`` (the levels'), at the wavelength where the reference
    is brightest relative to its noise."""
    rng = np.random.default_rng(args.seed)
    names = [f"random-{i}" for i in range(8)] + ["earth", "mars", "exo-co2-thick"]
    n_cos, n_phi, n_points = args.grid
    print("| atmosphere | camera | light | ray | brute force [1/sr] | coarser grid | reference / brute force (z) | "
          "hemispheres / brute force | lit-band / brute force |")
    print("|---|---|---|---|---|---|---|---|---|")
    for _ in range(args.sample):
        name = names[rng.integers(len(names))]
        light = ("twilight", "deep-twilight")[rng.integers(2)]
        camera, ray = CAMERAS[rng.integers(len(CAMERAS))], int(rng.integers(2))
        atm, x, v, s, ref, k = suite_ray(name, light, camera, ray, args.collisions)
        one, two = brute_force(atm, x, v, s, n_cos, n_phi, n_points)
        _, coarse = brute_force(atm, x, v, s, n_cos // 2, n_phi // 2, max(2 * n_points // 3, 2))
        got = tables_first_two_orders(atm, x, v, s, [(10, 10)], ["hemispheres", "lit-band"])
        want = one + two
        w = int(np.argmax(ref.radiance[k] / np.maximum(ref.stderr[k], 1e-300)))
        error = np.hypot(ref.stderr[k][w], (one + coarse)[w] - want[w])
        print(f"| {name} | {camera} | {light} | {ray} | {want[w]:.3e} | {(one + coarse)[w] / want[w]:.4f} | "
              f"{ref.radiance[k][w] / want[w]:.4f} ({(ref.radiance[k][w] - want[w]) / error:+.1f}) | "
              f"{got['hemispheres', (10, 10)][w] / want[w]:.4f} | {got['lit-band', (10, 10)][w] / want[w]:.4f} |",
              flush=True)


def limb_ray(atm):
    """(x, v, s): a camera 1000 km above ``atm``'s planet looking through the limb, the view ray's lowest point 10 km
    up, and the sun 10 deg above the horizon there, 90 deg in azimuth from the view."""
    bottom = atm.bottom_radius_m
    x = np.array([0.0, 0.0, bottom + 1e6])
    a = np.arcsin((bottom + 1e4) / (bottom + 1e6))
    v = np.array([np.sin(a), 0.0, -np.cos(a)])
    lowest = x - (x @ v) * v
    up = lowest / np.linalg.norm(lowest)
    side = np.cross(up, v)
    side /= np.linalg.norm(side)
    e = np.radians(10.0)
    return x, v, np.sin(e) * up + np.cos(e) * side


def limb(args):
    """``--limb``: order 2 of :func:`limb_ray` on Earth by brute force (and on the coarser grid), against the
    standard tables' order 2 with each kind of ``multiple.QUADRATURES`` at 10 x 10 directions."""
    atm = load_atmosphere("earth")
    x, v, s = limb_ray(atm)
    n_cos, n_phi, n_points = args.grid
    _, two = brute_force(atm, x, v, s, n_cos, n_phi, n_points)
    _, coarse = brute_force(atm, x, v, s, n_cos // 2, n_phi // 2, max(2 * n_points // 3, 2))
    print(f"brute force, order 2:   {two}  (the coarser grid {coarse / two} of it)")
    tables = precompute(atm, QUALITY["standard"], cache=TableCache())
    one = sky_radiance(single_scattering_only(tables), atm, x[None], v[None], s[None])[0][0]
    for (kind, _), got in tables_first_two_orders(atm, x, v, s, [(10, 10)], QUADRATURES).items():
        print(f"tables 10x10 {kind:<11}: {got - one}  ({(got - one) / two} of the brute force)")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--atmosphere", default="random-0")
    ap.add_argument("--light", default="twilight")
    ap.add_argument("--camera", default="aircraft", choices=CAMERAS)
    ap.add_argument("--ray", type=int, default=0, choices=(0, 1))
    ap.add_argument("--grid", type=int, nargs=3, default=(60, 72, 12), metavar=("N_COS", "N_PHI", "N_POINTS"))
    ap.add_argument("--directions", type=int, nargs="+", default=[10, 10, 20, 10, 40, 10])
    ap.add_argument("--sample", type=int, default=0, metavar="N",
                    help="N rays drawn at random from the tuning split's twilight classes instead, one line each")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--limb", action="store_true", help="Earth's limb from 1000 km instead (limb_ray)")
    ap.add_argument("--collisions", default=DEFAULT_COLLISIONS, choices=COLLISIONS,
                    help="the stored reference's way of drawing its collisions (tables_orders.py's folders)")
    args = ap.parse_args()
    if len(args.directions) % 2:
        ap.error("--directions: pairs N_THETA N_PHI")
    np.set_printoptions(formatter={"float": "{:.4g}".format})
    if args.sample:
        sample(args)
        return
    if args.limb:
        limb(args)
        return
    atm, x, v, s, ref, k = suite_ray(args.atmosphere, args.light, args.camera, args.ray, args.collisions)
    up = x / np.linalg.norm(x)
    print(f"{args.atmosphere}, {args.camera} ray {args.ray} in {args.light}: "
          f"{np.linalg.norm(x) - atm.bottom_radius_m:.0f} m up, view {np.degrees(np.arcsin(v @ up)):.2f} deg, "
          f"sun {np.degrees(np.arcsin(s @ up)):.2f} deg, nu {v @ s:.3f}")
    n_cos, n_phi, n_points = args.grid
    one, two = brute_force(atm, x, v, s, n_cos, n_phi, n_points)
    _, two_coarse = brute_force(atm, x, v, s, n_cos // 2, n_phi // 2, max(2 * n_points // 3, 2))
    print(f"brute force, orders 1 + 2:       {one + two}  (order 1 {one})")
    print(f"  on the coarser grid:           {one + two_coarse}")
    print(f"Monte Carlo (max_order=2):       {ref.radiance[k]} +- {ref.stderr[k]}  "
          f"({ref.radiance[k] / (one + two)} of the brute force, z {(ref.radiance[k] - one - two) / ref.stderr[k]})")
    pairs = [tuple(args.directions[i:i + 2]) for i in range(0, len(args.directions), 2)]
    for (kind, pair), got in tables_first_two_orders(atm, x, v, s, pairs, QUADRATURES).items():
        print(f"tables {pair[0]}x{pair[1]} {kind:<11}: {got}  ({got / (one + two)} of the brute force)")


if __name__ == "__main__":
    main()
