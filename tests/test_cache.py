"""The table cache: which stages run for each kind of change, the OpenEXR files, and bad files."""
import json
import warnings

import numpy as np
import pytest

from planetviz import load_atmosphere
from planetviz.tables import TableCache, TableSizes, precompute
from planetviz.tables import cache as cache_module
from planetviz.tables.evaluator import sky_radiance

# Tiny tables: the stage logic does not depend on the sizes, and each precompute takes ~0.1 s.
TINY = TableSizes(transmittance=(32, 8), irradiance=(16, 4), scattering=(4, 8, 16, 8), transmittance_samples=8,
                  scattering_samples=4, multiple=(2, 8, 16, 8), multiple_samples=3, directions=(4, 4),
                  tolerance=1e-2)
EARTH = load_atmosphere("earth")
ALL = ["transmittance", "single_scattering", "multiple_scattering"]


def changed(atm, path, value):
    d = atm.to_dict()
    node = d
    for key in path[:-1]:
        node = node[key]
    node[path[-1]] = value
    return type(atm).from_dict(d)


CHANGES = [
    ("nothing (same atmosphere: the sun, camera and exposure are not table inputs)", None, []),
    ("ground albedo", (("ground_albedo",), [0.1, 0.2, 0.3]), ["multiple_scattering"]),
    ("Mie phase g1", (("mie", "phase", "g1"), [0.7, 0.7, 0.7]), ["multiple_scattering"]),
    ("Rayleigh phase", (("rayleigh", "phase"), "penndorf"), ["multiple_scattering"]),
    ("Mie scattering (same extinction: the transmittance stage's scattering share changes)",
     (("mie", "scattering_m"), [3e-6, 3e-6, 3e-6]), ALL),
    ("Rayleigh scale height", (("rayleigh", "profile", "scale_height_m"), 8500.0), ALL),
    ("absorption coefficient", (("absorption", 0, "extinction_m"), [7e-7, 2e-6, 1e-7]), ALL),
]


@pytest.mark.parametrize("what, change, expected", CHANGES, ids=[c[0].split(" (")[0] for c in CHANGES])
def test_only_the_stages_a_change_touches_run(tmp_path, what, change, expected):
    first = precompute(EARTH, TINY, cache=TableCache(tmp_path))
    assert first.computed == ALL
    atm = EARTH if change is None else changed(EARTH, *change)
    again = precompute(atm, TINY, cache=TableCache(tmp_path))      # a new process: reads the disk
    assert again.computed == expected, what
    # What came from the cache is what a fresh computation gives (bit for bit: same code, same inputs).
    fresh = precompute(atm, TINY)
    for name in ("optical_depth", "rayleigh", "mie", "multiple", "irradiance"):
        assert np.array_equal(getattr(again, name), getattr(fresh, name)), name
    assert again.orders == fresh.orders


@pytest.mark.parametrize("quadrature", ["horizon", "hemispheres"])
def test_another_direction_quadrature_recomputes_only_the_multiple_scattering(tmp_path, quadrature):
    # The scattering density's direction quadrature (TableSizes.quadrature) is an input of the multiple-scattering
    # stage alone: cached tables of another quadrature must not be read back for it.
    from dataclasses import replace
    assert TINY.quadrature != quadrature
    precompute(EARTH, TINY, cache=TableCache(tmp_path))
    other = precompute(EARTH, replace(TINY, quadrature=quadrature), cache=TableCache(tmp_path))
    assert other.computed == ["multiple_scattering"]
    assert not np.array_equal(other.multiple, precompute(EARTH, TINY, cache=TableCache(tmp_path)).multiple)


def test_a_new_sun_direction_reuses_the_tables(tmp_path):
    cache = TableCache(tmp_path)
    tables = precompute(EARTH, TINY, cache=cache)
    cam = [[0.0, 0.0, EARTH.bottom_radius_m + 2.0]]
    for sun in ([0, 0, 1.0], [0, 0.6, 0.8], [0, 1.0, 0.0]):
        again = precompute(EARTH, TINY, cache=cache)
        assert again.computed == []
        assert np.array_equal(sky_radiance(again, EARTH, cam, [[0, 0.3, 0.95]], sun)[0],
                              sky_radiance(tables, EARTH, cam, [[0, 0.3, 0.95]], sun)[0])


def test_cache_files_are_float32_openexr_with_parameters_and_hash(tmp_path):
    import OpenEXR
    tables = precompute(EARTH, TINY, cache=TableCache(tmp_path))
    params = cache_module.stage_parameters(EARTH, TINY)
    key = cache_module.parameters_hash(params["single_scattering"])
    f = OpenEXR.File(str(tmp_path / f"rayleigh-{key}.exr"), separate_channels=True)
    h = f.header()
    assert h["planetviz_hash"] == key and json.loads(h["planetviz_parameters"]) == params["single_scattering"]
    ch = f.channels()
    assert sorted(ch) == ["rayleigh.0_680nm", "rayleigh.1_550nm", "rayleigh.2_440nm"]
    pixels = ch["rayleigh.2_440nm"].pixels
    assert pixels.dtype == np.float32
    n_r, n_mu, n_nu, n_mu_s, _ = tables.rayleigh.shape
    # The 3D texture the shader samples: n_r slices of (n_mu, n_nu * n_mu_s) stacked vertically.
    assert np.array_equal(pixels.reshape(n_r, n_mu, n_nu, n_mu_s), tables.rayleigh[..., 2])


def _damage(path, how):
    data = path.read_bytes()
    if how == "truncated":
        path.write_bytes(data[: len(data) // 2])
    elif how == "garbage":
        path.write_bytes(b"not an exr file" * 64)
    elif how == "flipped byte":
        b = bytearray(data)
        b[-40] ^= 0xFF
        path.write_bytes(bytes(b))


@pytest.mark.parametrize("how", ["truncated", "garbage", "flipped byte", "old format"])
def test_bad_cache_files_are_recomputed_with_a_warning(tmp_path, monkeypatch, how):
    current = cache_module.FORMAT_VERSION
    if how == "old format":
        monkeypatch.setattr(cache_module, "FORMAT_VERSION", current - 1)
    good = precompute(EARTH, TINY, cache=TableCache(tmp_path))
    monkeypatch.setattr(cache_module, "FORMAT_VERSION", current)
    if how != "old format":
        (target,) = tmp_path.glob("multiple-*.exr")
        _damage(target, how)
    with pytest.warns(UserWarning, match="unusable"):
        again = precompute(EARTH, TINY, cache=TableCache(tmp_path))
    assert "multiple_scattering" in again.computed
    assert np.array_equal(again.multiple, good.multiple)
    with warnings.catch_warnings():
        warnings.simplefilter("error")                      # the rewritten file is good again
        assert precompute(EARTH, TINY, cache=TableCache(tmp_path)).computed == []
