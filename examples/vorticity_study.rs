//! The measurements behind docs/vorticity.md (grid study, the staggered scheme's stability and
//! convergence, timings): printed tables, no assertions (the asserting checks are in
//! tests/suite/vorticity_*.rs). Run one with
//!
//! ```text
//! cargo run --release --example vorticity_study -- MEASUREMENT
//! ```
//!
//! MEASUREMENT: `grid`, `stability`, `threshold`, `convergence`, `staggered-timing`,
//! `monolithic-timing`, `scan`, `scan-lagged` (see `MEASUREMENTS` below); none: the list.

use magbubble::analysis::dispersion::LinearMode;
use magbubble::model::vorticity::linear::{full_root, initial_guess, LinearCoupling};
use magbubble::model::vorticity::staggered::{Staggered, WallCoupling};
use magbubble::model::vorticity::Grid;

/// The hand-built scenes and modes of the test suite (the paper's bubble).
#[path = "../tests/suite/common/mod.rs"]
mod common;

/// (name, what it prints, the measurement)
const MEASUREMENTS: [(&str, &str, fn()); 8] = [
    ("grid", "discrete vs exact root per grid, k = 2, 8, 16, 32 (docs/vorticity.md, grid table)", grid_study),
    ("stability", "staggered scheme bounded or not per k and Δt′ over 10 µs", staggered_stability),
    ("threshold", "largest stable Δt′ of the staggered scheme per k (bisection)", staggered_stability_threshold),
    ("convergence", "staggered free-decay convergence, k = 2…16 (docs/vorticity.md)", staggered_free_decay_convergence),
    ("staggered-timing", "staggered steps per second, 100 and 200 points", staggered_timing),
    ("monolithic-timing", "monolithic Radau5 work and time against the staggered scheme", monolithic_timing),
    ("scan", "stability scan, T_w in the right-hand side (docs/vorticity.md)", staggered_stability_scan),
    ("scan-lagged", "stability scan, T_w lagged (the paper's wording)", staggered_stability_scan_lagged_wall),
];

fn main() {
    let which = std::env::args().nth(1);
    match MEASUREMENTS.iter().find(|m| Some(m.0) == which.as_deref()) {
        Some((_, _, run)) => run(),
        None => {
            if let Some(w) = which {
                eprintln!("unknown measurement {w:?}");
            }
            eprintln!("usage: cargo run --release --example vorticity_study -- MEASUREMENT");
            for (name, what, _) in MEASUREMENTS {
                eprintln!("  {name:18} {what}");
            }
            std::process::exit(2);
        }
    }
}

fn mode(k: usize) -> LinearMode {
    crate::common::paper_mode(k)
}

fn grid_study() {
    for k in [2usize, 8, 16, 32] {
        let m = mode(k);
        let ex = m.exact_root(initial_guess(&m)).unwrap();
        println!("k = {k}: exact decay {:.6e} omega {:.6e}", -ex.re, ex.im);
        for &(ymax, pts, st) in &[
            (2.0, 100, 1.0), (2.0, 100, 10.0), (2.0, 100, 30.0), (3.0, 100, 30.0),
            (2.0, 200, 10.0), (2.0, 200, 30.0), (3.0, 200, 30.0), (3.0, 400, 30.0), (2.0, 400, 1.0), (2.0, 50, 20.0),
        ] {
            let g = Grid::new(ymax, pts, st).unwrap();
            let d = full_root(&m, &g, ex).unwrap();
            println!(
                "  Ymax {ymax} n {pts:4} stretch {st:5}: h0 {:.2e}  rel err decay {:.2e} omega {:.2e}",
                g.h0(),
                ((d.re - ex.re) / ex.re).abs(),
                ((d.im - ex.im) / ex.im).abs()
            );
        }
    }
}

fn staggered_stability() {
    let t_star = (1000.0f64 * 1e-15 / 0.2).sqrt();
    let g = Grid::new(3.0, 200, 30.0).unwrap();
    for k in [2usize, 4, 8, 12, 16, 20, 24, 32] {
        let m = mode(k);
        let c = LinearCoupling::new(vec![m]);
        let mut line = format!("k = {k:2}:");
        for dtp in [1e-4, 2e-4, 5e-4, 1e-3, 2e-3, 5e-3] {
            let mut st = Staggered::new(&c, g.clone(), dtp * t_star).unwrap();
            let a0 = 1e-3 * m.r0;
            let mut s = st.initial_state(0.0, m.r0, 0.0, vec![a0], vec![0.0], vec![0.0]);
            let mut maxa: f64 = 0.0;
            let res = st.run(&mut s, 10e-6, |s, _| {
                maxa = maxa.max(s.a[0].abs());
                maxa < 1e3 * a0
            });
            let ok = res.is_ok() && maxa < 1e3 * a0 && s.a[0].abs() < a0;
            line += &format!("  {dtp:.0e}:{}", if ok { "ok" } else { "UNSTABLE" });
        }
        println!("{line}");
    }
}

/// Largest stable Δt′ of the staggered scheme per k (bisection on free decay over 10 µs).
fn staggered_stability_threshold() {
    let t_star = (1000.0f64 * 1e-15 / 0.2).sqrt();
    let g = Grid::new(3.0, 200, 30.0).unwrap();
    let stable = |k: usize, dtp: f64| {
        let m = mode(k);
        let c = LinearCoupling::new(vec![m]);
        let mut st = Staggered::new(&c, g.clone(), dtp * t_star).unwrap();
        let a0 = 1e-3 * m.r0;
        let mut s = st.initial_state(0.0, m.r0, 0.0, vec![a0], vec![0.0], vec![0.0]);
        let mut maxa: f64 = 0.0;
        let res = st.run(&mut s, 20e-6, |s, _| {
            maxa = maxa.max(s.a[0].abs());
            maxa < 1e3 * a0
        });
        res.is_ok() && maxa < 1e3 * a0 && s.a[0].abs() < a0
    };
    for k in [2usize, 4, 8, 12, 16, 20, 24, 28, 32] {
        let (mut lo, mut hi) = (1e-4, 1e-1);
        if !stable(k, lo) {
            println!("k = {k}: unstable already at {lo}");
            continue;
        }
        for _ in 0..14 {
            let mid = (lo * hi).sqrt();
            if stable(k, mid) { lo = mid } else { hi = mid }
        }
        let m = mode(k);
        let w0 = g.h0() / 2.0;
        let lam_b = m.s12 * w0 * m.r0 / (m.eta * (1.0 + 2.0 * w0));
        println!("k = {k:2}: largest stable dt' ≈ {lo:.3e}  (λ_b,grid t* = {:.3e}, 2.785/(λ_b t*) = {:.3e})", lam_b * t_star, 2.785 / (lam_b * t_star));
    }
}

fn staggered_free_decay_convergence() {
    use magbubble::analysis::convergence::convergence_study;
    let t_star = (1000.0f64 * 1e-15 / 0.2).sqrt();
    let g = Grid::new(3.0, 200, 30.0).unwrap();
    let modes: Vec<LinearMode> = (1..=8).map(|i| mode(2 * i)).collect();
    let c = LinearCoupling::new(modes.clone());
    let a0: Vec<f64> = modes.iter().map(|m| 1e-3 * m.r0 / m.k as f64).collect();
    let st = Staggered::new(&c, g.clone(), 1.0).unwrap();
    let init = st.initial_state(0.0, 10e-6, 0.0, a0, vec![0.0; 8], vec![0.0; 8]);
    let rep = convergence_study(&c, &g, &init, 20e-6, 1.7e-4 * t_star, &[2, 4, 8, 16]).unwrap();
    for r in &rep.rows {
        println!("dt' {:.3e}: e_s {:.3e} (k={}) e_f {:.3e}  {:.2}s", r.dt / t_star, r.e_s, r.worst_k_s, r.e_f, r.seconds);
    }
    println!("orders: s {:?} f {:?}", rep.order_s, rep.order_f);
}

fn staggered_timing() {
    let t_star = (1000.0f64 * 1e-15 / 0.2).sqrt();
    for pts in [100usize, 200] {
        let g = Grid::new(3.0, pts, 30.0).unwrap();
        let modes: Vec<LinearMode> = (1..=8).map(|i| mode(2 * i)).collect();
        let c = LinearCoupling::new(modes.clone());
        let a0: Vec<f64> = modes.iter().map(|m| 1e-3 * m.r0 / m.k as f64).collect();
        let mut st = Staggered::new(&c, g.clone(), 1e-3 * t_star).unwrap();
        let mut s = st.initial_state(0.0, 10e-6, 0.0, a0, vec![0.0; 8], vec![0.0; 8]);
        let t0 = std::time::Instant::now();
        let n = st.run(&mut s, 100e-6, |_, _| true).unwrap();
        let el = t0.elapsed().as_secs_f64();
        println!("points {pts}: {n} steps in {el:.3} s ({:.2} µs/step)", el / n as f64 * 1e6);
    }
}

/// The paper's bubble in the nondimensional units of FORMULATION §4.5 (R0 = ρ = 1, c1 = 1/2,
/// t* = 2.236 µs, Re = 44.7).
fn mode_nd(k: usize) -> LinearMode {
    crate::common::paper_mode_nd(k, 44.72)
}

fn monolithic_timing() {
    use magbubble::integrate::{solve, Control, Method, Output};
    use magbubble::model::vorticity::monolithic::Monolithic;
    for pts in [100usize, 200] {
        let g = Grid::new(3.0, pts, 30.0).unwrap();
        let modes: Vec<LinearMode> = (1..=8).map(|i| mode_nd(2 * i)).collect();
        let c = LinearCoupling::new(modes.clone());
        let sys = Monolithic::new(&c, g.clone());
        let a0: Vec<f64> = modes.iter().map(|m| 1e-3 / m.k as f64).collect();
        let st = Staggered::new(&c, g.clone(), 1.0).unwrap();
        let init = st.initial_state(0.0, 1.0, 0.0, a0, vec![0.0; 8], vec![0.0; 8]);
        for rtol in [1e-4, 1e-6] {
            let t0 = std::time::Instant::now();
            let sol = solve(&sys, 0.0, &sys.pack(&init), 44.72, &Method::Radau5 { rtol, atol: 1e-10 }, Output::Steps, 1_000_000, &mut |_, _| Control::Continue).unwrap();
            let (stats, y) = (sol.stats, sol.y);
            let el = t0.elapsed().as_secs_f64();
            // reference: staggered at small dt
            println!("points {pts} rtol {rtol:e}: {stats:?} in {el:.3} s; a2(end) = {:.6e}", y[sys.layout().a(0)]);
        }
        let mut stg = Staggered::new(&c, g.clone(), 1e-4).unwrap();
        let mut s = init.clone();
        stg.run(&mut s, 44.72, |_, _| true).unwrap();
        println!("   staggered dt' 1e-4: a2(end) = {:.6e}", s.a[0]);
    }
}

/// Prints, per mode k and step Δt′ (units of t*), whether the staggered scheme with this wall
/// coupling stays bounded over 40 µs from a_k = 10⁻³ R0 (`.`) or not (`X`).
fn staggered_scan(wall: WallCoupling) {
    let t_star = (1000.0f64 * 1e-15 / 0.2).sqrt();
    let g = Grid::new(3.0, 201, 20.0).unwrap();
    let ladder = [5e-4, 1e-3, 1.5e-3, 2e-3, 3e-3, 4e-3, 6e-3, 8e-3, 1.2e-2, 1.6e-2, 2.4e-2];
    println!("dt' ladder {ladder:?}");
    for k in [2usize, 4, 8, 12, 16, 20, 24, 28, 32] {
        let m = mode(k);
        let c = LinearCoupling::new(vec![m]);
        let mut line = format!("k = {k:2}:");
        for &dtp in &ladder {
            let mut st = Staggered::new(&c, g.clone(), dtp * t_star).unwrap().with_wall(wall);
            let a0 = 1e-3 * m.r0;
            let mut s = st.initial_state(0.0, m.r0, 0.0, vec![a0], vec![0.0], vec![0.0]);
            let mut maxa: f64 = 0.0;
            let res = st.run(&mut s, 40e-6, |s, _| {
                maxa = maxa.max(s.a[0].abs());
                maxa < 1e3 * a0
            });
            let ok = res.is_ok() && maxa < 1e3 * a0 && s.a[0].abs() < a0;
            line += if ok { " ." } else { " X" };
        }
        println!("{line}");
    }
}

fn staggered_stability_scan() {
    staggered_scan(WallCoupling::default());
}

fn staggered_stability_scan_lagged_wall() {
    staggered_scan(WallCoupling::Lagged);
}
