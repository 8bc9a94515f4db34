//! `magbubble run` with fake simulations: files, atomicity, cleanup.

use crate::integrate::Stats;
use crate::model::{Groups, ModelError};
use crate::scene::Scene;
use super::*;

/// `run SCENE --out OUT` (no overrides, no plot).
fn args(scene: PathBuf, out: &Path) -> RunArgs {
    RunArgs { scene, out: Some(out.to_path_buf()), set: vec![], plot: false }
}

fn report(status: RunStatus, names: &[String]) -> RunReport {
    RunReport {
        status,
        t_end: 1e-6,
        stats: Stats {
            steps: 10,
            rejected: 1,
            rhs_evals: 70,
            ..Stats::default()
        },
        wall_seconds: 0.0,
        max_abs: names.iter().map(|n| (n.clone(), 1.0)).collect(),
        final_state: names.iter().map(|n| (n.clone(), 0.5)).collect(),
        active_effects: vec!["radial".into()],
        state_dimension: 2,
        groups: Groups {
            t_star: 2.2e-6,
            reynolds: 10.0,
            p: Some(10.0),
            alpha: Some(1.2),
            p_g0_pa: 101325.0,
            p_g0_rule: "equilibrium",
            mach: None,
            rn: None,
            mn: None,
            omega_d_star: None,
        },
        shell_branches: None,
        integrator: None,
    }
}

/// A decaying "radius" sampled 11 times, with the right row width for `scene`.
fn decay(scene: &Scene, observer: &mut dyn FnMut(f64, &[f64])) -> Result<RunReport, ModelError> {
    let width = series_header(scene).len() - 1;
    let mut row = vec![0.0; width];
    for i in 0..=10 {
        let t = i as f64 * 1e-7;
        row[0] = scene.bubble.radius * (1.0 + 0.01 * (-t / 1e-7).exp());
        observer(t, &row);
    }
    let names: Vec<String> = series_header(scene)[1..].to_vec();
    Ok(report(RunStatus::Completed, &names))
}

fn failing(_: &Scene, observer: &mut dyn FnMut(f64, &[f64])) -> Result<RunReport, ModelError> {
    observer(0.0, &[1e-5]); // a row is written before the failure
    Err(ModelError::Unsupported { key: "test", value: "x".into(), reason: "a failing stand-in simulation" })
}

fn write_scene(dir: &Path, text: &str) -> PathBuf {
    let path = dir.join("s.toml");
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn run_writes_series_and_summary_and_no_temp_files() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = write_scene(
        tmp.path(),
        "[modes]\nmax_order = 4\n[run]\nduration = 1e-6\nsample_interval = 1e-7\n",
    );
    let out = tmp.path().join("deep/out");
    let args = RunArgs { set: vec!["shell.c1=0.2".into()], ..args(scene, &out) };
    execute(&args, decay).unwrap();

    let csv = std::fs::read_to_string(out.join("series.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines[0], "t,R,a2,b2,a4,b4");
    assert_eq!(lines.len(), 12);
    let first: Vec<f64> = lines[1].split(',').map(|x| x.parse().unwrap()).collect();
    assert_eq!(first, vec![0.0, 10e-6 * 1.01, 0.0, 0.0, 0.0, 0.0]);

    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["status"], "completed");
    assert_eq!(summary["steps"], 10);
    assert_eq!(summary["rejected_steps"], 1);
    assert_eq!(summary["rhs_evaluations"], 70);
    assert_eq!(summary["rows"], 11);
    assert_eq!(summary["scene"]["shell"]["c1"], 0.2);
    assert_eq!(summary["scene"]["run"]["integrator"]["method"], "auto"); // the default; the stand-in simulate records no choice
    assert_eq!(summary["source"]["overrides"][0], "shell.c1=0.2");
    let keys: Vec<&String> = summary["max_abs"].as_object().unwrap().keys().collect();
    assert_eq!(keys.len(), 5);

    let mut names: Vec<String> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    names.sort();
    assert_eq!(names, ["series.csv", "summary.json"]);
}

#[test]
fn status_blow_up_serializes_with_time_and_mode() {
    let r = report(
        RunStatus::BlowUp {
            t: 3e-5,
            mode: "a12".into(),
        },
        &[],
    );
    let v = serde_json::to_value(&r.status).unwrap();
    assert_eq!(
        v,
        serde_json::json!({"blow_up": {"t": 3e-5, "mode": "a12"}})
    );
}

#[test]
fn failed_model_leaves_no_directory_and_no_files() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = write_scene(tmp.path(), "[modes]\nmax_order = 0\n");
    let out = tmp.path().join("fresh");
    let err = execute(
        &args(scene, &out),
        failing,
    )
    .unwrap_err();
    assert!(format!("{err:#}").contains("cannot simulate"), "{err:#}");
    assert!(!out.exists(), "output directory left behind");
}

#[test]
fn failed_model_in_an_existing_directory_keeps_it_but_leaves_no_files() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = write_scene(tmp.path(), "[modes]\nmax_order = 0\n");
    let out = tmp.path().join("existing");
    std::fs::create_dir(&out).unwrap();
    execute(
        &args(scene, &out),
        failing,
    )
    .unwrap_err();
    assert!(out.exists());
    assert_eq!(std::fs::read_dir(&out).unwrap().count(), 0);
}

#[test]
fn invalid_scene_creates_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = write_scene(tmp.path(), "[shell]\nc1 = -1.0\n");
    let out = tmp.path().join("never");
    let err = execute(
        &args(scene, &out),
        decay,
    )
    .unwrap_err();
    assert!(
        err.to_string().contains("`shell.c1` = -1.0: must be >= 0"),
        "{err}"
    );
    assert!(!out.exists());
}

#[test]
fn default_out_dir_is_out_slash_stem() {
    assert_eq!(
        default_out_dir(Path::new("scenes/coil_static.toml")),
        Path::new("out/coil_static")
    );
}
