//! Issue 30 part 1, the drives (docs/model.md, "Drives"): bursts, tones, measured waveforms;
//! their stop times; Floquet's refusal of a non-periodic drive; every bad input a clear error.

use magbubble::analysis::stability::{check_scene, floquet, Criterion, FloquetOptions};
use magbubble::model::{simulate, Model, RunStatus};
use magbubble::scene::{load_str, Scene};
use std::process::Command;

const NONE: &[&str] = &[];

/// A free-ish radial scene (the paper's shell, no modes), RK-adaptive, with `drive` as [drive].
fn scene(drive: &str, extra: &str) -> String {
    format!(
        "[bubble]\nradius = 10e-6\n[shell]\nc1 = 0.1\nc2 = 0.12\n[drive]\n{drive}\n[modes]\nmax_order = 0\n\
         [run]\nduration = 4e-6\nsample_interval = 2e-8\n[run.integrator]\nmethod = \"dop853\"\nrtol = 1e-11\natol = 1e-13\n{extra}"
    )
}

fn load(text: &str) -> Scene {
    load_str(text, "drives-test", NONE).unwrap_or_else(|e| panic!("{e}"))
}

fn err(text: &str) -> String {
    load_str(text, "drives-test", NONE).unwrap_err().to_string()
}

fn radius(s: &Scene) -> Vec<(f64, f64)> {
    let mut v = Vec::new();
    let r = simulate(s, &mut |t, row| v.push((t, row[0]))).unwrap();
    assert_eq!(r.status, RunStatus::Completed);
    v
}

fn write(dir: &std::path::Path, name: &str, text: &str) -> String {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p.display().to_string()
}

/// Before the burst starts the bubble sits at rest (p_a = 0); afterwards it moves.
#[test]
fn burst_is_silent_before_its_delay() {
    let s = load(&scene("amplitude = 0.3\nenvelope = \"hann\"\ncycles = 2\ndelay = 1e-6", ""));
    let r = radius(&s);
    // strictly before the start (at the edge itself the loop interpolates a step that crosses
    // it until it stops there: the stop times, Model::stop_times)
    for &(t, x) in &r {
        if t < 1e-6 - 1e-12 {
            assert_eq!(x, 10e-6, "t = {t}");
        }
    }
    assert!(r.iter().any(|&(_, x)| (x - 10e-6).abs() > 1e-8));
    let m = Model::from_scene(&s).unwrap();
    let ts = m.time_scale();
    let stops: Vec<f64> = m.stop_times().iter().map(|t| t * ts).collect();
    assert_eq!(stops.len(), 2);
    assert!((stops[0] - 1e-6).abs() < 1e-18 && (stops[1] - 3e-6).abs() < 1e-18, "{stops:?}");
    assert!(m.active_effects().iter().any(|e| e == "acoustic drive (burst)"));
}

/// A cosine sampled into a CSV drives the bubble as the cosine does, to the interpolation
/// error: at 200 samples per period the linear interpolant is off by ≤ (2π/200)²/8 = 1.2e-4 of
/// the amplitude; R(t) agrees to a comparable fraction of its excursion.
#[test]
fn sampled_cosine_matches_the_cosine() {
    let dir = tempfile::tempdir().unwrap();
    let (eps, p0, f) = (0.3, 101325.0, 1e6);
    let mut csv = String::from("t,p\n");
    let n = 200 * 5;
    for i in 0..=n {
        let t = i as f64 * 5e-6 / n as f64;
        csv.push_str(&format!("{t:e},{:e}\n", eps * p0 * (2.0 * std::f64::consts::PI * f * t).cos()));
    }
    let path = write(dir.path(), "cos.csv", &csv);
    let cosine = radius(&load(&scene("amplitude = 0.3", "")));
    let sampled = radius(&load(&scene(&format!("file = \"{path}\""), "")));
    let excursion = cosine.iter().map(|p| (p.1 - 10e-6).abs()).fold(0.0, f64::max);
    let diff = cosine.iter().zip(&sampled).map(|(a, b)| (a.1 - b.1).abs()).fold(0.0, f64::max);
    assert!(excursion > 1e-7);
    assert!(diff < 5e-4 * excursion, "max |ΔR| = {diff:e} of excursion {excursion:e}");
    // and not trivially: a half-amplitude file differs by far more
    let half = radius(&load(&scene(&format!("file = \"{path}\"\nfile_scale = 0.5"), "")));
    let d2 = cosine.iter().zip(&half).map(|(a, b)| (a.1 - b.1).abs()).fold(0.0, f64::max);
    assert!(d2 > 0.1 * excursion);
}

/// Pulse inversion: a component at the main frequency with phase π cancels it exactly.
#[test]
fn pulse_inversion_cancels() {
    let s = load(&scene("amplitude = 0.3\ncomponents = [{ amplitude = 0.3, frequency_hz = 1e6, phase = 3.141592653589793 }]", ""));
    let m = Model::from_scene(&s).unwrap();
    let w = m.drive().unwrap();
    for i in 0..100 {
        assert!(w.pressure(i as f64 * 0.37).abs() < 1e-12);
    }
}

/// Floquet refuses a burst (pointing at the series criterion), accepts commensurate tones with
/// their common period, refuses incommensurate ones naming the key and the value.
#[test]
fn floquet_needs_a_periodic_drive() {
    let with_modes = |d: &str| load(&scene(d, "").replace("max_order = 0", "max_order = 2"));
    let e = check_scene(&with_modes("amplitude = 0.1\nenvelope = \"gaussian\"\ncycles = 2"), Criterion::Floquet).unwrap_err().to_string();
    assert!(e.contains("gaussian") && e.contains("stability --method series"), "{e}");
    assert!(check_scene(&with_modes("amplitude = 0.1\nenvelope = \"gaussian\"\ncycles = 2"), Criterion::Series).is_ok());
    let s = with_modes("amplitude = 0.1\ncomponents = [{ amplitude = 0.05, frequency_hz = 1.4142135623730951e6 }]");
    let e = floquet(&s, &FloquetOptions::default()).unwrap_err().to_string();
    assert!(e.contains("drive.components[0].frequency_hz = 1.41421356") && e.contains("incommensurate"), "{e}");
    let s = with_modes("amplitude = 0.05\ncomponents = [{ amplitude = 0.02, frequency_hz = 2e6 }]");
    let r = floquet(&s, &FloquetOptions { convergence_check: false, ..FloquetOptions::default() }).unwrap();
    assert_eq!(r.drive_period_s, Some(1e-6));
}

/// Every bad drive input: an error naming the key and the value, and `run` writes nothing.
#[test]
fn bad_drive_input() {
    let dir = tempfile::tempdir().unwrap();
    let unsorted = write(dir.path(), "unsorted.csv", "t,p\n0,0\n2e-6,1\n1e-6,2\n");
    let nan = write(dir.path(), "nan.csv", "t,p\n0,0\n1e-6,NaN\n");
    let short = write(dir.path(), "short.csv", "t,p\n0,0\n");
    let good = write(dir.path(), "good.csv", "t,p\n0,0\n1e-6,1e3\n");
    let cases = [
        (format!("file = \"{}/missing.csv\"", dir.path().display()), "`drive.file` = \"", "cannot read"),
        (format!("file = \"{unsorted}\""), "`drive.file`", "not strictly increasing: data row 3 has t = 1e-6 after t = 2e-6"),
        (format!("file = \"{nan}\""), "`drive.file`", "not finite"),
        (format!("file = \"{short}\""), "`drive.file`", "at least 2"),
        (format!("file = \"{good}\"\namplitude = 0.3"), "`drive.amplitude` = 0.3", "cannot be combined with drive.file"),
        ("amplitude = 0.3\nenvelope = \"hann\"\ncycles = 0".into(), "`drive.cycles` = 0.0", "must be > 0"),
        ("amplitude = 0.3\nenvelope = \"hann\"\ncycles = -2".into(), "`drive.cycles` = -2.0", "must be > 0"),
        ("amplitude = 0.3\nenvelope = \"tukey\"".into(), "`drive.cycles`", "required with drive.envelope = \"tukey\""),
        ("amplitude = 0.3\ncycles = 3".into(), "`drive.cycles` = 3.0", "does nothing with drive.envelope = \"continuous\""),
        ("amplitude = 0.3\nenvelope = \"hann\"\ncycles = 3\nrepeat_hz = 5e5".into(), "`drive.repeat_hz` = 500000.0", "overlap"),
        ("amplitude = 0.3\nenvelope = \"blackman\"".into(), "`drive.envelope` = \"blackman\"", "hann"),
        ("amplitude = 0.3\ncomponents = [{ amplitude = 0.1 }]".into(), "`drive.components.frequency_hz`", "required"),
        ("amplitude = 0.3\ncomponents = [{ amplitude = 0.1, frequency_hz = 2e6, phse = 1 }]".into(), "`drive.components.phse`", "unknown key"),
    ];
    for (drive, key, reason) in &cases {
        let text = scene(drive, "");
        let e = err(&text);
        assert!(e.contains(key) && e.contains(reason), "{drive}: {e}");
        let file = write(dir.path(), "bad.toml", &text);
        let out = dir.path().join("out");
        let o = Command::new(env!("CARGO_BIN_EXE_magbubble")).arg("run").arg(&file).arg("--out").arg(&out).output().unwrap();
        assert!(!o.status.success() && !out.exists(), "{drive}: wrote output");
        assert!(String::from_utf8_lossy(&o.stderr).contains(key), "{drive}");
    }
}

/// A relative drive.file is read from the scene file's directory.
#[test]
fn relative_file_is_beside_the_scene() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "pulse.csv", "t,p\n0,0\n1e-6,1e4\n2e-6,0\n");
    let path = write(dir.path(), "s.toml", &scene("file = \"pulse.csv\"", ""));
    let s = magbubble::scene::load(&path, NONE).unwrap();
    let m = Model::from_scene(&s).unwrap();
    let ts = m.time_scale();
    let stops: Vec<f64> = m.stop_times().iter().map(|t| t * ts).collect();
    assert_eq!(stops.len(), 2, "the knots inside (0, 4 µs): {stops:?}");
    assert!((stops[1] - 2e-6).abs() < 1e-18);
}
