"""The tables against the reference solver on random legal atmospheres and the presets, per ray class, for the
tuning and the held-out split.

    python benchmarks/tables_suite.py [--split tuning held-out] [--atmospheres 8] [--rays 2] [--quality standard]
                                      [--paths 4096] [--presets earth mars exo-co2-thick] [--worst 10] [--single]
                                      [--conditions] [--multiple N_NU N_MU_S N_MU N_R]
                                      [--scattering N_NU N_MU_S N_MU N_R]
                                      [--quadrature hemispheres|horizon|lit-band]
                                      [--collisions extinction|scattering]

Atmospheres: planetviz.validation.random_atmosphere over the first ``--atmospheres`` seeds of each split (the
held-out split's seeds are never read while tuning), and the presets with the tuning split. Rays:
planetviz.validation.rays, ``--rays`` per camera class (ground, aircraft, stratosphere, within 100 m of the top,
the disc and the limb from space) and light class (the sun's elevation where the ray looks: day >= 2 deg,
twilight 0 to -6 deg, deep twilight -6 to -18 deg). The reference (``--paths`` per ray and wavelength) is stored
in benchmarks/data/suite/ and recomputed only when the atmosphere, the rays or the solver change; the tables come
from the table cache. ``--collisions``: how the reference draws its collisions (``solve``'s ``collisions``; by
default the solver's; the others' results in benchmarks/data/suite-<collisions>/).

Printed per split, light class and camera class: the number of values (ray x wavelength, where the reference is
above 1e-12 / sr), the RMS and the 95th percentile of the tables' relative error, and the RMS of the reference's
relative standard error. An RMS error counts when that noise is at most a third of it; otherwise the row reads
"below resolution". Then the ``--worst`` largest errors with their atmosphere and ray.

``--single`` compares instead the tables' first order (single scattering and the directly lit ground, the
multiple-scattering and sky-irradiance tables set to 0) with the deterministic quadrature of
planetviz/reference/single.py, which has no noise (relative error below 1e-4): most of the light by day, and
resolvable at any level. The difference is taken relative to the whole radiance (the stored reference's, all
orders), so that a ray whose first order is a small part of its light (the twilight sky seen from the planet's
shadow) weighs by that part; the noise column is then 0. ``--scattering`` and ``--multiple`` set the single- and
the multiple-scattering tables' sizes (n_nu, n_mu_s, n_mu, n_r) in place of the quality level's, ``--quadrature``
the kind of the scattering density's direction quadrature (``planetviz.tables.multiple.QUADRATURES``).
"""
import argparse
from dataclasses import replace
from pathlib import Path

import numpy as np

from planetviz import load_atmosphere
from planetviz.reference.montecarlo import COLLISIONS, DEFAULT_COLLISIONS
from planetviz.reference.stored import stored_reference
from planetviz.tables import QUALITY, TableCache, precompute
from planetviz.tables.evaluator import sky_radiance
from planetviz.tables.multiple import QUADRATURES
from planetviz.validation import CAMERAS, LIGHT, SPLITS, random_atmosphere, rays
from planetviz.tables.validated import CONDITIONS
from planetviz.validation.single_scattering import reference_single_scattering, single_scattering_only

DATA = Path(__file__).resolve().parent / "data" / "suite"


def data_folder(base, collisions):
    """Where references whose collisions are drawn as ``collisions`` says are stored: ``base`` for the solver's
    default, ``base``-<collisions> for the other way."""
    return base if collisions == DEFAULT_COLLISIONS else base.with_name(f"{base.name}-{collisions}")


def cases(split, count, presets):
    """(name, atmosphere, seed) of a split: its first ``count`` random atmospheres, and the presets (tuning)."""
    for seed in list(SPLITS[split])[:count]:
        yield f"random-{seed}", random_atmosphere(seed), seed
    if split == "tuning":
        for name in presets:
            yield name, load_atmosphere(name), 0


def compare(split, args):
    """Rows (atmosphere, camera class, light class, camera altitude [m], relative error (W,), relative noise (W,))."""
    rows = []
    cache = TableCache()
    sizes = QUALITY[args.quality]
    if args.multiple:
        sizes = replace(sizes, multiple=tuple(args.multiple))
    if args.scattering:
        sizes = replace(sizes, scattering=tuple(args.scattering))
    if args.quadrature:
        sizes = replace(sizes, quadrature=args.quadrature)
    if args.transmittance:
        sizes = replace(sizes, transmittance=tuple(args.transmittance))
    folder = data_folder(DATA, args.collisions)
    for name, atm, seed in cases(split, args.atmospheres, args.presets):
        tables = precompute(atm, sizes, cache=cache)
        for light in LIGHT:
            batch = [rays(atm, seed, camera, light, n=args.rays) for camera in CAMERAS]
            cams, views, suns = (np.concatenate(x) for x in zip(*batch))
            ref = stored_reference(folder, f"{name}-{light}", atm, cams, views, suns, samples=args.paths,
                                   seed=seed + 7, collisions=args.collisions)
            total, noise = ref.radiance, ref.stderr
            if args.single:
                want_all = reference_single_scattering(atm, cams, views, suns)
                noise = np.zeros_like(noise)
                got, _ = sky_radiance(single_scattering_only(tables), atm, cams, views, suns)
            else:
                want_all = total
                got, _ = sky_radiance(tables, atm, cams, views, suns)
            for k in range(len(cams)):
                ok = total[k] > 1e-12
                rows.append((name, CAMERAS[k // args.rays], light, float(np.linalg.norm(cams[k]) - atm.bottom_radius_m),
                             (got[k][ok] - want_all[k][ok]) / total[k][ok], noise[k][ok] / total[k][ok]))
        print(f"  {split}: {name} done", flush=True)
    return rows


def report(split, rows, worst):
    print(f"\n{split} split: {len({r[0] for r in rows})} atmospheres")
    print("| light | camera | values | RMS error | p95 error | reference noise (RMS) |")
    print("|---|---|---|---|---|---|")
    for light in LIGHT:
        for camera in (*CAMERAS, "all"):
            sel = [r for r in rows if r[2] == light and camera in (r[1], "all")]
            err = np.concatenate([r[4] for r in sel]) if sel else np.zeros(0)
            noise = np.concatenate([r[5] for r in sel]) if sel else np.zeros(0)
            if not err.size:
                continue
            rms, p95, n_rms = np.sqrt(np.mean(err ** 2)), np.percentile(np.abs(err), 95), np.sqrt(np.mean(noise ** 2))
            figure = f"{100 * rms:.2f}%" if n_rms <= rms / 3 else f"below resolution ({100 * rms:.2f}%)"
            print(f"| {light} | {camera} | {err.size} | {figure} | {100 * p95:.2f}% | {100 * n_rms:.2f}% |")
    flat = [(abs(e), e, n, r) for r in rows for e, n in zip(r[4], r[5])]
    print(f"\nlargest errors ({split}):")
    for _, e, n, r in sorted(flat, key=lambda x: -x[0])[:worst]:
        print(f"  {e:+.3f} (noise {n:.3f})  {r[0]}, {r[1]} ({r[3]:.4g} m), {r[2]}")


def report_conditions(rows_by_split, atmospheres):
    """Daylight errors grouped by planetviz.tables.validated's conditions (an atmosphere in every group whose
    condition it meets, "none" for those inside the validated range), over both splits: what CONDITIONS carries."""
    print("\n| condition | atmospheres | values | RMS error | p95 error | reference noise (RMS) |")
    print("|---|---|---|---|---|---|")
    rows = [r for split_rows in rows_by_split for r in split_rows if r[2] == "day"]
    groups = {c.name: [n for n, atm in atmospheres.items() if c.measure(atm) > c.limit] for c in CONDITIONS}
    groups["none"] = [n for n in atmospheres if not any(n in g for g in groups.values())]
    for name, members in groups.items():
        err = np.concatenate([r[4] for r in rows if r[0] in members] or [np.zeros(0)])
        noise = np.concatenate([r[5] for r in rows if r[0] in members] or [np.zeros(0)])
        if err.size:
            print(f"| {name} | {', '.join(members)} | {err.size} | {100 * np.sqrt(np.mean(err ** 2)):.2f}% | "
                  f"{100 * np.percentile(np.abs(err), 95):.2f}% | {100 * np.sqrt(np.mean(noise ** 2)):.2f}% |")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--split", nargs="+", default=list(SPLITS), choices=list(SPLITS))
    ap.add_argument("--atmospheres", type=int, default=8)
    ap.add_argument("--rays", type=int, default=2)
    ap.add_argument("--quality", default="standard", choices=list(QUALITY))
    ap.add_argument("--paths", type=int, default=4096)
    ap.add_argument("--presets", nargs="*", default=["earth", "mars", "exo-co2-thick"])
    ap.add_argument("--worst", type=int, default=10)
    ap.add_argument("--collisions", default=DEFAULT_COLLISIONS, choices=COLLISIONS)
    ap.add_argument("--single", action="store_true", help="the first order against the reference quadrature")
    ap.add_argument("--conditions", action="store_true",
                    help="also the daylight errors grouped by planetviz.tables.validated's conditions")
    ap.add_argument("--multiple", type=int, nargs=4, metavar=("N_NU", "N_MU_S", "N_MU", "N_R"),
                    help="the multiple-scattering tables' size instead of the quality level's")
    ap.add_argument("--scattering", type=int, nargs=4, metavar=("N_NU", "N_MU_S", "N_MU", "N_R"),
                    help="the single-scattering tables' size instead of the quality level's")
    ap.add_argument("--transmittance", type=int, nargs=2, metavar=("N_MU", "N_R"),
                    help="the transmittance table's size instead of the quality level's")
    ap.add_argument("--quadrature", choices=list(QUADRATURES),
                    help="the scattering density's direction quadrature instead of the quality level's")
    args = ap.parse_args()
    results = []
    for split in args.split:
        results.append(compare(split, args))
        report(split, results[-1], args.worst)
    if args.conditions:
        report_conditions(results, {name: atm for split in args.split
                                    for name, atm, _ in cases(split, args.atmospheres, args.presets)})


if __name__ == "__main__":
    main()
