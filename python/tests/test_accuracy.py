"""accuracy: the work–precision study from Python, equal to the CLI's accuracy.csv / sizes.csv
(every column but the wall times) and critical.csv."""

import pandas as pd
import pytest

import magbubble as mb

SCENE = "scenes/free_bubble.toml"
NOT_TIMED = ["method", "setting", "e_r", "e_a", "error", "rhs_evals", "steps", "rejected"]


def test_study_equals_the_cli(cli, tmp_path):
    cli("accuracy", SCENE, "--quick", "--out", tmp_path)
    theirs = pd.read_csv(tmp_path / "accuracy.csv")
    ours = mb.accuracy(SCENE, quick=True, progress=False)
    assert list(ours.ladders.columns[:-1]) == list(theirs.columns)
    pd.testing.assert_frame_equal(ours.ladders[NOT_TIMED], theirs[NOT_TIMED], check_dtype=False)
    assert (ours.ladders["status"] == "completed").all()
    sizes = pd.read_csv(tmp_path / "sizes.csv")
    cols = ["ladder", "size", "rhs_evals", "steps", "delta_r", "delta_a2"]
    pd.testing.assert_frame_equal(ours.sizes[cols], sizes[cols], check_dtype=False)
    # every adaptive method's error falls along its ladder (what the study is for)
    for method, rows in ours.ladders.groupby("method"):
        assert rows["error"].iloc[-1] < rows["error"].iloc[0], method
    assert set(ours.orders["method"]) == set(ours.ladders["method"])


def test_progress_counts_the_simulations():
    calls = []
    mb.accuracy(SCENE, quick=True, progress=lambda done, total: calls.append((done, total)))
    done, total = calls[-1]
    assert done == total > 10


def test_critical_equals_the_cli(cli, tmp_path):
    sets = {"modes.max_order": 2}
    cli("accuracy", "scenes/no_field.toml", "--critical", "1e6", "--quick", "--set", "modes.max_order=2", "--out", tmp_path)
    theirs = pd.read_csv(tmp_path / "critical.csv")
    ours = mb.accuracy("scenes/no_field.toml", sets, critical=1e6, quick=True)
    cols = ["ladder", "setting", "critical", "error", "evaluations"]
    pd.testing.assert_frame_equal(ours.rungs[cols], theirs[cols], check_dtype=False)


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"repeats": 0}, "--repeats = 0"),
        ({"duration": -1.0}, "--duration = -1"),
        ({"critical": -5.0}, "--critical -5"),
        ({"critical": 1e6, "duration": 1e-6}, "no meaning with critical"),
    ],
)
def test_bad_arguments_raise_before_any_work(kwargs, message):
    with pytest.raises(ValueError, match=message):
        mb.accuracy(SCENE, quick=True, progress=False, **kwargs)
