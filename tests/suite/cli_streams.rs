//! Defect class 1 of issue 15: a closed or full stdout/stderr is an error, never a panic (exit
//! 101). A broken pipe (`| head`) ends the command quietly with status 141; a full device
//! (`> /dev/full`) gives one clear error and status 1.

use std::path::Path;
use std::process::{Command, Output, Stdio};

fn scene(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes").join(name).display().to_string()
}

/// Every command that prints to stdout, with arguments that make it quick.
fn printing_commands(tmp: &Path) -> Vec<Vec<String>> {
    let out = |n: &str| tmp.join(n).display().to_string();
    let s = |v: &[&str]| v.iter().map(|x| x.to_string()).collect::<Vec<_>>();
    vec![
        s(&["scene", "new"]),
        s(&["scene", "explain"]),
        s(&["scene", "explain", "shell"]),
        vec!["scene".into(), "check".into(), scene("coil_static.toml")],
        s(&["coefficients", "--field", "coil", "--kmax", "8"]),
        s(&["figure", "list"]),
        vec!["modes".into(), scene("coil_static.toml")],
        vec!["floquet".into(), scene("radial_only.toml"), "--json".into(), "--steps".into(), "50".into(), "--set".into(), "modes.max_order=4".into()],
        vec!["floquet".into(), scene("radial_only.toml"), "--steps".into(), "50".into(), "--set".into(), "modes.max_order=4".into()],
        vec![
            "run".into(),
            scene("radial_only.toml"),
            "--out".into(),
            out("run"),
            "--set".into(),
            "run.duration=1e-6".into(),
        ],
    ]
}

fn run_with(args: &[String], stdout: Stdio, stderr: Stdio) -> Output {
    Command::new(env!("CARGO_BIN_EXE_magbubble"))
        .args(args)
        .stdout(stdout)
        .stderr(stderr)
        .output()
        .unwrap()
}

/// A pipe whose read end is already closed: the first write gets EPIPE.
fn closed_pipe() -> Stdio {
    let (reader, writer) = std::io::pipe().unwrap();
    drop(reader);
    Stdio::from(writer)
}

fn dev_full() -> Option<Stdio> {
    std::fs::OpenOptions::new().write(true).open("/dev/full").ok().map(Stdio::from)
}

#[test]
fn closed_stdout_ends_quietly_for_every_printing_command() {
    let tmp = tempfile::tempdir().unwrap();
    for args in printing_commands(tmp.path()) {
        let o = run_with(&args, closed_pipe(), Stdio::piped());
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(141), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        assert!(err.is_empty(), "{args:?} should be quiet on a broken pipe: {err}");
    }
}

#[test]
fn full_stdout_is_a_clear_error_for_every_printing_command() {
    let tmp = tempfile::tempdir().unwrap();
    if dev_full().is_none() {
        return; // not Linux
    }
    for args in printing_commands(tmp.path()) {
        let o = run_with(&args, dev_full().unwrap(), Stdio::piped());
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {err}");
        assert!(err.contains("cannot write to standard output"), "{args:?}: {err}");
        assert!(err.contains("No space left on device"), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
    }
}

#[test]
fn unwritable_stderr_does_not_stop_a_command() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("st");
    let args: Vec<String> = vec![
        "stability".into(),
        scene("radial_only.toml"),
        "--freq".into(),
        "1e6:1e6:1".into(),
        "--scan".into(),
        "2".into(),
        "--tol".into(),
        "0.2".into(),
        "--out".into(),
        out.display().to_string(),
        "--set".into(),
        "modes.max_order=4".into(),
    ];
    for stderr in [Some(closed_pipe()), dev_full()].into_iter().flatten() {
        let o = run_with(&args, Stdio::null(), stderr);
        assert_eq!(o.status.code(), Some(0), "stability with an unwritable stderr");
        assert!(out.join("stability.csv").exists());
    }
}
