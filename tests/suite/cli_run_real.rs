//! `magbubble run` end to end on shipped scenes, with the real model.

use std::path::Path;
use std::process::Command;

fn magbubble(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_magbubble"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("the magbubble binary runs")
}

fn summary(dir: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(dir.join("summary.json")).expect("summary.json written");
    serde_json::from_str(&text).expect("summary.json is JSON")
}

#[test]
fn radial_only_completes_and_plots() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("radial");
    let o = magbubble(&[
        "run", "scenes/radial_only.toml", "--out", out.to_str().unwrap(),
        "--set", "run.duration=5e-6", "--plot",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let s = summary(&out);
    assert_eq!(s["status"], "completed");
    assert_eq!(s["state_dimension"], 2);
    let csv = std::fs::read_to_string(out.join("series.csv")).unwrap();
    assert_eq!(csv.lines().next().unwrap(), "t,R");
    // 5 µs sampled every 10 ns, both ends included.
    assert_eq!(csv.lines().count(), 1 + 501);
    assert!(out.join("series.svg").exists() && out.join("series.png").exists());
}

#[test]
fn coil_static_reports_the_growing_mode() {
    // FORMULATION §5: with the fig-12 parameters the corrected model is parametrically unstable;
    // the run must end as `blow_up` with a mode and a time, not as a crash or NaN.
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("coil");
    let o = magbubble(&["run", "scenes/coil_static.toml", "--out", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let s = summary(&out);
    let blow = &s["status"]["blow_up"];
    // README: "`run scenes/coil_static.toml` … ends as `blow_up` of a16 at about 20 µs"
    assert_eq!(blow["mode"], "a16", "{s}");
    let t = blow["t"].as_f64().unwrap();
    assert!((t - 20e-6).abs() < 1e-6, "README says about 20 µs, got {t}");
    let effects: Vec<String> = serde_json::from_value(s["active_effects"].clone()).unwrap();
    assert!(effects.iter().any(|e| e.contains("coil")), "{effects:?}");
}

#[test]
fn no_field_scene_lists_no_magnetic_effect() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("nf");
    let o = magbubble(&[
        "run", "scenes/no_field.toml", "--out", out.to_str().unwrap(), "--set", "run.duration=2e-6",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let s = summary(&out);
    let effects: Vec<String> = serde_json::from_value(s["active_effects"].clone()).unwrap();
    assert!(!effects.iter().any(|e| e.contains("field")), "{effects:?}");
    assert!(s["groups"].get("rn").is_none());
}
