//! `modes.coupling = "quadratic"` with the vorticity closure (issue 12: the viscous part keeps
//! either linear closure; model/vorticity/equations.rs `coupled_mode_rates`): the reduced
//! Jacobian of the monolithic system — ä⁽¹⁾ inside the quadratic loads depends on the vorticity
//! functionals, so R̈ and G_n do too — against central differences; the structured solve of
//! σI − J against a dense one; and `compare` on small-amplitude quadratic scenes: the two
//! closures agree as closely as on the linear scene, and quadratic − linear under the vorticity
//! closure scales as ε² (halving ε divides it by 4), for both time schemes.

use magbubble::model::layout::StateLayout;
use magbubble::analysis::compare::run_both;
use magbubble::integrate::OdeSystem;
use magbubble::model::vorticity::equations::reduced_jacobian;
use magbubble::model::vorticity::monolithic::Monolithic;
use magbubble::model::vorticity::scene::FullModel;
use magbubble::model::vorticity::structured::StructuredJacobian;
use magbubble::model::{simulate, RunStatus};
use magbubble::scene::{load, Scene};
use nalgebra::DMatrix;

/// `file` with quadratic coupling and the vorticity closure on a small grid, k ≤ 6, plus `extra`.
fn quadratic_scene(file: &str, extra: &[&str]) -> Scene {
    let mut o = vec!["modes.coupling=\"quadratic\"", "modes.viscous=\"vorticity\"", "modes.max_order=6", "vorticity.points=24"];
    o.extend_from_slice(extra);
    load(file, &o).expect("scene")
}

/// A generic state of the monolithic system: R ≠ R0, Ṙ ≠ 0, every amplitude and T node ≠ 0.
fn generic_state(n: usize) -> Vec<f64> {
    (0..n).map(|i| if i == 0 { 1.07 } else if i == 1 { -0.21 } else { 3e-2 * ((i as f64) * 0.7 + 0.3).sin() }).collect()
}

/// max |exact − central difference| / (1 + |exact|) over the entries of ∂(f_z, T_w)/∂(z, p),
/// and max_q |∂R̈/∂p_q| (zero for linear coupling: R̈ sees the vorticity only through ä⁽¹⁾ in Q_0).
fn reduced_jacobian_error(scene: &Scene) -> (f64, f64) {
    let fm = FullModel::from_scene(scene).expect("quadratic vorticity model");
    let c = fm.coupling();
    let sys = Monolithic::new(&c, fm.grid.clone());
    let m = fm.base().orders().len();
    let (nz, np) = (StateLayout::reduced(m).dim(), 2 * m);
    let y = generic_state(sys.dim());
    let (mut z, mut p) = (vec![0.0; nz], vec![0.0; np]);
    sys.split(&y, &mut z, &mut p);
    let w0 = sys.operators()[0].w0();
    let t = 0.37;
    let (mut gz, mut gp) = (DMatrix::zeros(nz + m, nz), DMatrix::zeros(nz + m, np));
    reduced_jacobian(&c, t, &z, &p, w0, &mut gz, &mut gp);
    // f_z and T_w stacked, at (z, p)
    let eval = |z: &[f64], p: &[f64]| {
        let (mut fz, mut tw) = (vec![0.0; nz], vec![0.0; m]);
        sys.reduced(t, z, p, &mut fz, &mut tw);
        fz.extend(tw);
        fz
    };
    let mut worst: f64 = 0.0;
    for (cols, is_p) in [(nz, false), (np, true)] {
        for j in 0..cols {
            let h = 1e-5 * (if is_p { p[j] } else { z[j] }).abs().max(1e-2);
            let (mut zp, mut zm, mut pp, mut pm) = (z.clone(), z.clone(), p.clone(), p.clone());
            if is_p {
                pp[j] += h;
                pm[j] -= h;
            } else {
                zp[j] += h;
                zm[j] -= h;
            }
            let (fp, fm_) = (eval(&zp, &pp), eval(&zm, &pm));
            for i in 0..nz + m {
                let fd = (fp[i] - fm_[i]) / (2.0 * h);
                let ex = if is_p { gp[(i, j)] } else { gz[(i, j)] };
                worst = worst.max((ex - fd).abs() / (1.0 + ex.abs()));
            }
        }
    }
    (worst, (0..np).map(|q| gp[(1, q)].abs()).fold(0.0, f64::max))
}

#[test]
fn reduced_jacobian_with_quadratic_coupling_matches_central_differences() {
    let cases: [(&str, &[&str]); 3] = [
        ("scenes/free_bubble.toml", &["shell.surface_tension=0.072"]),
        ("scenes/no_field.toml", &[]),
        ("scenes/coil_static.toml", &[]),
    ];
    for (file, extra) in cases {
        let s = quadratic_scene(file, extra);
        let (err, dr_dp) = reduced_jacobian_error(&s);
        let mut lin = s.clone();
        lin.modes.coupling = magbubble::scene::Coupling::Linear;
        let (err_lin, dr_dp_lin) = reduced_jacobian_error(&lin);
        eprintln!("{file}: max relative difference {err:.2e} (linear coupling {err_lin:.2e}); max |∂R̈/∂p| {dr_dp:.2e} (linear {dr_dp_lin:.1e})");
        // central differences with h = 1e-5 |x|: truncation and rounding ~1e-7 (the linear
        // scene's level); the p columns of R̈'s row, absent in the linear model, are checked too
        assert!(err < 1e-6, "{file}: exact reduced Jacobian and central differences differ by {err:.2e}");
        assert_eq!(dr_dp_lin, 0.0);
        assert!(dr_dp > 1e3 * err, "{file}: ∂R̈/∂p = {dr_dp:.2e} is not resolved by the check");
    }
}

#[test]
fn structured_solve_matches_dense_solve_with_quadratic_coupling() {
    let s = quadratic_scene("scenes/no_field.toml", &[]);
    let fm = FullModel::from_scene(&s).unwrap();
    let c = fm.coupling();
    let sys = Monolithic::new(&c, fm.grid.clone());
    let n = sys.dim();
    let y = generic_state(n);
    // the dense J by central differences (truncation and rounding ~1e-8 here)
    let mut jd = DMatrix::zeros(n, n);
    let (mut fp, mut fm_) = (vec![0.0; n], vec![0.0; n]);
    for j in 0..n {
        let h = 1e-5 * y[j].abs().max(1e-2);
        let (mut yp, mut ym) = (y.clone(), y.clone());
        yp[j] += h;
        ym[j] -= h;
        sys.rhs(0.1, &yp, &mut fp);
        sys.rhs(0.1, &ym, &mut fm_);
        for i in 0..n {
            jd[(i, j)] = (fp[i] - fm_[i]) / (2.0 * h);
        }
    }
    let js = StructuredJacobian::new(&sys, 0.1, &y);
    let b: Vec<f64> = (0..n).map(|i| ((i * 7 % 11) as f64) - 5.0).collect();
    let sigma = 40.0;
    let mut x = b.clone();
    js.factor(sigma).expect("non-singular").solve(&mut x);
    let mut dense = -jd;
    for i in 0..n {
        dense[(i, i)] += sigma;
    }
    let xd = dense.lu().solve(&nalgebra::DVector::from_column_slice(&b)).unwrap();
    let err = x.iter().zip(xd.iter()).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    eprintln!("structured vs dense (central-difference J): {err:.2e} (scale {:.2e})", xd.amax());
    assert!(err < 1e-7 * xd.amax(), "structured and dense solves differ by {err}");
}

/// The undriven free bubble of `quadratic_runtime` (R0 = 5 µm, γ = 0.072 N/m) in water
/// (η = 10⁻³ Pa s: the closures differ), a_2(0) = ε R0, k ≤ 4, 4 µs, the vorticity closure with
/// `scheme` (`compare` runs both closures).
fn free(eps: f64, coupling: &str, scheme: &str) -> Scene {
    let a2 = format!("bubble.initial.a={{2 = {:e}}}", eps * R0);
    let c = format!("modes.coupling=\"{coupling}\"");
    let v = format!("vorticity.scheme=\"{scheme}\"");
    load(
        "scenes/free_bubble.toml",
        &[
            "shell.surface_tension=0.072",
            "drive.amplitude=0.0",
            "modes.max_order=4",
            "liquid.viscosity=1e-3",
            "modes.viscous=\"vorticity\"",
            "run.duration=4e-6",
            "run.sample_interval=2e-8",
            "run.integrator.rtol=1e-10",
            "run.integrator.atol=1e-15",
            "run.integrator.dt=2.5e-10",
            &a2,
            &c,
            &v,
        ],
    )
    .expect("scene")
}

const R0: f64 = 5e-6;
const COLUMNS: [(usize, &str); 4] = [(0, "R"), (1, "a2"), (2, "b2"), (3, "a4")];

/// max over the samples of |x − y| per column, in units of R0.
fn max_diff(x: &[Vec<f64>], y: &[Vec<f64>]) -> Vec<f64> {
    assert_eq!(x.len(), y.len());
    (0..x[0].len()).map(|c| x.iter().zip(y).map(|(u, v)| (u[c] - v[c]).abs()).fold(0.0, f64::max) / R0).collect()
}

#[test]
fn compare_accepts_quadratic_scenes_and_the_closures_agree_as_in_the_linear_model() {
    let runs = |eps: f64, coupling: &str| run_both(&free(eps, coupling, "monolithic")).expect("compare runs");
    let (l1, q1, l2, q2) = (runs(2e-3, "linear"), runs(2e-3, "quadratic"), runs(1e-3, "linear"), runs(1e-3, "quadratic"));
    for r in [&l1, &q1, &l2, &q2] {
        assert!(r.report_bl.status == RunStatus::Completed && r.report_full.status == RunStatus::Completed);
        assert_eq!(r.t.len(), 201);
    }
    assert!(q1.report_full.active_effects.iter().any(|e| e.contains("quadratic")), "{:?}", q1.report_full.active_effects);
    // boundary layer vs vorticity: the same relative difference of the linearly excited columns
    // as in the linear model (the quadratic terms change them by O(ε) relatively)
    for c in [1, 2] {
        let (dl, dq) = (&l1.diffs[c], &q1.diffs[c]);
        eprintln!("{}: closures differ by {:.4e} (linear), {:.4e} (quadratic) of max|x|", dl.name, dl.max_rel_diff, dq.max_rel_diff);
        assert!(dl.max_rel_diff > 1e-2, "{}: the closures should differ", dl.name);
        assert!((dq.max_rel_diff / dl.max_rel_diff - 1.0).abs() < 0.02, "{}: quadratic {} vs linear {}", dl.name, dq.max_rel_diff, dl.max_rel_diff);
    }
    // quadratic − linear, per closure, at ε and ε/2: O(ε²) under both, and of the same size
    let (bl1, bl2) = (max_diff(&q1.bl, &l1.bl), max_diff(&q2.bl, &l2.bl));
    let (fu1, fu2) = (max_diff(&q1.full, &l1.full), max_diff(&q2.full, &l2.full));
    for (c, name) in COLUMNS {
        let (rb, rf) = (bl1[c] / bl2[c], fu1[c] / fu2[c]);
        eprintln!(
            "{name}: max|q − l|/R0 boundary layer {:.3e} → {:.3e} (ratio {rb:.4}), vorticity {:.3e} → {:.3e} (ratio {rf:.4}); vorticity/boundary layer {:.3}",
            bl1[c], bl2[c], fu1[c], fu2[c], fu1[c] / bl1[c]
        );
        assert!(fu2[c] > 0.0, "{name}: no quadratic effect under the vorticity closure");
        assert!((rf - 4.0).abs() < 0.2, "{name}: vorticity closure, halving ε divides quadratic − linear by {rf}, not 4");
    }
}

#[test]
fn staggered_scheme_quadratic_minus_linear_scales_as_eps_squared() {
    let full = |eps: f64, coupling: &str, dt: &str| {
        let mut v = Vec::new();
        let mut s = free(eps, coupling, "staggered");
        s.run.integrator.dt = dt.parse().unwrap();
        let rep = simulate(&s, &mut |_, row| v.push(row.to_vec())).expect("runs");
        assert_eq!(rep.status, RunStatus::Completed);
        v
    };
    let d1 = max_diff(&full(2e-3, "quadratic", "2.5e-10"), &full(2e-3, "linear", "2.5e-10"));
    let d2 = max_diff(&full(1e-3, "quadratic", "2.5e-10"), &full(1e-3, "linear", "2.5e-10"));
    // and the staggered runs against the monolithic ones (the scheme's own error, first order in Δt)
    let mono_q = run_both(&free(2e-3, "quadratic", "monolithic")).unwrap().full;
    let mono_l = run_both(&free(2e-3, "linear", "monolithic")).unwrap().full;
    let (eq1, eq2) = (max_diff(&full(2e-3, "quadratic", "2.5e-10"), &mono_q), max_diff(&full(2e-3, "quadratic", "1.25e-10"), &mono_q));
    let (el1, el2) = (max_diff(&full(2e-3, "linear", "2.5e-10"), &mono_l), max_diff(&full(2e-3, "linear", "1.25e-10"), &mono_l));
    for (c, name) in COLUMNS {
        let ratio = d1[c] / d2[c];
        eprintln!("{name}: staggered max|q − l|/R0 {:.3e} → {:.3e} (ratio {ratio:.4}); staggered − monolithic: quadratic {:.2e} → {:.2e} (dt/2), linear {:.2e} → {:.2e}", d1[c], d2[c], eq1[c], eq2[c], el1[c], el2[c]);
        assert!(d2[c] > 0.0, "{name}: no quadratic effect");
        assert!((ratio - 4.0).abs() < 0.2, "{name}: staggered, halving ε divides quadratic − linear by {ratio}, not 4");
        // first order in Δt, as the linear scheme (the lagged integrals, FORMULATION audit 12)
        assert!((eq1[c] / eq2[c] - 2.0).abs() < 0.2, "{name}: staggered − monolithic {} → {} on halving Δt", eq1[c], eq2[c]);
        // and no larger than the linear scheme's error plus a small part of the quadratic effect
        assert!(eq1[c] <= el1[c] + 0.1 * d1[c], "{name}: the scheme's error {} (linear {}, q − l {})", eq1[c], el1[c], d1[c]);
    }
}
