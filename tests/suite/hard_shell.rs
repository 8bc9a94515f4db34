//! Hard cases of the shell laws (issue 11, docs/hard-cases.md): scenes/hard/skalak_c1000.toml
//! (Skalak, C = 1e3: a stiff radial mode), bending_large.toml (k_b so large that the highest
//! retained mode is the stiffest), supplementary_eps15.toml (the 2 µm supplementary bubble with
//! its tabled shell viscosities at ε_p = 1.5: blows up in a_2) — each completed or classified,
//! never NaN or a crash, with the accuracy study run on each — and the three shipped
//! supplementary scenes, scenes/supplementary/r{1,2,3}um.toml, against docs/supplementary.md.

use magbubble::analysis::accuracy::{accuracy_study, AccuracyOptions};
use magbubble::analysis::frequencies::natural_frequencies;
use magbubble::model::{simulate, RunReport, RunStatus};
use magbubble::scene::{self, Scene};

fn load(path: &str, overrides: &[&str]) -> Scene {
    let path = format!("{}/scenes/{path}.toml", env!("CARGO_MANIFEST_DIR"));
    scene::load(&path, overrides).unwrap_or_else(|e| panic!("{path}: {e}"))
}

/// A run with every row finite; the report and (min R, max R) over the rows [m].
fn run(s: &Scene) -> (RunReport, (f64, f64)) {
    let mut span = (f64::MAX, 0.0f64);
    let report = simulate(s, &mut |t, row| {
        assert!(t.is_finite() && row.iter().all(|v| v.is_finite()), "non-finite row at t = {t}: {row:?}");
        span = (span.0.min(row[0]), span.1.max(row[0]));
    })
    .expect("model assembles");
    (report, span)
}

fn max_shape(report: &RunReport, r0: f64) -> f64 {
    report.max_abs.iter().filter(|(n, _)| n != "R").map(|(_, v)| v / r0).fold(0.0, f64::max)
}

/// Completed, bounded, and the explicit dopri5 needs more than `ratio` times radau5's steps for
/// the same final state (the stiffness is real, and both agree).
fn stiff_and_bounded(name: &str, ratio: u64) {
    let s = load(name, &[]);
    let r0 = s.bubble.radius;
    let (rep, (lo, hi)) = run(&s);
    assert_eq!(rep.status, RunStatus::Completed, "{name}");
    assert!(lo > 0.2 * r0 && hi < 3.0 * r0, "{name}: R in [{lo}, {hi}]");
    assert!(max_shape(&rep, r0) < 0.05, "{name}: shapes {}", max_shape(&rep, r0));
    let (exp, _) = run(&load(name, &["run.integrator.method=dopri5"]));
    assert_eq!(exp.status, RunStatus::Completed, "{name} dopri5");
    eprintln!("{name}: radau5 {} steps, dopri5 {} steps, R/R0 in [{:.4}, {:.4}]", rep.stats.steps, exp.stats.steps, lo / r0, hi / r0);
    assert!(exp.stats.steps > ratio * rep.stats.steps, "{name}: {} vs {}", exp.stats.steps, rep.stats.steps);
    for ((n, x), (_, y)) in rep.final_state.iter().zip(&exp.final_state) {
        let scale = rep.max_abs.iter().find(|(m, _)| m == n).map_or(0.0, |p| p.1);
        assert!((x - y).abs() <= 1e-4 * scale + 1e-18, "{name} {n}: radau5 {x} vs dopri5 {y}");
    }
}

#[test]
fn skalak_c1000_is_stiff_and_bounded() {
    let s = load("hard/skalak_c1000", &[]);
    let f = natural_frequencies(&s, 16).unwrap();
    // K = G_s(1 + 2C): ω0² = (3κp_g0 + 4K/R0)/(ρR0²) (tests/suite/shell_runtime.rs), here ≈ 133/t*
    let k: f64 = 0.44 * 2001.0;
    let w0 = ((3.0 * 1.4 * 101325.0 + 4.0 * k / 10e-6) / (1000.0 * 1e-10)).sqrt();
    assert!((f.radial.omega_rad_s / w0 - 1.0).abs() < 1e-6, "ω0 {} vs {w0}", f.radial.omega_rad_s);
    stiff_and_bounded("hard/skalak_c1000", 10);
}

#[test]
fn large_bending_makes_the_highest_mode_the_stiffest_and_stays_bounded() {
    let s = load("hard/bending_large", &[]);
    let f = natural_frequencies(&s, 16).unwrap();
    let top = f.shape.iter().max_by(|a, b| a.omega_rad_s.total_cmp(&b.omega_rad_s)).unwrap();
    assert_eq!(top.k, 16);
    assert!(top.omega_rad_s > 3.0 * f.radial.omega_rad_s, "ω_16 {} vs ω0 {}", top.omega_rad_s, f.radial.omega_rad_s);
    stiff_and_bounded("hard/bending_large", 5);
}

#[test]
fn supplementary_bubble_at_eps_1_5_blows_up_classified_and_its_accuracy_study_runs() {
    let s = load("hard/supplementary_eps15", &[]);
    let (rep, _) = run(&s);
    let (exp, _) = run(&load("hard/supplementary_eps15", &["run.integrator.method=dopri5"]));
    let t = match (&rep.status, &exp.status) {
        (RunStatus::BlowUp { t, mode }, RunStatus::BlowUp { t: t2, mode: m2 }) => {
            assert!(mode == "a2" && m2 == "a2", "{mode}, {m2}");
            assert!((t - t2).abs() < 1e-4 * t, "radau5 {t} vs dopri5 {t2}");
            *t
        }
        other => panic!("expected blow-up in a2 from both: {other:?}"),
    };
    eprintln!("supplementary_eps15: blow-up of a2 at {t:e} s (dopri5 agrees)");
    assert!(t > 5e-6 && t < 7e-6, "{t}");

    // the quick accuracy study over the first 5 µs (before the blow-up)
    let rep = accuracy_study(&s, &AccuracyOptions::quick()).unwrap();
    eprintln!("reference: {} (error {:e}), {} s compared", rep.reference, rep.reference_error, rep.duration);
    assert!(rep.reference_error < 1e-6, "reference error {}", rep.reference_error);
    for l in &rep.ladders {
        let e: Vec<f64> = l.rungs.iter().map(|r| r.error).collect();
        eprintln!("{}: errors {e:?}, order_dt {:?}, order_work {:?}", l.method, l.order_dt, l.order_work);
        for r in &l.rungs {
            assert_eq!(r.status, "completed", "{} at {}: {}", l.method, r.setting, r.status);
        }
        // tightening rtol must pay; dop853's sampled error is capped by its cubic Hermite dense
        // output (integrate/explicit.rs), so it only has to decrease
        if l.setting_name == "rtol" && l.method == "dop853" {
            assert!(e.windows(2).all(|w| w[1] < w[0]), "{}: {e:?}", l.method);
        } else if l.setting_name == "rtol" {
            assert!(e.last().unwrap() < &(1e-2 * e[0]), "{}: tightening rtol must pay: {e:?}", l.method);
        }
    }
    assert!(rep.modes.iter().all(|m| m.status == "completed"), "{:?}", rep.modes);
}

/// The three shipped supplementary scenes reproduce docs/supplementary.md's shaped-run table.
#[test]
fn supplementary_scenes_run_as_documented() {
    for (name, status, lo, hi) in [("r1um", None, 0.9160e-6, 1.2246e-6), ("r2um", Some(6.58e-6), 1.2055e-6, 3.8396e-6), ("r3um", None, 1.8540e-6, 5.7337e-6)] {
        let s = load(&format!("supplementary/{name}"), &[]);
        assert!(s.shell.shear_viscosity > 0.0 && s.shell.dilatational_viscosity > 0.0, "{name}: tabled viscosities");
        let (rep, (a, b)) = run(&s);
        match (status, &rep.status) {
            (None, RunStatus::Completed) => {}
            (Some(tb), RunStatus::BlowUp { t, mode }) => assert!(mode == "a2" && (t - tb).abs() < 0.01e-6, "{name}: {mode} at {t}"),
            (want, got) => panic!("{name}: {got:?}, expected blow-up at {want:?}"),
        }
        assert!((a - lo).abs() < 1e-4 * lo && (b - hi).abs() < 1e-4 * hi, "{name}: R in [{a}, {b}] vs [{lo}, {hi}]");
    }
}

/// The quick accuracy study on a stiff hard case: the RK4 reference is unstable at its step, so
/// the study takes Radau5 at rtol 1e-11 as the reference (and says so); the fixed-step RK4 rungs
/// end as classified blow-ups (never NaN in a row, never a crash); every adaptive rung completes,
/// tightening Radau5's rtol pays, and the explicit methods pay for the stiffness in rhs calls.
fn accuracy_on_a_stiff_case(name: &str) -> String {
    let s = load(name, &[]);
    let rep = accuracy_study(&s, &AccuracyOptions::quick()).unwrap_or_else(|e| panic!("{name}: {e}"));
    eprintln!("{name}: reference {} (error {:e})", rep.reference, rep.reference_error);
    assert!(rep.reference_error < 1e-9, "{name}: reference error {}", rep.reference_error);
    let radau = rep.ladders.iter().find(|l| l.method == "radau5").expect("radau5 ladder");
    let e: Vec<f64> = radau.rungs.iter().map(|r| r.error).collect();
    assert!(radau.rungs.iter().all(|r| r.status == "completed"), "{name}: {:?}", radau.rungs);
    assert!(e.last().unwrap() < &(1e-2 * e[0]), "{name}: radau5 errors {e:?}");
    for l in rep.ladders.iter().filter(|l| l.method != "rk4") {
        for r in &l.rungs {
            assert_eq!(r.status, "completed", "{name} {} at {}: {}", l.method, r.setting, r.status);
            assert!(r.error.is_finite(), "{name} {} at {}", l.method, r.setting);
        }
    }
    for l in rep.ladders.iter().filter(|l| l.method == "rk4") {
        for r in &l.rungs {
            assert!(r.status == "completed" || r.status.starts_with("blow_up"), "{name} rk4 at {}: {}", r.setting, r.status);
        }
    }
    if rep.reference.starts_with("Radau5") {
        let dopri = rep.ladders.iter().find(|l| l.method == "dopri5").expect("dopri5 ladder");
        let (explicit, implicit) = (dopri.rungs[0].stats.rhs_evals, radau.rungs[0].stats.rhs_evals);
        assert!(explicit > 10 * implicit, "{name}: dopri5 {explicit} vs radau5 {implicit} rhs calls");
    }
    rep.reference
}

#[test]
fn skalak_c1000_accuracy_study_takes_an_implicit_reference() {
    let reference = accuracy_on_a_stiff_case("hard/skalak_c1000");
    assert!(reference.starts_with("Radau5"), "{reference}");
}

#[test]
fn large_bending_accuracy_study_runs() {
    accuracy_on_a_stiff_case("hard/bending_large");
}
