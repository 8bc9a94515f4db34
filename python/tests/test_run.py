"""run(): the series bit for bit the CLI's series.csv, the summary its summary.json."""

import csv
import json

import numpy as np
import pandas as pd
import pytest

import magbubble as mb
from magbubble._util import override_list


def _read_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    return rows[0], np.array([[float(v) for v in r] for r in rows[1:]])


@pytest.mark.parametrize(
    "scene, sets",
    [
        ("scenes/radial_only.toml", {"run.duration": 20e-6}),
        ("scenes/coil_static.toml", {"run.duration": 5e-6, "modes.max_order": 6}),
        ("scenes/hard/reduced_collapse.toml", {"run.duration": 5e-6}),
        # the reduced thermal model with shape modes: p_b after the a_k, b_k columns
        ("scenes/coil_static.toml", {"run.duration": 5e-6, "modes.max_order": 4, "gas.thermal": "reduced"}),
    ],
)
def test_series_and_summary_equal_the_cli(cli, tmp_path, scene, sets):
    args = ["run", scene, "--out", tmp_path]
    # the --set texts the Python call makes of `sets` (so the recorded overrides agree too)
    for text in override_list(sets):
        args += ["--set", text]
    cli(*args)
    header, values = _read_csv(tmp_path / "series.csv")
    r = mb.run(scene, overrides=sets)
    assert isinstance(r.series, pd.DataFrame)
    assert list(r.series.columns) == header
    assert r.series.shape == values.shape
    ours = r.series.to_numpy()
    assert ours.dtype == np.float64
    # bit for bit (also the sign of zeros)
    assert np.array_equal(ours.view(np.uint64), values.view(np.uint64))
    summary = json.loads((tmp_path / "series.csv").with_name("summary.json").read_text())
    assert list(r.summary) == list(summary)
    for key in summary:
        if key != "wall_seconds":
            assert r.summary[key] == summary[key], key
    assert r.status == "completed"
    assert r.summary["rows"] == len(r.series)


def test_the_reduced_thermal_model_has_a_p_b_column():
    r = mb.run("scenes/hard/reduced_collapse.toml", overrides={"run.duration": 2e-6}, progress=False)
    assert list(r.series.columns) == ["t", "R", "p_b"]
    # the gas starts at rest at R0: p_b(0) = p_g0 (equilibrium with surface tension)
    assert r.series["p_b"].iloc[0] == pytest.approx(r.summary["groups"]["p_g0_pa"], rel=1e-15)


def test_blow_up_is_a_status():
    r = mb.run("scenes/coil_static.toml", overrides={"run.duration": 40e-6}, progress=False)
    assert r.status == "blow_up"
    assert r.blow_up["mode"].startswith("a")
    assert r.series["t"].iloc[-1] == pytest.approx(r.blow_up["t"])


def test_run_says_which_integrator_ran_and_why():
    """Issue 34: the default `auto` choice is in the summary and on `Run.integrator`."""
    radial = mb.run("scenes/radial_only.toml", overrides={"run.duration": 2e-6}, progress=False)
    assert radial.integrator == radial.summary["integrator"]
    assert (radial.integrator["method"], radial.integrator["chosen"]) == ("dop853", "auto")
    assert radial.integrator["spectral_radius_per_s"] > 0
    assert "spectral radius" in radial.integrator["reason"]
    stiff = mb.run("scenes/coil_static.toml", overrides={"run.duration": 2e-6}, progress=False)
    assert (stiff.integrator["method"], stiff.integrator["chosen"]) == ("radau5", "auto")
    given = mb.run("scenes/coil_static.toml", overrides={"run.duration": 2e-6, "run.integrator.method": "dopri5"}, progress=False)
    assert (given.integrator["method"], given.integrator["chosen"]) == ("dopri5", "scene")
