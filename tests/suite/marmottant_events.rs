//! The kinked Marmottant law's branch switches as events of the run loop (issue 31;
//! docs/model.md, "Branch switches"; runtime/model/events.rs): each switch located at R_b / R_r
//! to the stated tolerance, fixed-step RK4 converging at order 4 across the switches with the
//! events and not without them, the end state independent of the sample interval, and the
//! summary's fractions of time on each branch.

use magbubble::integrate::run_loop::{run, Action, Direction, Event, Schedule};
use magbubble::integrate::{stepper, Control, Method, Output};
use magbubble::model::{Model, RunStatus};
use magbubble::scene::Scene;
use std::cell::RefCell;

/// coil_static's bubble without the field, a Marmottant shell (χ = 0.5 N/m, σ(R0) = 0.02 N/m,
/// σ_r = 0.072 N/m: R_b = 0.981 R0, R_r = 1.049 R0), driven at 400 kHz near its radial
/// resonance with ε_p = `eps`, shape modes up to k = `n` seeded with a2 = 1e-8 m: it buckles and
/// ruptures every cycle.
fn scene(eps: f64, n: usize, extra: &[&str]) -> Scene {
    let mut set = vec![
        "shell.law=\"marmottant\"".to_string(),
        "shell.elasticity=0.5".into(),
        "shell.initial_tension=0.02".into(),
        "shell.dilatational_viscosity=5e-9".into(),
        format!("drive.amplitude={eps}"),
        "drive.frequency_hz=4e5".into(),
        format!("modes.max_order={n}"),
        "run.duration=7.5e-6".into(),
        "bubble.initial.a.2=1e-8".into(),
    ];
    set.extend(extra.iter().map(|s| s.to_string()));
    magbubble::scene::load("scenes/no_field.toml", &set).unwrap()
}

/// Records every Restart event's (t, R) through `update`.
struct Spy<'a> {
    inner: &'a dyn Event,
    index: usize,
    seen: &'a RefCell<Vec<(usize, f64, f64, f64)>>,
}

impl Event for Spy<'_> {
    fn g(&self, t: f64, z: &[f64]) -> f64 {
        self.inner.g(t, z)
    }
    fn direction(&self) -> Direction {
        self.inner.direction()
    }
    fn action(&self) -> Action {
        self.inner.action()
    }
    fn fires_at_start(&self) -> bool {
        self.inner.fires_at_start()
    }
    fn rate(&self, t: f64, z: &[f64]) -> Option<f64> {
        self.inner.rate(t, z)
    }
    fn update(&self, t: f64, y: &mut [f64]) {
        self.seen.borrow_mut().push((self.index, t, y[0], y[1]));
        self.inner.update(t, y);
    }
}

/// Runs `model` to its end with `method` (model units), with or without the branch events;
/// the end state and the recorded switches (event index, t, R, Ṙ).
fn integrate(model: &Model, method: Method, t_end: f64, sample: f64, branches: bool) -> (Vec<f64>, Vec<(usize, f64, f64, f64)>) {
    let sys = model.system();
    let y0 = model.initial_state();
    let mut st = stepper(sys, &method, 0.0, y0, t_end).unwrap();
    let seen = RefCell::new(Vec::new());
    let evs = if branches { model.events() } else { model.events_without_branches() };
    let spies: Vec<Spy> = evs.iter().enumerate().map(|(index, e)| Spy { inner: &**e, index, seen: &seen }).collect();
    let refs: Vec<&dyn Event> = spies.iter().map(|s| s as &dyn Event).collect();
    if branches {
        model.start_branches(0.0, y0);
    }
    let schedule = Schedule { events: &refs, ..Schedule::new(t_end, Output::Every(sample), 10_000_000) };
    let fin = run(&mut *st, sys, schedule, &mut |_, _| Control::Continue).unwrap();
    assert!(fin.t == t_end, "the run stopped at {} of {t_end}", fin.t);
    if branches {
        model.finish_branches(t_end);
    }
    let y = st.y().to_vec();
    drop(spies);
    (y, seen.into_inner())
}

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max)
}

#[test]
fn each_switch_is_located_at_the_branch_radius_to_the_last_float() {
    let s = scene(1.0, 4, &[]);
    let model = Model::from_scene(&s).unwrap();
    let t_end = s.run.duration / model.time_scale();
    let (_, seen) = integrate(&model, Method::Dop853 { rtol: 1e-10, atol: 1e-14 }, t_end, 0.01 * t_end, true);
    let law = magbubble::model::effects::lipid::LipidLaw::from_scene(&s.shell.law, model.scales()).unwrap();
    let (rb, rr) = law.radii();
    let (mut nb, mut nr) = (0, 0);
    for &(index, t, r, rd) in &seen {
        let x = match index {
            1 => rb,
            2 => rr,
            _ => panic!("a Restart from event {index}"),
        };
        if index == 1 { nb += 1 } else { nr += 1 }
        // located to the last float: |R − R_x| ≤ |Ṙ| times one ulp of t, plus R's rounding
        let bound = rd.abs() * 2.0 * (t.next_up() - t) + 4.0 * f64::EPSILON;
        assert!((r - x).abs() <= bound, "event {index} at t = {t}: R = {r}, R_x = {x}, |ΔR| = {:e} > {bound:e}", (r - x).abs());
    }
    println!("{nb} buckling-radius and {nr} rupture-radius switches located");
    assert!(nb >= 4 && nr >= 4, "the run should buckle and rupture every cycle: {nb} {nr}");
}

#[test]
fn fixed_step_rk4_converges_at_order_4_across_the_switches_only_with_the_events() {
    // end state at t = 3 periods by RK4 with 3·n steps per period against Dop853 at rtol 1e-13
    // with the events; with them the error falls as h⁴, without them (the law re-decided from R
    // in every stage, steps straddling the kinks) the shape modes' stiffness jumps inside a step
    let s = scene(1.0, 4, &[]);
    let model = Model::from_scene(&s).unwrap();
    let t_end = s.run.duration / model.time_scale();
    let (reference, _) = integrate(&model, Method::Dop853 { rtol: 1e-13, atol: 1e-16 }, t_end, t_end / 8.0, true);
    let order = |branches: bool| {
        let errs: Vec<f64> = [200.0, 400.0, 800.0]
            .iter()
            .map(|&n| max_diff(&integrate(&model, Method::Rk4 { dt: t_end / n }, t_end, t_end / 8.0, branches).0, &reference))
            .collect();
        let p = [(errs[0] / errs[1]).log2(), (errs[1] / errs[2]).log2()];
        println!("events {branches}: errors {errs:?}, orders {p:.2?}");
        (errs, p)
    };
    let (on, p_on) = order(true);
    let (off, p_off) = order(false);
    assert!(p_on.iter().all(|&p| p > 3.6), "with the events: orders {p_on:?} ({on:?})");
    assert!(p_off[1] < 2.5, "without the events the order should collapse: {p_off:?} ({off:?})");
    assert!(on[2] < off[2] / 10.0, "{on:?} vs {off:?}");
}

#[test]
fn the_end_state_does_not_depend_on_the_sample_interval() {
    let s = scene(1.0, 4, &[]);
    let model = Model::from_scene(&s).unwrap();
    let t_end = s.run.duration / model.time_scale();
    let m = Method::Dopri5 { rtol: 1e-10, atol: 1e-14 };
    let (a, sa) = integrate(&model, m, t_end, t_end / 100.0, true);
    let (b, sb) = integrate(&model, m, t_end, t_end / 37.0, true);
    assert_eq!(sa.len(), sb.len());
    let d = max_diff(&a, &b);
    println!("end states at two sample intervals differ by {d:e} ({} switches)", sa.len());
    // the switches located to the last float: the same trajectory, bit for bit
    assert_eq!(sa.iter().map(|s| s.1).collect::<Vec<_>>(), sb.iter().map(|s| s.1).collect::<Vec<_>>(), "switch times");
    assert_eq!(d, 0.0, "{d:e}");
}

#[test]
fn the_summary_reports_the_fraction_of_time_on_each_branch() {
    let s = scene(1.0, 4, &["run.sample_interval=1e-9"]);
    let mut rows = Vec::new();
    let rep = magbubble::model::simulate(&s, &mut |t, row| rows.push((t, row[0]))).unwrap();
    assert!(matches!(rep.status, RunStatus::Completed), "{:?}", rep.status);
    let f = rep.shell_branches.expect("a kinked Marmottant run reports its branches");
    assert!((f.buckled + f.elastic + f.ruptured - 1.0).abs() < 1e-12, "{f:?}");
    // against the output rows classified by R (1 ns samples: the fractions to ~2e-4)
    let sc = magbubble::model::Scales::from_scene(&s);
    let law = magbubble::model::effects::lipid::LipidLaw::from_scene(&s.shell.law, &sc).unwrap();
    let (rb, rr) = law.radii();
    let mut spent = [0.0; 3];
    for w in rows.windows(2) {
        let r = 0.5 * (w[0].1 + w[1].1) / sc.length;
        spent[if r < rb { 0 } else if r > rr { 2 } else { 1 }] += w[1].0 - w[0].0;
    }
    let total: f64 = spent.iter().sum();
    let got = [f.buckled, f.elastic, f.ruptured];
    println!("fractions {got:?}, from the rows {:?}, {} switches", spent.map(|x| x / total), f.switches);
    for i in 0..3 {
        assert!((got[i] - spent[i] / total).abs() < 2e-3, "branch {i}: {} vs {}", got[i], spent[i] / total);
        assert!(got[i] > 0.05, "every branch is visited: {got:?}");
    }
    // a law without kinks reports none
    let s = magbubble::scene::load("scenes/no_field.toml", &["run.duration=1e-6"]).unwrap();
    assert!(magbubble::model::simulate(&s, &mut |_, _| {}).unwrap().shell_branches.is_none());
}

/// The radial Keller–Miksis Marmottant case of the APECSS comparison (benches/apecss.py: R0 =
/// 5 µm, χ = 0.5 N/m, σ(R0) = 0.02 N/m, 1 MHz, ε_p = 0.1, 50 periods): R reaches R_r by only a
/// little in some cycles, so both crossings of an excursion can fall inside one loose step.
const APECSS_MARMOTTANT: &str = r#"
[bubble]
radius = 5e-06
[shell]
law = "marmottant"
elasticity = 0.5
initial_tension = 0.02
rupture_tension = 0.072
dilatational_viscosity = 1e-09
[gas]
polytropic_exponent = 1.4
[liquid]
density = 1000.0
viscosity = 0.001
ambient_pressure = 101325.0
sound_speed = 1500.0
[drive]
amplitude = 0.1
frequency_hz = 1000000.0
[modes]
max_order = 0
[run]
duration = 5e-05
sample_interval = 5e-05
"#;

#[test]
fn no_pair_of_switches_is_stepped_over_at_a_loose_tolerance() {
    // Before the events carried their rate (Ṙ), DOP853 at rtol 1e-5 saw 102 of the 106 switches
    // (two rupture excursions each inside one step, run on the elastic formula) and ended
    // 1.0e-6 R0 from the reference; every method and tolerance now sees all of them
    let s = magbubble::scene::load_str(APECSS_MARMOTTANT, "apecss_marmottant", &[] as &[&str]).unwrap();
    let model = Model::from_scene(&s).unwrap();
    let t_end = s.run.duration / model.time_scale();
    let (reference, tight) = integrate(&model, Method::Dop853 { rtol: 1e-12, atol: 1e-12 }, t_end, t_end, true);
    for m in [Method::Dop853 { rtol: 1e-5, atol: 1e-5 }, Method::Dop853 { rtol: 3.2e-7, atol: 3.2e-7 }, Method::Dopri5 { rtol: 1e-5, atol: 1e-5 }, Method::Radau5 { rtol: 1e-5, atol: 1e-5 }] {
        let (end, seen) = integrate(&model, m, t_end, t_end, true);
        let err = (end[0] - reference[0]).abs();
        println!("{m:?}: {} switches (reference {}), |ΔR(t_end)| = {err:.2e} R0", seen.len(), tight.len());
        assert_eq!(seen.len(), tight.len(), "{m:?}: switches");
        for (a, b) in seen.iter().zip(&tight) {
            assert_eq!(a.0, b.0, "{m:?}: the same switch in the same order");
            assert!((a.1 - b.1).abs() < 1e-3, "{m:?}: switch at {} against {}", a.1, b.1);
        }
        assert!(err < 1e-6, "{m:?}: {err:e}");
    }
}
