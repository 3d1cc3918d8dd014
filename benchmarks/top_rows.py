"""The tables' single scattering and optical depth for cameras just below the top of the atmosphere, against the
reference quadrature.

    python benchmarks/top_rows.py [--atmosphere earth] [--quality standard] [--sun-elevation 28.6]

Cameras 1 m to 5 km below the top, views from 64 deg above to 64 deg below the horizontal toward the sun's
azimuth; prints the relative error of the tables' single scattering (the multiple-scattering tables set to 0)
per view (the largest over the wavelengths), against planetviz/reference/single.py (deterministic quadrature),
and of the optical-depth table's tau to the top for the views that leave through it, against
planetviz/reference/optical_depth.py.
"""
import argparse

import numpy as np

from planetviz import load_atmosphere
from planetviz.reference import optical_depth
from planetviz.tables.lookup import get_optical_depth_to_top_atmosphere_boundary
from planetviz.tables import QUALITY, TableCache, precompute
from planetviz.validation.single_scattering import altitude_rays, reference_single_scattering, single_scattering_error

MUS = (0.9, 0.3, 0.05, 0.0, -0.05, -0.3, -0.9)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--atmosphere", default="earth")
    ap.add_argument("--quality", default="standard", choices=list(QUALITY))
    ap.add_argument("--sun-elevation", type=float, default=28.6)
    args = ap.parse_args()
    atm = load_atmosphere(args.atmosphere)
    tables = precompute(atm, QUALITY[args.quality], cache=TableCache())
    print(f"{atm.name}, {args.quality}: largest relative error over the wavelengths, view cosine " + " ".join(
        f"{mu:+.2f}" for mu in MUS))
    for below in (1.0, 10.0, 100.0, 500.0, 2000.0, 5000.0):
        cams, views, suns = altitude_rays(atm, atm.thickness_m - below, MUS, (args.sun_elevation,), (0,))
        err = single_scattering_error(tables, atm, cams, views, suns,
                                      reference_single_scattering(atm, cams, views, suns))
        print(f"{below:7g} m below the top: " + " ".join(f"{e:6.3f}" for e in err))
    print("optical depth to the top, largest relative error over the wavelengths, view cosine " + " ".join(
        f"{mu:+.2f}" for mu in MUS if mu >= 0))
    for below in (1.0, 10.0, 100.0, 500.0, 2000.0, 5000.0):
        cams, views, _ = altitude_rays(atm, atm.thickness_m - below, [mu for mu in MUS if mu >= 0], (0,), (0,))
        r = np.linalg.norm(cams, axis=1)
        got = get_optical_depth_to_top_atmosphere_boundary(tables, r, np.einsum("ij,ij->i", cams, views) / r)
        want = optical_depth(atm, cams, views, np.inf)
        print(f"{below:7g} m below the top: " + " ".join(f"{e:6.4f}" for e in np.max(np.abs(got / want - 1), 1)))


if __name__ == "__main__":
    main()
