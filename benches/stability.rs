//! Issue 5 performance: a 64-frequency Floquet stability curve (f_d = 0.5…6 MHz, modes k = 2…32,
//! ε_p ∈ [0, 1], scan 8, tol 1e-3, BL closure, no field), parallel over frequencies (rayon), and
//! the same curve by the time-series criterion on 8 of the 64 frequencies (every 8th; the
//! per-point cost is extrapolated ×8 to the full curve in docs/stability.md).
//! `MAGBUBBLE_BENCH_QUICK=1`: 8 frequencies with modes up to 16 for Floquet, 2 for the series.

use criterion::{criterion_group, criterion_main, Criterion};
use magbubble::analysis::stability::{critical_point, Criterion as Crit, CriticalOptions};
use magbubble::scene::{self, Scene};
use rayon::prelude::*;

fn scene_at(base: &Scene, f: f64, eps: f64) -> Scene {
    let mut s = base.clone();
    s.drive = Some(scene::Drive::cosine(eps, f));
    s
}

fn curve(base: &Scene, freqs: &[f64], criterion: Crit) -> usize {
    let opts = CriticalOptions {
        criterion,
        lo: 0.0,
        hi: 1.0,
        scan: 8,
        tol: 1e-3,
        relative_tol: false,
        floquet: Default::default(),
        series: Default::default(),
    };
    freqs
        .par_iter()
        .map(|&f| {
            let at = |p: f64| Ok(scene_at(base, f, p));
            critical_point(&at, &opts).map(|c| c.outcome.evaluations()).unwrap_or(0)
        })
        .sum()
}

fn bench(c: &mut Criterion) {
    let quick = std::env::var_os("MAGBUBBLE_BENCH_QUICK").is_some();
    let (n_modes, n_freq, n_series) = if quick { (16, 8, 2) } else { (32, 64, 8) };
    let text = format!(
        "[bubble]\nradius = 10e-6\n[shell]\nc1 = 0.1\nc2 = 0.12\n[drive]\namplitude = 0.1\nfrequency_hz = 1e6\n[modes]\nmax_order = {n_modes}\n"
    );
    let base = scene::load_str(&text, "bench", &[] as &[&str]).expect("bench scene");
    let freqs: Vec<f64> = (0..n_freq).map(|i| 0.5e6 + 5.5e6 * i as f64 / (n_freq - 1) as f64).collect();
    let series_freqs: Vec<f64> = freqs.iter().step_by(n_freq / n_series).copied().collect();
    let mut g = c.benchmark_group("stability_curve");
    g.sample_size(10);
    g.bench_function(format!("floquet_{n_freq}freq_{n_modes}modes"), |b| b.iter(|| curve(&base, &freqs, Crit::Floquet)));
    g.bench_function(format!("series_{}freq_{n_modes}modes", series_freqs.len()), |b| {
        b.iter(|| curve(&base, &series_freqs, Crit::Series))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
