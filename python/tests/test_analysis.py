"""modes / floquet / coefficients: the same dicts as the CLI's --json."""

import json

import pytest

import magbubble as mb

SCENE = "scenes/coil_static.toml"


def test_modes_equal_the_cli(cli_json):
    assert mb.modes(SCENE) == cli_json("modes", SCENE, "--json")
    assert mb.modes(SCENE, 12, overrides={"bubble.radius": 15e-6}) == cli_json(
        "modes", SCENE, "--kmax", 12, "--set", "bubble.radius=15e-6", "--json"
    )


def test_damped_modes_equal_the_cli(cli_json):
    assert mb.modes(SCENE, 6, damped=True) == cli_json("modes", SCENE, "--kmax", 6, "--damped", "--json")


FLOQUET = {"modes.max_order": 4, "drive.frequency_hz": 1.5e6, "drive.amplitude": 0.2}


def test_floquet_multipliers_exactly_the_cli(cli_json):
    sets = []
    for k, v in FLOQUET.items():
        sets += ["--set", f"{k}={v!r}"]
    ours = mb.floquet(SCENE, overrides=FLOQUET)
    theirs = cli_json("floquet", SCENE, *sets, "--json")
    assert ours["status"] == "ok"
    assert ours["multipliers"] == theirs["multipliers"]  # exactly: the same floats
    assert ours == theirs


def test_floquet_from_a_scene_object_names_its_origin():
    s = mb.Scene.load(SCENE).with_overrides(FLOQUET)
    r = mb.floquet(s)
    assert r["parameters"]["scene_file"] == SCENE
    assert r["parameters"]["overrides"] == s.overrides


def test_floquet_bad_arguments_raise(cli):
    with pytest.raises(ValueError, match="at least 16 Magnus steps"):
        mb.floquet(SCENE, steps=4)
    with pytest.raises(ValueError, match="variant"):
        mb.floquet(SCENE, variant="nope")


def test_floquet_failure_is_the_cli_status_object(cli):
    # no shape modes: the analysis fails; the dict is the status object the CLI prints (exit 1)
    ours = mb.floquet(SCENE, overrides={"modes.max_order": 0})
    p = cli("floquet", SCENE, "--set", "modes.max_order=0", "--json", check=False)
    assert p.returncode == 1
    assert ours["status"] == "error" and ours["kind"] == "no_shape_modes"
    assert ours == json.loads(p.stdout)


@pytest.mark.parametrize("field", ["coil", "dipole"])
def test_coefficients_equal_the_cli(cli_json, field):
    ours = mb.coefficients(field, 8)
    assert ours == cli_json("coefficients", "--field", field, "--kmax", 8, "--json")
    assert list(ours) == ["field", "kmax", "prefactor", "zero_order", "couplings", "exact", "appendix", "differs"]


def test_coefficients_bad_arguments():
    with pytest.raises(ValueError, match="out of range"):
        mb.coefficients("coil", mb.KMAX + 1)
    with pytest.raises(ValueError, match="expected 'coil' or 'dipole'"):
        mb.coefficients("solenoid", 4)


@pytest.mark.parametrize("kmax, message", [(-1, "kmax = -1: must be ≥ 2"), (1, "--kmax 1: must be ≥ 2"), (1000, "stop at k = 64")])
def test_bad_kmax_is_a_value_error(kmax, message):
    with pytest.raises(ValueError, match=message):
        mb.modes(SCENE, kmax)
