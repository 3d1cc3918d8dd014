"""Standard tables against the stored high-quality reference on the 12 daylight rays of
tests/test_tables.py::test_standard_tables_against_the_reference, per preset.

    cd benchmarks && python tables_vs_reference.py

Prints the tables' RMS relative error, the reference's RMS relative standard error beside it, and the
three largest errors.
"""
from pathlib import Path

import numpy as np

from planetviz import load_atmosphere
from planetviz.reference.montecarlo import QUALITY_SAMPLES
from planetviz.reference.stored import stored_reference
from planetviz.tables.evaluator import sky_radiance
from planetviz.tables.precompute import QUALITY, precompute
from planetviz.validation import daylight_check_rays

DATA = Path(__file__).resolve().parent / "data"


def main():
    for preset in ("earth", "mars", "exo-co2-thick"):
        atm = load_atmosphere(preset)
        r = atm.bottom_radius_m
        cams, views, sun = daylight_check_rays(atm)
        ref = stored_reference(DATA, f"tables-{preset}", atm, cams, views, sun, samples=QUALITY_SAMPLES["high"], seed=21)
        tables, _ = sky_radiance(precompute(atm, QUALITY["standard"]), atm, cams, views, sun)
        rel = (tables - ref.radiance) / ref.radiance
        noise = ref.stderr / ref.radiance
        worst = rel.ravel()[np.argsort(-np.abs(rel.ravel()))[:3]]
        print(f"{preset}: RMS {np.sqrt(np.mean(rel ** 2)):.4f} (reference noise RMS {np.sqrt(np.mean(noise ** 2)):.4f}, "
              f"max {noise.max():.4f}); largest {np.round(worst, 3)}")
        for k in range(len(cams)):
            print(f"  camera {cams[k, 2] - r:9.0f} m, view {np.round(views[k], 2)}: "
                  + " ".join(f"{e:+.3f}" for e in rel[k]) + "  (noise " + " ".join(f"{x:.3f}" for x in noise[k]) + ")")


if __name__ == "__main__":
    main()
