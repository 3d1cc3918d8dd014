"""Energy the tables lose: the upward flux at the top of a conservative atmosphere, tables against reference.

    python benchmarks/energy_balance.py [--quality standard] [--samples 4096] [--set FIELD=VALUE ...] [PRESET ...]
    python benchmarks/energy_balance.py --balance [--quality standard] [--set FIELD=VALUE ...] [PRESET ...]
    python benchmarks/energy_balance.py --random SEED ... [--quality draft]

Each preset (default: earth, mars, exo-co2-thick) is made conservative as in tests/test_stability.py: no
absorbing layers, the particles' extinction equal to their scattering, a white ground (albedo 1). Every photon of
the sun's beam then leaves the atmosphere again, and the upward flux above the sub-solar point (the sun at the
zenith) is 1 per unit solar irradiance, less what leaves through grazing directions from the limb, where the
sun is lower: about 2% for the Earth. The Monte Carlo reference solver (all orders) measures that; the tables'
shortfall against it is energy lost by the precompute, order after order. ``--set`` changes one table size of
the quality level (for example ``--set multiple=4,32,128,16``) to see which resolution holds the loss.
Prints, per preset and wavelength, the tables' flux, the reference's with its standard error, and their ratio.

``--balance`` needs no reference: the ground black and the sun 60 deg up, every photon either leaves at the top
or reaches the ground, so mu_s = F_up(top) + E_sky(ground) + E_sun(ground) per unit solar irradiance, each flux
from the tables (``planetviz.validation.flux_balance``); it prints their sum over mu_s (Earth: 1.000 / 0.999 /
0.998 at standard), faster than the reference for sweeping sizes.

``--random SEED ...`` does the same balance for random legal atmospheres (``planetviz.validation.random_atmosphere``)
in their plane-parallel limit (``validation.disort.plane_parallel_twin``: a slab at most 20 km thick on a planet of
1e9 m, where nothing leaves through the sides) made conservative over a black ground, the sun 60 and 20 deg up:
the orders of scattering of any atmosphere the format allows against a conservation law, with no reference.
"""
import argparse
import time
from dataclasses import fields, replace

from planetviz.reference import solve
from planetviz.tables import QUALITY, precompute
from planetviz.tables.evaluator import sky_radiance
from planetviz.validation import (conservative, conservative_atmosphere, flux_balance, random_atmosphere,
                                  upward_flux_at_the_top)
from planetviz.validation.disort import plane_parallel_twin


def sizes(quality, settings):
    """``QUALITY[quality]`` with the ``FIELD=VALUE`` settings applied (tuples as comma-separated integers)."""
    base = QUALITY[quality]
    names = [f.name for f in fields(base)]
    changes = {}
    for item in settings:
        key, _, value = item.partition("=")
        if key not in names:
            raise SystemExit(f"--set: unknown table size {key!r}; one of {', '.join(names)}")
        kind = type(getattr(base, key))
        changes[key] = tuple(int(v) for v in value.split(",")) if kind is tuple else kind(value)
    return replace(QUALITY[quality], **changes)


def random_balance(seeds, table_sizes):
    """The black-ground balance (``flux_balance``) of random atmospheres' plane-parallel, conservative twins, the
    sun 60 and 20 deg up, with their largest vertical optical depth."""
    print("| atmosphere | largest optical depth | precompute s | balance, sun 60 deg up | sun 20 deg up |")
    print("|---|---|---|---|---|")
    for seed in seeds:
        atm = conservative(plane_parallel_twin(random_atmosphere(seed)), albedo=0.0)
        start = time.perf_counter()
        tables = precompute(atm, table_sizes, cache=None)
        seconds = time.perf_counter() - start
        cells = [" / ".join(f"{b:.3f}" for b in flux_balance(tables, atm, elevation)) for elevation in (60.0, 20.0)]
        print(f"| random-{seed} | {max(atm.vertical_optical_depth()):.3g} | {seconds:.0f} | {cells[0]} | {cells[1]} |",
              flush=True)


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("presets", nargs="*", default=["earth", "mars", "exo-co2-thick"])
    p.add_argument("--quality", default="standard", choices=list(QUALITY))
    p.add_argument("--samples", type=int, default=4096, help="reference paths per direction")
    p.add_argument("--set", dest="settings", action="append", default=[], metavar="FIELD=VALUE")
    p.add_argument("--balance", action="store_true", help="the black-ground balance, no reference")
    p.add_argument("--random", type=int, nargs="+", default=[], metavar="SEED",
                   help="the black-ground balance of these random atmospheres' plane-parallel twins")
    args = p.parse_args()
    table_sizes = sizes(args.quality, args.settings)
    print(f"quality {args.quality}" + "".join(f", {s}" for s in args.settings))
    if args.random:
        random_balance(args.random, table_sizes)
        return
    if args.balance:
        print("| preset | orders | precompute s | balance per wavelength |")
        print("|---|---|---|---|")
        for name in args.presets:
            atm = conservative_atmosphere(preset=name, albedo=0.0)
            start = time.perf_counter()
            tables = precompute(atm, table_sizes)
            seconds = time.perf_counter() - start
            values = " / ".join(f"{b:.3f}" for b in flux_balance(tables, atm))
            print(f"| {name} | {tables.orders} | {seconds:.1f} | {values} |", flush=True)
        return
    print("| preset | orders | precompute s | wavelength nm | tables | reference | tables / reference |")
    print("|---|---|---|---|---|---|---|")
    for name in args.presets:
        atm = conservative_atmosphere(preset=name)
        start = time.perf_counter()
        tables = precompute(atm, table_sizes)
        seconds = time.perf_counter() - start
        got = upward_flux_at_the_top(atm, lambda c, v, s: (sky_radiance(tables, atm, c, v, s)[0], 0.0))[0]

        def reference(c, v, s):
            res = solve(atm, c, v, s, samples=args.samples, seed=3)
            return res.radiance, res.stderr

        want, error = upward_flux_at_the_top(atm, reference, n=16)
        for k, wl in enumerate(atm.wavelengths_nm):
            print(f"| {name} | {tables.orders} | {seconds:.1f} | {wl:g} | {got[k]:.3f} | {want[k]:.3f} +- "
                  f"{error[k]:.3f} | {got[k] / want[k]:.3f} |", flush=True)


if __name__ == "__main__":
    main()
