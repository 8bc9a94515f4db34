//! Every command line quoted in README.md and docs/*.md runs (issue 29 item 16). The commands
//! are read from the docs themselves — lines in fenced code blocks starting with `magbubble `,
//! and README's indented `cargo run --release -- …` lines — so the docs and this test cannot
//! drift. They run in a temporary directory with the shipped scenes copied to ./scenes; each
//! must exit 0, the files the docs say it writes must exist, and the numbers they quote that are
//! deterministic are checked. The three guides run in order in one directory (later commands
//! read earlier outputs); every other document in a directory of its own.

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

/// The command lines of a document: fenced code blocks (```sh or a bare ```) lines starting
/// with `magbubble ` (a trailing `\` continues the line; ` # comment` dropped), and indented
/// `cargo run --release -- ARGS` lines (README), as `magbubble ARGS`.
fn doc_commands(doc: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(doc).unwrap();
    let (mut fenced, mut out, mut pending) = (None::<bool>, Vec::new(), String::new());
    for line in text.lines() {
        let l = line.trim();
        if l.starts_with("```") {
            fenced = match fenced {
                Some(_) => None,
                None => Some(l == "```sh" || l == "```"),
            };
            continue;
        }
        let cmd = if !pending.is_empty() {
            Some(l.to_string())
        } else if fenced == Some(true) && l.starts_with("magbubble ") {
            Some(l.to_string())
        } else if fenced.is_none() && line.starts_with("    ") && l.starts_with("cargo run --release -- ") {
            Some(format!("magbubble {}", &l["cargo run --release -- ".len()..]))
        } else {
            None
        };
        let Some(cmd) = cmd else { continue };
        let cmd = cmd.split(" #").next().unwrap().trim().to_string();
        match cmd.strip_suffix('\\') {
            Some(head) => pending.push_str(head),
            None => {
                pending.push_str(&cmd);
                out.push(std::mem::take(&mut pending).split_whitespace().collect::<Vec<_>>().join(" "));
            }
        }
    }
    out
}

/// A command written as a template (`--out DIR`, `KEY=KB`): an upper-case word of two or more
/// letters where a value goes.
fn is_template(cmd: &str) -> bool {
    cmd.split(|c: char| c.is_whitespace() || c == '=' || c == ',').any(|w| w.len() >= 2 && w.chars().all(|c| c.is_ascii_uppercase()))
}

fn run_in(dir: &Path, cmd: &str) -> std::process::Output {
    let (cmd_part, redirect) = match cmd.split_once(" > ") {
        Some((c, f)) => (c, Some(f.trim())),
        None => (cmd, None),
    };
    let args: Vec<&str> = cmd_part.split_whitespace().skip(1).collect();
    let start = std::time::Instant::now();
    let o = Command::new(env!("CARGO_BIN_EXE_magbubble")).args(&args).current_dir(dir).output().unwrap();
    eprintln!("{:6.2} s  {cmd}", start.elapsed().as_secs_f64());
    assert!(
        o.status.success(),
        "`{cmd}` failed:\n{}\n{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    if let Some(f) = redirect {
        assert!(!o.stdout.is_empty(), "`{cmd}` printed nothing");
        std::fs::write(dir.join(f), &o.stdout).unwrap();
    }
    o
}

/// Every document but the three guides: each command runs as written (in a directory of its
/// document's own), except `figure all`, run with `--quick`: the full one is 50 s of CPU
/// (tests/suite/figures.rs checks the full figures' numbers).
#[test]
fn every_other_documented_command_runs() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut docs = vec![root.join("README.md")];
    let mut listed: Vec<_> = std::fs::read_dir(root.join("docs")).unwrap().map(|e| e.unwrap().path()).collect();
    listed.sort();
    docs.extend(listed.into_iter().filter(|p| {
        let name = p.file_name().unwrap().to_str().unwrap();
        name.ends_with(".md") && !["user-guide.md", "adding-a-field.md", "adding-a-shell-law.md"].contains(&name)
    }));
    let (mut ran, mut templates) = (Vec::new(), Vec::new());
    for doc in &docs {
        let cmds = doc_commands(doc);
        if cmds.is_empty() {
            continue;
        }
        let dir = tempfile::tempdir().unwrap();
        copy_dir(&root.join("scenes"), &dir.path().join("scenes"));
        for cmd in cmds {
            if is_template(&cmd) {
                templates.push(cmd);
                continue;
            }
            let cmd = if cmd.starts_with("magbubble figure all") { format!("{cmd} --quick") } else { cmd };
            let o = run_in(dir.path(), &cmd);
            if doc.ends_with("README.md") && cmd.starts_with("magbubble run scenes/coil_marmottant.toml --out out/coil_marmottant") {
                // README: "it completes 400 µs … while R buckles in each compression (about a
                // quarter of the time)"
                let s: serde_json::Value =
                    serde_json::from_str(&std::fs::read_to_string(dir.path().join("out/coil_marmottant/summary.json")).unwrap()).unwrap();
                assert_eq!(s["status"], "completed", "{s}");
                assert!((s["t_end"].as_f64().unwrap() - 400e-6).abs() < 1e-12, "{s}");
                let buckled = s["shell_branches"]["buckled"].as_f64().unwrap();
                assert!((0.2..0.3).contains(&buckled), "README says about a quarter of the time buckled: {buckled}");
                assert!(dir.path().join("out/coil_marmottant/series.png").is_file());
                let _ = o;
            }
            ran.push(cmd);
        }
    }
    // the README's first command and every fenced block of scenes.md, figures.md, supplementary.md
    assert!(ran.iter().any(|c| c.starts_with("magbubble run scenes/coil_marmottant.toml")), "README's first command not found: {ran:?}");
    assert!(ran.len() >= 9, "only {} commands found: {ran:?}", ran.len());
    // README names every shipped scene of scenes/ (issue 29 item 16: it missed five)
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    for e in std::fs::read_dir(root.join("scenes")).unwrap() {
        let p = e.unwrap().path();
        let name = p.file_stem().unwrap().to_str().unwrap();
        let needle = if p.is_dir() { format!("`scenes/{name}/`") } else { format!("`{name}`") };
        assert!(readme.contains(&needle), "README.md does not list the shipped scene {needle}");
    }
    // a new template is a decision: say here why it cannot run as written
    let known = ["magbubble stability scenes/figures/fig05_modes.toml --freq 1e6,1.5e6,2e6 --family modes.max_order=12,16,20,24,28,32 --set shell.bending_modulus=KB --out DIR"];
    assert_eq!(templates, known, "templates (not run)");
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
        run_in(dir.path(), cmd);
    }
    // The outputs the guide describes.
    for f in [
        "out/coil/series.csv",
        "out/fit/fit.json",
        "out/fit/fit.csv",
        "out/fit_att/fit.json",
        "out/fit_att/fit.csv",
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
        "out/pop/population.csv",
        "out/pop/population_bins.csv",
        "out/att/attenuation.csv",
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
