"""The seam at the horizon's direction on denser rays than the test's: error next to the horizon against away.

    python benchmarks/horizon_seam.py [--quality standard] [--altitudes 300 1000 ...]

The seam test (tests/test_stability_horizon.py) compares the tables' single scattering on 9 rays 1e-6 to 1e-2 (in mu)
either side of the horizon with the same error on rays at least 0.05 away, 5 azimuths x 3 suns. Its 9 offsets
may miss the middle of a texel interval, where interpolation errs most. Here: 46 offsets from 1e-6 to 3e-2
above the horizon, the sun 5 and 20 deg up, toward it and away from it, against the reference quadrature
(reference/single.py), beside the test's own away set. Prints per altitude the largest error at offsets up to
1e-2 (and the offset), at 1e-2 to 3e-2 (not part of the test's near set), away, and near over away (the test
allows 1.25). Takes about a minute per altitude (the reference quadrature).
"""
import argparse

import numpy as np

from planetviz import load_atmosphere
from planetviz.tables import QUALITY, precompute
from planetviz.validation.single_scattering import altitude_rays, reference_single_scattering, single_scattering_error

EARTH = load_atmosphere("earth")
R = EARTH.bottom_radius_m
OFFSETS = np.logspace(-6, -1.5, 46)


def error(tables, alt, mus, sun_elevations_deg=(5, 20, 60), azimuths_deg=(0, 45, 90, 135, 180)):
    """Per ray, the largest relative error over the wavelengths of the tables' single scattering."""
    cams, views, suns = altitude_rays(EARTH, alt, mus, sun_elevations_deg, azimuths_deg)
    return single_scattering_error(tables, EARTH, cams, views, suns,
                                   reference_single_scattering(EARTH, cams, views, suns))


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
        away = error(tables, alt, np.concatenate([np.linspace(-1, mu_h - 0.05, 12),
                                                  np.linspace(mu_h + 0.05, 1, 12)])).max()
        offsets = np.repeat(OFFSETS, 4)
        err = error(tables, alt, mu_h + OFFSETS, (5, 20), (0, 180))
        near, far = err[offsets <= 1e-2], err[offsets > 1e-2]
        at = offsets[offsets <= 1e-2][np.argmax(near)]
        print(f"| {alt:g} | {100 * near.max():.2f}% | {at:.1e} | {100 * far.max():.2f}% | {100 * away:.2f}% | "
              f"{near.max() / away:.2f} |", flush=True)


if __name__ == "__main__":
    main()
