//! `magbubble accuracy --quick` on radial_only and no_field (issue 6, part 1): the CSV exists,
//! the error decreases along every ladder and RK4's observed order is near 4.

use std::path::Path;
use std::process::Command;

/// CSV rows as (first column, the other columns as numbers).
fn labeled_rows(csv: &str) -> Vec<(String, Vec<f64>)> {
    csv.lines()
        .skip(1)
        .map(|l| {
            let (name, rest) = l.split_once(',').unwrap();
            (name.to_string(), rest.split(',').map(|v| v.parse().unwrap()).collect())
        })
        .collect()
}

fn run_quick(scene: &str) -> (String, Vec<(String, Vec<f64>)>) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("acc");
    let scene_path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes").join(scene);
    let o = Command::new(env!("CARGO_BIN_EXE_magbubble"))
        .args(["accuracy", scene_path.to_str().unwrap(), "--quick", "--out", out.to_str().unwrap()])
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(o.status.success(), "accuracy failed: {}\n{}", stdout, String::from_utf8_lossy(&o.stderr));
    let csv = std::fs::read_to_string(out.join("accuracy.csv")).unwrap();
    assert_eq!(csv.lines().next().unwrap(), "method,setting,e_r,e_a,error,wall_seconds,rhs_evals,steps,rejected");
    let rows = labeled_rows(&csv);
    assert!(out.join("accuracy.json").exists() && out.join("sizes.csv").exists());
    (stdout, rows)
}

fn check(scene: &str) {
    let (stdout, rows) = run_quick(scene);
    // four ladders, three rungs each; columns after `method`: setting (0), error (3), rhs_evals (5)
    assert_eq!(rows.len(), 12, "{scene}: {rows:?}");
    for id in ["rk4", "dopri5", "dop853", "radau5"] {
        let ladder: Vec<&Vec<f64>> = rows.iter().filter(|r| r.0 == id).map(|r| &r.1).collect();
        assert_eq!(ladder.len(), 3, "{scene}: ladder {id}");
        let e: Vec<f64> = ladder.iter().map(|r| r[3]).collect();
        assert!(e.iter().all(|e| e.is_finite() && *e > 0.0), "{scene}: ladder {id}: errors {e:?}");
        // rungs go from loose to tight: the error must drop, and overall by a clear factor
        for w in e.windows(2) {
            assert!(w[1] < w[0], "{scene}: ladder {id}: error does not decrease: {e:?}");
        }
        assert!(e[2] < 0.2 * e[0], "{scene}: ladder {id}: {e:?}");
        // tighter settings cost more rhs evaluations
        assert!(ladder[2][5] > ladder[0][5], "{scene}: ladder {id}: work does not grow");
    }
    // RK4's observed order against dt, from the CSV
    let rk: Vec<&Vec<f64>> = rows.iter().filter(|r| r.0 == "rk4").map(|r| &r.1).collect();
    let x: Vec<f64> = rk.iter().map(|r| r[0].ln()).collect();
    let y: Vec<f64> = rk.iter().map(|r| r[3].ln()).collect();
    let (mx, my) = (x.iter().sum::<f64>() / 3.0, y.iter().sum::<f64>() / 3.0);
    let slope = x.iter().zip(&y).map(|(a, b)| (a - mx) * (b - my)).sum::<f64>()
        / x.iter().map(|a| (a - mx) * (a - mx)).sum::<f64>();
    assert!((slope - 4.0).abs() < 0.3, "{scene}: RK4 observed order {slope}");
    assert!(stdout.contains("rk4 observed order: vs dt"), "{stdout}");
}

#[test]
fn quick_study_on_radial_only() {
    check("radial_only.toml");
}

#[test]
fn quick_study_on_no_field() {
    check("no_field.toml");
}

#[test]
fn quick_study_on_the_full_vorticity_model() {
    // staggered over dt, monolithic over rtol; the monolithic error must fall with rtol
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("acc");
    let scene_path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/no_field.toml");
    let o = Command::new(env!("CARGO_BIN_EXE_magbubble"))
        .args(["accuracy", scene_path.to_str().unwrap(), "--quick", "--out", out.to_str().unwrap()])
        .args(["--set", "modes.viscous=vorticity", "--set", "modes.max_order=4", "--set", "vorticity.points=51"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let csv = std::fs::read_to_string(out.join("accuracy.csv")).unwrap();
    let rows = labeled_rows(&csv);
    assert_eq!(rows.iter().filter(|r| r.0 == "staggered").count(), 3, "{rows:?}");
    let mono: Vec<f64> = rows.iter().filter(|r| r.0 == "monolithic").map(|r| r.1[3]).collect();
    assert_eq!(mono.len(), 3);
    assert!(mono.iter().all(|e| e.is_finite()) && mono[2] < 0.1 * mono[0], "monolithic errors {mono:?}");
    let stag: Vec<f64> = rows.iter().filter(|r| r.0 == "staggered").map(|r| r.1[3]).collect();
    assert!(stag[2] < stag[0], "staggered errors {stag:?}");
    let sizes = std::fs::read_to_string(out.join("sizes.csv")).unwrap();
    assert!(sizes.lines().any(|l| l.starts_with("grid,5.1e1")), "grid ladder missing:\n{sizes}");
}

/// Issue 15 class 9: no order against work when the work barely changes along the ladder
/// (it printed "vs work 695.88" for a 1 % change); a real spread still gives the slope.
#[test]
fn no_order_against_work_that_barely_changes() {
    use magbubble::analysis::accuracy::{order_vs_work, MIN_WORK_RATIO};
    let err = [1e-4, 1e-7, 1e-10];
    let (order, ratio) = order_vs_work(&[1000.0, 1005.0, 1010.0], &err);
    assert_eq!(order, None);
    assert!((ratio - 1.01).abs() < 1e-12, "{ratio}");
    let work = [1000.0, 2000.0, 4000.0];
    let err: Vec<f64> = work.iter().map(|w: &f64| 3.0 * w.powf(-5.0)).collect();
    let (order, ratio) = order_vs_work(&work, &err);
    assert!((order.unwrap() - 5.0).abs() < 1e-12 && ratio == 4.0 && ratio >= MIN_WORK_RATIO);
    // a failed rung (error ∞) does not count towards the spread
    assert_eq!(order_vs_work(&[1000.0, 1010.0, 9000.0], &[1e-4, 1e-6, f64::INFINITY]).0, None);
}
