//! The sweep machinery: thread-count independence, resume, shards + merge == unsharded.

use magbubble::analysis::sweep::{self, Shard, SweepError, SweepMeta};
use std::fs;
use std::sync::atomic::{AtomicUsize, Ordering};

/// A deterministic but not-trivial per-point computation (a tiny Newton iteration).
fn point(i: usize) -> Vec<String> {
    let f = 1e5 * (1.0 + i as f64);
    let mut x = 1.0f64;
    for _ in 0..30 {
        x -= (x * x * x - f.ln()) / (3.0 * x * x);
    }
    vec![format!("{f:.6e}"), format!("{x:.17e}"), if i % 3 == 0 { "critical".into() } else { "stable".into() }]
}

fn meta(total: usize, shard: Shard) -> SweepMeta {
    SweepMeta {
        fingerprint: "test-sweep v1".into(),
        total,
        shard,
        header: vec!["f_hz".into(), "x".into(), "outcome".into()],
    }
}

fn run_in_pool(threads: usize, csv: &std::path::Path, m: &SweepMeta) -> sweep::SweepReport {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
    pool.install(|| sweep::run(csv, m, false, point)).unwrap()
}

#[test]
fn independent_of_thread_count() {
    let dir = tempfile::tempdir().unwrap();
    let (a, b) = (dir.path().join("one.csv"), dir.path().join("two.csv"));
    run_in_pool(1, &a, &meta(37, Shard::ALL));
    run_in_pool(2, &b, &meta(37, Shard::ALL));
    let (ta, tb) = (fs::read_to_string(&a).unwrap(), fs::read_to_string(&b).unwrap());
    assert_eq!(ta, tb);
    assert_eq!(ta.lines().count(), 38);
}

#[test]
fn resume_skips_finished_rows_and_discards_a_torn_line() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("out/s.csv");
    let m = meta(20, Shard::ALL);
    let reference = dir.path().join("ref.csv");
    run_in_pool(2, &reference, &m);
    // Simulate an interrupted run: the first 7 rows, then half a row.
    let full = fs::read_to_string(&reference).unwrap();
    let lines: Vec<&str> = full.lines().collect();
    fs::create_dir_all(csv.parent().unwrap()).unwrap();
    let mut partial = lines[..8].join("\n");
    partial.push('\n');
    partial.push_str(&lines[8][..5]);
    fs::write(&csv, partial).unwrap();
    fs::write(sweep::meta_path(&csv), serde_json::to_string(&m).unwrap()).unwrap();
    let calls = AtomicUsize::new(0);
    let report = sweep::run(&csv, &m, false, |i| {
        calls.fetch_add(1, Ordering::Relaxed);
        point(i)
    })
    .unwrap();
    assert_eq!(report.resumed, 7);
    assert_eq!(report.computed, 13);
    assert_eq!(calls.load(Ordering::Relaxed), 13);
    assert_eq!(fs::read_to_string(&csv).unwrap(), full);
    // A second run has nothing left to do.
    let again = sweep::run(&csv, &m, false, |_| panic!("nothing to compute")).unwrap();
    assert_eq!((again.resumed, again.computed), (20, 0));
    // A different sweep refuses to append.
    let other = SweepMeta { fingerprint: "another".into(), ..m };
    assert!(matches!(sweep::run(&csv, &other, false, point), Err(SweepError::Mismatch { .. })));
}

#[test]
fn shards_merge_to_the_unsharded_result() {
    let dir = tempfile::tempdir().unwrap();
    let whole = dir.path().join("whole.csv");
    run_in_pool(2, &whole, &meta(23, Shard::ALL));
    let shards: Vec<_> = (0..3)
        .map(|i| {
            let p = dir.path().join(format!("shard{i}.csv"));
            let r = run_in_pool(1, &p, &meta(23, Shard { index: i, count: 3 }));
            assert!(r.rows.iter().all(|(idx, _)| idx % 3 == i));
            p
        })
        .collect();
    let merged = dir.path().join("merged.csv");
    let m = sweep::merge(&shards, &merged).unwrap();
    assert_eq!(m.shard, Shard::ALL);
    assert_eq!(fs::read_to_string(&merged).unwrap(), fs::read_to_string(&whole).unwrap());
    // Incomplete and overlapping inputs are refused.
    let err = sweep::merge(&shards[..2], &dir.path().join("x.csv")).unwrap_err();
    assert!(err.to_string().contains("incomplete"), "{err}");
    let dup = vec![shards[0].clone(), shards[1].clone(), shards[2].clone(), shards[0].clone()];
    let err = sweep::merge(&dup, &dir.path().join("y.csv")).unwrap_err();
    assert!(err.to_string().contains("appears in both"), "{err}");
    // issue 29 item 11: each defect says what is wrong and what to do
    let say = |inputs: Vec<std::path::PathBuf>| sweep::merge(&inputs, &dir.path().join("z.csv")).unwrap_err().to_string();
    let e = say(vec![shards[0].clone(), shards[1].clone(), shards[2].clone(), whole.clone()]);
    assert!(e.contains("different splits") && e.contains("shard 0/3") && e.contains("shard 0/1"), "{e}");
    let e = say(vec![shards[0].clone(), dir.path().join("missing.csv")]);
    assert!(e.contains("missing.csv: no such file"), "{e}");
    let lone = dir.path().join("lone.csv");
    fs::copy(&shards[1], &lone).unwrap();
    let e = say(vec![shards[0].clone(), lone.clone(), shards[2].clone()]);
    assert!(e.contains("has no") && e.contains("lone.csv.meta.json") && e.contains("run that shard again"), "{e}");
    let cut = |name: &str, keep: usize| {
        let p = dir.path().join(name);
        let text = fs::read_to_string(&shards[1]).unwrap();
        fs::write(&p, &text.as_bytes()[..keep.min(text.len())]).unwrap();
        fs::copy(sweep::meta_path(&shards[1]), sweep::meta_path(&p)).unwrap();
        p
    };
    let e = say(vec![shards[0].clone(), cut("empty.csv", 0), shards[2].clone()]);
    assert!(e.contains("holds 0 of the 8 points of shard 1/3") && e.contains("empty"), "{e}");
    let len = fs::read_to_string(&shards[1]).unwrap().len();
    let e = say(vec![shards[0].clone(), cut("torn.csv", len / 2), shards[2].clone()]);
    assert!(e.contains("torn.csv holds") && e.contains("truncated or unfinished") && e.contains("run that shard again"), "{e}");
}
