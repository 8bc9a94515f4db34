//! `magbubble::api`, the library the CLI and Python call: its typed results equal what the
//! command line writes (the summary serialises to summary.json, the series are the CSV's
//! values, the sweep's typed columns are the CSV's cells), and its monitor cancels.

use magbubble::api::sweep::{SweepRequest, SweepTable};
use magbubble::api::table::{Column, Table};
use magbubble::api::{self, Monitor, Scene};
use std::path::Path;
use std::process::Command;
use std::sync::atomic::{AtomicBool, Ordering};

fn scene_file(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes").join(name).display().to_string()
}

fn cli(args: &[&str]) {
    let o = Command::new(env!("CARGO_BIN_EXE_magbubble")).args(args).output().unwrap();
    assert!(o.status.success(), "{args:?}: {}", String::from_utf8_lossy(&o.stderr));
}

/// The file's text without its `wall_seconds` line(s).
fn without_wall(text: &str) -> String {
    text.lines().filter(|l| !l.contains("wall_seconds")).collect::<Vec<_>>().join("\n")
}

#[test]
fn run_series_and_summary_are_what_run_writes() {
    let tmp = tempfile::tempdir().unwrap();
    let file = scene_file("coil_static.toml");
    let sets = ["run.duration=4e-6", "modes.max_order=6"];
    cli(&["run", &file, "--out", tmp.path().to_str().unwrap(), "--set", sets[0], "--set", sets[1]]);
    let r = api::run::run(&Scene::load(&file, &sets).unwrap(), &Monitor::default()).unwrap();

    let csv = std::fs::read_to_string(tmp.path().join("series.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(lines.next().unwrap(), r.outcome.columns.join(","));
    let values: Vec<f64> = lines.flat_map(|l| l.split(',').map(|c| c.parse::<f64>().unwrap()).collect::<Vec<_>>()).collect();
    assert_eq!(values.len(), r.values.len());
    assert!(values.iter().zip(&r.values).all(|(a, b)| a.to_bits() == b.to_bits()), "series differ");
    assert_eq!(r.outcome.rows as usize * r.outcome.columns.len(), r.values.len());

    let written = std::fs::read_to_string(tmp.path().join("summary.json")).unwrap();
    let ours = serde_json::to_string_pretty(&r.outcome.summary).unwrap();
    assert_eq!(without_wall(&ours), without_wall(&written));
    assert_eq!(r.outcome.summary.source.overrides, sets);
}

#[test]
fn a_cancelled_run_stops_with_cancelled() {
    let scene = Scene::load(scene_file("radial_only.toml"), &["run.duration=1e-3"]).unwrap();
    let flag = AtomicBool::new(false);
    let seen = std::sync::Mutex::new(0.0f64);
    let report = |t: f64, total: f64| {
        assert_eq!(total, 1e-3);
        *seen.lock().unwrap() = t;
        if t > 1e-6 {
            flag.store(true, Ordering::Relaxed);
        }
    };
    let m = Monitor { report: Some(&report), cancel: Some(&flag), bar: false };
    let err = api::run::run(&scene, &m).unwrap_err();
    assert!(err.is::<api::common::Cancelled>(), "{err:#}");
    let t = *seen.lock().unwrap();
    assert!(t > 1e-6 && t < 2e-6, "stopped at t = {t}");
}

#[test]
fn sweep_table_columns_are_the_csv_cells_typed() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = Scene::load(scene_file("coil_static.toml"), &["run.duration=3e-6", "modes.max_order=4"]).unwrap();
    let axes = [
        api::sweep::GridAxis::parse("bubble.radius=8e-6,1e-5").unwrap(),
        api::sweep::GridAxis::parse("drive.frequency_hz=0.5e6:1e6:2").unwrap(),
    ];
    let plan = api::sweep::plan(&scene, &axes).unwrap();
    let req = SweepRequest { out: Some(tmp.path().to_path_buf()), ..SweepRequest::default() };
    let mut table = SweepTable::new(&plan);
    let summary = api::sweep::sweep(&plan, &req, &Monitor::default(), &mut |row| table.push(row)).unwrap();
    let (table, _) = table.finish();
    assert_eq!((summary.rows, table.rows()), (4, 4));

    let csv = std::fs::read_to_string(summary.path.unwrap()).unwrap();
    let mut lines = csv.lines();
    let names: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    assert_eq!(names, table.names);
    let rows: Vec<Vec<String>> = lines.map(|l| l.split(',').map(String::from).collect()).collect();
    let from_csv = Table::from_fields(names, rows.iter().map(Vec::as_slice));
    let same = |a: &Column, b: &Column| match (a, b) {
        (Column::Float(x), Column::Float(y)) => x.iter().zip(y).all(|(p, q)| p.to_bits() == q.to_bits() || (p.is_nan() && q.is_nan())),
        _ => a == b,
    };
    for (i, name) in table.names.iter().enumerate() {
        if name != "wall_seconds" {
            assert!(same(&table.columns[i], &from_csv.columns[i]), "{name}: {:?} vs {:?}", table.columns[i], from_csv.columns[i]);
        }
    }
    assert!(matches!(table.columns[1], Column::Float(_)), "bubble.radius is numeric");
    assert!(matches!(table.columns[3], Column::Text { .. }), "status is text");
}
