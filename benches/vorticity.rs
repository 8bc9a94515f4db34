//! Full vorticity model, modes k = 2…16, 100 µs, default (converged) grid, driven (ε_p = 0.2,
//! f_d = 1 MHz, coil field I = 100 kA so that every mode is excited): the staggered scheme at Δt′ = 10⁻³ and the monolithic scheme at rtol 10⁻⁶
//! (issue 4, performance). `MAGBUBBLE_BENCH_SHORT=1` runs 10 µs instead (CI).

use criterion::{criterion_group, criterion_main, Criterion};
use magbubble::model::vorticity::scene::{FullModel, SchemeSettings};
use magbubble::scene::{self, VorticityScheme};

fn bench(c: &mut Criterion) {
    let short = std::env::var_os("MAGBUBBLE_BENCH_SHORT").is_some();
    let duration = if short { 10e-6 } else { 100e-6 };
    let text = format!(
        "[bubble]\nradius = 10e-6\n[drive]\namplitude = 0.2\nfrequency_hz = 1e6\n[field.coil]\ncurrent = 100e3\n[modes]\nmax_order = 16\nviscous = \"vorticity\"\n[run]\nduration = {duration}\nsample_interval = 1e-7\n"
    );
    let sc = scene::load_str(&text, "bench", &[] as &[&str]).expect("bench scene");
    let fm = FullModel::from_scene(&sc).expect("full model");
    let ts = fm.base().time_scale();
    let mut g = c.benchmark_group("vorticity_16_modes");
    g.sample_size(10);
    for (name, scheme, dt, rtol) in [
        ("staggered_dt1e-3", VorticityScheme::Staggered, 1e-3, 0.0),
        ("monolithic_rtol1e-6", VorticityScheme::Monolithic, 0.0, 1e-6),
    ] {
        let settings = SchemeSettings { scheme, dt, rtol, atol: 1e-9, t_end: duration / ts, sample: 1e-7 / ts, max_steps: 50_000_000 };
        g.bench_function(name, |b| {
            b.iter(|| fm.run_nondim(&settings, &mut |_| true).expect("run completes"));
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
