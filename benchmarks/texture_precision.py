"""What 16-bit float tables would cost in accuracy: the NumPy evaluator on tables rounded to float16 against
the float32 tables, on the benchmark query set (Earth, standard).

    python benchmarks/texture_precision.py
"""
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from tables_pareto import query_set  # noqa: E402

from planetviz import load_atmosphere  # noqa: E402
from planetviz.tables import QUALITY, TableCache, precompute  # noqa: E402
from planetviz.tables.evaluator import sky_radiance  # noqa: E402


def main():
    atm = load_atmosphere("earth")
    q = query_set(atm)
    tables = precompute(atm, QUALITY["standard"], cache=TableCache())
    half = replace(tables, **{name: getattr(tables, name).astype(np.float16).astype(np.float32)
                              for name in ("optical_depth", "irradiance", "rayleigh", "mie", "multiple",
                                           "multiple_mie")})
    full, _ = sky_radiance(tables, atm, *q[:3])
    rounded, _ = sky_radiance(half, atm, *q[:3])
    el = q[3][:, None]
    ok = full > 1e-12
    rel = np.abs(rounded - full)[ok] / full[ok]
    print("| sun | values | RMS relative change | max | read as 0 |")
    print("|---|---|---|---|---|")
    for name, sel in (("daylight (>= 2 deg)", el >= 2), ("twilight (0 to -6 deg)", el < 2)):
        m = ok & sel
        r = np.abs(rounded - full)[m] / full[m]
        zero = np.mean(rounded[m] == 0)
        print(f"| {name} | {m.sum()} | {np.sqrt(np.mean(r ** 2)):.2e} | {r.max():.2e} | {zero:.0%} |")
    smallest = min(float(np.min(t[t > 0])) for t in (tables.rayleigh, tables.mie, tables.multiple))
    print(f"smallest positive scattering texel: {smallest:.1e} (float16: subnormal below 6.1e-5, 0 below 6e-8)")
    print(f"overall RMS {np.sqrt(np.mean(rel ** 2)):.2e}")


if __name__ == "__main__":
    main()
