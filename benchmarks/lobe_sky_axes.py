"""A forward-lobed, optically thick sky and the 4D tables' axes: random atmosphere 4's plane-parallel twin at one
wavelength against DISORT, the axes' placement of texels changed.

    python benchmarks/lobe_sky_axes.py [--g 0.65] [--scale 1] [--suns 30 70] [--variants "" "multiple=(4,32,256,16)"]
                                       [--mu-s-angle-share 0 0.2] [--view-zenith-share 0 0.5]
                                       [--view-angle-offset 0 1.5e-3] [--order2]
    python benchmarks/lobe_sky_axes.py --interpolation earth [--mu-s-angle-share 0 0.2] [--view-zenith-share 0 0.5]

The atmosphere: random atmosphere 4 of the tuning split (``planetviz.validation.random_atmosphere``) at 550 nm
only, without its absorbing layer, on a planet of 1e9 m (its 2,323 km of air then plane-parallel within 0.2%), its
particles given one Henyey-Greenstein lobe of ``--g`` and their and the molecules' coefficients multiplied by
``--scale`` (vertical optical depth 2.8 at 1). Rays: at the ground looking up (printed) and at the top looking
down (in the RMS), view zenith 10, 20, 35, 55 and 78 deg x azimuth 0, 90 and 180 deg from the sun's. DISORT as in
benchmarks/tables_disort.py (its own error 0.3%, ../shared/notes/disort.md). Each ``--variants`` entry is a set of
``TableSizes`` fields changed from the standard level; ``--mu-s-angle-share``, ``--view-zenith-share`` and
``--view-angle-offset`` set ``parameterization.SUN_ANGLE_SHARE`` (the sun-zenith coordinate's share of the angle;
0 is Bruneton's), ``VIEW_ANGLE_SHARE`` and ``VIEW_ANGLE_OFFSET`` (the view-zenith coordinate's angle-like part;
share 0 is the distance coordinate alone; the offset is the ground half's and, times the camera's altitude over the
thickness, the sky half's: ``parameterization.sky_angle_offset``) for this run, the tables' values by default, every combination
run. ``--order2``: the tables' order 2 (``multiple.first_two_orders`` less their first) against a brute-force
plane-parallel order 2 instead of DISORT (the first order's light from 4,001 levels, integrated over 192
Gauss-Legendre cosines x 360 azimuths at 201 levels; the first order printed beside it shows the brute force's
agreement with the tables where both are exact). ``--interpolation PRESET``: what each pair of axes costs a
preset instead, its standard tables against the same axes with 4 times the sun and view-zenith texels (single
scattering 192 x 480, multiple scattering 128 x 256, irradiance 512; the interpolation is what differs) from 2 m,
10 km and 40 km, views 5-95 deg from the zenith x 5 azimuths, suns from 60 deg up to 16 deg down, RMS and largest
relative difference per class (day, twilight to -6 deg, deep twilight), radiances above 1e-6 of the finer tables'
largest.
"""
import argparse
from dataclasses import replace

import numpy as np

from planetviz import load_atmosphere
from planetviz.tables import QUALITY, parameterization, precompute
from planetviz.tables.evaluator import sky_radiance
from planetviz.tables.multiple import first_two_orders
from planetviz.tables.precompute import sizes_for
from planetviz.validation import random_atmosphere
from planetviz.validation.disort import disort_radiance, ground_and_top_views
from planetviz.validation.single_scattering import single_scattering_only

ZENITHS = (10.0, 20.0, 35.0, 55.0, 78.0)


def twin(g, scale):
    """Random atmosphere 4 at 550 nm without its absorbing layer, on 1e9 m, one lobe of g, coefficients x scale."""
    atm = random_atmosphere(4)
    d = atm.to_dict()
    d.update(name="random-4-twin", bottom_radius_m=1e9, top_radius_m=1e9 + d["top_radius_m"] - d["bottom_radius_m"],
             absorption=[], wavelengths_nm=[550.0], ground_albedo=[d["ground_albedo"][1]])
    d["rayleigh"] = dict(d["rayleigh"], scattering_m=[scale * d["rayleigh"]["scattering_m"][1]])
    d["mie"] = dict(d["mie"], scattering_m=[scale * d["mie"]["scattering_m"][1]],
                    extinction_m=[scale * d["mie"]["extinction_m"][1]], phase={"g1": [g], "g2": [0.0], "alpha": [1.0]})
    return type(atm).from_dict(d)


def axes(sun_shares, view_shares, view_offsets):
    """Every (sun share, view share, view offset), set for this process (``parameterization.SUN_ANGLE_SHARE``,
    ``VIEW_ANGLE_SHARE``, ``VIEW_ANGLE_OFFSET``; the tables are computed without a cache) before it is yielded."""
    kept = parameterization.SUN_ANGLE_SHARE, parameterization.VIEW_ANGLE_SHARE, parameterization.VIEW_ANGLE_OFFSET
    for sun_share in sun_shares:
        for view_share in view_shares:
            for offset in view_offsets:
                parameterization.SUN_ANGLE_SHARE = sun_share
                parameterization.VIEW_ANGLE_SHARE, parameterization.VIEW_ANGLE_OFFSET = view_share, offset
                yield f"sun share {sun_share:g}, view share {view_share:g}, offset {offset:g}"
    parameterization.SUN_ANGLE_SHARE, parameterization.VIEW_ANGLE_SHARE, parameterization.VIEW_ANGLE_OFFSET = kept


def brute_force_orders(atm, dirs, sun, levels=4001, step=20, n_cos=96, n_phi=360):
    """(order 1, order 2) (n,) at the ground looking along ``dirs`` (n, 3), plane-parallel, per unit irradiance.

    L1(z, w) = P_R(w . s) A_R(z, mu_w) + P_M(w . s) A_M(z, mu_w) + the sunlit ground seen along w, A_c the
    integral of beta_c T_sun T / |mu_w| along w (trapezoids on ``levels`` altitudes); J2(z, v) = sum_c beta_c(z)
    sum_w P_c(v . w) L1(z, w) dw on Gauss-Legendre cosines per hemisphere x midpoint azimuths, at every ``step``-th
    level; order 2 = int J2 T dz / mu_v."""
    z = np.linspace(0.0, atm.thickness_m, levels)
    b_r = atm.rayleigh.profile.density(z) * atm.rayleigh.scattering_m[0]
    b_m = atm.mie.profile.density(z) * atm.mie.scattering_m[0]
    b_e = b_r + atm.mie.profile.density(z) * atm.mie.extinction_m[0]
    tau = np.concatenate([[0.0], np.cumsum(0.5 * (b_e[1:] + b_e[:-1]) * np.diff(z))])
    tau = tau[-1] - tau                                                     # from the top down to z
    t_sun = np.exp(-tau / sun[2])
    x, wx = np.polynomial.legendre.leggauss(n_cos)
    mu_w, w_mu = np.concatenate([(x - 1) / 2, (x + 1) / 2]), np.concatenate([wx, wx]) / 2
    at = np.arange(0, levels, step)

    def along(beta):
        out = np.zeros((len(at), len(mu_w)))
        for a, i in enumerate(at):
            for b, m in enumerate(mu_w):
                part = slice(i, None) if m > 0 else slice(0, i + 1)
                f = beta[part] * t_sun[part] * np.exp(-np.abs(tau[i] - tau[part]) / abs(m)) / abs(m)
                out[a, b] = np.trapezoid(f, z[part]) if f.size > 1 else 0.0
        return out

    ground = np.where(mu_w < 0, np.exp(-(tau[0] - tau[at][:, None]) / np.abs(mu_w)) * atm.ground_albedo[0] / np.pi
                      * sun[2] * t_sun[0], 0.0)
    phi = (np.arange(n_phi) + 0.5) * 2.0 * np.pi / n_phi
    m, p = np.meshgrid(mu_w, phi, indexing="ij")
    w = np.stack([np.sqrt(1 - m * m) * np.cos(p), np.sqrt(1 - m * m) * np.sin(p), m], -1).reshape(-1, 3)
    dw = np.repeat(w_mu, n_phi) * (2.0 * np.pi / n_phi)
    p_r = lambda c: atm.rayleigh.phase_function(c)
    p_m = lambda c: atm.mie.phase_function(c)[..., 0]
    nu_w = w @ sun
    l1 = p_r(nu_w) * np.repeat(along(b_r), n_phi, 1) + p_m(nu_w) * np.repeat(along(b_m), n_phi, 1) + \
        np.repeat(ground, n_phi, 1)
    first, second = [], []
    for v in dirs:
        c = w @ v
        j2 = b_r[at] * (l1 @ (p_r(c) * dw)) + b_m[at] * (l1 @ (p_m(c) * dw))
        second.append(np.trapezoid(j2 * np.exp(-(tau[0] - tau[at]) / v[2]), z[at]) / v[2])
        nu = v @ sun
        first.append(np.trapezoid((b_r * p_r(nu) + b_m * p_m(nu)) * t_sun * np.exp(-(tau[0] - tau) / v[2]), z) / v[2])
    return np.array(first), np.array(second)


def interpolation(preset, sun_shares, view_shares, view_offsets):
    """Print, per pair of axes, the standard tables' difference from the same with 4x the sun and view texels."""
    atm = load_atmosphere(preset)
    standard = QUALITY["standard"]
    fine = replace(standard, scattering=(8, 192, 480, 32), multiple=(4, 128, 256, 16), lobe_mu_s=128,
                   irradiance=(512, 16))
    zenith, azimuth = (np.radians(a).ravel() for a in np.meshgrid([5, 15, 30, 60, 80, 88, 91, 95],
                                                                  [0, 45, 90, 135, 180]))
    dirs = np.stack([np.sin(zenith) * np.cos(azimuth), np.sin(zenith) * np.sin(azimuth), np.cos(zenith)], -1)
    dirs = np.concatenate([dirs] * 3)
    cams = np.zeros(dirs.shape)
    cams[:, 2] = atm.bottom_radius_m + np.repeat([2.0, 10e3, 40e3], len(zenith))
    for name in axes(sun_shares, view_shares, view_offsets):
        coarse, finer = precompute(atm, standard), precompute(atm, fine)
        classes = {}
        for elevation in (60, 30, 10, 3, -1, -3, -5, -8, -12, -16):
            e = np.radians(elevation)
            sun = np.array([np.cos(e), 0.0, np.sin(e)])
            a, b = (sky_radiance(t, atm, cams, dirs, sun)[0] for t in (coarse, finer))
            lit = b > 1e-6 * b.max()
            kind = "day" if elevation > 0 else "twilight" if elevation >= -6 else "deep twilight"
            classes.setdefault(kind, []).append(a[lit] / b[lit] - 1.0)
        print(f"{preset}, {name}:", "; ".join(
            f"{k} RMS {np.sqrt(np.mean(np.concatenate(v) ** 2)):.4f}, largest {np.abs(np.concatenate(v)).max():.3f}"
            for k, v in classes.items()), flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--g", type=float, default=0.65)
    ap.add_argument("--scale", type=float, default=1.0)
    ap.add_argument("--suns", type=float, nargs="+", default=[30.0, 70.0], help="sun zenith angles [deg]")
    ap.add_argument("--variants", nargs="+", default=[""], help='TableSizes changes, e.g. "multiple=(4,32,256,16)"')
    ap.add_argument("--mu-s-angle-share", type=float, nargs="+", default=[parameterization.SUN_ANGLE_SHARE])
    ap.add_argument("--view-zenith-share", type=float, nargs="+", default=[parameterization.VIEW_ANGLE_SHARE])
    ap.add_argument("--view-angle-offset", type=float, nargs="+", default=[parameterization.VIEW_ANGLE_OFFSET])
    ap.add_argument("--order2", action="store_true")
    ap.add_argument("--interpolation", metavar="PRESET")
    args = ap.parse_args()
    if args.interpolation:
        return interpolation(args.interpolation, args.mu_s_angle_share, args.view_zenith_share,
                             args.view_angle_offset)
    atm = twin(args.g, args.scale)
    views, cams, dirs = ground_and_top_views(atm, zeniths_deg=ZENITHS)
    print(f"g {args.g}, vertical optical depth {atm.vertical_optical_depth()[0]:.2f}; ground views (zenith, angle "
          "from the sun) then the error")
    for zenith in args.suns:
        theta = np.radians(zenith)
        sun = np.array([np.sin(theta), 0.0, np.cos(theta)])
        ground = slice(0, None, 2)
        print(f"sun zenith {zenith:g}:", " ".join(f"{np.degrees(np.arccos(v[2])):.0f}/{np.degrees(np.arccos(v @ sun)):.0f}"
                                               for v in dirs[ground]))
        if args.order2:
            want = np.concatenate(brute_force_orders(atm, dirs[ground], sun))
        else:
            want = disort_radiance(atm, 0, np.cos(theta), views)
        for name in axes(args.mu_s_angle_share, args.view_zenith_share, args.view_angle_offset):
            for spec in args.variants:
                level = replace(QUALITY["standard"], **eval(f"dict({spec})"))
                tables = precompute(atm, level)
                if args.order2:
                    one = sky_radiance(single_scattering_only(tables), atm, cams[ground], dirs[ground], sun)[0][:, 0]
                    two = sky_radiance(first_two_orders(tables, atm, sizes_for(atm, level)), atm, cams[ground],
                                       dirs[ground], sun)[0][:, 0]
                    got = np.concatenate([one, two - one])
                    n = len(one)
                    rel = got / want - 1.0
                    print(f"  {name}, {spec or 'standard'}: order 1", " ".join(f"{x:+.3f}" for x in rel[:n]),
                          "| order 2", " ".join(f"{x:+.3f}" for x in rel[n:]))
                    continue
                got = sky_radiance(tables, atm, cams, dirs, sun)[0][:, 0]
                rel = got / want - 1.0
                print(f"  {name}, {spec or 'standard'}: ground", " ".join(f"{x:+.3f}" for x in rel[ground]),
                      f"| RMS ground and top {np.sqrt(np.mean(rel ** 2)):.4f}", flush=True)


if __name__ == "__main__":
    main()
