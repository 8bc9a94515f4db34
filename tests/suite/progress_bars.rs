//! `accuracy` shows a fraction-done bar on a terminal (issue 15 "Progress on long work"): it
//! knows how many simulations its ladders contain, counts every one, and prints nothing of
//! the bar in a pipe.

use magbubble::analysis::accuracy::{accuracy_study_with, planned_runs, AccuracyOptions};
use std::cell::Cell;
use std::path::Path;
use std::process::Command;

fn scene() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/no_field.toml")
}

#[test]
fn the_study_counts_the_runs_it_planned() {
    let s = magbubble::scene::load(&scene(), &[] as &[String]).unwrap();
    let opts = AccuracyOptions::quick();
    let planned = planned_runs(&s, &opts);
    // quick: 2 reference runs, rk4 3 rungs, dopri5/dop853/radau5 3 each, mode ladder 4, 8.
    assert_eq!(planned, 2 + 3 + 3 * 3 + 2);
    let seen = Cell::new(Vec::new());
    let rep = accuracy_study_with(&s, &opts, &|done, total| {
        let mut v = seen.take();
        v.push((done, total));
        seen.set(v);
    })
    .unwrap();
    let seen = seen.take();
    assert_eq!(seen.len(), planned, "one report per simulation");
    assert!(seen.iter().enumerate().all(|(i, &(d, t))| d == i + 1 && t == planned), "{seen:?}");
    assert_eq!(rep.ladders.len(), 4);
    let mut two = opts.clone();
    two.repeats = 2;
    assert_eq!(planned_runs(&s, &two), 2 + 2 * (3 + 3 * 3 + 2));
}

#[test]
fn the_bar_is_drawn_on_a_terminal_and_not_in_a_pipe() {
    let exe = env!("CARGO_BIN_EXE_magbubble");
    let tmp = tempfile::tempdir().unwrap();
    let piped = Command::new(exe)
        .args(["accuracy", scene().to_str().unwrap(), "--quick", "--out"])
        .arg(tmp.path().join("piped"))
        .output()
        .unwrap();
    assert!(piped.status.success());
    assert!(piped.stderr.is_empty(), "stderr in a pipe: {}", String::from_utf8_lossy(&piped.stderr));
    // A terminal: util-linux `script` runs the command on a pseudo-terminal.
    if Command::new("script").arg("--version").output().is_err() {
        eprintln!("no `script` here: the terminal half is not checked");
        return;
    }
    let log = tmp.path().join("typescript");
    let cmd = format!(
        "{exe} accuracy {} --quick --out {}",
        scene().display(),
        tmp.path().join("tty").display()
    );
    let o = Command::new("script").args(["-qfec", &cmd]).arg(&log).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8_lossy(&std::fs::read(&log).unwrap()).into_owned();
    assert!(text.contains("accuracy study [") && text.contains("/16 runs"), "no bar on the terminal:\n{text}");
}
