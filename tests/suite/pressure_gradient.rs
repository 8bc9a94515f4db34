//! The terms' pressure-only gradients (`Term::add_pressure_gradient`, issue 16: the exact 2 × 2
//! radial Jacobian of the periodic-orbit search) against central differences of the term's own
//! pressure and against the pressure row of their full `add_jacobian`, and the stability
//! search's radial Jacobian against central differences of its right-hand side (random states;
//! proptest, failures persist in tests/suite/proptest-regressions/pressure_gradient.txt).

use magbubble::analysis::stability::Radial;
use magbubble::integrate::OdeSystem;
use magbubble::model::effects::{At, LoadJacobian, Loads};
use magbubble::model::Model;
use magbubble::scene::{load, Scene};
use proptest::prelude::*;
use proptest::test_runner::FileFailurePersistence;

/// Every shipped field, both membrane forms, every optional shell and gas term, Keller–Miksis
/// with and without a field, the quadratic coupling (modes up to k = 16).
fn scenes() -> Vec<Scene> {
    let with = |s: &str, over: &[&str]| {
        let mut o = vec!["modes.max_order=16"];
        o.extend_from_slice(over);
        load(format!("scenes/{s}.toml"), &o).expect("shipped scene")
    };
    vec![
        with("no_field", &[]),
        with("coil_static", &[]),
        with("coil_ac_current", &[]),
        with("coil_oscillating_distance", &[]),
        with("dipole", &[]),
        with("coil_h4", &[]),
        with("coil_static", &["shell.form=\"tension\"", "shell.surface_tension=0.03", "shell.bending_modulus=1e-18"]),
        with("no_field", &["shell.shear_viscosity=1e-9", "shell.dilatational_viscosity=2e-9", "gas.vapour_pressure=2300"]),
        with("keller_miksis", &[]),
        with("coil_static", &["liquid.sound_speed=1500"]),
        with("free_bubble", &["shell.surface_tension=0.072", "modes.coupling=\"quadratic\""]),
    ]
}

/// Number of scenes of [`scenes`] (the proptest ranges need a constant).
const SCENES: usize = 11;

fn config(cases: u32) -> ProptestConfig {
    ProptestConfig {
        cases,
        failure_persistence: Some(Box::new(FileFailurePersistence::Direct(
            "tests/suite/proptest-regressions/pressure_gradient.txt",
        ))),
        ..ProptestConfig::default()
    }
}

/// A random state near the sphere with shape amplitudes ~ 1e-2 (M = 8 modes).
fn state() -> impl Strategy<Value = (f64, Vec<f64>)> {
    (0.0..30.0f64, 0.6..1.6f64, -0.5..0.5f64, prop::collection::vec(-1e-2..1e-2f64, 3 * 8)).prop_map(|(t, r, rd, x)| {
        let mut y = vec![r, rd];
        y.extend(x);
        (t, y)
    })
}

/// The proptests draw from `0..SCENES`: every scene of the list is drawn, and no index is past it.
#[test]
fn the_proptests_draw_every_scene() {
    assert_eq!(scenes().len(), SCENES);
}

/// ∂P/∂(R, Ṙ) of every term against central differences of the term's own pressure
/// (`Term::add` with no shape loads), Richardson-extrapolated (error O(h⁴)): an independent check
/// of the gradient the two proptests below compare with the Jacobian's row. Deterministic states
/// (a generic one per scene; the proptests vary them).
#[test]
fn pressure_gradient_matches_differences_of_the_pressure() {
    let mut checked = 0;
    for (which, scene) in scenes().iter().enumerate() {
        let model = Model::from_scene(scene).unwrap();
        let eq = model.boundary_layer().unwrap().equations();
        let n = model.system().dim();
        let z: Vec<f64> = (0..n).map(|i| match i {
            0 => 1.13,
            1 => -0.27,
            i => 4e-3 * (0.9 * i as f64 + 0.3).sin(),
        }).collect();
        let t = 0.61;
        for term in eq.terms() {
            let pressure = |j: usize, h: f64| {
                let mut zh = z.clone();
                zh[j] += h;
                let mut loads = Loads { pressure: 0.0, gn: &mut [], gt: &mut [] };
                term.add(&At { t, z: &zh }, &mut loads);
                loads.pressure
            };
            let mut dp = [0.0; 2];
            term.add_pressure_gradient(&At { t, z: &z }, &mut dp);
            for j in 0..2 {
                let h = 1e-4 * z[j].abs().max(1e-2);
                let d = |h: f64| (pressure(j, h) - pressure(j, -h)) / (2.0 * h);
                let fd = (4.0 * d(h / 2.0) - d(h)) / 3.0;
                let scale = dp[j].abs() + pressure(j, 0.0).abs() / z[j].abs().max(1e-2) + 1e-300;
                assert!(
                    (dp[j] - fd).abs() <= 1e-8 * scale,
                    "scene {which}, term {}: ∂P/∂z_{j} = {:e}, central differences {fd:e}", term.name(), dp[j]
                );
                checked += usize::from(dp[j] != 0.0);
            }
        }
    }
    assert!(checked >= 2 * SCENES, "non-zero gradients checked: {checked}");
}

proptest! {
    #![proptest_config(config(32))]

    /// Per term: ∂P/∂(R, Ṙ) equals the first two entries of the term's full pressure gradient.
    #[test]
    fn pressure_gradient_is_the_jacobians_pressure_row(which in 0usize..SCENES, (t, z) in state()) {
        let model = Model::from_scene(&scenes()[which]).unwrap();
        let eq = model.boundary_layer().unwrap().equations();
        let at = At { t, z: &z };
        for term in eq.terms() {
            let mut full = LoadJacobian::new(8);
            term.add_jacobian(&at, &mut full);
            let mut dp = [0.0; 2];
            term.add_pressure_gradient(&at, &mut dp);
            for j in 0..2 {
                let tol = 1e-13 * full.pressure[j].abs().max(1e-300);
                prop_assert!(
                    (dp[j] - full.pressure[j]).abs() <= tol,
                    "scene {which}, term {}: ∂P/∂z_{j} = {} vs add_jacobian {}", term.name(), dp[j], full.pressure[j]
                );
            }
        }
    }

    /// Per term: the one-call pressure and gradient (`Term::add_pressure_and_gradient`, the orbit
    /// search's Jacobian) is `add` with no shape loads plus `add_pressure_gradient`, to the bit,
    /// at a general state and at the radial one (a_k = b_k = 0).
    #[test]
    fn pressure_and_gradient_in_one_call_is_the_two_calls(which in 0usize..SCENES, (t, z) in state(), radial in any::<bool>()) {
        let model = Model::from_scene(&scenes()[which]).unwrap();
        let eq = model.boundary_layer().unwrap().equations();
        let mut z = z;
        if radial {
            z[magbubble::model::layout::StateLayout::RADIAL..].fill(0.0);
        }
        let at = At { t, z: &z };
        for term in eq.terms() {
            let (p0, dp0) = (0.37, [0.11, -0.23]);
            let mut loads = Loads { pressure: p0, gn: &mut [], gt: &mut [] };
            term.add(&at, &mut loads);
            let mut dp_two = dp0;
            term.add_pressure_gradient(&at, &mut dp_two);
            let (mut p_one, mut dp_one) = (p0, dp0);
            term.add_pressure_and_gradient(&at, &mut p_one, &mut dp_one);
            prop_assert_eq!(p_one.to_bits(), loads.pressure.to_bits(), "scene {}, term {}: P", which, term.name());
            for j in 0..2 {
                prop_assert_eq!(dp_one[j].to_bits(), dp_two[j].to_bits(), "scene {}, term {}: ∂P/∂z_{}", which, term.name(), j);
            }
        }
    }

    /// The orbit search's radial system (a_k = b_k = 0): the exact Jacobian against central
    /// differences of its rhs (step 1e-6 max(1e-2, |y_j|)).
    #[test]
    fn radial_jacobian_matches_differences(which in 0usize..SCENES, t in 0.0..30.0f64, r in 0.6..1.6f64, rd in -0.5..0.5f64) {
        let model = Model::from_scene(&scenes()[which]).unwrap();
        let sys = Radial::of(&model).unwrap();
        let y = [r, rd];
        let mut an = [0.0; 4];
        prop_assert!(sys.jacobian(t, &y, &mut an));
        let (mut fp, mut fm) = ([0.0; 2], [0.0; 2]);
        for j in 0..2 {
            let h = 1e-6 * y[j].abs().max(1e-2);
            let (mut yp, mut ym) = (y, y);
            yp[j] += h;
            ym[j] -= h;
            sys.rhs(t, &yp, &mut fp);
            sys.rhs(t, &ym, &mut fm);
            for i in 0..2 {
                let fd = (fp[i] - fm[i]) / (2.0 * h);
                let scale = (0..2).map(|c| (an[i * 2 + c] * y[c].abs().max(1e-2)).abs()).fold(0.0, f64::max);
                prop_assert!(
                    (an[i * 2 + j] - fd).abs() * y[j].abs().max(1e-2) <= 1e-6 * scale + 1e-9,
                    "scene {which}: J[{i}][{j}] exact {} vs fd {fd}", an[i * 2 + j]
                );
            }
        }
    }
}
