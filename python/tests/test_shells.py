"""Issue 31 through the typed API: the new shell laws' and thermal model's scene keys reach
mb.run, and summary.json's shell_branches (kinked Marmottant) is in the summary dict, equal to
the CLI's."""

import json

import pytest

import magbubble as mb


def test_marmottant_branch_fractions_reach_python_equal_to_the_cli(cli, tmp_path):
    sets = {"run.duration": 5e-6}
    cli("run", "scenes/coil_marmottant.toml", "--out", tmp_path, "--set", "run.duration=5e-6")
    want = json.loads((tmp_path / "summary.json").read_text())["shell_branches"]
    r = mb.run("scenes/coil_marmottant.toml", overrides=sets)
    got = r.summary["shell_branches"]
    assert got == want
    assert set(got) == {"buckled", "elastic", "ruptured", "switches"}
    assert got["switches"] > 0
    assert got["buckled"] + got["elastic"] + got["ruptured"] == pytest.approx(1.0, abs=1e-12)


@pytest.mark.parametrize(
    "sets, effect",
    [
        ({"gas.thermal": "prosperetti", "gas.thermal_diffusivity": 2e-5}, "thermal damping (Prosperetti"),
        ({"shell.law": "sarkar", "shell.elasticity": 0.55, "shell.elasticity_decay": 1.5, "shell.reference_tension": 0.02}, "sarkar shell"),
        ({"shell.law": "church-hoff", "shell.modulus": 5e7, "shell.viscosity": 0.8}, "church-hoff shell"),
    ],
)
def test_new_keys_reach_the_run(sets, effect):
    scene = "scenes/radial_only.toml" if sets.get("shell.law") == "church-hoff" else "scenes/no_field.toml"
    r = mb.run(scene, overrides={"run.duration": 2e-6, **sets})
    assert r.summary["status"] == "completed"
    assert any(effect in e for e in r.summary["active_effects"]), r.summary["active_effects"]
    assert "shell_branches" not in r.summary


def test_a_thermal_key_without_a_thermal_model_is_an_error():
    with pytest.raises(Exception, match="gas.thermal_diffusivity"):
        mb.run("scenes/no_field.toml", overrides={"gas.thermal_diffusivity": 1e-5})
