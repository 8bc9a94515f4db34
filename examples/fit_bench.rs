//! The fit's cost (issue 32, docs/performance.md "Fit"): one sensitivity solve with p
//! parameters against a plain solve of the same run, and a 3-parameter fit of a 100 µs
//! boundary-layer run against 1,000 points in units of plain solves. Interleaved repetitions,
//! the minimum of each kept (the machine is shared).
//!
//! cargo run --release --example fit_bench [-- SCENE]

use magbubble::api::fit::{fit, Data, FitRequest};
use magbubble::api::{self, Monitor, Scene};
use magbubble::fit::sensitivities::ModelRates;
use magbubble::fit::solve::{model_time, solve};
use magbubble::model::Model;
use std::time::Instant;

fn main() {
    let path = std::env::args().nth(1).unwrap_or_else(|| "scenes/no_field.toml".into());
    // 100 µs, 1,000 samples
    let scene = Scene::load(&path, &["run.duration=100e-6", "run.sample_interval=1e-7"]).unwrap();
    let sc = scene.scene().clone();
    let model = Model::from_scene(&sc).unwrap();
    let run = api::run::run(&scene, &Monitor::default()).unwrap();
    let w = run.outcome.columns.len();
    let t: Vec<f64> = run.values.chunks(w).map(|r| r[0]).collect();
    let times: Vec<f64> = t.iter().map(|&x| model_time(x, &model, &sc.run)).collect();
    let keys = ["shell.c1", "shell.c2", "drive.amplitude"];
    let values = [sc.shell.c1, sc.shell.c2, sc.drive.as_ref().unwrap().amplitude];
    let only = std::env::var("FIT_BENCH_ONLY").ok();
    if let Some(p) = only.as_deref().and_then(|p| p.parse::<usize>().ok()) {
        // one solve, for callgrind: "0" plain, "1".."3" sensitivities ("fit1", "fit2": one fit)
        let rates = (p > 0).then(|| ModelRates::new(scene.template(), &keys[..p], &values[..p], &model).unwrap());
        let c = solve(&model, &sc.run, &times, rates.as_ref());
        println!("{:?}", c.stats);
        return;
    }
    let reps = if only.is_some() { 0 } else { 3 };
    let mut plain = f64::INFINITY;
    let mut sens = [f64::INFINITY; 3];
    let mut stats = Vec::new();
    for _ in 0..reps {
        let t0 = Instant::now();
        let c = solve(&model, &sc.run, &times, None);
        plain = plain.min(t0.elapsed().as_secs_f64());
        stats.push(("plain".to_string(), c.stats));
        for p in 1..=3 {
            let t0 = Instant::now();
            let rates = ModelRates::new(scene.template(), &keys[..p], &values[..p], &model).unwrap();
            let c = solve(&model, &sc.run, &times, Some(&rates));
            sens[p - 1] = sens[p - 1].min(t0.elapsed().as_secs_f64());
            stats.push((format!("p={p} {:?}", rates.derivative), c.stats));
        }
    }
    if only.is_none() {
    println!("scene {path}: {} points, state dimension {}", times.len(), model.initial_state().len());
    println!("plain solve: {:.4} s", plain);
    for p in 1..=3 {
        println!("sensitivity solve, p = {p}: {:.4} s = {:.2} plain (target <= {})", sens[p - 1], sens[p - 1] / plain, 1 + p);
    }
    for (what, s) in stats.iter().take(4) {
        println!("  {what}: steps {} rejected {} rhs {} jac {} lu {}", s.steps, s.rejected, s.rhs_evals, s.jac_evals, s.lu_decompositions);
    }
    }
    // a 3-parameter fit: data from the run at the scene's values with 1 % R0 noise on R, the
    // fit starting 10 % off
    let r0 = sc.bubble.radius;
    let mut state = 0x1234_5678_9abc_def1u64;
    let mut normal = || {
        let mut u = || {
            state ^= state >> 12;
            state ^= state << 25;
            state ^= state >> 27;
            ((state.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 + 0.5) / (1u64 << 53) as f64
        };
        let (a, b) = (u(), u());
        (-2.0 * a.ln()).sqrt() * (2.0 * std::f64::consts::PI * b).cos()
    };
    let rvals: Vec<f64> = run.values.chunks(w).map(|r| r[1] + 0.01 * r0 * normal()).collect();
    let data = Data::from_columns(vec![("t".into(), t.clone()), ("R".into(), rvals), ("sigma_R".into(), vec![0.01 * r0; t.len()])]).unwrap();
    let start = scene
        .with_overrides(&[format!("shell.c1={}", values[0] * 1.1), format!("shell.c2={}", values[1] * 0.9), format!("drive.amplitude={}", values[2] * 1.1)])
        .unwrap();
    let req = FitRequest::new(data, keys.iter().map(|k| k.parse().unwrap()).collect());
    if only.as_deref() != Some("fit2") {
        timed_fit("3-parameter fit", &start, &req, plain);
    }
    if only.as_deref() == Some("fit1") {
        return;
    }
    // the same with an identifiable set: c1, the drive amplitude and the liquid viscosity
    let keys2 = ["shell.c1", "drive.amplitude", "liquid.viscosity"];
    let eta = sc.liquid.viscosity;
    let start2 = scene
        .with_overrides(&[format!("shell.c1={}", values[0] * 1.1), format!("drive.amplitude={}", values[2] * 1.1), format!("liquid.viscosity={}", eta * 0.9)])
        .unwrap();
    let req2 = FitRequest { params: keys2.iter().map(|k| k.parse().unwrap()).collect(), ..req };
    timed_fit("3-parameter fit (c1, eps_p, eta)", &start2, &req2, plain);
}

/// Runs one fit and prints its cost in plain solves, its counts and its parameters.
fn timed_fit(label: &str, start: &Scene, req: &FitRequest, plain: f64) {
    let t0 = Instant::now();
    let rep = fit(start, req, &Monitor::default()).unwrap();
    let secs = t0.elapsed().as_secs_f64();
    println!(
        "{label}: {:.3} s = {:.1} plain solves (target <= 30): status {}, {} iterations, {} plain + {} sensitivity solves",
        secs,
        secs / plain,
        rep.status,
        rep.iterations,
        rep.plain_solves,
        rep.sensitivity_solves
    );
    for p in &rep.parameters {
        println!("  {} = {:e} ± {:e} ({})", p.key, p.value, p.std_error, p.derivative);
    }
    println!("  warnings: {:?}", rep.warnings);
}
