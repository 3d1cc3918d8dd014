"""The atmosphere dataclass: the JSON contract round-trips, and every kind of bad input is refused."""
import copy
import json
import subprocess
import sys

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from planetviz import Atmosphere, AtmosphereError, PRESETS, load_atmosphere
from planetviz.model.presets import load_dict

EARTH_JSON = json.loads(PRESETS["earth"].read_text())


def test_issue_contract_loads_verbatim_and_round_trips(tmp_path):
    atm = Atmosphere.from_dict(EARTH_JSON)
    assert atm.to_dict() == EARTH_JSON
    path = tmp_path / "a.json"
    atm.save(path)
    assert load_atmosphere(path) == atm


@pytest.mark.parametrize("preset", sorted(PRESETS))
def test_presets_derive_valid_standard_atmospheres_that_round_trip(preset):
    atm = load_atmosphere(preset)
    assert Atmosphere.from_json(atm.to_json()) == atm


def mutated(path, value):
    d = copy.deepcopy(EARTH_JSON)
    *parents, last = path
    node = d
    for p in parents:
        node = node[p]
    if value is KeyError:
        del node[last]
    else:
        node[last] = value
    return d


BAD = [  # (path, value, expected field in the message, words the message must contain)
    (("rayleigh", "scattering_m", 1), -1e-6, "rayleigh.scattering_m[1]", "allowed range [0, 1]"),
    (("mie", "profile", "scale_height_m"), -5.0, "mie.profile.scale_height_m", "allowed range"),
    (("mie", "profile", "scale_height_m"), 0.0, "mie.profile.scale_height_m", "allowed range"),
    (("top_radius_m",), 6360000.0, "top_radius_m", "outside"),
    (("top_radius_m",), 6000000.0, "top_radius_m", "outside"),
    (("mie", "phase", "g1", 0), 1.0, "mie.phase.g1[0]", "allowed range [-0.999, 0.999]"),
    (("mie", "phase", "g2", 2), -1.5, "mie.phase.g2[2]", "allowed range"),
    (("mie", "phase", "alpha", 1), 1.2, "mie.phase.alpha[1]", "allowed range [0, 1]"),
    (("ground_albedo", 0), -0.1, "ground_albedo[0]", "allowed range [0, 1]"),
    (("ground_albedo", 2), 1.01, "ground_albedo[2]", "allowed range [0, 1]"),
    (("mie", "scattering_m"), [1e-6, 1e-6], "mie.scattering_m", "expected 3"),
    (("ground_albedo",), [0.3] * 4, "ground_albedo", "expected 3"),
    (("mie", "extinction_m", 0), 1e-7, "mie.extinction_m[0]", "below scattering_m[0]"),
    (("rayleigh", "scattering_m", 0), "0.1", "rayleigh.scattering_m[0]", "must be a number"),
    (("rayleigh", "phase"), "mie", "rayleigh.phase", "'rayleigh', 'penndorf'"),
    (("rayleigh", "profile", "type"), "linear", "rayleigh.profile.type", "exponential"),
    (("absorption", 0, "profile", "half_width_m"), 0.0, "absorption[0].profile.half_width_m", "allowed range"),
    (("rayleigh", "colour"), "blue", "rayleigh.colour", "unknown field"),
    (("surprise",), 1, "surprise", "unknown field"),
    (("mie", "phase"), KeyError, "mie.phase", "missing"),
    (("bottom_radius_m",), KeyError, "bottom_radius_m", "missing"),
    (("wavelengths_nm",), [], "wavelengths_nm", "1 to 256"),
    (("wavelengths_nm", 1), 680.0, "wavelengths_nm", "repeat"),
    (("bottom_radius_m",), True, "bottom_radius_m", "must be a number"),
    (("name",), "", "name", "non-empty"),
]


@pytest.mark.parametrize("path,value,field,words", BAD)
def test_bad_values_raise_value_error_naming_the_field(path, value, field, words):
    with pytest.raises(ValueError) as info:
        Atmosphere.from_dict(mutated(path, value))
    assert isinstance(info.value, AtmosphereError)
    assert info.value.field == field
    assert words in str(info.value)


@pytest.mark.parametrize("token", ["NaN", "Infinity", "-Infinity"])
def test_nan_and_infinity_in_json_are_refused(token):
    text = json.dumps(EARTH_JSON).replace("0.3, 0.3, 0.3", f"0.3, {token}, 0.3")
    with pytest.raises(AtmosphereError, match="finite"):
        Atmosphere.from_json(text)


def test_nan_from_python_is_refused():
    with pytest.raises(AtmosphereError, match=r"ground_albedo\[1\]: must be finite"):
        Atmosphere.from_dict(mutated(("ground_albedo", 1), float("nan")))


def test_malformed_json_names_line_and_column():
    with pytest.raises(AtmosphereError, match="malformed JSON at line 1 column"):
        Atmosphere.from_json('{"name": "x",,}')


def test_replace_validates():
    atm = load_atmosphere("earth")
    with pytest.raises(AtmosphereError, match="top_radius_m"):
        atm.replace(top_radius_m=atm.bottom_radius_m - 1)


def test_advanced_files_fail_with_field_names():
    d = json.loads(PRESETS["mars"].read_text())
    d["mie"]["particles"]["radius_m"] = -1e-6
    with pytest.raises(AtmosphereError, match=r"mie\.particles\.radius_m"):
        load_dict(d)
    d = json.loads(PRESETS["exo-mdwarf"].read_text())
    d["rayleigh"]["gases"]["Xe"] = 0.1
    with pytest.raises(AtmosphereError, match=r"rayleigh\.gases\.Xe: unknown gas"):
        load_dict(d)
    d = json.loads(PRESETS["earth-advanced"].read_text())
    d["mie"]["extinction"]["scattering_ratio"] = 0.0
    with pytest.raises(AtmosphereError, match=r"mie\.extinction\.scattering_ratio"):
        load_dict(d)


@pytest.mark.parametrize("content,field", [
    ("{not json", "malformed JSON"),
    (json.dumps(mutated(("mie", "phase", "g1", 0), 1.5)), "mie.phase.g1[0]"),
    (json.dumps(mutated(("rayleigh", "scattering_m"), [1, 2])), "rayleigh.scattering_m"),
    ("[1, 2, 3]", "must be a JSON object"),
])
def test_cli_exits_2_with_one_line_and_no_traceback(tmp_path, content, field):
    path = tmp_path / "bad.json"
    path.write_text(content)
    proc = subprocess.run([sys.executable, "-m", "planetviz", "atmosphere", str(path)],
                          capture_output=True, text=True)
    assert proc.returncode == 2
    assert proc.stdout == ""
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and field in lines[0] and "Traceback" not in proc.stderr


finite = st.floats(allow_nan=False, allow_infinity=False, width=64)


@settings(max_examples=150, deadline=None)
@given(st.sampled_from(["rayleigh.scattering_m", "mie.phase.g1", "mie.phase.alpha", "ground_albedo"]),
       st.integers(0, 2), finite)
def test_any_number_is_either_accepted_in_range_or_refused_naming_the_field(field, i, value):
    # Property: a single changed number never yields a half-valid atmosphere or a non-ValueError.
    ranges = {"rayleigh.scattering_m": (0, 1), "mie.phase.g1": (-0.999, 0.999),
              "mie.phase.alpha": (0, 1), "ground_albedo": (0, 1)}
    lo, hi = ranges[field]
    d = mutated(tuple(field.split(".")) + (i,), value)
    if lo <= value <= hi:
        atm = Atmosphere.from_dict(d)
        node = atm.to_dict()
        for key in field.split("."):
            node = node[key]
        assert node[i] == value
    else:
        with pytest.raises(AtmosphereError) as info:
            Atmosphere.from_dict(d)
        assert info.value.field == f"{field}[{i}]"


@pytest.mark.parametrize("split", ["tuning", "held-out"])
def test_every_random_atmosphere_of_the_validation_suite_is_legal(split):
    """The suite draws from everything the format allows and nothing beyond it: on a large planet an absorbing
    layer drawn at a share of a thick atmosphere's height must stay within the format's altitude limit."""
    from planetviz.validation import SPLITS, random_atmosphere
    for seed in SPLITS[split]:
        random_atmosphere(seed)
