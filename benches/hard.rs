//! Hard cases (docs/hard-cases.md): run time of the tiny-amplitude scene at a_2(0) = 1e-3 R0
//! and 1e-30 R0 — no denormal slowdown (the ratio is printed and must stay within a generous
//! factor 3) — and of the stiff N = 32 / N = 64 scenes with Radau5.
//! `cargo bench --bench hard` (short variant: `-- --quick`).

use std::hint::black_box;
use std::time::Instant;

use criterion::{criterion_group, criterion_main, Criterion};
use magbubble::model::simulate;
use magbubble::scene::{self, Scene};

fn load(name: &str, overrides: &[String]) -> Scene {
    let path = format!("{}/scenes/hard/{name}.toml", env!("CARGO_MANIFEST_DIR"));
    scene::load(&path, overrides).unwrap_or_else(|e| panic!("{path}: {e}"))
}

fn tiny(rel: f64) -> Scene {
    // 1000 drive periods: the damped a_2 decays ~0.37 decades/µs, so the 1e-30 R0 run passes
    // through the subnormal range (< 2.2e-308) and ends at exactly 0 (so does 1e-3 R0, later).
    load("tiny_amplitude", &[format!("bubble.initial.a.2={:e}", rel * 10e-6), "run.duration=1000e-6".into()])
}

/// Median wall time of `n` runs.
fn median_seconds(scene: &Scene, n: usize) -> f64 {
    let mut v: Vec<f64> = (0..n)
        .map(|_| {
            let t = Instant::now();
            black_box(simulate(scene, &mut |_, _| {}).expect("runs"));
            t.elapsed().as_secs_f64()
        })
        .collect();
    v.sort_by(f64::total_cmp);
    v[n / 2]
}

fn hard(c: &mut Criterion) {
    let (big, small) = (tiny(1e-3), tiny(1e-30));
    let (tb, ts) = (median_seconds(&big, 7), median_seconds(&small, 7));
    let ratio = ts / tb;
    eprintln!("tiny amplitude: 1e-3 R0 {tb:.4} s, 1e-30 R0 {ts:.4} s, ratio {ratio:.2}");
    assert!(ratio < 3.0, "denormal slowdown? 1e-30 R0 takes {ratio:.2}x the time of 1e-3 R0");
    let mut g = c.benchmark_group("hard");
    g.sample_size(10);
    g.bench_function("tiny_amplitude_1e-3", |b| b.iter(|| simulate(&big, &mut |_, _| {}).unwrap()));
    g.bench_function("tiny_amplitude_1e-30", |b| b.iter(|| simulate(&small, &mut |_, _| {}).unwrap()));
    for name in ["stiff_n32", "stiff_n64"] {
        let s = load(name, &[]);
        g.bench_function(name, |b| b.iter(|| simulate(&s, &mut |_, _| {}).unwrap()));
    }
    g.finish();
}

criterion_group!(benches, hard);
criterion_main!(benches);
