"""sweep(): the grid of runs of `magbubble sweep`, resumable, with series on request."""

import numpy as np
import pytest

import magbubble as mb

SCENE = "scenes/coil_static.toml"
SETS = {"modes.max_order": 4, "run.duration": 5e-6}


def _cli_sweep(cli, out, *grid):
    args = ["sweep", SCENE, "--out", out]
    for g in grid:
        args += ["--grid", g]
    for k, v in SETS.items():
        args += ["--set", f"{k}={v!r}"]
    cli(*args)
    return (out / "sweep.csv").read_text()


def _without_wall(text):
    return [line.rsplit(",", 1)[0] for line in text.splitlines()]


def test_sweep_writes_the_cli_csv(cli, tmp_path):
    grid = {"bubble.radius": ["8e-6", "1e-5"], "drive.frequency_hz": "0.5e6:1e6:2"}
    df = mb.sweep(SCENE, grid=grid, overrides=SETS, out=tmp_path / "py")
    theirs = _cli_sweep(cli, tmp_path / "cli", "bubble.radius=8e-6,1e-5", "drive.frequency_hz=0.5e6:1e6:2")
    ours = (tmp_path / "py" / "sweep.csv").read_text()
    assert _without_wall(ours) == _without_wall(theirs)  # every column but the wall time
    assert list(df.columns) == theirs.splitlines()[0].split(",")
    assert len(df) == 4
    assert df["index"].tolist() == [0, 1, 2, 3]
    assert df["bubble.radius"].tolist() == [8e-6, 8e-6, 1e-5, 1e-5]
    assert set(df["status"]) <= {"completed", "blow_up", "failed"}
    again = mb.sweep(SCENE, grid=grid, overrides=SETS, out=tmp_path / "py")
    assert again.attrs["computed"] == 0 and again.attrs["resumed"] == 4


def test_sweep_figures_equal_single_runs():
    df = mb.sweep(SCENE, grid={"bubble.radius": [8e-6, 1.2e-5]}, overrides=SETS, series=True)
    for _, row in df.iterrows():
        r = mb.run(SCENE, overrides={**SETS, "bubble.radius": row["bubble.radius"]})
        assert row["status"] == r.status
        assert row["R_max"] == r.summary["max_abs"]["R"]
        assert row["max_a2"] == r.summary["max_abs"]["a2"]
        s = row["series"]
        assert list(s.columns) == list(r.series.columns)
        assert np.array_equal(s.to_numpy().view(np.uint64), r.series.to_numpy().view(np.uint64))


def test_sweep_bad_value_raises_with_the_set_message(cli, tmp_path):
    with pytest.raises(ValueError) as info:
        mb.sweep(SCENE, grid={"bubble.radius": [1e-5, -1.0]}, overrides=SETS, out=tmp_path / "x")
    p = cli("sweep", SCENE, "--grid", "bubble.radius=1e-05,-1.0", "--out", tmp_path / "y", check=False)
    assert p.returncode == 1
    assert p.stderr == f"error: {info.value}\n"
    assert "bubble.radius" in str(info.value)
    assert not (tmp_path / "x").exists()


def test_interrupted_sweep_keeps_whole_rows_and_resumes(tmp_path):
    grid = {"bubble.radius": [6e-6, 7e-6, 8e-6, 9e-6, 1e-5, 1.1e-5, 1.2e-5, 1.3e-5]}
    # radial runs of 5 ms (5000 drive periods): long enough to be interrupted after the first
    long = {"run.duration": 5e-3, "run.sample_interval": 1e-6}
    radial = "scenes/radial_only.toml"

    def stop(done, total):
        if done >= 1:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        mb.sweep(radial, grid=grid, overrides=long, out=tmp_path, progress=stop)
    lines = (tmp_path / "sweep.csv").read_text().splitlines()
    ncol = len(lines[0].split(","))
    assert all(len(l.split(",")) == ncol for l in lines[1:])
    assert 1 <= len(lines) - 1 < 8, "the interrupt came too late to test anything"
    df = mb.sweep(radial, grid=grid, overrides=long, out=tmp_path, progress=False)
    assert df.attrs["resumed"] == len(lines) - 1
    assert df.attrs["computed"] == 8 - (len(lines) - 1)
    assert df["index"].tolist() == list(range(8))


def test_sweep_columns_are_typed_and_text_is_shared():
    grid = {"bubble.radius": [8e-6, 1e-5, 1.2e-5], "run.integrator.method": ["radau5", "dopri5"]}
    df = mb.sweep(SCENE, grid=grid, overrides=SETS, progress=False)
    assert len(df) == 6
    for col in ["index", "steps", "rejected_steps", "rhs_evaluations"]:
        assert df[col].dtype == np.int64, col
    for col in ["bubble.radius", "t_end", "R_min", "R_max", "max_a2", "max_b4", "wall_seconds"]:
        assert df[col].dtype == np.float64, col
    # 5 µs: no blow-up, no failure; the empty columns are NaN, as the CSV's empty cells read
    assert df["status"].dtype == object and set(df["status"]) == {"completed"}
    assert df["t_blow_up"].isna().all() and df["note"].isna().all()
    assert df["run.integrator.method"].tolist() == ["radau5", "dopri5"] * 3
    # a text column holds each distinct value once (one object, many references)
    assert len({id(v) for v in df["run.integrator.method"]}) == 2
