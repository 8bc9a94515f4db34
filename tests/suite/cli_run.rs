//! The `magbubble` binary: `run` and `scene` on valid and invalid scenes.

use std::path::Path;
use std::process::Command;

fn magbubble() -> Command {
    Command::new(env!("CARGO_BIN_EXE_magbubble"))
}

#[test]
fn run_with_invalid_scene_fails_and_creates_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = tmp.path().join("bad.toml");
    std::fs::write(&scene, "[shell]\nc1 = -0.1\n[modes]\nmax_order = 3\n").unwrap();
    let out = tmp.path().join("not/yet");
    let o = magbubble()
        .arg("run")
        .arg(&scene)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("`shell.c1` = -0.1: must be >= 0"), "{err}");
    assert!(err.contains("`modes.max_order` = 3"), "{err}");
    assert!(
        !out.exists() && !tmp.path().join("not").exists(),
        "output created for an invalid scene"
    );
}

#[test]
fn run_with_bad_set_fails_and_creates_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/radial_only.toml");
    let out = tmp.path().join("o");
    let o = magbubble()
        .arg("run")
        .arg(&scene)
        .args(["--out"])
        .arg(&out)
        .args(["--set", "drive.amplitud=0.3"])
        .output()
        .unwrap();
    assert!(!o.status.success());
    assert!(
        String::from_utf8_lossy(&o.stderr).contains("`drive.amplitud` = 0.3: --set: no such key")
    );
    assert!(!out.exists());
}

#[test]
fn scene_check_accepts_new_and_rejects_with_every_error() {
    let tmp = tempfile::tempdir().unwrap();
    let new = magbubble().args(["scene", "new"]).output().unwrap();
    assert!(new.status.success());
    let path = tmp.path().join("new.toml");
    std::fs::write(&path, &new.stdout).unwrap();
    let ok = magbubble()
        .args(["scene", "check"])
        .arg(&path)
        .args(["--set", "drive.amplitude=0.3"])
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&ok.stdout);
    assert!(
        ok.status.success(),
        "{}",
        String::from_utf8_lossy(&ok.stderr)
    );
    assert!(
        stdout.contains("valid scene") && stdout.contains("eps_p = 0.3"),
        "{stdout}"
    );

    let bad = magbubble()
        .args(["scene", "check"])
        .arg(&path)
        .args(["--set", "run.duration=0", "--set", "shell.c1=abc"])
        .output()
        .unwrap();
    assert!(!bad.status.success());
    let err = String::from_utf8_lossy(&bad.stderr);
    assert!(
        err.contains("2 problems") && err.contains("`run.duration` = 0.0: must be > 0"),
        "{err}"
    );
}
