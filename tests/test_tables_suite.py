"""The tables on random legal atmospheres, per ray class and split (benchmarks/tables_suite.py's rays and stored
references): what holds of the targets, with bounds set by the references' own error."""
import numpy as np
import pytest
from conftest import REFERENCE_DATA

from planetviz.reference.stored import stored_reference
from planetviz.tables import QUALITY, precompute
from planetviz.tables.evaluator import sky_radiance
from planetviz.validation import CAMERAS, SPLITS, random_atmosphere, rays
from planetviz.validation.single_scattering import reference_single_scattering, single_scattering_only

#: The targets of the standard tables per light class: RMS relative error per ray class.
TARGET_RMS = {"day": 0.01, "twilight": 0.03, "deep-twilight": 0.05}

#: The daylight target's 95th percentile of the relative error per ray class.
TARGET_P95_DAY = 0.03


@pytest.mark.slow
@pytest.mark.parametrize("light", list(TARGET_RMS))
@pytest.mark.parametrize("split", list(SPLITS))
def test_first_order_meets_the_target_in_every_class(split, light):
    # The standard tables' first order (single scattering and the directly lit ground) against the reference
    # quadrature (reference/single.py, relative error below 1e-4: no noise), on benchmarks/tables_suite.py's
    # rays of the light class and the split's first 8 random atmospheres, the difference relative to the whole
    # radiance (the stored 4096-path reference, all orders; its noise, 0.5-3% by day, only scales the figure).
    # Bound: the light class's target for all orders itself, per camera class, which the first order must meet
    # on its own; by day also every value within the target's 95th percentile (3%), which 5% of a class's values
    # may exceed only if the other orders bring them back. With the transmittance table at 64 r rows instead of
    # 128 the held-out split's ground ray along the horizon of random atmosphere 100000 (radius 1.4e8 m, optical
    # depth 3 at 440 nm) read 4.0% of the whole radiance low. Where the tables were read for the first order of
    # the twilight rays, the classes read 3-12% RMS (twilight) and up to 184 times the whole radiance (deep twilight, limb rays in the planet's shadow); by day,
    # tables that held S instead of S / (1 - T) read the class within 100 m of the top 19.6% (tuning) and 21.4%
    # (held-out) RMS off, relative to the first order alone. The orders above the first are not checked here
    # (the reference's noise, 0.5-3% per class at 4096 paths by day, is above a third of the target).
    errors = {camera: [] for camera in CAMERAS}
    for seed in list(SPLITS[split])[:8]:
        atm = random_atmosphere(seed)
        tables = single_scattering_only(precompute(atm, QUALITY["standard"], multiple=False))
        batch = [rays(atm, seed, camera, light, n=2) for camera in CAMERAS]
        cams, views, suns = (np.concatenate(x) for x in zip(*batch))
        total = stored_reference(REFERENCE_DATA / "suite", f"random-{seed}-{light}", atm, cams, views, suns,
                                 samples=4096, seed=seed + 7).radiance
        got, _ = sky_radiance(tables, atm, cams, views, suns)
        want = reference_single_scattering(atm, cams, views, suns)
        for k, camera in enumerate(np.repeat(CAMERAS, 2)):
            lit = total[k] > 1e-12
            errors[camera].append((got[k] - want[k])[lit] / total[k][lit])
    rms = {camera: float(np.sqrt(np.mean(np.concatenate(e) ** 2))) for camera, e in errors.items()}
    assert max(rms.values()) <= TARGET_RMS[light], rms
    if light == "day":
        worst = {camera: float(np.max(np.abs(np.concatenate(e)))) for camera, e in errors.items()}
        assert max(worst.values()) <= TARGET_P95_DAY, worst
