//! Issue 29 item 7: the grid planner is lazy (a shard owns its points only; index → values by
//! mixed-radix arithmetic), refuses what cannot be done, and plans 10^8 and 10^12 points in
//! the memory of its axes.
use magbubble::analysis::grid::{plan_grid, GridAxis, GridPlan, MAX_SHARD_POINTS};
use magbubble::analysis::sweep::Shard;
use magbubble::scene::SceneTemplate;
use std::time::Instant;

fn template() -> SceneTemplate {
    SceneTemplate::load("scenes/no_field.toml", &["run.duration=1e-7", "modes.max_order=2"]).unwrap()
}

fn plan(spec: &[&str]) -> Result<GridPlan, String> {
    let axes: Vec<GridAxis> = spec.iter().map(|g| GridAxis::parse(g).unwrap()).collect();
    plan_grid(&template(), &axes).map_err(|e| e.to_string())
}

#[test]
fn a_grid_of_ten_to_the_eight_points_is_planned_lazily() {
    let start = Instant::now();
    let p = plan(&["bubble.radius=8e-6:12e-6:10000", "drive.frequency_hz=0.5e6:2e6:10000"]).unwrap();
    assert_eq!(p.len(), 100_000_000);
    let shard = Shard { index: 0, count: 100_000 };
    assert_eq!(p.shard_len(shard), 1000);
    // mixed radix, first axis slowest: point 10001 = (radius 1, frequency 1)
    let s = p.scene(10_001).unwrap();
    let r = 8e-6 + 4e-6 / 9999.0;
    assert!((s.bubble.radius / r - 1.0).abs() < 1e-12 && (s.drive.unwrap().frequency_hz / (0.5e6 + 1.5e6 / 9999.0) - 1.0).abs() < 1e-12);
    let last: Vec<f64> = p.values(99_999_999).iter().map(|v| v.parse().unwrap()).collect();
    assert!((last[0] / 1.2e-5 - 1.0).abs() < 1e-12 && (last[1] / 2e6 - 1.0).abs() < 1e-12, "{last:?}");
    let pts: Vec<usize> = p.shard_points(shard).take(3).collect();
    assert_eq!(pts, [0, 100_000, 200_000]);
    assert_eq!(p.shard_points(Shard { index: 99_999, count: 100_000 }).count(), 1000);
    // the shard's 1000 points validated, nothing run
    assert_eq!(p.check_shard(shard).unwrap(), 1000);
    // was: 49.6 GB for the scenes of every point (exit 134)
    assert!(start.elapsed().as_secs_f64() < 30.0, "planning took {:?}", start.elapsed());
}

#[test]
fn what_cannot_be_done_is_refused_with_a_reason() {
    // 10^12 points: planned, but a shard of 10^7 is more than one process runs
    let p = plan(&["bubble.radius=8e-6:12e-6:1000000", "drive.frequency_hz=0.5e6:2e6:1000000"]).unwrap();
    assert_eq!(p.len(), 1_000_000_000_000);
    let e = p.check_shard(Shard { index: 0, count: 100_000 }).unwrap_err().to_string();
    assert!(e.contains("--shard 0/100000") && e.contains(&MAX_SHARD_POINTS.to_string()) && e.contains("1000000 shards"), "{e}");
    // more points than 2^64: the product overflows
    let e = plan(&[
        "bubble.radius=8e-6:12e-6:100000",
        "drive.frequency_hz=0.5e6:2e6:100000",
        "drive.amplitude=0.1:0.5:100000",
        "shell.c2=0.1:0.2:100000",
    ])
    .unwrap_err();
    assert!(e.contains("overflows"), "{e}");
    // a long axis is checked at its ends: a bad end is named before anything runs
    let e = plan(&["bubble.radius=-1e-6:12e-6:200000"]).unwrap_err();
    assert!(e.contains("bubble.radius"), "{e}");
}
