"""One random atmosphere's first two orders with each table size of the standard level changed in turn, against the
reference's first two orders stored by benchmarks/tables_orders.py: whether an error there is the tables' resolution.

    python benchmarks/orders_sizes.py --atmosphere 4 [--light day]

Printed per configuration: the relative error per ray (the suite's camera classes, 2 rays each) and wavelength
(680, 550, 440 nm), then the reference's relative standard errors. The reference must be stored (run
tables_orders.py with at least as many atmospheres of that split first; otherwise it is computed, minutes).
"""
import argparse
from dataclasses import replace

from planetviz.tables import QUALITY, precompute
from planetviz.tables.evaluator import sky_radiance
from planetviz.tables.multiple import first_two_orders
from planetviz.tables.precompute import sizes_for
from planetviz.validation import CAMERAS, LIGHT, random_atmosphere
from tables_orders import reference_orders


def variants(base):
    """{name: changes to the standard level}, each one size of ``base`` (the atmosphere's sizes) made finer."""
    n_nu, n_mu_s, n_mu, n_r = base.multiple
    return {"standard": {}, "ms nodes 8": dict(multiple_samples=8), "ms rows 32": dict(multiple=(n_nu, n_mu_s, n_mu, 32)),
            "ms mu 128": dict(multiple=(n_nu, n_mu_s, 128, n_r)), "ms mu_s 64": dict(multiple=(n_nu, 64, n_mu, n_r)),
            "dirs 16x16": dict(directions=(16, 16)), "T 512x256": dict(transmittance=(512, 256)),
            "single r 64": dict(scattering=base.scattering[:3] + (64,)), "irradiance 256x64": dict(irradiance=(256, 64))}


def row(values):
    """One line: each ray's camera class and index, then its wavelengths' strings ``values[k]``."""
    return " ".join(f"{CAMERAS[k // 2][:5]}{k % 2}:" + ",".join(values[k]) for k in range(len(values)))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--atmosphere", type=int, required=True, help="the random atmosphere's seed")
    ap.add_argument("--light", default="day", choices=list(LIGHT))
    ap.add_argument("--paths", type=int, default=16384)
    args = ap.parse_args()
    atm = random_atmosphere(args.atmosphere)
    cams, views, suns, ref = reference_orders(f"random-{args.atmosphere}", atm, args.atmosphere, args.light,
                                              args.paths)
    for name, change in variants(sizes_for(atm, QUALITY["standard"])).items():
        level = replace(QUALITY["standard"], **change)
        sizes = sizes_for(atm, level)
        two = first_two_orders(precompute(atm, level, multiple=False), atm, sizes)
        got, _ = sky_radiance(two, atm, cams, views, suns)
        print(f"{name:18s}", row([[f"{x:+.3f}" for x in e] for e in got / ref.radiance - 1.0]), flush=True)
    print(f"{'noise':18s}", row([[f"{x:.3f}" for x in e] for e in ref.stderr / ref.radiance]))


if __name__ == "__main__":
    main()
