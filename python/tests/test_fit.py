"""mb.fit (issue 32): a path or a DataFrame, the result's frames, the CLI's numbers."""

import numpy as np
import pandas as pd
import pytest

import magbubble as mb

SCENE = """
[bubble]
radius = 10e-6
[bubble.initial]
a = { 2 = 2e-8 }
[shell]
c1 = 0.1
c2 = 0.12
[drive]
amplitude = 0.4
frequency_hz = 1e6
[modes]
max_order = 2
[run]
duration = 4e-6
sample_interval = 5e-8
"""


@pytest.fixture()
def truth(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text(SCENE)
    return mb.Scene.load(path)


def data_of(scene, sigma=0.0, seed=0):
    s = mb.run(scene, progress=False).series
    rng = np.random.default_rng(seed)
    return pd.DataFrame({"t": s["t"], "R": s["R"] + sigma * rng.standard_normal(len(s)), "a2": s["a2"]})


def test_dataframe_and_path_agree(truth, tmp_path):
    df = data_of(truth, sigma=1e-8)
    start = truth.with_overrides({"shell.c1": 0.12})
    a = mb.fit(start, df, ["shell.c1=0.01:1"])
    csv = tmp_path / "d.csv"
    df.to_csv(csv, index=False, float_format="%.17g")
    b = mb.fit(start, csv, ["shell.c1=0.01:1"])
    assert a.status == b.status == "converged"
    assert list(a.parameters.columns[:5]) == ["key", "value", "std_error", "low", "high"]
    assert a.parameters["value"][0] == pytest.approx(b.parameters["value"][0], rel=1e-12)
    assert abs(a.parameters["value"][0] - 0.1) < 3 * a.parameters["std_error"][0]
    assert list(a.curves.columns) == ["t", "R_data", "R_model", "R_residual", "a2_data", "a2_model", "a2_residual"]
    assert a.correlation.loc["shell.c1", "shell.c1"] == pytest.approx(1.0)


def test_model_curve_is_run(truth):
    df = data_of(truth)
    f = mb.fit(truth.with_overrides({"shell.c1": 0.11}), df, ["shell.c1"])
    fitted = truth.with_overrides({"shell.c1": f.parameters["value"][0]})
    s = mb.run(fitted, progress=False).series
    assert np.array_equal(f.curves["R_model"].to_numpy(), s["R"].to_numpy())


def test_bad_input_raises(truth):
    df = data_of(truth)
    with pytest.raises(ValueError, match="shell.c9"):
        mb.fit(truth, df, ["shell.c9"])
    with pytest.raises(ValueError, match="reversed"):
        mb.fit(truth, df, ["shell.c1=1:0.1"])
    bad = df.copy()
    bad.loc[3, "t"] = bad.loc[2, "t"]
    with pytest.raises(ValueError, match="duplicated"):
        mb.fit(truth, bad, ["shell.c1"])
