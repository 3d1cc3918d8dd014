"""The ``planetviz`` command.

    planetviz sky        [--atmosphere A] [--sun-elevation DEG] [--sun-azimuth DEG] [--quality Q]
    planetviz atmosphere PRESET_OR_FILE
    planetviz precompute --atmosphere A [--quality draft|standard|high] [--no-cache]
    planetviz queries    [--atmosphere A] --out Q.npz [--latitude DEG] [--longitude DEG] [--altitude M]
                         [--sun-elevation DEG] [--sun-azimuth DEG] [--elevations DEG ...] [--azimuths DEG ...]
    planetviz radiance   --atmosphere A --queries Q.npz --out OUT.npz
                         [--method reference|tables|quick] [--quality draft|standard|high] [--no-cache]
                         [--samples N] [--tables 4d|compact]
    planetviz sun        --site LAT,LON --time ISO8601|now [--json]
    planetviz render     [--atmosphere|--preset A] [--view space|ground] [--sun-elevation DEG] [--sun-azimuth DEG]
                         [--site LAT,LON --time ISO8601] [--size WxH] [--screenshot OUT.png] [--exr OUT.exr]
                         [--quality Q] [--method tables|quick] [--tables 4d|compact] [--samples N]
                         [--sweep-sun A B STEP | --time-lapse START STOP STEP | --flight N]
                         [--fisheye DOME.png|.exr] [--panorama SKY.exr]   (planetviz/app/render_options.py)

Tables are cached in $PLANETVIZ_CACHE (default ~/.cache/planetviz) as OpenEXR files; --no-cache
computes them afresh and writes nothing.

Invalid input exits with code 2 and one line naming the field and the allowed range.
"""
from __future__ import annotations

import argparse
import sys

import numpy as np

from ..model.geometry import EYE_HEIGHT_M
from ..model.presets import PRESETS, load_atmosphere
from ..reference.montecarlo import QUALITY_SAMPLES as REFERENCE_SAMPLES
from ..tables.compact import TABLE_KINDS
from .render_options import add_render_options, run_render



class _Parser(argparse.ArgumentParser):
    def error(self, message):
        self.exit(2, f"{self.prog}: error: {message}\n")


def _cmd_atmosphere(args) -> int:
    atm = load_atmosphere(args.atmosphere)
    tau_total = atm.vertical_optical_depth()
    print(f"atmosphere: {atm.name}   ground radius {atm.bottom_radius_m:.6g} m, "
          f"top {atm.top_radius_m:.6g} m ({atm.thickness_m / 1e3:.4g} km)")
    print(f"Rayleigh phase: {atm.rayleigh.phase}; profile {atm.rayleigh.profile.to_dict()}")
    print(f"Mie profile {atm.mie.profile.to_dict()}; light: {atm.star.type}"
          + (f" {atm.star.temperature_k:g} K" if atm.star.temperature_k else "")
          + f"; air mass: {atm.air_mass}")
    head = (f"{'lambda [nm]':>11} {'beta_R^scat':>12} {'beta_M^scat':>12} {'beta_M^ext':>12} "
            f"{'beta_abs':>12} {'tau_R':>8} {'tau_M':>8} {'tau_abs':>8} {'tau':>8} "
            f"{'g1':>6} {'g2':>6} {'alpha':>6} {'albedo':>6}")
    print(head)
    comps = atm.components()
    depth = atm.component_optical_depths()
    for i, lam in enumerate(atm.wavelengths_nm):
        absorb = sum(c[1][i] for c in comps[2:])
        tau_abs = sum(d[i] for d in depth[2:])
        print(f"{lam:11.1f} {comps[0][0][i]:12.5e} {comps[1][0][i]:12.5e} {comps[1][1][i]:12.5e} "
              f"{absorb:12.5e} {depth[0][i]:8.4f} {depth[1][i]:8.4f} {tau_abs:8.4f} {tau_total[i]:8.4f} "
              f"{atm.mie.g1[i]:6.3f} {atm.mie.g2[i]:6.3f} {atm.mie.alpha[i]:6.3f} {atm.ground_albedo[i]:6.3f}")
    print("(coefficients at the ground in 1/m; absorption layers' peak extinction; tau = vertical optical depth)")
    return 0


def _table_cache(args):
    from ..tables.cache import TableCache
    return None if args.no_cache else TableCache()


def _solve(atm, queries, method, quality, samples, seed, cache=None, tables="4d"):
    if method == "tables":
        from ..reference import ReferenceResult
        from ..tables.compact import tables_of_kind
        from ..tables.evaluator import sky_radiance
        from ..tables.precompute import QUALITY, precompute
        read = tables_of_kind(precompute(atm, QUALITY[quality], cache=cache), atm, tables)
        radiance, transmittance = sky_radiance(read, atm, queries.camera_m, queries.view_dir, queries.sun_dir)
        return ReferenceResult(radiance, np.zeros_like(radiance), transmittance, 0)
    if method == "quick":
        from ..quick_view.single_scattering import quick_view_radiance
        from ..reference import ReferenceResult
        n = 8 if samples is None else samples
        radiance, transmittance = quick_view_radiance(atm, queries.camera_m, queries.view_dir, queries.sun_dir,
                                                    samples=n)
        return ReferenceResult(radiance, np.zeros_like(radiance), transmittance, n)
    from ..reference import solve
    return solve(atm, queries.camera_m, queries.view_dir, queries.sun_dir,
                 samples=samples or REFERENCE_SAMPLES[quality], seed=seed)


def _cmd_radiance(args) -> int:
    from ..model.queries import load_queries
    atm = load_atmosphere(args.atmosphere)
    queries = load_queries(args.queries, atm.bottom_radius_m)
    if args.tables != "4d" and args.method != "tables":
        raise ValueError(f"tables: {args.tables} tables are read with --method tables, not {args.method}")
    result = _solve(atm, queries, args.method, args.quality, args.samples, args.seed,
                    cache=_table_cache(args) if args.method == "tables" else None, tables=args.tables)
    extra = {"radiance_stderr": result.stderr} if args.method == "reference" else {}
    np.savez(args.out, radiance=result.radiance, transmittance=result.transmittance,
             wavelengths_nm=np.asarray(atm.wavelengths_nm, dtype=float), **extra)
    how = {"reference": f"{result.samples} paths per ray", "tables": f"{args.quality} tables",
           "quick": f"{result.samples} samples per path, single scattering"}[args.method]
    print(f"wrote {args.out}: {len(queries.camera_m)} rays x {atm.n_wavelengths} wavelengths ({args.method}, {how})")
    return 0


def _cmd_sun(args) -> int:
    """The Sun's geometric elevation and azimuth for a site and a time (planetviz/model/sun.py)."""
    import json
    from ..model.sun import parse_site, parse_time, sun_position
    latitude, longitude = parse_site(args.site)
    time = parse_time(args.time)
    elevation, azimuth = sun_position(latitude, longitude, time)
    if args.json:
        print(json.dumps({"elevation_deg": elevation, "azimuth_deg": azimuth}))
    else:
        print(f"sun seen from {latitude:g}, {longitude:g} at {time.isoformat()}: elevation {elevation:.4f} deg, "
              f"azimuth {azimuth:.4f} deg from north through east (geometric, no refraction; NREL SPA)")
    return 0


def _cmd_queries(args) -> int:
    from ..model.queries import site_queries
    atm = load_atmosphere(args.atmosphere)
    q = site_queries(atm.bottom_radius_m, args.latitude, args.longitude, args.altitude, args.sun_elevation,
                     args.sun_azimuth, args.elevations, args.azimuths)
    np.savez(args.out, camera_m=q.camera_m, view_dir=q.view_dir, sun_dir=q.sun_dir[0])
    print(f"wrote {args.out}: {len(q.camera_m)} views from {args.altitude:g} m above ({args.latitude:g}, "
          f"{args.longitude:g}) on {atm.name}, sun {args.sun_elevation:g} deg up at azimuth {args.sun_azimuth:g}")
    return 0


def _cmd_sky(args) -> int:
    """The sky seen from eye height at a site on the equator (latitude and longitude 0), with the sun at
    ``--sun-elevation`` and ``--sun-azimuth`` (from north through east, as everywhere): six views named by
    their place relative to the sun, by the reference solver."""
    from ..model.color import radiance_to_srgb
    from ..model.geometry import local_frame, site_direction
    from ..reference import ground_sun_transmittance, solve
    from .probe import readings
    atm = load_atmosphere(args.atmosphere)
    sun = site_direction(args.sun_elevation, args.sun_azimuth)
    camera = (atm.bottom_radius_m + EYE_HEIGHT_M) * local_frame(0.0, 0.0)[0]
    relative = {"zenith": (90, 0), "45 deg toward sun": (45, 0), "45 deg away from sun": (45, 180),
                "horizon toward sun": (2, 0), "horizon at 90 deg": (2, 90), "horizon away from sun": (2, 180)}
    views = {name: (e, (args.sun_azimuth + a) % 360.0) for name, (e, a) in relative.items()}
    dirs = np.array([site_direction(e, a) for e, a in views.values()])
    res = solve(atm, np.repeat(camera[None], len(dirs), 0), dirs, sun,
                samples=REFERENCE_SAMPLES[args.quality], seed=args.seed)
    rgb = radiance_to_srgb(res.radiance, atm)
    print(f"{atm.name}: sky seen from {EYE_HEIGHT_M:g} m above the ground, sun {args.sun_elevation:g} deg above the "
          f"horizon at azimuth {args.sun_azimuth:g} deg (reference solver, {res.samples} paths per ray)")
    print(f"{'view':>22}  {'el, az [deg]':>12}  " + "  ".join(f"L({lam:g} nm) [1/sr]" for lam in atm.wavelengths_nm) + "   sRGB (8-bit)")
    for k, name in enumerate(views):
        vals = "  ".join(f"{v:10.4e} +- {e:7.1e}" for v, e in zip(res.radiance[k], res.stderr[k]))
        el, az = views[name]
        print(f"{name:>22}  {el:5g}, {az:5g}  {vals}   {tuple(int(c) for c in rgb[k])}")
    print(f"{'view':>22}  {'luminance':>12}  {'linear sRGB [cd/m^2 scale]':>26}  spectral radiance "
          "[W m^-2 sr^-1 nm^-1] (the star's spectrum)")
    for name, reading in zip(views, readings(res.radiance, atm, camera, dirs, "reference solver")):
        rgb_text = ", ".join(f"{c:.4g}" for c in reading.linear_srgb)
        print(f"{name:>22}  {reading.luminance:7.4g} cd/m2  {rgb_text:>26}  "
              + "  ".join(f"{v:.4e}" for v in reading.spectral_radiance))
    sun_t = ground_sun_transmittance(atm, args.sun_elevation)[0]
    print(f"{'sun disc transmittance':>22}  {'':>12}  " + "  ".join(f"{t:10.4f}" + " " * 11 for t in sun_t)
          + f"   ({atm.air_mass} air mass)")
    print("(radiance per unit solar irradiance at the top of the atmosphere; colour: spectral radiance x star "
          "spectrum -> CIE XYZ -> sRGB, exposure so that the brightest view is 0.8)")
    return 0


class _ProgressBar:
    """One line per stage on a terminal-less stream: 'stage [#####.....] 50%', redrawn with \r."""

    def __init__(self, stream):
        self.stream, self.stage = stream, None

    def __call__(self, stage, fraction):
        if stage != self.stage and self.stage is not None:
            self.stream.write("\n")
        self.stage = stage
        filled = int(round(30 * fraction))
        self.stream.write(f"\r{stage:<34} [{'#' * filled}{'.' * (30 - filled)}] {100 * fraction:5.1f}%")
        self.stream.flush()


def _cmd_precompute(args) -> int:
    from ..tables.precompute import QUALITY, precompute
    from ..tables.validated import outside_validated_range
    atm = load_atmosphere(args.atmosphere)
    for condition in outside_validated_range(atm):
        print(f"warning: {condition.message(atm, args.quality)}", file=sys.stderr)
    bar = _ProgressBar(sys.stdout)
    cache = _table_cache(args)
    tables = precompute(atm, QUALITY[args.quality], progress=bar, cache=cache)
    print()
    for stage, seconds in tables.timings.items():
        how = "computed" if stage in tables.computed else "from the cache"
        print(f"{stage:<22} {seconds:8.2f} s   {how}")
    print(f"{'total':<22} {sum(tables.timings.values()):8.2f} s   ({tables.orders} scattering orders)")
    sizes = {"transmittance": tables.optical_depth, "scattering share": tables.scattering_share,
             "irradiance": tables.irradiance,
             "single Rayleigh": tables.rayleigh, "single Mie": tables.mie, "multiple": tables.multiple}
    for name, table in sizes.items():
        print(f"{name:<22} {str(table.shape):<26} {table.nbytes / 1e6:8.2f} MB")
    print(f"{'table memory':<22} {tables.nbytes / 1e6:8.2f} MB (float32)")
    if cache is not None:
        print(f"cache: {cache.directory}")
    return 0


def build_parser() -> argparse.ArgumentParser:
    presets = ", ".join(PRESETS)
    parser = _Parser(prog="planetviz", description="Planets with physically based atmospheres.")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)

    p = sub.add_parser("sky", help="print the sky seen from the ground (the default Earth sky)")
    p.add_argument("--atmosphere", default="earth", help=f"preset ({presets}) or JSON file")
    p.add_argument("--sun-elevation", type=float, default=30.0, help="degrees above the horizon")
    p.add_argument("--sun-azimuth", type=float, default=180.0, help="from north through east [deg]")
    p.add_argument("--quality", choices=REFERENCE_SAMPLES, default="draft")
    p.add_argument("--seed", type=int, default=0)
    p.set_defaults(func=_cmd_sky)

    p = sub.add_parser("atmosphere", help="print the derived standard-mode coefficients and optical depths")
    p.add_argument("atmosphere", metavar="PRESET_OR_FILE", help=f"preset ({presets}) or JSON file")
    p.set_defaults(func=_cmd_atmosphere)

    p = sub.add_parser("precompute", help="compute the scattering tables, with timings and memory")
    p.add_argument("--atmosphere", required=True, help=f"preset ({presets}) or JSON file")
    p.add_argument("--quality", choices=("draft", "standard", "high"), default="standard")
    p.add_argument("--no-cache", action="store_true", help="neither read nor write the table cache")
    p.set_defaults(func=_cmd_precompute)

    p = sub.add_parser("sun", help="print the Sun's elevation and azimuth for a site on Earth and a time")
    p.add_argument("--site", required=True, help="LAT,LON [deg], north and east positive")
    p.add_argument("--time", required=True, help="ISO 8601 (with an offset, or UTC), or now")
    p.add_argument("--json", action="store_true", help='print {"elevation_deg": ..., "azimuth_deg": ...}')
    p.set_defaults(func=_cmd_sun)

    p = sub.add_parser("queries", help="write a queries file (Q.npz) of views from one site, for radiance")
    p.add_argument("--atmosphere", default="earth", help=f"preset ({presets}) or JSON file (its ground radius)")
    p.add_argument("--out", required=True, help="output npz (camera_m, view_dir, sun_dir)")
    p.add_argument("--latitude", type=float, default=0.0, help="site [deg]")
    p.add_argument("--longitude", type=float, default=0.0, help="site [deg]")
    p.add_argument("--altitude", type=float, default=EYE_HEIGHT_M, help="camera above the ground [m]")
    p.add_argument("--sun-elevation", type=float, default=30.0, help="seen from the site [deg]")
    p.add_argument("--sun-azimuth", type=float, default=180.0, help="from north through east [deg]")
    p.add_argument("--elevations", type=float, nargs="+", default=[90.0, 45.0, 10.0, 2.0],
                   help="view elevations [deg] (90: the zenith, once)")
    p.add_argument("--azimuths", type=float, nargs="+", default=[0.0, 90.0, 180.0, 270.0],
                   help="view azimuths from north through east [deg]")
    p.set_defaults(func=_cmd_queries)

    p = sub.add_parser("radiance", help="radiance for a set of rays (Q.npz -> OUT.npz)")
    p.add_argument("--atmosphere", required=True, help=f"preset ({presets}) or JSON file")
    p.add_argument("--queries", required=True, help="npz with camera_m, view_dir, sun_dir")
    p.add_argument("--out", required=True, help="output npz (radiance, transmittance, wavelengths_nm)")
    p.add_argument("--method", choices=("reference", "tables", "quick"), default="reference")
    p.add_argument("--tables", choices=TABLE_KINDS, default="4d",
                   help="tables: the 4D tables or the compact ones made from them (docs/benchmarks.md)")
    p.add_argument("--quality", choices=("draft", "standard", "high"), default="standard")
    p.add_argument("--samples", type=int, default=None,
                   help="reference: paths per ray (overrides --quality); quick: points per path (default 8)")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--no-cache", action="store_true", help="neither read nor write the table cache (tables)")
    p.set_defaults(func=_cmd_radiance)

    p = sub.add_parser("render", help="render the planet off-screen: PNG, OpenEXR, batches, dome, panorama")
    add_render_options(p)
    p.set_defaults(func=run_render)
    return parser


def main(argv=None) -> int:
    args = build_parser().parse_args(argv)
    try:
        return args.func(args)
    except ValueError as exc:
        print(f"planetviz: error: {exc}", file=sys.stderr)
        return 2
    except OSError as exc:
        print(f"planetviz: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
