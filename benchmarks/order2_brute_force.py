"""The first two orders of scattering along one of the suite's rays by brute force, against the stored Monte Carlo
reference of benchmarks/tables_orders.py and the tables' first two orders with each direction quadrature.

    python benchmarks/order2_brute_force.py [--atmosphere random-0] [--light twilight] [--camera aircraft]
                                            [--ray 0] [--grid 60 72 12] [--directions 10 10 20 10 40 10]

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
error beside it); the tables' first two orders are ``multiple.first_two_orders`` with each ``--directions`` pair of
each kind of ``multiple.QUADRATURES``.
"""
import argparse

import numpy as np

from planetviz import load_atmosphere
from planetviz.quick_view.single_scattering import coefficients
from planetviz.reference.single import single_scattering
from planetviz.reference.stored import stored_reference
from planetviz.tables import QUALITY, TableCache, precompute
from planetviz.tables.evaluator import sky_radiance
from planetviz.tables.multiple import QUADRATURES, first_two_orders
from planetviz.tables.precompute import sizes_for
from planetviz.validation import CAMERAS, random_atmosphere, rays
from tables_orders import DATA


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


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--atmosphere", default="random-0")
    ap.add_argument("--light", default="twilight")
    ap.add_argument("--camera", default="aircraft", choices=CAMERAS)
    ap.add_argument("--ray", type=int, default=0, choices=(0, 1))
    ap.add_argument("--grid", type=int, nargs=3, default=(60, 72, 12), metavar=("N_COS", "N_PHI", "N_POINTS"))
    ap.add_argument("--directions", type=int, nargs="+", default=[10, 10, 20, 10, 40, 10])
    args = ap.parse_args()
    if len(args.directions) % 2:
        ap.error("--directions: pairs N_THETA N_PHI")
    if args.atmosphere.startswith("random-"):
        name, seed = args.atmosphere, int(args.atmosphere.split("-")[1])
        atm = random_atmosphere(seed)
    else:
        name, atm, seed = args.atmosphere, load_atmosphere(args.atmosphere), 0
    batch = [rays(atm, seed, camera, args.light, n=2) for camera in CAMERAS]
    cams, views, suns = (np.concatenate(x) for x in zip(*batch))
    k = 2 * CAMERAS.index(args.camera) + args.ray
    ref = stored_reference(DATA, f"{name}-{args.light}", atm, cams, views, suns, samples=16384, seed=seed + 11,
                           max_order=2)
    x, v, s = cams[k], views[k] / np.linalg.norm(views[k]), suns[k] / np.linalg.norm(suns[k])
    up = x / np.linalg.norm(x)
    print(f"{name}, {args.camera} ray {args.ray} in {args.light}: {np.linalg.norm(x) - atm.bottom_radius_m:.0f} m up, "
          f"view {np.degrees(np.arcsin(v @ up)):.2f} deg, sun {np.degrees(np.arcsin(s @ up)):.2f} deg, nu {v @ s:.3f}")
    np.set_printoptions(formatter={"float": "{:.4g}".format})
    n_cos, n_phi, n_points = args.grid
    one, two = brute_force(atm, x, v, s, n_cos, n_phi, n_points)
    _, two_coarse = brute_force(atm, x, v, s, n_cos // 2, n_phi // 2, max(2 * n_points // 3, 2))
    print(f"brute force, orders 1 + 2:       {one + two}  (order 1 {one})")
    print(f"  on the coarser grid:           {one + two_coarse}")
    print(f"Monte Carlo (max_order=2):       {ref.radiance[k]} +- {ref.stderr[k]}  "
          f"({ref.radiance[k] / (one + two)} of the brute force, z {(ref.radiance[k] - one - two) / ref.stderr[k]})")
    sizes = sizes_for(atm, QUALITY["standard"])
    tables = precompute(atm, QUALITY["standard"], cache=TableCache())
    for kind in QUADRATURES:
        for i in range(0, len(args.directions), 2):
            pair = tuple(args.directions[i:i + 2])
            got, _ = sky_radiance(first_two_orders(tables, atm, sizes, pair, quadrature=kind), atm, cams[k:k + 1],
                                  views[k:k + 1], suns[k:k + 1])
            print(f"tables {pair[0]}x{pair[1]} {kind:<11}: {got[0]}  ({got[0] / (one + two)} of the brute force)")


if __name__ == "__main__":
    main()
