//! Quadratic coupling in the run pipeline (issue 12): the `out_of_credible_range` status
//! (`modes.credible_amplitude`), and `accuracy`, `figure --set`, `floquet` on quadratic scenes
//! from the command line (Floquet says it stays linear).

use std::path::Path;
use std::process::Command;

use magbubble::model::{simulate, RunStatus};
use magbubble::scene::load;

const LARGE_A2: &str = "scenes/hard/quadratic_large_a2.toml";

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_magbubble"))
}

fn path(p: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(p).display().to_string()
}

#[test]
fn a_start_above_the_credible_bound_is_classified_not_blown_up() {
    let s = load(LARGE_A2, &[] as &[&str]).expect("scene");
    let r = simulate(&s, &mut |_, _| {}).expect("runs");
    assert_eq!(r.status, RunStatus::OutOfCredibleRange { t: 0.0, mode: "a2".into(), bound: 0.1 });
    let json = serde_json::to_value(&r.status).unwrap();
    assert_eq!(json, serde_json::json!({"out_of_credible_range": {"t": 0.0, "mode": "a2", "bound": 0.1}}));
    // the same state with linear coupling: the bound is not applied
    let lin = load(LARGE_A2, &["modes.coupling=\"linear\"", "run.duration=1e-6"]).expect("scene");
    assert_eq!(simulate(&lin, &mut |_, _| {}).expect("runs").status, RunStatus::Completed);
}

#[test]
fn a_raised_bound_follows_the_run_and_a_crossing_is_timed() {
    // bound 0.45: the 0.2 R0 start runs to the end; a_4 is driven at second order by a_2²
    let s = load(LARGE_A2, &["modes.credible_amplitude=0.45", "run.duration=5e-6"]).expect("scene");
    let mut a4 = 0.0f64;
    let r = simulate(&s, &mut |_, row| a4 = a4.max(row[3].abs())).expect("runs");
    assert_eq!(r.status, RunStatus::Completed);
    assert!(a4 / 5e-6 > 1e-2, "a4/R0 = {}", a4 / 5e-6);
    // the fig-12 scene (ε_p = 0.5): the linear run blows up (a16, ≈ 20.6 µs); the quadratic one
    // leaves the credible range first, timed on the dense output (measured 18.48 µs)
    let f12 = "scenes/figures/fig12_chi.toml";
    let q = load(f12, &["modes.coupling=\"quadratic\"", "run.duration=30e-6"]).expect("scene");
    match simulate(&q, &mut |_, _| {}).expect("runs").status {
        RunStatus::OutOfCredibleRange { t, mode, bound } => {
            assert_eq!(bound, 0.1);
            assert!(mode.starts_with('a') && t > 5e-6 && t < 30e-6, "{mode} at {t}");
        }
        other => panic!("expected out_of_credible_range, got {other:?}"),
    }
    let l = load(f12, &["run.duration=30e-6"]).expect("scene");
    assert!(matches!(simulate(&l, &mut |_, _| {}).expect("runs").status, RunStatus::BlowUp { .. }));
}

#[test]
fn accuracy_runs_on_a_quadratic_scene() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("acc");
    let o = bin()
        .args(["accuracy", &path(LARGE_A2), "--quick", "--out", out.to_str().unwrap()])
        .args(["--set", "modes.credible_amplitude=0.45"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let csv = std::fs::read_to_string(out.join("accuracy.csv")).unwrap();
    assert!(csv.lines().count() > 10, "{csv}");
    // every rung completed (the scene is quadratic; the raised bound lets the 0.2 R0 start run)
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("completed") && !stdout.contains("out_of_credible_range"), "{stdout}");
}

#[test]
fn figure_set_runs_a_time_series_figure_with_quadratic_coupling_and_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let o = bin()
        .args(["figure", "13", "--quick", "--out", dir.path().to_str().unwrap(), "--scenes", &path("scenes/figures")])
        .args(["--set", "modes.coupling=\"quadratic\""])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let note = std::fs::read_to_string(dir.path().join("fig13.md")).unwrap();
    assert!(note.contains("modes.coupling=\"quadratic\""), "{note}");
    let svg = std::fs::read_to_string(dir.path().join("fig13.svg")).unwrap();
    assert!(svg.contains("quadratic"), "the plot title names the model");
    // a stability figure refuses --set
    let o = bin()
        .args(["figure", "6", "--quick", "--out", dir.path().to_str().unwrap(), "--scenes", &path("scenes/figures")])
        .args(["--set", "modes.coupling=\"quadratic\""])
        .output()
        .unwrap();
    assert!(!o.status.success() && String::from_utf8_lossy(&o.stderr).contains("time-series figures"));
}

#[test]
fn floquet_on_a_quadratic_scene_says_it_is_linear() {
    let o = bin()
        .args(["floquet", &path("scenes/free_bubble.toml"), "--json", "--steps", "200"])
        .args(["--set", "modes.coupling=\"quadratic\"", "--set", "shell.surface_tension=0.072", "--set", "modes.max_order=4"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let w = v["warnings"].to_string();
    assert!(w.contains("Floquet analysis is linear") && w.contains("quadratic"), "{w}");
}
