"""The orders of scattering summed two ways, against their plain sum over many orders: the geometric tail of the
last order alone, and with reduced rank extrapolation (planetviz/tables/extrapolation.py, the precompute's).

    python benchmarks/orders_sum.py [--quality draft] [--orders 300] [ATMOSPHERE ...]

ATMOSPHERE: a preset, ``random-SEED`` (planetviz.validation.random_atmosphere), ``twin-SEED`` (its plane-parallel
twin, validation.disort.plane_parallel_twin) or ``conservative`` (exo-co2-thick with nothing absorbed over a white
ground, validation.conservative_atmosphere); default: twin-4 random-1 exo-co2-thick conservative. Printed per
atmosphere and way: the orders, the multiple-scattering stage's seconds, and the largest and RMS relative
difference of the molecules' and particles' tables from the plain sum of ``--orders`` orders (tolerance 0), over the
texels above 1e-3 of their wavelength's largest; and the plain sum's own remainder, its last order's geometric tail
over the sum.
"""
import argparse
import time

import numpy as np

from planetviz import load_atmosphere
from planetviz.tables import QUALITY, precompute
from planetviz.tables.multiple import multiple_scattering
from planetviz.tables.precompute import sizes_for


def atmosphere(name):
    """The atmosphere ``name`` (see the module's docstring); a preset imports nothing else of planetviz, so that
    precompute_ab.py can time commits older than planetviz.validation."""
    if name not in ("conservative",) and not name.startswith(("random-", "twin-")):
        return load_atmosphere(name)
    from planetviz.validation import conservative_atmosphere, random_atmosphere
    if name == "conservative":
        return conservative_atmosphere(preset="exo-co2-thick")
    if name.startswith("random-"):
        return random_atmosphere(int(name.split("-")[1]))
    from planetviz.validation.disort import plane_parallel_twin
    return plane_parallel_twin(random_atmosphere(int(name.split("-")[1])))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("atmospheres", nargs="*", default=["twin-4", "random-1", "exo-co2-thick", "conservative"])
    ap.add_argument("--quality", default="draft", choices=list(QUALITY))
    ap.add_argument("--orders", type=int, default=300)
    args = ap.parse_args()
    print(f"quality {args.quality}, against the plain sum of {args.orders} orders")
    print("| atmosphere | way | orders | seconds | largest | RMS |")
    print("|---|---|---|---|---|---|")
    for name in args.atmospheres:
        atm = atmosphere(name)
        sizes = sizes_for(atm, QUALITY[args.quality])
        single = precompute(atm, QUALITY[args.quality], multiple=False)
        shares = []

        def orders(**kw):
            t = time.perf_counter()
            out = multiple_scattering(single, atm, sizes.multiple, *sizes.directions, samples=sizes.multiple_samples,
                                      quadrature=sizes.quadrature, **kw)
            return np.concatenate([out.multiple, out.multiple_mie], -1), out.orders, time.perf_counter() - t

        plain, n, seconds = orders(tolerance=0.0, max_orders=args.orders,
                                   progress=lambda stage, done: shares.append(1.0 - done))
        q = shares[-2] / shares[-3] if shares[-3] > 0.0 else 0.0      # 0: the orders fell below float64's step
        axes = tuple(range(plain.ndim - 1))
        bright = plain > 1e-3 * plain.max(axis=axes)
        print(f"| {name} | plain sum | {n} | {seconds:.1f} | remainder {shares[-2] * q / (1 - q):.1e} | |", flush=True)
        for way, extrapolate in (("geometric tail", False), ("extrapolated", True)):
            got, n, seconds = orders(tolerance=sizes.tolerance, extrapolate=extrapolate)
            error = np.abs(got[bright] / plain[bright] - 1.0)
            print(f"| {name} | {way} | {n} | {seconds:.1f} | {error.max():.2%} | {np.sqrt(np.mean(error ** 2)):.3%} |",
                  flush=True)


if __name__ == "__main__":
    main()
