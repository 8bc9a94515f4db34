"""Scene.load / from_toml / with_overrides / to_toml, and errors with the CLI's messages."""

import pytest

import magbubble as mb

SCENE = "scenes/coil_static.toml"


def test_load_and_resolved():
    s = mb.Scene.load(SCENE)
    assert s.origin == SCENE
    assert s.overrides == []
    r = s.resolved()
    assert r["bubble"]["radius"] == 10e-6
    assert "drive" in r


def test_with_overrides_sets_values_exactly_and_keeps_the_original():
    s = mb.Scene.load(SCENE)
    t = s.with_overrides({"drive.amplitude": 0.1 + 0.2, "modes.max_order": 8})
    assert t.resolved()["drive"]["amplitude"] == 0.1 + 0.2  # repr round-trips, bit for bit
    assert t.resolved()["modes"]["max_order"] == 8
    assert s.resolved()["modes"]["max_order"] != 8
    assert t.overrides == ["drive.amplitude=0.30000000000000004", "modes.max_order=8"]


def test_to_toml_reads_back_to_the_same_scene():
    s = mb.Scene.load(SCENE).with_overrides({"drive.amplitude": 0.25})
    back = mb.Scene.from_toml(s.to_toml(), origin="copy")
    assert back.resolved() == s.resolved()
    assert back.origin == "copy"


def test_load_with_overrides_equals_with_overrides():
    a = mb.Scene.load(SCENE, {"drive.frequency_hz": 1.5e6})
    b = mb.Scene.load(SCENE).with_overrides({"drive.frequency_hz": 1.5e6})
    assert a.resolved() == b.resolved()


def _cli_message(cli, *args):
    p = cli(*args, check=False)
    assert p.returncode == 1
    assert p.stderr.startswith("error: ")
    return p.stderr[len("error: "):].rstrip("\n")


@pytest.mark.parametrize(
    "overrides, sets",
    [
        ({"shell.c1": -1.0}, ["shell.c1=-1.0"]),
        ({"no.such.key": 1}, ["no.such.key=1"]),
        ({"drive.amplitude": "a b"}, ["drive.amplitude=a b"]),
        ({"shell.c1": -1.0, "bubble.radius": 0}, ["shell.c1=-1.0", "bubble.radius=0"]),
    ],
)
def test_bad_override_raises_value_error_with_the_cli_message(cli, overrides, sets):
    with pytest.raises(ValueError) as info:
        mb.Scene.load(SCENE, overrides)
    args = ["modes", SCENE]
    for s in sets:
        args += ["--set", s]
    assert str(info.value) == _cli_message(cli, *args)
    # the same problems through with_overrides on a loaded scene
    with pytest.raises(ValueError) as again:
        mb.Scene.load(SCENE).with_overrides(overrides)
    assert str(again.value) == str(info.value)


def test_bad_file_raises_value_error_with_the_cli_message(cli, tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text("[bubble]\nradius = -3\n[shell]\nc1 = 'x'\n")
    with pytest.raises(ValueError) as info:
        mb.Scene.load(bad)
    assert str(info.value) == _cli_message(cli, "modes", bad)
    assert "bubble.radius" in str(info.value)
    syntax = tmp_path / "syntax.toml"
    syntax.write_text("[bubble\n")
    with pytest.raises(ValueError) as info:
        mb.Scene.load(syntax)
    assert str(info.value) == _cli_message(cli, "modes", syntax)


def test_missing_file_and_wrong_type():
    with pytest.raises(ValueError, match="cannot read scene file"):
        mb.Scene.load("scenes/does_not_exist.toml")
    with pytest.raises(TypeError):
        mb.run(42)
    with pytest.raises(TypeError):
        mb.Scene.load(SCENE).with_overrides(["drive.amplitude=0.3"])
