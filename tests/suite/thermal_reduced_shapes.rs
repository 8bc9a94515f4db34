//! `gas.thermal = "reduced"` with shape modes (issue 31 part 2 in the shape-mode model;
//! docs/model.md, "Reduced thermal model"; runtime/model/boundary_layer.rs, linearize.rs): the
//! boundary-layer system carries the gas slot p_b after the mode blocks, p_b enters R̈ through P
//! and the mode rows through R̈. Checked here: the exact Jacobian (its p_b column and row
//! included) and the Jacobian product against central differences of the rhs, with
//! Rayleigh–Plesset and Keller–Miksis, with a field and with ḃ loads; the shape-mode run's
//! adiabatic (D → 0) and isothermal (D → ∞) limits against the polytropic runs (R and every a_k);
//! the combinations refused with the reason.

use magbubble::model::{simulate, Model, RunStatus};
use magbubble::scene::{load, Scene};

const R0: f64 = 10e-6;

/// scenes/coil_static.toml (coil field, k ≤ 16 cut to `max_order`) with `extra` overrides.
fn coil(max_order: usize, extra: &[&str]) -> Scene {
    let mut o = vec![format!("modes.max_order={max_order}")];
    o.extend(extra.iter().map(|s| s.to_string()));
    load("scenes/coil_static.toml", &o).expect("scene")
}

/// The (t, y) the Jacobian is checked at: the initial state moved off rest in every slot (R, Ṙ
/// and p_b by O(0.1), the shape amplitudes by O(1e-3)).
fn states(model: &Model) -> Vec<(f64, Vec<f64>)> {
    let y0 = model.initial_state();
    let n = y0.len();
    let off = |s: f64| -> Vec<f64> {
        (0..n).map(|i| y0[i] + s * (1.0 + 0.1 * i as f64) * if i < 2 || i == n - 1 { 0.5 } else { 1e-2 }).collect()
    };
    vec![(0.0, off(0.13)), (0.37, off(-0.21))]
}

#[test]
fn the_jacobian_with_the_gas_slot_matches_differences() {
    let cases: [&[&str]; 4] = [
        &[],
        // Keller–Miksis with a field: R̈ needs the closure's ḃ_k
        &["liquid.sound_speed=1500.0"],
        // ḃ loads (the shell's dilatational viscosity): ḃ solved implicitly in every mode row
        &["shell.dilatational_viscosity=1e-9"],
        &["liquid.sound_speed=1500.0", "shell.dilatational_viscosity=1e-9"],
    ];
    for extra in cases {
        let mut o = vec!["gas.thermal=\"reduced\""];
        o.extend_from_slice(extra);
        let model = Model::from_scene(&coil(6, &o)).unwrap();
        let sys = model.system();
        let n = sys.dim();
        assert_eq!(n, 2 + 3 * 3 + 1, "{extra:?}: R, Ṙ, three mode blocks and p_b");
        for (t, y) in states(&model) {
            let y = &y[..];
            let mut jac = vec![0.0; n * n];
            assert!(sys.jacobian(t, y, &mut jac));
            let mut worst: f64 = 0.0;
            for j in 0..n {
                let h = 1e-6 * y[j].abs().max(1.0);
                let (mut p, mut m) = (y.to_vec(), y.to_vec());
                p[j] += h;
                m[j] -= h;
                let (mut fp, mut fm) = (vec![0.0; n], vec![0.0; n]);
                sys.rhs(t, &p, &mut fp);
                sys.rhs(t, &m, &mut fm);
                for i in 0..n {
                    let fd = (fp[i] - fm[i]) / (p[j] - m[j]);
                    let scale = 1.0 + fd.abs().max(jac[i * n + j].abs());
                    let e = (fd - jac[i * n + j]).abs() / scale;
                    worst = worst.max(e);
                    assert!(e < 1e-6, "{extra:?}: J[{i}][{j}] = {} vs differences {fd}", jac[i * n + j]);
                }
            }
            // the p_b column is not empty: R̈ and every ä see p_b
            assert!(jac[n + n - 1] != 0.0 && jac[3 * n + n - 1] != 0.0, "{extra:?}");
            // J·S without the dense J equals the dense product
            let s: Vec<f64> = (0..2 * n).map(|i| ((i * 7 + 3) % 11) as f64 / 11.0 - 0.4).collect();
            let mut prod = vec![0.0; 2 * n];
            assert!(sys.jacobian_product(t, y, &s, &mut prod));
            for (b, (sb, pb)) in s.chunks(n).zip(prod.chunks(n)).enumerate() {
                for i in 0..n {
                    let dense: f64 = (0..n).map(|j| jac[i * n + j] * sb[j]).sum();
                    assert!((dense - pb[i]).abs() <= 1e-12 * (1.0 + dense.abs()), "{extra:?} direction {b} row {i}: {} vs {dense}", pb[i]);
                }
            }
            println!("{extra:?}: worst relative difference {worst:e}");
        }
    }
}

/// (R, a_2, a_4 …) rows of a run.
fn rows(s: &Scene) -> Vec<Vec<f64>> {
    let mut out = vec![];
    let rep = simulate(s, &mut |_, row| out.push(row.to_vec())).unwrap();
    assert!(matches!(rep.status, RunStatus::Completed), "{:?}", rep.status);
    out
}

/// D → 0 is the adiabatic polytropic gas (κ = γ), D → ∞ the isothermal one (κ = 1): with shape
/// modes and the coil's forcing, R(t) and every a_k(t), b_k(t) of the reduced runs converge to
/// the polytropic runs' (the p_b column dropped).
#[test]
fn the_shape_run_tends_to_the_polytropic_runs_in_both_limits() {
    let common = ["run.duration=3e-6", "run.sample_interval=2e-8", "run.integrator={ method = \"radau5\", rtol = 1e-10, atol = 1e-13 }"];
    // per column (R, a_k, b_k), the largest difference over the largest magnitude of the
    // polytropic run's column: each amplitude measured against its own size
    let diff = |a: &[Vec<f64>], b: &[Vec<f64>]| {
        (0..b[0].len())
            .map(|c| {
                let size = b.iter().map(|r| r[c].abs()).fold(0.0, f64::max);
                a.iter().zip(b).map(|(x, y)| (x[c] - y[c]).abs()).fold(0.0, f64::max) / size
            })
            .fold(0.0, f64::max)
    };
    for (kappa, ds) in [(1.4, ["1e-12", "1e-14", "1e-16"]), (1.0, ["1e0", "1e2", "1e4"])] {
        let mut o: Vec<String> = common.iter().map(|s| s.to_string()).collect();
        o.push(format!("gas.polytropic_exponent={kappa}"));
        let poly = rows(&coil(4, &o.iter().map(String::as_str).collect::<Vec<_>>()));
        let a2 = poly.iter().map(|r| r[1].abs()).fold(0.0, f64::max);
        assert!(a2 > 1e-4 * R0, "the coil forces a_2 (max {a2:e} m)");
        let mut errs = vec![];
        for d in ds {
            let mut o: Vec<String> = common.iter().map(|s| s.to_string()).collect();
            o.extend(["gas.thermal=\"reduced\"".to_string(), format!("gas.thermal_diffusivity={d}")]);
            let red = rows(&coil(4, &o.iter().map(String::as_str).collect::<Vec<_>>()));
            let cut: Vec<Vec<f64>> = red.iter().map(|r| r[..r.len() - 1].to_vec()).collect();
            assert_eq!(cut[0].len(), poly[0].len());
            errs.push(diff(&cut, &poly));
        }
        println!("kappa = {kappa}: D = {ds:?}: max over R, a_k, b_k of |x - x_polytropic|/max|x_polytropic| = {errs:?}");
        assert!(errs[0] > errs[1] && errs[1] > errs[2], "{errs:?}");
        assert!(errs[2] < 1e-5, "kappa = {kappa}: {errs:?}");
    }
}

#[test]
fn the_combinations_without_the_gas_slot_are_refused_with_the_reason() {
    let base = ["gas.thermal=\"reduced\""];
    let e = load("scenes/coil_static.toml", &[base[0], "modes.coupling=\"quadratic\""]).unwrap_err().to_string();
    assert!(e.contains("modes.coupling") && e.contains("reduced") && e.contains("p_b"), "{e}");
    let e = load("scenes/coil_static.toml", &[base[0], "modes.viscous=\"vorticity\""]).unwrap_err().to_string();
    assert!(e.contains("modes.viscous") && e.contains("gas slot"), "{e}");
    // the full model built from a boundary-layer scene (accuracy studies, comparisons)
    let s = coil(4, &base);
    let e = magbubble::model::vorticity::scene::FullModel::from_scene(&s).err().expect("refused").to_string();
    assert!(e.contains("gas.thermal") && e.contains("vorticity"), "{e}");
    // Floquet and the frequencies linearise without p_b: refused, naming gas.thermal
    let e = magbubble::analysis::stability::base_model(&s).unwrap_err().to_string();
    assert!(e.contains("gas.thermal") && e.contains("Floquet"), "{e}");
    let e = magbubble::analysis::frequencies::natural_frequencies(&s, 4).unwrap_err().to_string();
    assert!(e.contains("gas.thermal") && e.contains("reduced"), "{e}");
}
