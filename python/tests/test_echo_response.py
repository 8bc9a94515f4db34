"""Run.echo, Run.spectrum and mb.response(): the tables the CLI writes (echo.csv, spectrum.csv,
response.csv), bit for bit, converted from the typed results."""

import csv
import json

import numpy as np
import pandas as pd
import pytest

import magbubble as mb

BURST = {"run.duration": 2e-6, "run.sample_interval": 2e-9}


def _read_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    return rows[0], np.array([[float(v) for v in r] for r in rows[1:]])


def _same_bits(a, b):
    return a.shape == b.shape and np.array_equal(a.view(np.uint64), b.view(np.uint64))


def test_echo_and_spectrum_equal_the_cli(cli, tmp_path):
    args = ["run", "scenes/hann_burst.toml", "--out", tmp_path]
    for k, v in BURST.items():
        args += ["--set", f"{k}={v!r}"]
    cli(*args)
    r = mb.run("scenes/hann_burst.toml", overrides=BURST, progress=False)
    for frame_, name in [(r.echo, "echo.csv"), (r.spectrum, "spectrum.csv")]:
        header, values = _read_csv(tmp_path / name)
        assert isinstance(frame_, pd.DataFrame)
        assert list(frame_.columns) == header, name
        assert _same_bits(frame_.to_numpy(), values), name
    assert list(r.echo.columns) == ["t", "p_0.05m_0deg"]
    assert list(r.spectrum.columns) == ["frequency_hz", "p_0.05m_0deg_db"]
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert r.summary["echo"] == summary["echo"]
    # the fundamental of the 2 MHz burst is the spectrum's largest level within ±1 bin of it
    f = r.spectrum["frequency_hz"].to_numpy()
    j = int(np.argmin(abs(f - 2e6)))
    line = r.spectrum["p_0.05m_0deg_db"].to_numpy()[j - 1 : j + 2].max()
    assert line == r.summary["echo"]["fundamental_db"]


def test_no_echo_without_the_table():
    r = mb.run("scenes/radial_only.toml", overrides={"run.duration": 2e-6}, progress=False)
    assert r.echo is None and r.spectrum is None and "echo" not in r.summary


def test_response_equals_the_cli(cli, tmp_path):
    cli("response", "scenes/hann_burst.toml", "--freq", "1e5:2e7:300:log", "--out", tmp_path)
    header, values = _read_csv(tmp_path / "response.csv")
    df = mb.response("scenes/hann_burst.toml", "1e5:2e7:300:log")
    assert list(df.columns) == header
    assert _same_bits(df.to_numpy(), values)
    doc = json.loads((tmp_path / "response.json").read_text())
    assert df.attrs["natural_frequency_hz"] == doc["natural_frequency_hz"]
    assert df.attrs["resonance_frequency_hz"] == doc["resonance_frequency_hz"]
    assert df.attrs["damping_rates_per_s"] == doc["damping_rates_per_s"]


def test_response_takes_a_list_and_refuses_bad_frequencies():
    scene = mb.Scene.load("scenes/hann_burst.toml")
    grid = mb.response(scene, "1e6:3e6:3")
    listed = mb.response(scene, [1e6, 2e6, 3e6])
    assert _same_bits(grid.to_numpy(), listed.to_numpy())
    with pytest.raises(ValueError, match=r"frequency \[1\] = -1"):
        mb.response(scene, [1e6, -1.0])
    with pytest.raises(ValueError, match="A:B:N"):
        mb.response(scene, "1e6:3e6")
