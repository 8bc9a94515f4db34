//! `stability --modes auto` (issue 31 part 5; analysis/cutoff.rs): the cutoff N raised until the
//! critical value moves by less than the bracket tolerance. A free bubble and the Marmottant
//! shell converge; the Mooney–Rivlin membrane at the fig-12 setting (1 MHz, negative tension in
//! compression) does not, and the row says which mode leads and that the tension goes negative.

use magbubble::analysis::sweep::Shard;
use magbubble::api::stability::{stability, Criterion, FreqAxis, Modes, StabilityRequest};
use magbubble::api::{Monitor, Scene};
use std::collections::HashMap;
use std::path::Path;
use std::process::Command;

const FREE: &str = "[bubble]\nradius = 10e-6\n[shell]\nc1 = 0.0\nc2 = 0.0\nsurface_tension = 0.072\n\
                    [drive]\namplitude = 1e-4\nfrequency_hz = 1e6\n[modes]\nmax_order = 4\n";

fn request(out: &Path, freq: f64, modes: Modes) -> StabilityRequest {
    StabilityRequest {
        freq: FreqAxis::list(&[freq]).unwrap(),
        method: Criterion::Floquet,
        family: None,
        vary: "drive.amplitude".into(),
        freq_key: None,
        range: (0.0, 1.0),
        tol: 1e-3,
        abs_tol: None,
        scan: 8,
        out: out.to_path_buf(),
        shard: Shard::ALL,
        modes,
    }
}

/// The one row of a one-frequency diagram, by column name.
fn row(scene: &Scene, req: &StabilityRequest) -> HashMap<String, String> {
    let out = stability(scene, req, &Monitor::default()).unwrap();
    let c = &out.curves[0];
    c.header.iter().cloned().zip(c.report.rows[0].1.iter().cloned()).collect()
}

fn num(r: &HashMap<String, String>, k: &str) -> f64 {
    r[k].parse().unwrap_or_else(|_| panic!("{k} = {}", r[k]))
}

fn auto(limit: usize) -> Modes {
    Modes::parse("auto", Some(limit)).unwrap()
}

#[test]
fn a_free_bubble_converges_and_the_last_rung_is_the_fixed_cutoff_search() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("free.toml");
    std::fs::write(&path, FREE).unwrap();
    let scene = Scene::load(&path, &[] as &[String]).unwrap();
    let r = row(&scene, &request(&dir.path().join("auto"), 0.5e6, auto(16)));
    eprintln!("{r:?}");
    assert_eq!(r["cutoff_converged"], "true");
    let used: usize = r["max_order_used"].parse().unwrap();
    assert!(used == 8 || used == 16, "N = 4 → 8 (→ 16): {used}");
    // the row's critical value is that of a plain search at N = max_order_used, bit for bit
    let fixed = Scene::load(&path, &[format!("modes.max_order={used}")]).unwrap();
    let f = row(&fixed, &request(&dir.path().join("fixed"), 0.5e6, Modes::Scene));
    assert_eq!(r["critical"], f["critical"]);
    assert!(!f.contains_key("cutoff_converged"), "a fixed cutoff keeps the old columns");
    // the error bar holds the bracket width at least (the width from the CSV's 9 significant
    // digits, each end rounded by up to 5e-9 of itself: an error bar that is the bracket width
    // alone can print below it by that much)
    let width = num(&r, "unstable") - num(&r, "stable");
    let rounding = 1e-8 * num(&r, "unstable");
    assert!(num(&r, "critical_error") >= width - rounding && num(&r, "critical_error") < 10.0 * width, "{r:?}");
    assert!(r["min_tension"] == "NaN", "a free bubble has no membrane tension");
}

#[test]
fn marmottant_converges_where_mooney_rivlin_does_not() {
    let dir = tempfile::tempdir().unwrap();
    let marm = Scene::load(Path::new("scenes/coil_marmottant.toml"), &["modes.max_order=8".to_string()]).unwrap();
    let m = row(&marm, &request(&dir.path().join("m"), 1e6, auto(32)));
    eprintln!("marmottant: {m:?}");
    assert_eq!(m["cutoff_converged"], "true", "{m:?}");
    assert!(num(&m, "min_tension") >= 0.0, "a lipid monolayer carries no compression");
    assert!(m["note"].is_empty(), "{m:?}");

    // the fig-12 setting with the Mooney–Rivlin membrane, no field: ε_c falls with N
    let mr = Scene::load(Path::new("scenes/no_field.toml"), &["modes.max_order=4".to_string()]).unwrap();
    let r = row(&mr, &request(&dir.path().join("mr"), 1e6, auto(16)));
    eprintln!("mooney-rivlin: {r:?}");
    assert_eq!(r["cutoff_converged"], "false");
    assert_eq!(r["max_order_used"], "16");
    assert!(num(&r, "min_tension") < 0.0, "negative tension in compression");
    let note = &r["note"];
    assert!(note.contains("cutoff not converged up to N=16") && note.contains(&format!("mode {} leads", r["mode"])), "{note}");
    assert!(note.contains("membrane tension negative on the orbit"), "{note}");
    // the error bar holds the last cutoff step (N = 8 → 16), parsed from the note
    let at = |n: &str| -> f64 { note.split(&format!("N={n}: ")).nth(1).unwrap().split([';', ',', ')']).next().unwrap().parse().unwrap() };
    let step = (at("8") - at("16")).abs();
    assert!(at("4") > at("8") && at("8") > at("16"), "{note}");
    // (the note prints 7 digits)
    assert!(num(&r, "critical_error") >= step * (1.0 - 1e-5), "{} < {step}", r["critical_error"]);
}

#[test]
fn bad_cutoff_arguments_are_errors_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("free.toml");
    std::fs::write(&scene, FREE).unwrap();
    let cases: [(&[&str], &str); 4] = [
        (&["--modes", "all"], "--modes 'all'"),
        (&["--cutoff-limit", "16"], "--cutoff-limit 16: only with --modes auto"),
        (&["--modes", "auto", "--cutoff-limit", "7"], "--cutoff-limit 7"),
        (&["--modes", "auto", "--cutoff-limit", "4"], "modes.max_order = 4"),
    ];
    for (args, want) in cases {
        let out = dir.path().join("out");
        let st = Command::new(env!("CARGO_BIN_EXE_magbubble"))
            .arg("stability")
            .arg(&scene)
            .args(["--freq", "1e6", "--out"])
            .arg(&out)
            .args(args)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&st.stderr);
        assert!(!st.status.success() && err.contains(want), "{args:?}: {err}");
        assert!(!out.join("stability.csv").exists(), "{args:?}: nothing written");
    }
}

#[test]
fn the_cli_csv_has_the_cutoff_columns() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("free.toml");
    std::fs::write(&scene, FREE).unwrap();
    let out = dir.path().join("out");
    let st = Command::new(env!("CARGO_BIN_EXE_magbubble"))
        .arg("stability")
        .arg(&scene)
        .args(["--freq", "1e6", "--modes", "auto", "--cutoff-limit", "8", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(st.status.success(), "{}", String::from_utf8_lossy(&st.stderr));
    let csv = std::fs::read_to_string(out.join("stability.csv")).unwrap();
    let header = csv.lines().next().unwrap();
    assert!(header.ends_with(",max_order_used,cutoff_converged,critical_error,min_tension,note"), "{header}");
}
