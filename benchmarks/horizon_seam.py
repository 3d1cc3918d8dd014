"""The seam at the horizon's direction on denser rays than the test's: error next to the horizon against away.

    python benchmarks/horizon_seam.py [--quality standard] [--altitudes 300 1000 ...]

The seam test (tests/test_stability.py) compares the tables' single scattering on 9 rays 1e-6 to 1e-2 (in mu)
either side of the horizon with the same error on rays at least 0.05 away, 5 azimuths x 3 suns. Its 9 offsets
may miss the middle of a texel interval, where interpolation errs most. Here: 46 offsets from 1e-6 to 3e-2
above the horizon, the sun 5 and 20 deg up, toward it and away from it, against the reference quadrature
(reference/single.py), beside the test's own away set. Prints per altitude the largest error at offsets up to
1e-2 (and the offset), at 1e-2 to 3e-2 (not part of the test's near set), away, and near over away (the test
allows 1.25). Takes about a minute per altitude (the reference quadrature).
"""
import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from planetviz.reference.single import single_scattering  # noqa: E402
from planetviz.tables import QUALITY, precompute  # noqa: E402
from planetviz.tables.evaluator import sky_radiance  # noqa: E402
from test_stability_horizon import EARTH, R, _single_scattering_error, single_scattering_only  # noqa: E402

OFFSETS = np.logspace(-6, -1.5, 46)


def dense_error(tables, alt):
    """(offsets, per-ray largest relative error over the wavelengths) of the single scattering on the dense rays."""
    mu_h = -np.sqrt(1 - (R / (R + alt)) ** 2)
    mu, az, el = (a.ravel() for a in np.meshgrid(mu_h + OFFSETS, np.radians([0, 180]), np.radians([5, 20]),
                                                 indexing="ij"))
    views = np.stack([np.sqrt(1 - mu ** 2) * np.cos(az), np.sqrt(1 - mu ** 2) * np.sin(az), mu], 1)
    suns = np.stack([np.cos(el), 0 * el, np.sin(el)], 1)
    cams = np.tile([0.0, 0.0, R + alt], (len(mu), 1))
    scatter, ground = single_scattering(EARTH, cams, views, suns)
    got, _ = sky_radiance(single_scattering_only(tables), EARTH, cams, views, suns)
    want = scatter + ground
    return np.repeat(OFFSETS, 4), np.max(np.abs(got - want) / want, axis=1)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quality", default="standard", choices=sorted(QUALITY))
    ap.add_argument("--altitudes", type=float, nargs="+",
                    default=[300, 1e3, 2e3, 3e3, 5e3, 7e3, 1e4, 1.5e4, 2e4, 3e4, 5e4])
    args = ap.parse_args()
    tables = precompute(EARTH, QUALITY[args.quality])
    print("| altitude [m] | near (<= 1e-2) | at offset | 1e-2 to 3e-2 | away | near / away |")
    print("|---|---|---|---|---|---|")
    for alt in args.altitudes:
        mu_h = -np.sqrt(1 - (R / (R + alt)) ** 2)
        away = _single_scattering_error(alt, np.concatenate([np.linspace(-1, mu_h - 0.05, 12),
                                                             np.linspace(mu_h + 0.05, 1, 12)]), tables).max()
        offsets, err = dense_error(tables, alt)
        near, far = err[offsets <= 1e-2], err[offsets > 1e-2]
        at = offsets[offsets <= 1e-2][np.argmax(near)]
        print(f"| {alt:g} | {100 * near.max():.2f}% | {at:.1e} | {100 * far.max():.2f}% | {100 * away:.2f}% | "
              f"{near.max() / away:.2f} |", flush=True)


if __name__ == "__main__":
    main()
