//! One step of each integrator on a 50-dimensional stiff-ish problem: the method-of-lines
//! Fisher–KPP equation u_t = D u_xx + u(1 − u) on (0, 1), Dirichlet, D = 0.01 (tridiagonal
//! Jacobian, spectral radius ≈ 100). Each sample clones a stepper advanced past its initial
//! transient and times one accepted step.
//!
//! Short variant for CI: `MAGBUBBLE_BENCH_QUICK=1 cargo bench --bench integrators`.

use criterion::{criterion_group, criterion_main, BatchSize, Criterion};
use magbubble::integrate::tableau::ButcherTableau;
use magbubble::integrate::{ExplicitRk, OdeSystem, Radau5, Rk4, Stepper};
use std::time::Duration;

const N: usize = 50;

struct Fisher {
    banded: bool,
}

impl OdeSystem for Fisher {
    fn dim(&self) -> usize {
        N
    }
    fn rhs(&self, _t: f64, u: &[f64], du: &mut [f64]) {
        let c = 0.01 * ((N + 1) as f64).powi(2);
        for i in 0..N {
            let l = if i > 0 { u[i - 1] } else { 0.0 };
            let r = if i + 1 < N { u[i + 1] } else { 0.0 };
            du[i] = c * (l - 2.0 * u[i] + r) + u[i] * (1.0 - u[i]);
        }
    }
    fn bandwidth(&self) -> Option<(usize, usize)> {
        self.banded.then_some((1, 1))
    }
}

fn y0() -> Vec<f64> {
    (1..=N).map(|i| (std::f64::consts::PI * i as f64 / (N + 1) as f64).sin().powi(2)).collect()
}

/// Advances a stepper to t = 1 so that the timed step is a typical one.
fn warmed<S: Stepper>(mut s: S, sys: &dyn OdeSystem) -> S {
    while s.t() < 1.0 {
        s.step(sys, 1.0).expect("warm-up");
    }
    s
}

/// Times one step of a warmed stepper; the setup (building and warming, not timed) runs per batch
/// because an implicit stepper owns its factorisations and is not `Clone`.
fn one_step<S: Stepper>(c: &mut Criterion, name: &str, sys: &dyn OdeSystem, make: impl Fn() -> S) {
    c.bench_function(name, |b| {
        b.iter_batched(|| warmed(make(), sys), |mut s| s.step(sys, f64::INFINITY).expect("step"), BatchSize::SmallInput)
    });
}

fn benches(c: &mut Criterion) {
    let (dense, band) = (Fisher { banded: false }, Fisher { banded: true });
    let y0 = y0();
    let tol = 1e-6;
    one_step(c, "rk4 step (dt 0.01)", &dense, || Rk4::new(&dense, 0.0, &y0, 0.01).unwrap());
    let erk = |tab| ExplicitRk::new(&dense, tab, 0.0, &y0, 10.0, tol, tol).unwrap();
    one_step(c, "dopri5 step (rtol 1e-6)", &dense, || erk(ButcherTableau::dopri5()));
    one_step(c, "dop853 step (rtol 1e-6)", &dense, || erk(ButcherTableau::dop853()));
    one_step(c, "radau5 step dense J (rtol 1e-6)", &dense, || Radau5::new(&dense, 0.0, &y0, 10.0, tol, tol).unwrap());
    one_step(c, "radau5 step banded J (rtol 1e-6)", &band, || Radau5::new(&band, 0.0, &y0, 10.0, tol, tol).unwrap());
}

fn config() -> Criterion {
    let c = Criterion::default();
    if std::env::var_os("MAGBUBBLE_BENCH_QUICK").is_some() {
        c.sample_size(10).warm_up_time(Duration::from_millis(200)).measurement_time(Duration::from_millis(500))
    } else {
        c
    }
}

criterion_group! { name = integrators; config = config(); targets = benches }
criterion_main!(integrators);
