//! The run loop's stop times and events (issue 28 part 3) against closed forms.
//!
//! A linear oscillator x'' + (ω² + κ·b) x = F·b with a rectangular burst b = 1 on [t_a, t_b):
//! piecewise a harmonic oscillator, so the solution and the monodromy are products of exact
//! 2 × 2 propagators. With the burst's edges as stop times (and the branch b taken from the
//! segment, set by the loop's stop-time callback) every method converges at its order across
//! the edges; without them (b decided by comparing t with the edges) the order collapses.

use magbubble::integrate::run_loop::{run, Action, Direction, Event, Schedule, StopReason};
use magbubble::integrate::tableau::ButcherTableau;
use magbubble::integrate::{
    stepper, Control, ExplicitRk, Method, OdeSystem, Output, Radau5, Rk4, Stepper, Variational,
};
use std::cell::Cell;

const OMEGA: f64 = 2.0;
const T_A: f64 = 1.234_567;
const T_B: f64 = 3.456_789;
const T_END: f64 = 6.0;
const Y0: [f64; 2] = [1.0, 0.0];

/// The burst oscillator. `segment`: the branch b comes from `on` (set at the stop times);
/// otherwise from t (b = 1 for T_A ≤ t < T_B).
struct Burst {
    force: f64,
    kappa: f64,
    segment: bool,
    on: Cell<bool>,
}

impl Burst {
    fn new(force: f64, kappa: f64, segment: bool) -> Self {
        Burst { force, kappa, segment, on: Cell::new(false) }
    }
    fn branch(&self, t: f64) -> bool {
        if self.segment { self.on.get() } else { (T_A..T_B).contains(&t) }
    }
}

impl OdeSystem for Burst {
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) {
        let b = if self.branch(t) { 1.0 } else { 0.0 };
        dy[0] = y[1];
        dy[1] = -(OMEGA * OMEGA + self.kappa * b) * y[0] + self.force * b;
    }
}

/// The exact propagator of x'' + w² x = c over a time s: (x, v) ← equilibrium c/w² plus the
/// rotated deviation; also the 2 × 2 matrix ∂(x, v)/∂(x0, v0).
fn propagate(w: f64, c: f64, s: f64, y: [f64; 2]) -> ([f64; 2], [[f64; 2]; 2]) {
    let (sn, cs) = (w * s).sin_cos();
    let xe = c / (w * w);
    let dx = y[0] - xe;
    let m = [[cs, sn / w], [-w * sn, cs]];
    ([xe + m[0][0] * dx + m[0][1] * y[1], m[1][0] * dx + m[1][1] * y[1]], m)
}

fn matmul(a: [[f64; 2]; 2], b: [[f64; 2]; 2]) -> [[f64; 2]; 2] {
    std::array::from_fn(|i| std::array::from_fn(|j| a[i][0] * b[0][j] + a[i][1] * b[1][j]))
}

/// The exact state at T_END from Y0 and the monodromy X(T_END) (three pieces).
fn exact(force: f64, kappa: f64) -> ([f64; 2], [[f64; 2]; 2]) {
    let wb = (OMEGA * OMEGA + kappa).sqrt();
    let (y1, m1) = propagate(OMEGA, 0.0, T_A, Y0);
    let (y2, m2) = propagate(wb, force, T_B - T_A, y1);
    let (y3, m3) = propagate(OMEGA, 0.0, T_END - T_B, y2);
    (y3, matmul(m3, matmul(m2, m1)))
}

/// Runs `st` on `sys` to T_END: with the edges as stop times (the callback flips the branch) or
/// without; returns the final state and the stepper's accepted and rejected steps.
fn integrate(sys: &Burst, st: &mut dyn Stepper, edges: bool) -> (Vec<f64>, u64, u64) {
    let stops = [T_A, T_B];
    let mut flip = |_t: f64, _y: &mut [f64]| sys.on.set(!sys.on.get());
    let schedule = Schedule {
        stop_times: if edges { &stops } else { &[] },
        on_stop_time: Some(&mut flip),
        ..Schedule::new(T_END, Output::Steps, 10_000_000)
    };
    let fin = run(st, sys, schedule, &mut |_, _| Control::Continue).expect("integrates");
    assert_eq!(fin.reason, StopReason::End);
    assert_eq!(fin.t, T_END);
    (fin.z, st.stats().steps, st.stats().rejected)
}

fn max_err(y: &[f64], r: &[f64]) -> f64 {
    y.iter().zip(r).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max)
}

/// Least-squares slope of log e against log h.
fn slope(h: &[f64], e: &[f64]) -> f64 {
    let n = h.len() as f64;
    let (x, y): (Vec<f64>, Vec<f64>) = h.iter().zip(e).map(|(h, e)| (h.ln(), e.ln())).unzip();
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let sxy: f64 = x.iter().zip(&y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = x.iter().map(|a| (a - mx) * (a - mx)).sum();
    sxy / sxx
}

/// A fixed-step stepper of `kind` with step h.
fn fixed(kind: &str, sys: &Burst, h: f64) -> Box<dyn Stepper> {
    match kind {
        "rk4" => Box::new(Rk4::new(sys, 0.0, &Y0, h).unwrap()),
        "dopri5" => Box::new(ExplicitRk::new(sys, ButcherTableau::dopri5(), 0.0, &Y0, T_END, 1e-6, 1e-9).unwrap().with_fixed_step(h)),
        "dop853" => Box::new(ExplicitRk::new(sys, ButcherTableau::dop853(), 0.0, &Y0, T_END, 1e-6, 1e-9).unwrap().with_fixed_step(h)),
        _ => Box::new(Radau5::new(sys, 0.0, &Y0, T_END, 1e-6, 1e-9).unwrap().with_fixed_step(h)),
    }
}

/// Observed order of `kind` with fixed steps T_END/n across the burst; `edges`: stop times
/// and branch from the segment; otherwise the branch from t and no stop times.
fn fixed_order(kind: &str, ns: &[usize], edges: bool) -> (f64, Vec<f64>) {
    let (ref_y, _) = exact(0.7, 0.0);
    let mut hs = vec![];
    let mut errs = vec![];
    for &n in ns {
        let h = T_END / n as f64;
        let sys = Burst::new(0.7, 0.0, edges);
        let mut st = fixed(kind, &sys, h);
        let (y, _, _) = integrate(&sys, &mut *st, edges);
        hs.push(h);
        errs.push(max_err(&y, &ref_y));
    }
    (slope(&hs, &errs), errs)
}

#[test]
fn fixed_steps_converge_at_the_order_across_the_burst_edges_and_not_without_stop_times() {
    // (method, its order, step counts in its asymptotic range above rounding)
    let cases: [(&str, f64, &[usize]); 4] = [
        ("rk4", 4.0, &[60, 120, 240, 480]),
        ("dopri5", 5.0, &[30, 60, 120, 240]),
        ("dop853", 8.0, &[12, 18, 27, 40]),
        ("radau5", 5.0, &[30, 60, 120, 240]),
    ];
    for (kind, order, ns) in cases {
        let (p, errs) = fixed_order(kind, ns, true);
        assert!((p - order).abs() < 0.4, "{kind} with stop times: order {p:.2} (errors {errs:?}), expected {order}");
        let (q, errs_off) = fixed_order(kind, ns, false);
        assert!(q < 2.0, "{kind} without stop times: order {q:.2} (errors {errs_off:?}) should collapse");
        let last = ns.len() - 1;
        assert!(errs[last] < 1e-3 * errs_off[last], "{kind}: {:.2e} with, {:.2e} without", errs[last], errs_off[last]);
    }
}

#[test]
fn stop_times_with_a_branch_decided_by_t_lose_the_order() {
    // a step landing on an edge evaluates its last stage at the edge: a branch read from t is
    // the wrong one there (the run loop's module doc, "Branches at an edge")
    let (ref_y, _) = exact(0.7, 0.0);
    let mut hs = vec![];
    let mut errs = vec![];
    for n in [60, 120, 240, 480] {
        let h = T_END / n as f64;
        let sys = Burst::new(0.7, 0.0, false);
        let mut st = Rk4::new(&sys, 0.0, &Y0, h).unwrap();
        let stops = [T_A, T_B];
        let schedule = Schedule { stop_times: &stops, ..Schedule::new(T_END, Output::Steps, 1_000_000) };
        let fin = run(&mut st, &sys, schedule, &mut |_, _| Control::Continue).unwrap();
        hs.push(h);
        errs.push(max_err(&fin.z, &ref_y));
    }
    let p = slope(&hs, &errs);
    assert!(p < 1.5, "order {p:.2} (errors {errs:?})");
}

#[test]
fn adaptive_errors_fall_with_the_tolerance_across_the_edges() {
    let (ref_y, _) = exact(0.7, 0.0);
    for method in ["dopri5", "dop853", "radau5", "rosenbrock23"] {
        let mut errs = vec![];
        let mut errs_off = vec![];
        let mut rejected = (0, 0);
        let tols = [1e-5, 1e-7, 1e-9];
        for &rtol in &tols {
            let m = match method {
                "dopri5" => Method::Dopri5 { rtol, atol: rtol },
                "dop853" => Method::Dop853 { rtol, atol: rtol },
                "radau5" => Method::Radau5 { rtol, atol: rtol },
                _ => Method::Rosenbrock23 { rtol, atol: rtol },
            };
            let run_with = |edges: bool| {
                let sys = Burst::new(0.7, 0.0, edges);
                let mut st = stepper(&sys, &m, 0.0, &Y0, T_END).unwrap();
                integrate(&sys, &mut *st, edges)
            };
            let (y, _, rej) = run_with(true);
            let (y_off, _, rej_off) = run_with(false);
            errs.push(max_err(&y, &ref_y));
            errs_off.push(max_err(&y_off, &ref_y));
            eprintln!("{method} rtol {rtol:.0e}: error {:.2e} with stop times ({rej} rejected), {:.2e} without ({rej_off} rejected)", errs.last().unwrap(), max_err(&y_off, &ref_y));
            rejected = (rejected.0 + rej, rejected.1 + rej_off);
        }
        // the global error is proportional to the tolerance to a power near 1 (to the method's
        // tolerance proportionality, measured for rosenbrock23's order 2 at ≈ 2/3 of it)
        let p = slope(&tols, &errs);
        assert!(p > 0.6 && p < 1.3, "{method}: error ∝ rtol^{p:.2} ({errs:?})");
        // measured at rtol 1e-9: dopri5 3.7e-9 (4.1e-7 without the stop times), dop853 4.5e-10
        // (3.7e-9), radau5 2.9e-9 (2.6e-7); rosenbrock23's global error (5.8e-6 either way) is
        // its order-2 accumulation over the smooth pieces, not the edges
        if method != "rosenbrock23" {
            assert!(errs[2] < 10.0 * tols[2], "{method}: {:.2e} at rtol {:.0e}", errs[2], tols[2]);
            assert!(errs_off[2] > 5.0 * errs[2], "{method}: {:.2e} without the stop times, {:.2e} with", errs_off[2], errs[2]);
        }
        assert!(errs[2] <= 1.01 * errs_off[2], "{method}: {:.2e} with the stop times, {:.2e} without", errs[2], errs_off[2]);
        // without the edges the error control must find them by rejections
        assert!(rejected.0 < rejected.1, "{method}: rejected {} with stop times, {} without", rejected.0, rejected.1);
    }
}

#[test]
fn variational_equations_carry_the_monodromy_across_the_stop_times() {
    // the burst also stiffens the spring (κ): the Jacobian jumps at the edges
    let (force, kappa) = (0.7, 5.0);
    let (_, x_exact) = exact(force, kappa);
    let cases = [
        (Method::Dop853 { rtol: 1e-11, atol: 1e-12 }, true, 1e-7),
        // fixed steps: (h ≈ 1e-3)⁴ with the stop times; a step across an edge costs O(h) without
        (Method::Rk4 { dt: 1e-3 }, true, 1e-9),
        (Method::Rk4 { dt: 1e-3 }, false, f64::INFINITY),
    ];
    for (method, edges, bound) in cases {
        let sys = Burst::new(force, kappa, edges);
        let var = Variational::new(&sys);
        let y0 = var.initial_state(&Y0);
        let mut st = stepper(&var, &method, 0.0, &y0, T_END).unwrap();
        let stops = [T_A, T_B];
        let mut flip = |_t: f64, _y: &mut [f64]| sys.on.set(!sys.on.get());
        let schedule = Schedule {
            stop_times: if edges { &stops } else { &[] },
            on_stop_time: Some(&mut flip),
            ..Schedule::new(T_END, Output::Steps, 1_000_000)
        };
        let fin = run(&mut *st, &var, schedule, &mut |_, _| Control::Continue).unwrap();
        let phi = var.fundamental(&fin.z); // column-major
        let err = (0..2).flat_map(|r| (0..2).map(move |c| (r, c))).map(|(r, c)| (phi[c * 2 + r] - x_exact[r][c]).abs()).fold(0.0, f64::max);
        eprintln!("{method:?}, stop times {edges}: monodromy error {err:.2e}");
        // the finite-difference Jacobian of the linear system is exact to rounding
        assert!(err < bound, "{method:?}: monodromy error {err:.2e} > {bound:.0e}");
        if !edges {
            assert!(err > 1e-5, "{method:?} without stop times: monodromy error {err:.2e} should be O(h)");
        }
    }
}

/// g = x − level, falling: x = cos ωt (free oscillator) crosses the level at arccos(level)/ω.
struct Level(f64);
impl Event for Level {
    fn g(&self, _t: f64, z: &[f64]) -> f64 {
        z[0] - self.0
    }
    fn direction(&self) -> Direction {
        Direction::Falling
    }
}

#[test]
fn an_event_is_located_to_the_last_representable_time_on_the_dense_output() {
    let level: f64 = 0.3;
    let t_exact = level.acos() / OMEGA;
    let sys = Burst::new(0.0, 0.0, true);
    let ev = Level(level);
    for m in [Method::Dopri5 { rtol: 1e-12, atol: 1e-14 }, Method::Radau5 { rtol: 1e-12, atol: 1e-14 }, Method::Rk4 { dt: 1e-3 }] {
        let mut st = stepper(&sys, &m, 0.0, &Y0, T_END).unwrap();
        let events: [&dyn Event; 1] = [&ev];
        let schedule = Schedule { events: &events, ..Schedule::new(T_END, Output::Every(0.05), 1_000_000) };
        let mut samples = vec![];
        let fin = run(&mut *st, &sys, schedule, &mut |t, _| {
            samples.push(t);
            Control::Continue
        })
        .unwrap();
        assert_eq!(fin.reason, StopReason::Event { index: 0 }, "{m:?}");
        // located to the last float on the dense output: crossed at t, not at the float before
        let mut z = [0.0; 2];
        st.interpolate(fin.t, &mut z);
        assert!(z[0] < level, "{m:?}");
        st.interpolate(fin.t.next_down(), &mut z);
        assert!(z[0] >= level, "{m:?}: {} at the float before t", z[0]);
        // and against the closed form, to the dense output's accuracy
        assert!((fin.t - t_exact).abs() < 1e-9, "{m:?}: {:.3e}", fin.t - t_exact);
        // the samples before the event were all emitted, none after it
        assert!(samples.iter().all(|&t| t < fin.t) && samples.len() == 1 + (fin.t / 0.05) as usize, "{m:?}: {samples:?}");
    }
}

/// g = x + depth, either direction, with or without its rate ẋ: x = cos ωt dips below −depth
/// for a short while around t = π/ω and comes back — a pair of crossings that a loose step
/// holds whole.
struct Dip {
    depth: f64,
    with_rate: bool,
}
impl Event for Dip {
    fn g(&self, _t: f64, z: &[f64]) -> f64 {
        z[0] + self.depth
    }
    fn direction(&self) -> Direction {
        Direction::Either
    }
    fn rate(&self, _t: f64, z: &[f64]) -> Option<f64> {
        self.with_rate.then_some(z[1])
    }
}

#[test]
fn a_pair_of_crossings_inside_one_step_is_found_through_the_rate() {
    // x = cos 2t dips below −0.9999 on |t − π/2| < arccos(0.9999)/2 = 0.0071: one step of a
    // loose DOP853 (h ≈ 0.3 here) holds both crossings, so g has the same sign at both ends
    let depth: f64 = 0.9999;
    let t_exact = (std::f64::consts::PI - depth.acos()) / OMEGA;
    let sys = Burst::new(0.0, 0.0, true);
    for m in [Method::Dop853 { rtol: 1e-6, atol: 1e-6 }, Method::Dopri5 { rtol: 1e-6, atol: 1e-6 }, Method::Radau5 { rtol: 1e-6, atol: 1e-6 }] {
        for with_rate in [false, true] {
            let ev = Dip { depth, with_rate };
            let mut st = stepper(&sys, &m, 0.0, &Y0, T_END).unwrap();
            let events: [&dyn Event; 1] = [&ev];
            let schedule = Schedule { events: &events, ..Schedule::new(T_END, Output::Steps, 1_000_000) };
            let fin = run(&mut *st, &sys, schedule, &mut |_, _| Control::Continue).unwrap();
            if with_rate {
                assert_eq!(fin.reason, StopReason::Event { index: 0 }, "{m:?}");
                // the first crossing of the pair, to the dense output's accuracy at this tolerance
                assert!((fin.t - t_exact).abs() < 1e-4, "{m:?}: {} vs {t_exact}", fin.t);
                assert!(fin.z[0] < -depth, "{m:?}: on the crossed side");
            } else {
                // the sign test alone steps over the dip (what the rate is for)
                assert_eq!(fin.reason, StopReason::End, "{m:?} without the rate: the pair should lie inside one step");
            }
        }
    }
}

/// g = t − at, rising: a crossing any sign test sees.
struct At(f64);
impl Event for At {
    fn g(&self, t: f64, _z: &[f64]) -> f64 {
        t - self.0
    }
}

#[test]
fn a_pair_of_crossings_is_found_beside_another_events_crossing_in_the_same_step() {
    // the dip of the test above, and a time event inside the dip (after the pair's first
    // crossing): the step holding the pair holds the time event's crossing too, which the sign
    // test sees; the pair's first crossing comes first and must end the run
    let depth: f64 = 0.9999;
    let t_exact = (std::f64::consts::PI - depth.acos()) / OMEGA;
    let sys = Burst::new(0.0, 0.0, true);
    let dip = Dip { depth, with_rate: true };
    let later = At(t_exact + 0.002);
    let mut st = stepper(&sys, &Method::Dop853 { rtol: 1e-6, atol: 1e-6 }, 0.0, &Y0, T_END).unwrap();
    let events: [&dyn Event; 2] = [&later, &dip];
    let schedule = Schedule { events: &events, ..Schedule::new(T_END, Output::Steps, 1_000_000) };
    let fin = run(&mut *st, &sys, schedule, &mut |_, _| Control::Continue).unwrap();
    assert_eq!(fin.reason, StopReason::Event { index: 1 }, "the dip's crossing at {t_exact}, not the time event's at {}", t_exact + 0.002);
    assert!((fin.t - t_exact).abs() < 1e-4, "{} vs {t_exact}", fin.t);
}

/// A ball under gravity bouncing with restitution e: y'' = −1, at y = 0 (falling) v ← −e·v.
struct Ball;
impl OdeSystem for Ball {
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&self, _t: f64, y: &[f64], dy: &mut [f64]) {
        dy[0] = y[1];
        dy[1] = -1.0;
    }
}
struct Bounce {
    restitution: f64,
    times: std::cell::RefCell<Vec<f64>>,
}
impl Event for Bounce {
    fn g(&self, _t: f64, z: &[f64]) -> f64 {
        z[0]
    }
    fn direction(&self) -> Direction {
        Direction::Falling
    }
    fn action(&self) -> Action {
        Action::Restart
    }
    fn update(&self, t: f64, y: &mut [f64]) {
        self.times.borrow_mut().push(t);
        y[0] = 0.0;
        y[1] = -self.restitution * y[1];
    }
}

#[test]
fn restart_events_update_the_state_and_continue() {
    // from y = 1.5 at rest: first impact at √3, then flights of 2·e^n·√3 (speed √3 at impact)
    let e = 0.8;
    let ev = Bounce { restitution: e, times: Default::default() };
    let sys = Ball;
    let mut st = stepper(&sys, &Method::Dop853 { rtol: 1e-10, atol: 1e-12 }, 0.0, &[1.5, 0.0], 12.0).unwrap();
    let events: [&dyn Event; 1] = [&ev];
    let fin = run(&mut *st, &sys, Schedule { events: &events, ..Schedule::new(12.0, Output::Steps, 100_000) }, &mut |_, _| Control::Continue).unwrap();
    assert_eq!(fin.reason, StopReason::End);
    let times = ev.times.borrow();
    let mut t = 3f64.sqrt();
    let mut expect = vec![t];
    for n in 1.. {
        t += 2.0 * e.powi(n) * 3f64.sqrt();
        if t > 12.0 {
            break;
        }
        expect.push(t);
    }
    assert_eq!(times.len(), expect.len(), "{times:?} vs {expect:?}");
    for (a, b) in times.iter().zip(&expect) {
        assert!((a - b).abs() < 1e-9, "{a} vs {b}");
    }
}
