//! Every example command of docs/user-guide.md, docs/adding-a-field.md and
//! docs/adding-a-shell-law.md runs. The commands are
//! read from the docs themselves (lines in ```sh blocks starting with `magbubble `), so the docs
//! and this test cannot drift.
//! They run in a temporary directory with the shipped scenes copied to ./scenes; each must exit 0
//! and the files the guide says it writes must exist.

use std::path::Path;
use std::process::Command;

fn guide_commands(doc: &str) -> Vec<String> {
    let text = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("docs").join(doc)).unwrap();
    let mut in_sh = false;
    let mut out = Vec::new();
    for line in text.lines() {
        let l = line.trim();
        if l.starts_with("```") {
            in_sh = l == "```sh";
            continue;
        }
        if in_sh && l.starts_with("magbubble ") {
            out.push(l.split(" #").next().unwrap().trim().to_string());
        }
    }
    out
}

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        let p = e.path();
        if p.is_dir() {
            copy_dir(&p, &to.join(e.file_name()));
        } else {
            std::fs::copy(&p, to.join(e.file_name())).unwrap();
        }
    }
}

#[test]
fn every_guide_example_runs() {
    let (guide, field) = (guide_commands("user-guide.md"), guide_commands("adding-a-field.md"));
    let shell = guide_commands("adding-a-shell-law.md");
    assert!(guide.len() >= 12, "found only {} example commands in the guide", guide.len());
    assert!(field.len() >= 2, "found only {} example commands in adding-a-field", field.len());
    assert!(shell.len() >= 3, "found only {} example commands in adding-a-shell-law", shell.len());
    let cmds = [guide, field, shell].concat();
    let dir = tempfile::tempdir().unwrap();
    copy_dir(Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes")), &dir.path().join("scenes"));
    for cmd in &cmds {
        // `> FILE` redirections in the guide: capture stdout into FILE.
        let (cmd_part, redirect) = match cmd.split_once(" > ") {
            Some((c, f)) => (c, Some(f.trim())),
            None => (cmd.as_str(), None),
        };
        let args: Vec<&str> = cmd_part.split_whitespace().skip(1).collect();
        let start = std::time::Instant::now();
        let o = Command::new(env!("CARGO_BIN_EXE_magbubble")).args(&args).current_dir(dir.path()).output().unwrap();
        eprintln!("{:6.2} s  {cmd}", start.elapsed().as_secs_f64());
        assert!(
            o.status.success(),
            "`{cmd}` failed:\n{}\n{}",
            String::from_utf8_lossy(&o.stdout),
            String::from_utf8_lossy(&o.stderr)
        );
        if let Some(f) = redirect {
            assert!(!o.stdout.is_empty(), "`{cmd}` printed nothing");
            std::fs::write(dir.path().join(f), &o.stdout).unwrap();
        }
    }
    // The outputs the guide describes.
    for f in [
        "out/coil/series.csv",
        "out/coil/summary.json",
        "out/coil_h4/summary.json",
        "out/stab/stability.csv",
        "out/s0/stability.shard-0-of-2.csv",
        "out/all.csv",
        "out/grid/sweep.csv",
        "out/grid_f/series/2.csv",
        "out/g/sweep.csv",
        "my_scene.toml",
        "out/skalak/series.png",
        "out/skalak/summary.json",
        "out/burst/echo.csv",
        "out/burst/spectrum.csv",
        "out/burst/echo.png",
        "out/burst-response/response.csv",
    ] {
        assert!(dir.path().join(f).is_file(), "{f} missing after the guide's examples");
    }
    // the guide plots out/coil_h4 (--plot), then adding-a-field.md runs the same scene into the
    // same default directory without --plot: the old plot would describe other data, so that
    // run removes it (issue 29 item 9)
    assert!(!dir.path().join("out/coil_h4/series.png").exists(), "a stale plot survived a run without --plot");
    let header = std::fs::read_to_string(dir.path().join("out/coil/series.csv")).unwrap();
    assert!(header.starts_with("t,R,a2,b2"), "series.csv header: {}", header.lines().next().unwrap_or(""));
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("out/coil/summary.json")).unwrap()).unwrap();
    assert_eq!(summary["status"], "completed", "{summary}");
    // the full-length run of scenes/coil_h4.toml (adding-a-field.md) completes 100 µs
    let h4: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("out/coil_h4/summary.json")).unwrap()).unwrap();
    assert_eq!(h4["status"], "completed", "{h4}");
}
