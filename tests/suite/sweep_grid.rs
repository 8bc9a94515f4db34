//! `magbubble sweep` and `analysis::grid`: expansion and validation before any work, rows equal
//! to separate `run`s, resume, shards + merge == one run, thread-count independence, cancel.

use magbubble::analysis::grid::{self, GridAxis, GridOptions, GridPlan, GridStatus};
use magbubble::analysis::sweep::SweepError;
use magbubble::scene::SceneTemplate;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::sync::atomic::{AtomicBool, Ordering};

fn scene_path() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/no_field.toml")
}

const SHORT: [&str; 2] = ["--set", "run.duration=5e-6"];

fn magbubble(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_magbubble")).args(args).output().unwrap()
}

fn sweep_cli(out: &Path, extra: &[&str]) -> Output {
    let scene = scene_path();
    let mut args = vec!["sweep", scene.to_str().unwrap(), "--out", out.to_str().unwrap()];
    args.extend_from_slice(&["--grid", "drive.frequency_hz=0.5e6,1e6", "--grid", "bubble.radius=8e-6,10e-6"]);
    args.extend_from_slice(&SHORT);
    args.extend_from_slice(extra);
    magbubble(&args)
}

/// The CSV without its last column (`wall_seconds`, the one non-deterministic column).
fn deterministic(csv: &str) -> String {
    csv.lines().map(|l| l.rsplit_once(',').map_or(l, |(a, _)| a).to_string() + "\n").collect()
}

fn template(duration: &str) -> SceneTemplate {
    SceneTemplate::load(scene_path(), &[format!("run.duration={duration}")]).unwrap()
}

fn plan_2x3() -> GridPlan {
    let axes = [GridAxis::numbers("drive.frequency_hz", &[0.6e6, 1.2e6]), GridAxis::parse("bubble.radius=8e-6:10e-6:3").unwrap()];
    grid::plan_grid(&template("3e-6"), &axes).unwrap()
}

#[test]
fn expansion_is_row_major_and_named_by_the_keys() {
    let plan = plan_2x3();
    assert_eq!(plan.len(), 6);
    assert_eq!(plan.keys(), ["drive.frequency_hz", "bubble.radius"]);
    assert_eq!(plan.values(0), ["6e5", "8e-6"]);
    assert_eq!(plan.values(1), ["6e5", "9e-6"]);
    assert_eq!(plan.values(5), ["1.2e6", "1e-5"]);
    assert_eq!(plan.scene(4).unwrap().drive.as_ref().map(|d| d.frequency_hz), Some(1.2e6));
    assert_eq!(plan.scene(4).unwrap().bubble.radius, 9e-6);
    let h = plan.header();
    assert_eq!(&h[..4], ["drive.frequency_hz", "bubble.radius", "status", "t_blow_up"]);
    assert!(h.contains(&"max_a16".to_string()) && h.last().unwrap() == "wall_seconds");
    // Log ranges, and an integer key set from numbers.
    let log = GridAxis::parse("drive.frequency_hz=1e5:1e7:3:log").unwrap();
    let p = grid::plan_grid(&template("3e-6"), &[log, GridAxis::numbers("modes.max_order", &[2.0, 4.0])]).unwrap();
    assert_eq!(p.values(0)[0].parse::<f64>().unwrap(), 1e5);
    assert!((p.values(2)[0].parse::<f64>().unwrap() / 1e6 - 1.0).abs() < 1e-12, "{:?}", p.values(2));
    assert_eq!(p.values(1)[1], "4");
    assert_eq!(p.scene(1).unwrap().modes.max_order, 4);
}

#[test]
fn bad_keys_and_values_name_them_and_write_nothing() {
    let t = template("3e-6");
    let err = |axes: &[GridAxis]| grid::plan_grid(&t, axes).unwrap_err();
    let e = err(&[GridAxis::texts("drive.frequncy_hz", &["1e6"])]);
    assert!(e.to_string().contains("drive.frequncy_hz") && e.to_string().contains("no such key"), "{e}");
    let e = err(&[GridAxis::texts("bubble.radius", &["1e-6", "-2e-6"])]);
    assert_eq!(e.issues()[0].key, "bubble.radius");
    assert!(e.to_string().contains("--grid bubble.radius=-2e-6") && e.to_string().contains("must be > 0"), "{e}");
    let e = err(&[GridAxis::numbers("drive.frequency_hz", &[f64::NAN])]);
    assert!(e.to_string().contains("not a finite number"), "{e}");
    let e = err(&[GridAxis::texts("bubble.radius", &["1e-6"]), GridAxis::texts("bubble.radius", &["2e-6"])]);
    assert!(e.to_string().contains("given twice"), "{e}");
    assert!(err(&[]).to_string().contains("at least one"));
    // On the command line: the --set messages, non-zero exit, no output directory.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    let scene = scene_path();
    for (grid, needles) in [
        ("drive.frequncy_hz=1e6,2e6", ["`drive.frequncy_hz` = 1e6", "no such key"]),
        ("drive.frequency_hz=1e6,abc", ["`drive.frequency_hz` = \"abc\"", "expected a number"]),
        ("bubble.radius=1e-6:2e-6:x", ["bubble.radius=1e-6:2e-6:x", "positive integer"]),
    ] {
        let o = magbubble(&["sweep", scene.to_str().unwrap(), "--grid", grid, "--out", out.to_str().unwrap()]);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success());
        for n in needles {
            assert!(stderr.contains(n), "{grid}: {stderr}");
        }
        assert!(!out.exists(), "{grid}: the output directory was created");
    }
}

/// The number after `"key": ` in a JSON text, parsed by Rust (exact; serde_json's default float
/// parser may be one ulp off).
fn raw_number(json: &str, key: &str) -> f64 {
    let at = json.find(&format!("\"{key}\": ")).unwrap_or_else(|| panic!("no {key}")) + key.len() + 4;
    let end = json[at..].find([',', '\n', '}']).unwrap() + at;
    json[at..end].trim().parse().unwrap()
}

/// The numbers of the JSON object `"key": { … }` (one level), by name.
fn raw_object<'a>(json: &'a str, key: &str) -> impl Fn(&str) -> f64 + 'a {
    let at = json.find(&format!("\"{key}\": {{")).unwrap();
    let body = &json[at..at + json[at..].find('}').unwrap()];
    move |name: &str| raw_number(body, name)
}

#[test]
fn rows_equal_separate_runs() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("grid");
    let o = sweep_cli(&out, &["--keep-series"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let csv = fs::read_to_string(out.join("sweep.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines.len(), 5);
    let header: Vec<&str> = lines[0].split(',').collect();
    let col = |row: &[&str], name: &str| row[header.iter().position(|h| *h == name).unwrap()].to_string();
    for line in &lines[1..] {
        let row: Vec<&str> = line.split(',').collect();
        let (f, r) = (col(&row, "drive.frequency_hz"), col(&row, "bubble.radius"));
        let run_dir = dir.path().join(format!("run{}", row[0]));
        let scene = scene_path();
        let o = magbubble(&[
            "run", scene.to_str().unwrap(), "--out", run_dir.to_str().unwrap(), SHORT[0], SHORT[1],
            "--set", &format!("drive.frequency_hz={f}"), "--set", &format!("bubble.radius={r}"),
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let series = fs::read_to_string(run_dir.join("series.csv")).unwrap();
        assert_eq!(fs::read_to_string(out.join(format!("series/{}.csv", row[0]))).unwrap(), series, "series of row {}", row[0]);
        let summary_text = fs::read_to_string(run_dir.join("summary.json")).unwrap();
        let summary: serde_json::Value = serde_json::from_str(&summary_text).unwrap();
        let max_abs = raw_object(&summary_text, "max_abs");
        assert_eq!(summary["status"], col(&row, "status").as_str());
        let num = |name: &str| col(&row, name).parse::<f64>().unwrap();
        assert_eq!(summary["steps"].as_u64().unwrap(), num("steps") as u64);
        assert_eq!(summary["rejected_steps"].as_u64().unwrap(), num("rejected_steps") as u64);
        assert_eq!(summary["rhs_evaluations"].as_u64().unwrap(), num("rhs_evaluations") as u64);
        assert_eq!(raw_number(&summary_text, "t_end"), num("t_end"));
        assert_eq!(max_abs("R"), num("R_max"));
        for k in (2..=16).step_by(2) {
            for ab in ["a", "b"] {
                assert_eq!(max_abs(&format!("{ab}{k}")), num(&format!("max_{ab}{k}")), "{ab}{k}");
            }
        }
        let r_min = series.lines().skip(1).map(|l| l.split(',').nth(1).unwrap().parse::<f64>().unwrap()).fold(f64::INFINITY, f64::min);
        assert_eq!(r_min, num("R_min"));
    }
}

#[test]
fn resume_skips_finished_rows_and_refuses_another_grid() {
    let dir = tempfile::tempdir().unwrap();
    let plan = plan_2x3();
    let reference = grid::run_grid(&plan, &GridOptions { out: Some(&dir.path().join("ref")), ..Default::default() }).unwrap();
    assert_eq!((reference.computed, reference.resumed, reference.cancelled), (6, 0, false));
    let full = fs::read_to_string(dir.path().join("ref/sweep.csv")).unwrap();
    // An interrupted sweep: three whole rows and a torn one.
    let out = dir.path().join("resumed");
    fs::create_dir_all(&out).unwrap();
    let lines: Vec<&str> = full.lines().collect();
    fs::write(out.join("sweep.csv"), format!("{}\n{}", lines[..4].join("\n"), &lines[4][..9])).unwrap();
    fs::copy(dir.path().join("ref/sweep.csv.meta.json"), out.join("sweep.csv.meta.json")).unwrap();
    let again = grid::run_grid(&plan, &GridOptions { out: Some(&out), ..Default::default() }).unwrap();
    assert_eq!((again.computed, again.resumed), (3, 3));
    let text = fs::read_to_string(out.join("sweep.csv")).unwrap();
    assert_eq!(deterministic(&text), deterministic(&full));
    // The resumed rows are those of the file, wall time included.
    assert_eq!(text.lines().take(4).collect::<Vec<_>>(), lines[..4]);
    for (a, b) in again.rows.iter().zip(&reference.rows) {
        assert_eq!((a.index, &a.values, a.status, a.steps, a.r_max), (b.index, &b.values, b.status, b.steps, b.r_max));
    }
    // Another grid into the same directory is refused.
    let other = grid::plan_grid(&template("3e-6"), &[GridAxis::numbers("drive.frequency_hz", &[0.6e6, 1.3e6])]).unwrap();
    let err = grid::run_grid(&other, &GridOptions { out: Some(&out), ..Default::default() }).unwrap_err();
    assert!(matches!(err, grid::GridError::Sweep(SweepError::Mismatch { .. })), "{err}");
}

#[test]
fn shards_and_threads_give_the_same_csv() {
    let dir = tempfile::tempdir().unwrap();
    let whole = dir.path().join("whole");
    assert!(sweep_cli(&whole, &[]).status.success());
    let shards = dir.path().join("shards");
    for s in ["0/3", "1/3", "2/3"] {
        let o = sweep_cli(&shards, &["--shard", s]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    let inputs: Vec<String> = (0..3).map(|i| shards.join(format!("sweep.shard-{i}-of-3.csv")).display().to_string()).collect();
    let merged = dir.path().join("merged.csv");
    let mut args = vec!["merge"];
    args.extend(inputs.iter().map(String::as_str));
    args.extend(["--out", merged.to_str().unwrap()]);
    let o = magbubble(&args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let single = fs::read_to_string(whole.join("sweep.csv")).unwrap();
    assert_eq!(deterministic(&fs::read_to_string(&merged).unwrap()), deterministic(&single));
    // Thread counts: 1 and 2 workers give the same rows.
    let plan = plan_2x3();
    let in_pool = |n: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(n).build().unwrap();
        let out = dir.path().join(format!("threads{n}"));
        pool.install(|| grid::run_grid(&plan, &GridOptions { out: Some(&out), ..Default::default() }).unwrap());
        deterministic(&fs::read_to_string(out.join("sweep.csv")).unwrap())
    };
    assert_eq!(in_pool(1), in_pool(2));
}

#[test]
fn cancel_keeps_whole_rows_and_a_rerun_completes() {
    let dir = tempfile::tempdir().unwrap();
    let plan = plan_2x3();
    let out = dir.path().join("c");
    let cancel = AtomicBool::new(false);
    let stop_after_two = |done: usize, _: usize| {
        if done >= 2 {
            cancel.store(true, Ordering::Relaxed);
        }
    };
    let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
    let first = pool.install(|| {
        let options = GridOptions { out: Some(&out), keep_series: true, cancel: Some(&cancel), on_run: Some(&stop_after_two), ..Default::default() };
        grid::run_grid(&plan, &options).unwrap()
    });
    assert!(first.cancelled);
    assert!((2..6).contains(&first.rows.len()), "{} rows", first.rows.len());
    let text = fs::read_to_string(out.join("sweep.csv")).unwrap();
    assert!(text.ends_with('\n'));
    assert_eq!(text.lines().count(), 1 + first.rows.len());
    // Only the series of finished rows, and no temporary file.
    let files: Vec<String> = fs::read_dir(out.join("series")).unwrap().map(|e| e.unwrap().file_name().into_string().unwrap()).collect();
    assert_eq!(files.len(), first.rows.len(), "{files:?}");
    assert!(files.iter().all(|f| !f.ends_with(".tmp")), "{files:?}");
    // Resuming finishes the grid, with the series returned for every row.
    let options = GridOptions { out: Some(&out), keep_series: true, return_series: true, ..Default::default() };
    let rest = grid::run_grid(&plan, &options).unwrap();
    assert_eq!((rest.resumed, rest.computed, rest.cancelled), (first.rows.len(), 6 - first.rows.len(), false));
    assert!(rest.rows.iter().all(|r| r.status == GridStatus::Completed));
    for r in &rest.rows {
        let s = r.series.as_ref().unwrap();
        assert_eq!(&s.columns[..2], ["t", "R"]);
        let file = fs::read_to_string(out.join(format!("series/{}.csv", r.index))).unwrap();
        assert_eq!(s.rows(), file.lines().count() - 1);
    }
    let reference = grid::run_grid(&plan, &GridOptions::default()).unwrap();
    assert!(reference.csv.is_none());
    let strip = |rows: &[grid::GridRow]| rows.iter().map(|r| { let f = r.fields(); f[..f.len() - 1].to_vec() }).collect::<Vec<_>>();
    assert_eq!(strip(&rest.rows), strip(&reference.rows));
    // A run already cancelled before it starts computes nothing and writes no row.
    let none = grid::run_grid(&plan, &GridOptions { cancel: Some(&AtomicBool::new(true)), ..Default::default() }).unwrap();
    assert!(none.cancelled && none.rows.is_empty());
}

#[test]
fn sigint_during_a_sweep_keeps_whole_rows_and_exits_130() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("s");
    let scene = scene_path();
    let args = [
        "sweep", scene.to_str().unwrap(), "--out", out.to_str().unwrap(), "--keep-series",
        "--grid", "drive.frequency_hz=0.5e6:1.5e6:40", "--set", "run.duration=1e-4",
    ];
    let child = Command::new(env!("CARGO_BIN_EXE_magbubble")).args(args).stdout(Stdio::null()).stderr(Stdio::piped()).spawn().unwrap();
    let csv = out.join("sweep.csv");
    let rows = || fs::read_to_string(&csv).map_or(0, |t| t.lines().count().saturating_sub(1));
    for _ in 0..400 {
        if rows() >= 1 {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    assert!(rows() >= 1, "the sweep did not start");
    assert!(Command::new("kill").arg("-INT").arg(child.id().to_string()).status().unwrap().success());
    let o = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(130), "{err}");
    assert!(err.contains("rerun the same command to resume"), "{err}");
    let text = fs::read_to_string(&csv).unwrap();
    let kept = text.lines().count() - 1;
    assert!(text.ends_with('\n') && kept < 40, "{kept} rows");
    let series: Vec<String> = fs::read_dir(out.join("series")).unwrap().map(|e| e.unwrap().file_name().into_string().unwrap()).collect();
    assert_eq!(series.len(), kept, "{series:?}");
    assert!(!out.join("sweep.csv.tmp").exists());
}

#[test]
fn a_failed_run_is_a_row_and_the_command_exits_non_zero() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("f");
    // Five steps are not enough: that run fails (step limit), the other completes.
    let scene = scene_path();
    let o = magbubble(&[
        "sweep", scene.to_str().unwrap(), "--out", out.to_str().unwrap(), SHORT[0], SHORT[1],
        "--grid", "run.integrator.max_steps=5,50000000",
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("1 of 2 runs failed") && err.contains("run.integrator.max_steps=5") && err.contains("step limit"), "{err}");
    let csv = fs::read_to_string(out.join("sweep.csv")).unwrap();
    let rows: Vec<Vec<&str>> = csv.lines().skip(1).map(|l| l.split(',').collect()).collect();
    assert_eq!((rows[0][2], rows[1][2]), ("failed", "completed"), "{csv}");
    assert!(rows[0][rows[0].len() - 2].contains("step limit"), "{csv}");
    assert_eq!(rows[0][rows[0].len() - 5], "5", "steps of the failed run: {csv}");
}
