//! Issue 15 class 4: `stability` and `merge` validate every argument before any work (no CSV of
//! error rows, no CSV left behind), and a resumed sweep never keeps an error row. Plus the one
//! in-memory scene override (`SceneTemplate`) the sweeps use (issue 16 part 5).

use magbubble::analysis::sweep::{self, Shard, SweepMeta};
use magbubble::scene::{self, Current, Field, SceneTemplate};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn scene(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes").join(name)
}

/// `stability` on radial_only with quick defaults; a flag in `extra` replaces its default.
fn stability(out: &Path, extra: &[&str]) -> Output {
    let defaults = [("--freq", "1e6:1e6:1"), ("--scan", "2"), ("--tol", "0.2"), ("--set", "modes.max_order=4")];
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_magbubble"));
    cmd.arg("stability").arg(scene("radial_only.toml"));
    for (flag, value) in defaults {
        if !extra.iter().any(|e| e.split("=").next() == Some(flag)) {
            cmd.args([flag, value]);
        }
    }
    cmd.arg("--out")
        .arg(out)
        .args(extra)
        .output()
        .unwrap()
}

/// Fails unless the command exits 1 with `needle` in stderr and wrote nothing.
fn refused(extra: &[&str], needle: &str) {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("st");
    let o = stability(&out, extra);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{extra:?}: {err}");
    assert!(err.contains(needle), "{extra:?}: expected '{needle}' in: {err}");
    assert!(!out.exists(), "{extra:?}: output written before the arguments were checked");
}

#[test]
fn bad_arguments_are_refused_before_any_work() {
    refused(&["--tol", "0"], "--tol 0: must be a finite number > 0");
    refused(&["--tol", "NaN"], "--tol NaN");
    refused(&["--scan", "0"], "--scan 0");
    refused(&["--vary", "no.such.key"], "--vary no.such.key: no scene key `no.such.key`");
    refused(&["--vary", "shell.form"], "is not a number");
    refused(&["--freq-key", "drive.amplitude"], "also the frequency axis");
    refused(&["--range=-1:1"], "`drive.amplitude` = -1.0: must be >= 0");
    refused(&["--family", "shell.c1=0.1,abc"], "--family shell.c1=abc");
    refused(&["--family", "shell.c1=0.1,-1"], "`shell.c1` = -1.0: must be >= 0");
    refused(&["--family", "shell.c1=0.1,,0.2"], "empty value");
    refused(&["--family", "shell.c3=1"], "--family shell.c3: no such scene key");
    refused(&["--family", "drive.amplitude=0.1,0.2"], "every curve would be the same");
    refused(&["--family", "drive.frequency_hz=1e6,2e6"], "every curve would be the same");
    refused(&["--set", "modes.max_order=0"], "needs shape modes");
}

#[test]
fn the_current_of_a_static_coil_is_not_swept_as_an_ac_one() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("st");
    let o = Command::new(env!("CARGO_BIN_EXE_magbubble"))
        .arg("stability")
        .arg(scene("coil_static.toml"))
        .args(["--freq", "1e6:1e6:1", "--vary", "field.coil.current.amplitude", "--range", "0:1e5"])
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("`field.coil.current` is a float in the scene, not a table"), "{err}");
    assert!(!out.exists());
}

#[test]
fn merge_refuses_to_overwrite_an_input() {
    let tmp = tempfile::tempdir().unwrap();
    let csv = tmp.path().join("s.csv");
    let meta = SweepMeta {
        fingerprint: "t".into(),
        total: 2,
        shard: Shard::ALL,
        header: vec!["f".into(), "x".into()],
    };
    sweep::run(&csv, &meta, false, |i| vec![i.to_string(), "1".into()]).unwrap();
    let before = std::fs::read_to_string(&csv).unwrap();
    let alias = tmp.path().join(".").join("s.csv");
    for out in [&csv, &alias] {
        let err = sweep::merge(std::slice::from_ref(&csv), out).unwrap_err().to_string();
        assert!(err.contains("is one of the inputs"), "{err}");
    }
    assert_eq!(std::fs::read_to_string(&csv).unwrap(), before);
}

#[test]
fn error_rows_are_computed_again_on_resume() {
    let tmp = tempfile::tempdir().unwrap();
    let csv = tmp.path().join("s.csv");
    let meta = SweepMeta {
        fingerprint: "t".into(),
        total: 3,
        shard: Shard::ALL,
        header: vec!["f".into(), "outcome".into()],
    };
    let is_error = |f: &[String]| f[1] == "error";
    sweep::run_retrying(&csv, &meta, false, is_error, |i| {
        vec![i.to_string(), if i == 1 { "error".into() } else { "critical".into() }]
    })
    .unwrap();
    let calls = std::sync::Mutex::new(Vec::new());
    let report = sweep::run_retrying(&csv, &meta, false, is_error, |i| {
        calls.lock().unwrap().push(i);
        vec![i.to_string(), "critical".into()]
    })
    .unwrap();
    assert_eq!(*calls.lock().unwrap(), vec![1]);
    assert_eq!((report.computed, report.resumed), (1, 2));
    assert!(!std::fs::read_to_string(&csv).unwrap().contains("error"));
}

#[test]
fn template_overrides_equal_set_and_are_validated() {
    let path = scene("coil_ac_current.toml");
    let t = SceneTemplate::load(&path, &["modes.max_order=4"]).unwrap();
    let direct = t.with(&[("field.coil.current.frequency_hz", 7e5), ("drive.amplitude", 0.25)]).unwrap();
    let via_set = scene::load(
        &path,
        &["modes.max_order=4", "field.coil.current.frequency_hz=7e5", "drive.amplitude=0.25"],
    )
    .unwrap();
    assert_eq!(format!("{direct:?}"), format!("{via_set:?}"));
    let err = t.with(&[("drive.amplitude", -0.5)]).unwrap_err().to_string();
    assert!(err.contains("`drive.amplitude` = -0.5: must be >= 0"), "{err}");
    let err = t.with(&[("shell.form", 1.0)]).unwrap_err().to_string();
    assert!(err.contains("not a number"), "{err}");
    assert_eq!(t.with(&[("modes.max_order", 6.0)]).unwrap().modes.max_order, 6);
    // A static coil stays static: sweeping its frequency is an error, not a 1 MHz AC current.
    let st = SceneTemplate::load(scene("coil_static.toml"), &[] as &[&str]).unwrap();
    assert!(st.with(&[("field.coil.current.frequency_hz", 1e6)]).is_err());
    match &st.scene().field {
        Some(Field::Coil(c)) => assert!(matches!(c.current, Current::Static { .. })),
        other => panic!("{other:?}"),
    }
}

/// Issue 15 class 8: a sweep stable at every frequency is a valid result: `--plot` exits 0 and
/// draws the stable frequencies as markers at the top of the searched range.
#[test]
fn a_sweep_stable_everywhere_is_plotted_not_an_error() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("st");
    let o = stability(&out, &["--freq", "1e6:2e6:2", "--range", "0:1e-6", "--plot"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "{err}");
    let csv = std::fs::read_to_string(out.join("stability.csv")).unwrap();
    assert_eq!(csv.matches(",stable_throughout,").count(), 2, "{csv}");
    let svg = std::fs::read_to_string(out.join("stability.svg")).unwrap();
    assert!(svg.contains("stable up to the range top"), "no marker legend in the svg");
    assert!(out.join("stability.png").exists());
    assert!(!out.join("stability_mode.svg").exists(), "a mode staircase with no unstable mode");
}

/// Issue 15 output conventions: one spelling of NaN. An error row spells its empty numbers as a
/// computed row does (`NaN`, which also parses back as NaN), never `nan`.
#[test]
fn error_rows_spell_nan_as_computed_rows_do() {
    use magbubble::analysis::stability::CRITICAL_HEADER;
    let f = magbubble::api::stability::error_fields("no orbit, at all");
    assert_eq!(f.len(), CRITICAL_HEADER.len());
    assert_eq!(f[1], "error");
    assert_eq!(f[f.len() - 1], "no orbit, at all");
    assert_eq!(f[CRITICAL_HEADER.iter().position(|h| *h == "mode").unwrap()], "");
    let computed_nan = format!("{:.8e}", f64::NAN);
    for (cell, name) in f.iter().zip(CRITICAL_HEADER).filter(|(_, n)| !["outcome", "mode", "note"].contains(n)) {
        assert_eq!(cell, &computed_nan, "{name}");
        assert!(cell.parse::<f64>().unwrap().is_nan());
    }
}
