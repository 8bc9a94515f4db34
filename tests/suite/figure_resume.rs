//! `magbubble figure` resumes (issue 15 "What people look at"): finished curves are kept in
//! `OUT/figNN.parts/`, a rerun of the same request reuses them, says so and writes the same
//! files byte for byte; a removed, corrupt or stale part (the scene changed) is recomputed;
//! an interrupted figure keeps its finished curves.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::{Duration, Instant};

fn magbubble() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_magbubble"));
    c.current_dir(env!("CARGO_MANIFEST_DIR"));
    c
}

fn figure(n: u32, out: &Path, extra: &[&str]) -> Output {
    let o = magbubble()
        .args(["figure", &n.to_string(), "--quick", "--out"])
        .arg(out)
        .args(extra)
        .output()
        .unwrap();
    assert!(o.status.success(), "figure {n} failed:\n{}", String::from_utf8_lossy(&o.stderr));
    o
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The figure's data and images, to compare runs byte for byte.
fn files(out: &Path, stem: &str) -> Vec<(PathBuf, Vec<u8>)> {
    ["csv", "svg", "png"]
        .iter()
        .map(|ext| {
            let p = out.join(format!("{stem}.{ext}"));
            let bytes = std::fs::read(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
            (p, bytes)
        })
        .collect()
}

fn assert_same(a: &[(PathBuf, Vec<u8>)], b: &[(PathBuf, Vec<u8>)], what: &str) {
    for ((p, x), (_, y)) in a.iter().zip(b) {
        assert!(x == y, "{what}: {} differs from the uninterrupted run", p.display());
    }
}

#[test]
fn a_rerun_reuses_finished_curves_and_writes_the_same_files() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("figs");
    let first = figure(13, &out, &[]);
    assert!(!stderr(&first).contains("reused"), "{}", stderr(&first));
    let parts = out.join("fig13.parts");
    for i in 0..3 {
        assert!(parts.join(format!("curve-{i:02}.json")).is_file(), "curve {i} not kept");
    }
    let reference = files(&out, "fig13");

    let again = figure(13, &out, &[]);
    assert!(stderr(&again).contains("reused 3 of 3 finished curves"), "{}", stderr(&again));
    assert_same(&reference, &files(&out, "fig13"), "full reuse");

    // One curve lost (as when a run is interrupted before it finished): only it is computed.
    std::fs::remove_file(parts.join("curve-01.json")).unwrap();
    let resumed = figure(13, &out, &[]);
    assert!(stderr(&resumed).contains("reused 2 of 3 finished curves"), "{}", stderr(&resumed));
    assert!(parts.join("curve-01.json").is_file());
    assert_same(&reference, &files(&out, "fig13"), "resumed");

    // A cut-off part file is recomputed, not an error.
    let p = parts.join("curve-00.json");
    let text = std::fs::read(&p).unwrap();
    std::fs::write(&p, &text[..text.len() / 2]).unwrap();
    let repaired = figure(13, &out, &[]);
    let err = stderr(&repaired);
    assert!(err.contains("reused 2 of 3") && err.contains("recomputed: the stored part is unreadable"), "{err}");
    assert_same(&reference, &files(&out, "fig13"), "repaired");

    let fresh = figure(13, &out, &["--fresh"]);
    assert!(!stderr(&fresh).contains("reused"), "{}", stderr(&fresh));
    assert_same(&reference, &files(&out, "fig13"), "--fresh");
}

#[test]
fn a_changed_scene_recomputes_every_curve() {
    let tmp = tempfile::tempdir().unwrap();
    let scenes = tmp.path().join("scenes");
    std::fs::create_dir(&scenes).unwrap();
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/figures");
    for e in std::fs::read_dir(&src).unwrap().flatten() {
        std::fs::copy(e.path(), scenes.join(e.file_name())).unwrap();
    }
    let out = tmp.path().join("figs");
    let with = ["--scenes", scenes.to_str().unwrap()];
    figure(14, &out, &with);
    assert!(stderr(&figure(14, &out, &with)).contains("reused"));
    let scene = scenes.join("fig14_current_frequency.toml");
    let mut text = std::fs::read_to_string(&scene).unwrap();
    text.push_str("\n# edited: a changed scene file is another request\n");
    std::fs::write(&scene, text).unwrap();
    let redone = figure(14, &out, &with);
    let err = stderr(&redone);
    assert!(!err.contains("reused"), "{err}");
    assert!(err.contains("recomputed: the stored part is for another scene file"), "{err}");
}

#[test]
fn an_interrupted_stability_figure_keeps_its_finished_curves() {
    let tmp = tempfile::tempdir().unwrap();
    let reference = tmp.path().join("whole");
    figure(10, &reference, &[]);
    let out = tmp.path().join("figs");
    let child = magbubble()
        .args(["figure", "10", "--quick", "--out"])
        .arg(&out)
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let first = out.join("fig10.parts/curve-00.json");
    let start = Instant::now();
    while !first.is_file() && start.elapsed() < Duration::from_secs(60) {
        std::thread::sleep(Duration::from_millis(2));
    }
    assert!(first.is_file(), "the first family was not kept within 60 s");
    // SAFETY: kill(2) on the child we started.
    unsafe { libc::kill(child.id() as libc::pid_t, libc::SIGINT) };
    let o = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    if o.status.success() {
        eprintln!("the figure finished before the signal arrived; checking the resume only");
    } else {
        assert_eq!(o.status.code(), Some(130), "{err}");
        assert!(err.contains("finished curves are kept"), "{err}");
    }
    let leftovers: Vec<_> = std::fs::read_dir(out.join("fig10.parts"))
        .unwrap()
        .flatten()
        .filter(|e| !e.file_name().to_string_lossy().ends_with(".json"))
        .collect();
    assert!(leftovers.is_empty() || !o.status.success(), "{leftovers:?}");
    let resumed = figure(10, &out, &[]);
    assert!(stderr(&resumed).contains("finished curves from"), "{}", stderr(&resumed));
    let left: Vec<_> = std::fs::read_dir(out.join("fig10.parts"))
        .unwrap()
        .flatten()
        .filter(|e| e.file_name().to_string_lossy().contains(".tmp"))
        .collect();
    assert!(left.is_empty(), "temporary files left after the resume: {left:?}");
    assert_same(&files(&reference, "fig10"), &files(&out, "fig10"), "interrupted and resumed");
}
