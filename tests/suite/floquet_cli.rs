//! Issue 13 parts 3 and 6: `floquet --json` always prints JSON, `--steps` is validated, the
//! convergence estimate is reported; `stability --freq` lists and log spacing.

use magbubble::api::stability::parse_freq;
use std::process::Command;

fn floquet(args: &[&str]) -> (bool, serde_json::Value) {
    let out = Command::new(env!("CARGO_BIN_EXE_magbubble"))
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .arg("floquet")
        .args(args)
        .output()
        .unwrap();
    let text = String::from_utf8(out.stdout).unwrap();
    let v: serde_json::Value = serde_json::from_str(&text).unwrap_or_else(|e| panic!("not JSON ({e}): {text}"));
    (out.status.success(), v)
}

#[test]
fn json_report_carries_the_orbit_and_the_convergence() {
    let (ok, v) = floquet(&["scenes/coil_static.toml", "--json", "--set", "modes.max_order=8"]);
    assert!(ok, "{v}");
    assert_eq!(v["status"], "ok");
    assert_eq!(v["orbit_multiple"], 2);
    let mu = v["max_multiplier"].as_f64().unwrap();
    assert!((mu - 250.30).abs() < 0.01, "{mu}");
    assert!((v["max_multiplier_per_drive_period"].as_f64().unwrap() - mu.sqrt()).abs() < 1e-9);
    assert!(v["r_min_m"].as_f64().unwrap() < v["r_max_m"].as_f64().unwrap());
    let dp = v["drive_period_s"].as_f64().unwrap();
    assert!((v["period_s"].as_f64().unwrap() - 2.0 * dp).abs() < 1e-12 * dp, "{v}");
    assert_eq!(v["parameters"]["scene"]["drive"]["amplitude"], 0.5);
    let c = &v["convergence"];
    assert_eq!(c["steps"], 400);
    assert!(c["difference"].as_f64().unwrap() < 1e-6 * mu && c["converged"] == true, "{c}");
}

#[test]
fn failures_are_json_status_objects_with_a_nonzero_exit() {
    for (args, kind) in [
        (vec!["scenes/coil_static.toml", "--json", "--steps", "1"], "invalid_argument"),
        (vec!["scenes/coil_static.toml", "--json", "--steps", "0"], "invalid_argument"),
        (vec!["scenes/radial_only.toml", "--json"], "no_shape_modes"),
        (vec!["scenes/no_such_file.toml", "--json"], "scene"),
    ] {
        let (ok, v) = floquet(&args);
        assert!(!ok, "{args:?}: {v}");
        assert_eq!(v["status"], "error", "{args:?}");
        assert_eq!(v["kind"], kind, "{args:?}: {v}");
        assert!(!v["message"].as_str().unwrap().is_empty());
    }
}

#[test]
fn too_few_steps_warn() {
    let (ok, v) = floquet(&["scenes/coil_static.toml", "--json", "--set", "modes.max_order=8", "--steps", "16"]);
    assert!(ok);
    assert_eq!(v["convergence"]["converged"], false, "{v}");
    assert!(v["warnings"][0].as_str().unwrap().contains("not converged"));
}

#[test]
fn frequency_lists_and_log_spacing() {
    assert_eq!(parse_freq("0.5e6,1e6,2e6").unwrap(), vec![0.5e6, 1e6, 2e6]);
    let f = parse_freq("1e5:1e7:3:log").unwrap();
    assert!((f[0] - 1e5).abs() < 1e-6 && (f[1] - 1e6).abs() < 1e-6 && (f[2] - 1e7).abs() < 1e-3, "{f:?}");
    assert_eq!(parse_freq("1e6:2e6:3").unwrap(), vec![1e6, 1.5e6, 2e6]);
    for bad in ["1e6,-2", "1e6:2e6:3:cubic", "2e6:1e6:3", "a,b", "1e6:2e6"] {
        assert!(parse_freq(bad).is_err(), "{bad}");
    }
}

/// Issue 15 class 9: a scene with nothing periodic has no drive period; the report says so
/// (JSON null, no "drive period" in the text) instead of calling t* one.
#[test]
fn an_undriven_scene_reports_no_drive_period() {
    let set = ["--set", "modes.max_order=4", "--set", "drive.amplitude=0"];
    let (ok, v) = floquet(&[&["scenes/radial_only.toml", "--json"][..], &set].concat());
    assert!(ok, "{v}");
    assert!(v["drive_period_s"].is_null(), "{v}");
    assert!(v["period_s"].as_f64().unwrap() > 0.0);
    let out = Command::new(env!("CARGO_BIN_EXE_magbubble"))
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .args([&["floquet", "scenes/radial_only.toml"][..], &set].concat())
        .output()
        .unwrap();
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(out.status.success());
    assert!(text.contains("no drive") && !text.contains("drive period"), "{text}");
}
