"""stability(): the CLI's CSV, resumable, and an interrupted call leaves a complete CSV."""

import math

import pandas as pd
import pytest

import magbubble as mb

SCENE = "scenes/coil_static.toml"
SMALL = {"modes.max_order": 4}
FREQ = "0.8e6,1e6,1.2e6"


def _cli_args(out, freq, sets, *extra):
    args = ["stability", SCENE, "--freq", freq, "--out", out, *extra]
    for k, v in sets.items():
        args += ["--set", f"{k}={v!r}"]
    return args


def test_stability_writes_the_cli_csv_and_returns_its_columns(cli, tmp_path):
    df = mb.stability(SCENE, freq=FREQ, overrides=SMALL, out=tmp_path / "py")
    cli(*_cli_args(tmp_path / "cli", FREQ, SMALL))
    ours = (tmp_path / "py" / "stability.csv").read_text()
    theirs = (tmp_path / "cli" / "stability.csv").read_text()
    assert ours == theirs
    header = theirs.splitlines()[0].split(",")
    assert list(df.columns) == header
    assert len(df) == 3
    rows = [line.split(",") for line in theirs.splitlines()[1:]]
    for col in ["critical", "stable", "max_multiplier_stable"]:
        j = header.index(col)
        want = [float(r[j]) for r in rows]
        got = df[col].tolist()
        assert all((math.isnan(a) and math.isnan(b)) or a == b for a, b in zip(got, want)), col
    assert df["outcome"].tolist() == [r[header.index("outcome")] for r in rows]
    assert df.attrs["computed"] == 3 and df.attrs["resumed"] == 0


def test_frequency_list_and_temporary_output():
    df = mb.stability(SCENE, freq=[0.8e6, 1.2e6], overrides=SMALL)
    assert df["drive.frequency_hz"].tolist() == [0.8e6, 1.2e6]
    assert df.attrs["csv"] == []


def test_family_rows_per_member_as_the_cli(cli, tmp_path):
    fam = {"shell.c1": [0.1, 0.2]}
    df = mb.stability(SCENE, freq="1e6,1.2e6", family=fam, overrides=SMALL, out=tmp_path / "py")
    cli(*_cli_args(tmp_path / "cli", "1e6,1.2e6", SMALL, "--family", "shell.c1=0.1,0.2"))
    for v in ["0.1", "0.2"]:
        name = f"stability_shell.c1={v}.csv"
        assert (tmp_path / "py" / name).read_text() == (tmp_path / "cli" / name).read_text()
    assert df.columns[0] == "shell.c1"
    assert df["shell.c1"].tolist() == [0.1, 0.1, 0.2, 0.2]
    assert len(df) == 4


def test_scene_object_is_resumable(tmp_path):
    s = mb.Scene.load(SCENE).with_overrides(SMALL)
    first = mb.stability(s, freq=FREQ, out=tmp_path)
    again = mb.stability(s, freq=FREQ, out=tmp_path)
    assert again.attrs["computed"] == 0 and again.attrs["resumed"] == 3
    pd.testing.assert_frame_equal(first, again)


def test_bad_arguments_raise_value_error_before_any_work(cli, tmp_path):
    with pytest.raises(ValueError) as info:
        mb.stability(SCENE, freq=FREQ, vary="no.such.key", out=tmp_path / "x")
    p = cli("stability", SCENE, "--freq", FREQ, "--vary", "no.such.key", "--out", tmp_path / "y", check=False)
    assert p.returncode == 1
    assert p.stderr == f"error: {info.value}\n"
    assert not (tmp_path / "x").exists()
    with pytest.raises(ValueError, match="drive.amplitude"):
        mb.stability(SCENE, freq=FREQ, overrides={"drive.amplitude": -2.0})


def test_interrupted_stability_leaves_a_complete_resumable_csv(tmp_path):
    freq = "0.5e6:2e6:12"
    sets = {"modes.max_order": 8}
    seen = []

    def interrupt_after_first_point(done, total):
        seen.append((done, total))
        if done >= 1:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        mb.stability(SCENE, freq=freq, overrides=sets, out=tmp_path / "cut", progress=interrupt_after_first_point)
    assert seen[-1][1] == 12
    text = (tmp_path / "cut" / "stability.csv").read_text()
    assert text.endswith("\n")
    lines = text.splitlines()
    ncol = len(lines[0].split(","))
    assert all(len(l.split(",")) == ncol for l in lines[1:])  # no torn rows
    done = lines[1:]
    assert 1 <= len(done) < 12, "the interrupt came too late to test anything"
    outcome = lines[0].split(",").index("outcome")
    assert all(l.split(",")[outcome] != "error" for l in done)  # abandoned points leave no row
    assert not list((tmp_path / "cut").glob("*.tmp"))
    # a rerun computes only what is missing, and gives what an uninterrupted run gives
    resumed = mb.stability(SCENE, freq=freq, overrides=sets, out=tmp_path / "cut", progress=False)
    assert resumed.attrs["resumed"] == len(done)
    assert resumed.attrs["computed"] == 12 - len(done)
    whole = mb.stability(SCENE, freq=freq, overrides=sets, out=tmp_path / "whole", progress=False)
    assert (tmp_path / "cut" / "stability.csv").read_text() == (tmp_path / "whole" / "stability.csv").read_text()
    pd.testing.assert_frame_equal(resumed, whole)


def test_modes_auto_equals_the_cli_and_has_the_cutoff_columns(cli, tmp_path):
    # issue 31 part 5: the cutoff raised through the library, the same CSV as `--modes auto`
    sets = {"modes.max_order": 4}
    df = mb.stability(SCENE, freq="1e6", overrides=sets, out=tmp_path / "py", modes="auto", cutoff_limit=8)
    cli(*_cli_args(tmp_path / "cli", "1e6", sets, "--modes", "auto", "--cutoff-limit", "8"))
    assert (tmp_path / "py" / "stability.csv").read_text() == (tmp_path / "cli" / "stability.csv").read_text()
    for col in ["max_order_used", "cutoff_converged", "critical_error", "min_tension"]:
        assert col in df.columns
    assert df["max_order_used"].tolist() == [8]
    with pytest.raises(ValueError, match="--modes 'every'"):
        mb.stability(SCENE, freq="1e6", overrides=sets, modes="every")
