"""The tables on random legal atmospheres, per ray class and split (benchmarks/tables_suite.py's rays and stored
references): what holds of the daylight targets, with bounds set by the references' own error."""
import numpy as np
import pytest
from conftest import REFERENCE_DATA

from planetviz.reference.stored import stored_reference
from planetviz.tables import QUALITY, precompute
from planetviz.tables.evaluator import sky_radiance
from planetviz.validation import CAMERAS, SPLITS, random_atmosphere, rays
from planetviz.validation.single_scattering import reference_single_scattering, single_scattering_only

#: The daylight target of the standard tables: RMS relative error per ray class.
DAYLIGHT_RMS = 0.01


@pytest.mark.slow
@pytest.mark.parametrize("split", list(SPLITS))
def test_first_order_meets_the_daylight_target_in_every_class(split):
    # The standard tables' first order (single scattering and the directly lit ground) against the reference
    # quadrature (reference/single.py, relative error below 1e-4: no noise), on benchmarks/tables_suite.py's
    # daylight rays of the split's first 8 random atmospheres, the difference relative to the whole radiance (the
    # stored 4096-path reference, all orders; its noise, 1-5%, only scales the figure). Bound: the daylight target
    # itself, 1% RMS per camera class. Before the tables held S / (1 - T) the class within 100 m of the top read
    # 19.6% (tuning) and 21.4% (held-out) RMS relative to the first order alone; the orders above the first are
    # not checked here (the reference's noise, 1-5% at 4096 paths, is above the target: docs/benchmarks.md).
    errors = {camera: [] for camera in CAMERAS}
    for seed in list(SPLITS[split])[:8]:
        atm = random_atmosphere(seed)
        tables = single_scattering_only(precompute(atm, QUALITY["standard"], multiple=False))
        batch = [rays(atm, seed, camera, "day", n=2) for camera in CAMERAS]
        cams, views, suns = (np.concatenate(x) for x in zip(*batch))
        total = stored_reference(REFERENCE_DATA / "suite", f"random-{seed}-day", atm, cams, views, suns,
                                 samples=4096, seed=seed + 7).radiance
        got, _ = sky_radiance(tables, atm, cams, views, suns)
        want = reference_single_scattering(atm, cams, views, suns)
        for k, camera in enumerate(np.repeat(CAMERAS, 2)):
            lit = total[k] > 1e-12
            errors[camera].append((got[k] - want[k])[lit] / total[k][lit])
    rms = {camera: float(np.sqrt(np.mean(np.concatenate(e) ** 2))) for camera, e in errors.items()}
    assert max(rms.values()) <= DAYLIGHT_RMS, rms
