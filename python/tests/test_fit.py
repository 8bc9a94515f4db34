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


# --- fit --attenuation (issue 32 part 4, issue 33 part 3) --------------------------------------

SHELL = """
[bubble]
radius = 3e-6
[shell]
c1 = 0.2
c2 = 0.12
dilatational_viscosity = 4e-9
[liquid]
sound_speed = 1500.0
[modes]
max_order = 2
"""

POPULATION = "[population]\nmedian_radius = 3e-6\ngeometric_std = 1.3\nbins = 8\nconcentration = 1e5\n"
TRUTH = {"shell.c1": 0.3, "shell.dilatational_viscosity": 6e-9}


def spectrum_of(text, tmp_path, seed):
    """`attenuation` at the true shell values (a one-bin population is the monodisperse
    suspension), 1 % noise."""
    path = tmp_path / "truth.toml"
    path.write_text(text)
    a = mb.attenuation(path, "0.5e6:10e6:30:log", overrides=TRUTH)
    rng = np.random.default_rng(seed)
    clean = a["attenuation_db_per_cm"].to_numpy()
    return pd.DataFrame({"f": a["frequency_hz"], "attenuation_db_per_cm": clean * (1 + 0.01 * rng.standard_normal(len(a))), "sigma": 0.01 * clean})


@pytest.mark.parametrize("population", [False, True])
def test_attenuation_recovers_shell_parameters(tmp_path, population):
    mono = "[population]\ngeometric_std = 1.0\nbins = 1\nconcentration = 1e5\n"
    df = spectrum_of(SHELL + (POPULATION if population else mono), tmp_path, seed=3)
    path = tmp_path / "s.toml"
    path.write_text(SHELL + (POPULATION if population else ""))
    kw = {} if population else {"concentration": 1e5}
    f = mb.fit(path, attenuation=df, params=list(TRUTH), **kw)
    assert f.status == "converged", f.reason
    for _, p in f.parameters.iterrows():
        assert abs(p["value"] - TRUTH[p["key"]]) <= 2 * p["std_error"], p.to_dict()
        assert p["derivative"] == "finite_difference"
    assert list(f.curves.columns) == ["f", "data", "model", "residual"]
    # the same through a CSV file
    df.to_csv(tmp_path / "att.csv", index=False)
    g = mb.fit(path, attenuation=tmp_path / "att.csv", params=list(TRUTH), **kw)
    assert np.allclose(g.parameters["value"], f.parameters["value"], rtol=1e-12)


def test_attenuation_bad_input_raises(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text(SHELL)
    df = pd.DataFrame({"f": [1e6, 2e6, 3e6], "attenuation_db_per_cm": [0.1, 0.2, 0.3]})
    with pytest.raises(ValueError, match="--concentration"):
        mb.fit(path, attenuation=df, params=["shell.c1"])
    with pytest.raises(ValueError, match="attenuation_db_per_cm"):
        mb.fit(path, attenuation=df.rename(columns={"attenuation_db_per_cm": "a"}), params=["shell.c1"], concentration=1e5)
    bad = df.copy()
    bad.loc[1, "attenuation_db_per_cm"] = float("nan")
    with pytest.raises(ValueError, match="NaN"):
        mb.fit(path, attenuation=bad, params=["shell.c1"], concentration=1e5)
    neg = df.copy()
    neg.loc[0, "f"] = -1e6
    with pytest.raises(ValueError, match="must be > 0"):
        mb.fit(path, attenuation=neg, params=["shell.c1"], concentration=1e5)
    with pytest.raises(ValueError, match="not both"):
        mb.fit(path, df, ["shell.c1"], attenuation=df)
