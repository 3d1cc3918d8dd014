"""Energy the tables lose: the upward flux at the top of a conservative atmosphere, tables against reference.

    python benchmarks/energy_balance.py [--quality standard] [--samples 4096] [--set FIELD=VALUE ...] [PRESET ...]
    python benchmarks/energy_balance.py --balance [--quality standard] [--set FIELD=VALUE ...] [PRESET ...]

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
from the tables (48 x 64 directions per hemisphere); it prints their sum over mu_s (Earth: 1.000 / 0.999 /
0.997 at standard), faster than the reference for sweeping sizes.
"""
import argparse
import sys
import time
from dataclasses import fields, replace
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from planetviz import load_atmosphere  # noqa: E402
from planetviz.reference import solve  # noqa: E402
from planetviz.tables import QUALITY, precompute  # noqa: E402
from planetviz.tables.evaluator import sky_radiance  # noqa: E402
from planetviz.tables.lookup import get_transmittance_to_sun  # noqa: E402
from test_stability import upward_flux_at_the_top  # noqa: E402


def conservative(name, albedo=1.0):
    """The preset ``name`` with nothing absorbed and a ground of ``albedo`` (white by default)."""
    d = load_atmosphere(name).to_dict()
    d["name"] = f"{name}-conservative"
    d["absorption"] = []
    d["mie"]["extinction_m"] = list(d["mie"]["scattering_m"])
    d["ground_albedo"] = [albedo] * len(d["wavelengths_nm"])
    return type(load_atmosphere(name)).from_dict(d)


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


def balance(atm, tables, elevation_deg=60.0, n_mu=48, n_phi=64):
    """(F_up(top) + E_sky(ground) + E_sun(ground)) / mu_s (W,): fluxes from the tables, Gauss-Legendre in mu and
    the midpoint rule in azimuth over each hemisphere, 1 m inside the top and above the ground."""
    x, w = np.polynomial.legendre.leggauss(n_mu)
    mu, phi = np.meshgrid(0.5 * (x + 1.0), (np.arange(n_phi) + 0.5) * 2 * np.pi / n_phi, indexing="ij")
    weight = (np.outer(0.5 * w, np.full(n_phi, 2 * np.pi / n_phi)) * mu).reshape(-1, 1)
    sin = np.sqrt(1.0 - mu * mu)
    up = np.stack([sin * np.cos(phi), sin * np.sin(phi), mu], -1).reshape(-1, 3)
    mu_s = np.sin(np.radians(elevation_deg))
    sun = np.array([np.cos(np.radians(elevation_deg)), 0.0, mu_s])
    total = 0.0
    for r, views in ((tables.top - 1.0, up * [1.0, 1.0, -1.0]), (tables.bottom + 1.0, up)):
        radiance, _ = sky_radiance(tables, atm, np.tile([0.0, 0.0, r], (len(views), 1)), views, sun)
        total = total + (radiance * weight).sum(0)
    direct = get_transmittance_to_sun(tables, np.array([tables.bottom + 1.0]), np.array([mu_s]))[0] * mu_s
    return (total + direct) / mu_s


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("presets", nargs="*", default=["earth", "mars", "exo-co2-thick"])
    p.add_argument("--quality", default="standard", choices=list(QUALITY))
    p.add_argument("--samples", type=int, default=4096, help="reference paths per direction")
    p.add_argument("--set", dest="settings", action="append", default=[], metavar="FIELD=VALUE")
    p.add_argument("--balance", action="store_true", help="the black-ground balance, no reference")
    args = p.parse_args()
    table_sizes = sizes(args.quality, args.settings)
    print(f"quality {args.quality}" + "".join(f", {s}" for s in args.settings))
    if args.balance:
        print("| preset | orders | precompute s | balance per wavelength |")
        print("|---|---|---|---|")
        for name in args.presets:
            atm = conservative(name, albedo=0.0)
            start = time.perf_counter()
            tables = precompute(atm, table_sizes)
            seconds = time.perf_counter() - start
            values = " / ".join(f"{b:.3f}" for b in balance(atm, tables))
            print(f"| {name} | {tables.orders} | {seconds:.1f} | {values} |", flush=True)
        return
    print("| preset | orders | precompute s | wavelength nm | tables | reference | tables / reference |")
    print("|---|---|---|---|---|---|---|")
    for name in args.presets:
        atm = conservative(name)
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
