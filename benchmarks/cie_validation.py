"""The paper's Fig. 7: relative sky luminance L / L_z of planetviz's Earth against the CIE clear sky.

    python benchmarks/cie_validation.py [--presets earth earth-advanced] [--quality high]
                                        [--plot docs/img/cie-validation.png]

A camera 2 m above the ground; the sun at zenith angles 20, 40, 60 and 75 deg (azimuth 0); sky elements
along the solar meridian (toward the sun, azimuth 0, and away from it, azimuth 180 deg) and across it
(azimuth 90 deg), view zenith 0-88 deg. Luminance is Y of the spectral radiance (radiance per unit
irradiance at the atmosphere's wavelengths x the solar spectrum, piecewise linear between them) through
the CIE 1931 2-degree observer, whose y-bar is the luminous efficiency V(lambda) (colour-science). The
radiance comes from the precomputed tables (all orders, sun disc excluded). Printed: per sun position and
azimuth, the RMS and largest relative difference of planetviz's L / L_z from CIE types 12 and 13.
"""
import argparse
from pathlib import Path

import numpy as np

from planetviz import load_atmosphere
from planetviz.validation.cie_sky import cie_relative_luminance
from planetviz.model.color import radiance_to_xyz
from planetviz.tables import QUALITY, TableCache, precompute
from planetviz.tables.evaluator import sky_radiance

SUN_ZENITHS = (20.0, 40.0, 60.0, 75.0)
AZIMUTHS = (0.0, 180.0, 90.0)
VIEW_ZENITHS = np.arange(0.0, 88.5, 2.0)


def relative_luminance(tables, atm, sun_zenith_deg, azimuth_deg):
    """planetviz's L / L_z at VIEW_ZENITHS along one azimuth (the sun at azimuth 0)."""
    zs = np.radians(sun_zenith_deg)
    sun = np.array([np.sin(zs), 0.0, np.cos(zs)])
    z = np.radians(np.concatenate([[0.0], VIEW_ZENITHS]))
    a = np.radians(azimuth_deg)
    views = np.stack([np.sin(z) * np.cos(a), np.sin(z) * np.sin(a), np.cos(z)], 1)
    cams = np.tile([0.0, 0.0, atm.bottom_radius_m + 2.0], (len(z), 1))
    radiance, _ = sky_radiance(tables, atm, cams, views, sun)
    y = radiance_to_xyz(radiance, atm)[:, 1]
    return y[1:] / y[0]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--presets", nargs="+", default=["earth", "earth-advanced"])
    ap.add_argument("--quality", default="high", choices=list(QUALITY))
    ap.add_argument("--plot", default=None)
    args = ap.parse_args()
    curves = {}
    print("| atmosphere | sun zenith | azimuth from sun | RMS vs type 12 | max vs type 12 | "
          "RMS vs type 13 | max vs type 13 |")
    print("|---|---|---|---|---|---|---|")
    for name in args.presets:
        atm = load_atmosphere(name)
        tables = precompute(atm, QUALITY[args.quality], cache=TableCache())
        for zs in SUN_ZENITHS:
            for az in AZIMUTHS:
                model = relative_luminance(tables, atm, zs, az)
                cie = {t: cie_relative_luminance(np.radians(VIEW_ZENITHS), np.radians(az), np.radians(zs), 0.0, t)
                       for t in (12, 13)}
                curves[(name, zs, az)] = (model, cie)
                cells = []
                for t in (12, 13):
                    rel = model / cie[t] - 1.0
                    cells += [f"{np.sqrt(np.mean(rel ** 2)):.3f}", f"{rel[np.argmax(np.abs(rel))]:+.3f}"]
                print(f"| {name} | {zs:.0f} | {az:.0f} | " + " | ".join(cells) + " |", flush=True)
    if args.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, axes = plt.subplots(1, len(SUN_ZENITHS), figsize=(4.2 * len(SUN_ZENITHS), 4.0), sharey=True)
        for ax, zs in zip(axes, SUN_ZENITHS):
            for az, style in zip(AZIMUTHS, ("-", "--", ":")):
                # The meridian drawn as one line: away from the sun on the left (negative zenith angles).
                x = VIEW_ZENITHS if az != 180 else -VIEW_ZENITHS
                for i, name in enumerate(args.presets):
                    model, cie = curves[(name, zs, az)]
                    ax.plot(x, model, style, color=f"C{i}", lw=1.4,
                            label=f"planetviz {name}" if az == 0 else None)
                ax.plot(x, cie[12], style, color="k", lw=1, label="CIE type 12" if az == 0 else None)
                ax.plot(x, cie[13], style, color="0.55", lw=1, label="CIE type 13" if az == 0 else None)
            ax.set_title(f"sun zenith {zs:.0f} deg (+: toward the sun; dotted: 90 deg azimuth)", fontsize=8)
            ax.set_xlabel("view zenith [deg]")
            ax.set_yscale("log")
        axes[0].set_ylabel("L / L_zenith")
        axes[0].legend(fontsize=7)
        fig.tight_layout()
        Path(args.plot).parent.mkdir(parents=True, exist_ok=True)
        fig.savefig(args.plot, dpi=110)
        print(f"plot: {args.plot}")


if __name__ == "__main__":
    main()
