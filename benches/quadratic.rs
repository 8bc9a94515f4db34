//! What the quadratic mode coupling costs (issue 12, "Performance"): one right-hand side of the
//! free bubble with surface tension, linear against quadratic, at k ≤ 8, 16, 32, the same for the
//! shelled fig-12 scene (Mooney–Rivlin + static coil, k ≤ 16: the membrane's second-order loads
//! too), and whole 100 µs runs (k ≤ 16, DOPRI5, rtol 1e-6) of the free bubble. The targets: quadratic
//! rhs ≤ 3× linear at k ≤ 16, a 100 µs run ≤ 3×. Ratios: docs/performance.md.
//! `cargo bench --bench quadratic` (short: `-- --quick`).

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use magbubble::model::Model;
use magbubble::scene::{load, Scene};

/// scenes/free_bubble.toml (R0 = 5 µm, ε_p = 0.2 at 500 kHz) with γ = 0.072 N/m, k ≤ `n`.
fn free(n: usize, coupling: &str, duration: &str) -> Scene {
    let (n, c, d) = (format!("modes.max_order={n}"), format!("modes.coupling=\"{coupling}\""), format!("run.duration={duration}"));
    load("scenes/free_bubble.toml", &["shell.surface_tension=0.072", n.as_str(), c.as_str(), d.as_str(), "bubble.initial.a={2 = 1e-8}"])
        .expect("free bubble scene")
}

/// scenes/figures/fig12_chi.toml (Mooney–Rivlin, static coil, k ≤ 16), 1 µs.
fn shelled(coupling: &str) -> Scene {
    let c = format!("modes.coupling=\"{coupling}\"");
    load("scenes/figures/fig12_chi.toml", &[c.as_str(), "run.duration=1e-6"]).expect("fig-12 scene")
}

/// One rhs of `s` at the state of effects' rhs bench (shape amplitudes 1e-4).
fn bench_rhs(c: &mut Criterion, name: &str, s: &Scene) {
    let m = Model::from_scene(s).expect("model");
    let sys = m.system();
    let mut y = m.initial_state().to_vec();
    for (i, v) in y.iter_mut().enumerate().skip(2) {
        *v = 1e-4 * ((i as f64) * 0.37).sin();
    }
    let mut dy = vec![0.0; y.len()];
    c.bench_function(name, |b| b.iter(|| sys.rhs(black_box(0.3), black_box(&y), &mut dy)));
}

fn rhs(c: &mut Criterion) {
    for n in [8, 16, 32] {
        for coupling in ["linear", "quadratic"] {
            bench_rhs(c, &format!("quadratic/rhs/N{n}/{coupling}"), &free(n, coupling, "1e-6"));
        }
    }
    for coupling in ["linear", "quadratic"] {
        bench_rhs(c, &format!("quadratic/rhs/fig12_N16/{coupling}"), &shelled(coupling));
    }
}

fn runs(c: &mut Criterion) {
    let mut g = c.benchmark_group("quadratic/run_100us_N16");
    g.sample_size(10);
    for coupling in ["linear", "quadratic"] {
        let s = free(16, coupling, "100e-6");
        let m = Model::from_scene(&s).expect("model");
        let rep = m.run(&s.run, &mut |_, _| {});
        eprintln!("{coupling}: status {:?}, steps {}, rhs {}", rep.status, rep.stats.steps, rep.stats.rhs_evals);
        g.bench_function(coupling, |b| b.iter(|| m.run(&s.run, &mut |_, _| {})));
    }
    g.finish();
}

criterion_group!(benches, rhs, runs);
criterion_main!(benches);
