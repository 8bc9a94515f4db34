//! The model's analytic linear structure (issue 16 part 2) against finite differences of its
//! right-hand side, on random states (proptest; failures persist in
//! tests/suite/proptest-regressions/equations_jacobian.txt, committed):
//! the boundary-layer Jacobian (every shipped field, both membrane forms, both δ_k branches),
//! the radial-only Jacobian, the linear mode system A(t), g(t) of Floquet, the sparsity pattern,
//! the vorticity closure's wall partials, the monolithic system's reduced Jacobian and the
//! vorticity operator's R, Ṙ derivatives.

use magbubble::model::layout::StateLayout;
use magbubble::integrate::OdeSystem;
use magbubble::model::equations::{var, wall_source, wall_source_partials};
use magbubble::model::vorticity::equations::{reduced_jacobian, wall, wall_linear};
use magbubble::model::vorticity::monolithic::Monolithic;
use magbubble::model::vorticity::operator::{ModeOperator, Rows};
use magbubble::model::vorticity::scene::FullModel;
use magbubble::model::vorticity::Grid;
use nalgebra::DMatrix;
use magbubble::model::{BoundaryLayerSystem, Model};
use magbubble::scene::{load, Scene};
use proptest::prelude::*;
use proptest::test_runner::FileFailurePersistence;

fn config(cases: u32) -> ProptestConfig {
    ProptestConfig {
        cases,
        failure_persistence: Some(Box::new(FileFailurePersistence::Direct(
            "tests/suite/proptest-regressions/equations_jacobian.txt",
        ))),
        ..ProptestConfig::default()
    }
}

/// The shipped scenes with shape modes up to k = 16 (fields: none, static, AC, oscillating
/// distance, dipole, H4 coil), one with the tension form of the membrane.
fn scenes() -> Vec<Scene> {
    let mut v: Vec<Scene> = ["no_field", "coil_static", "coil_ac_current", "coil_oscillating_distance", "dipole", "coil_h4"]
        .iter()
        .map(|s| load(format!("scenes/{s}.toml"), &["modes.max_order=16"]).expect("shipped scene"))
        .collect();
    v.push(load("scenes/coil_static.toml", &["modes.max_order=16", "shell.form=\"tension\""]).expect("tension"));
    // issue 12: the quadratic coupling of a free bubble with surface tension
    v.push(
        load("scenes/free_bubble.toml", &["modes.max_order=16", "shell.surface_tension=0.072", "modes.coupling=\"quadratic\""])
            .expect("quadratic"),
    );
    // issue 31: the Marmottant laws (kinked and smooth) with a shell viscosity
    let marmottant = ["modes.max_order=16", "shell.law=\"marmottant\"", "shell.elasticity=0.5", "shell.initial_tension=0.02", "shell.dilatational_viscosity=5e-9"];
    v.push(load("scenes/coil_static.toml", &marmottant).expect("marmottant"));
    let mut smooth = marmottant.to_vec();
    smooth[1] = "shell.law=\"marmottant-smooth\"";
    smooth.push("shell.smoothing=0.01");
    v.push(load("scenes/no_field.toml", &smooth).expect("marmottant-smooth"));
    v
}

/// True when R is not within 1e-4 R0 of a branch radius of a kinked Marmottant law (R_b, R_r).
fn away_from_lipid_kinks(scene: &Scene, r: f64) -> bool {
    match scene.shell.law {
        magbubble::scene::ShellLaw::Marmottant(l) => {
            let rb = l.buckling_radius / scene.bubble.radius;
            let rr = rb * (1.0 + l.rupture_tension / l.elasticity).sqrt();
            (r - rb).abs() > 1e-4 && (r - rr).abs() > 1e-4
        }
        _ => true,
    }
}

/// A random state near the sphere: R ∈ [0.6, 1.6], Ṙ ∈ [−0.5, 0.5], amplitudes ~ 1e−2.
fn state(n: usize) -> impl Strategy<Value = (f64, Vec<f64>)> {
    (0.0..30.0f64, 0.6..1.6f64, -0.5..0.5f64, prop::collection::vec(-1e-2..1e-2f64, n - 2)).prop_map(|(t, r, rd, x)| {
        let mut y = vec![r, rd];
        y.extend(x);
        (t, y)
    })
}

/// Central differences of `sys.rhs` (step h_j = 1e−6 max(1e−2, |y_j|)).
pub(crate) fn fd_jacobian(sys: &dyn OdeSystem, t: f64, y: &[f64]) -> Vec<f64> {
    let n = y.len();
    let (mut yp, mut fp, mut fm) = (y.to_vec(), vec![0.0; n], vec![0.0; n]);
    let mut jac = vec![0.0; n * n];
    for j in 0..n {
        let h = 1e-6 * y[j].abs().max(1e-2);
        yp[j] = y[j] + h;
        sys.rhs(t, &yp, &mut fp);
        yp[j] = y[j] - h;
        sys.rhs(t, &yp, &mut fm);
        yp[j] = y[j];
        for i in 0..n {
            jac[i * n + j] = (fp[i] - fm[i]) / (2.0 * h);
        }
    }
    jac
}

/// Entry-wise agreement, relative to the largest entry of the row scaled by its column's state
/// size (so entries are compared in the units they contribute to f_i).
fn assert_close(an: &[f64], fd: &[f64], y: &[f64], what: &str) -> Result<(), TestCaseError> {
    let n = y.len();
    for i in 0..n {
        let scale = |j: usize| y[j].abs().max(1e-2);
        let row_max = (0..n).map(|j| (an[i * n + j] * scale(j)).abs()).fold(0.0, f64::max);
        for j in 0..n {
            let err = (an[i * n + j] - fd[i * n + j]).abs() * scale(j);
            prop_assert!(
                err <= 1e-6 * row_max + 1e-9,
                "{what}: J[{i}][{j}] analytic {} vs fd {} (row max {row_max:e})",
                an[i * n + j],
                fd[i * n + j]
            );
        }
    }
    Ok(())
}

/// True when no δ_k = min(√(ν/ω), R/(2k)) is within the FD step of its kink.
fn away_from_kinks(bl: &BoundaryLayerSystem, r: f64) -> bool {
    bl.modes().iter().all(|m| (m.viscous_length - r / (2.0 * m.k)).abs() > 1e-4)
}

proptest! {
    #![proptest_config(config(24))]

    #[test]
    fn boundary_layer_jacobian_matches_differences(which in 0usize..10, (t, y) in state(StateLayout::reduced(8).dim())) {
        let scene = &scenes()[which];
        let model = Model::from_scene(scene).unwrap();
        let bl = model.boundary_layer().unwrap();
        prop_assume!(away_from_kinks(bl, y[0]) && away_from_lipid_kinks(scene, y[0]));
        let n = y.len();
        let mut an = vec![0.0; n * n];
        prop_assert!(bl.jacobian(t, &y, &mut an));
        let fd = fd_jacobian(bl, t, &y);
        assert_close(&an, &fd, &y, &format!("scene {which}"))?;
        // the documented sparsity: nothing outside the pattern
        let pat = bl.jacobian_pattern();
        for i in 0..n {
            for j in 0..n {
                prop_assert!(pat.may_be_nonzero(i, j) || an[i * n + j] == 0.0, "({i},{j}) outside the pattern");
            }
        }
    }

    #[test]
    fn radial_jacobian_matches_differences(which in 0usize..10, t in 0.0..30.0f64, r in 0.6..1.6f64, rd in -0.5..0.5f64) {
        let mut scene = scenes()[which].clone();
        prop_assume!(away_from_lipid_kinks(&scene, r));
        scene.modes.max_order = 0;
        let model = Model::from_scene(&scene).unwrap();
        let sys = model.system();
        let y = [r, rd];
        let mut an = [0.0; 4];
        prop_assert!(sys.jacobian(t, &y, &mut an));
        assert_close(&an, &fd_jacobian(sys, t, &y), &y, "radial")?;
    }

    /// The sensitivities' product J·S without the dense J (`jacobian_product`, issue 32) equals
    /// the dense J times S to rounding (1e-13 of Σ|J_ij S_j| per row), for every scene above and
    /// Keller–Miksis with a field (the implicit ḃ correction), three directions at once.
    #[test]
    fn jacobian_product_equals_dense_product(which in 0usize..11, (t, y) in state(StateLayout::reduced(8).dim()), dirs in prop::collection::vec(-1.0..1.0f64, 3 * StateLayout::reduced(8).dim())) {
        let scene = if which < 10 {
            scenes()[which].clone()
        } else {
            load("scenes/coil_static.toml", &["modes.max_order=16", "liquid.sound_speed=1500.0"]).expect("km field")
        };
        let model = Model::from_scene(&scene).unwrap();
        let bl = model.boundary_layer().unwrap();
        let n = y.len();
        let mut jac = vec![0.0; n * n];
        prop_assert!(bl.jacobian(t, &y, &mut jac));
        let mut out = vec![0.0; 3 * n];
        prop_assert!(bl.jacobian_product(t, &y, &dirs, &mut out));
        for (d, (sj, oj)) in dirs.chunks(n).zip(out.chunks(n)).enumerate() {
            for i in 0..n {
                let row = &jac[i * n..(i + 1) * n];
                let dense: f64 = row.iter().zip(sj).map(|(a, b)| a * b).sum();
                let size: f64 = row.iter().zip(sj).map(|(a, b)| (a * b).abs()).sum();
                prop_assert!((oj[i] - dense).abs() <= 1e-13 * size + 1e-300, "scene {which} direction {d} row {i}: {} vs {dense}", oj[i]);
            }
        }
    }

    /// A(t), g(t) reproduce the mode rates at prescribed (R, Ṙ, R̈) for any amplitudes (the
    /// equations are affine in them), and ∂/∂x of the rhs is A.
    #[test]
    fn linear_modes_reproduce_the_rates(which in 0usize..7, (t, y) in state(StateLayout::reduced(8).dim()), rdd in -2.0..2.0f64) {
        let scene = &scenes()[which];
        let model = Model::from_scene(scene).unwrap();
        let bl = model.boundary_layer().unwrap();
        let (a, g) = bl.linear_modes(t, y[0], y[1], rdd);
        let m = bl.modes().len();
        let (mut gn, mut gt) = (vec![0.0; m], vec![0.0; m]);
        bl.equations().loads(t, &y, &mut gn, &mut gt);
        let mut dy = vec![0.0; y.len()];
        bl.mode_rates(y[0], y[1], rdd, &gn, &gt, &y, &mut dy);
        let l = StateLayout::reduced(m);
        let x = nalgebra::DVector::from_column_slice(&y[l.shape()]);
        let lin = &a * &x + &g;
        for (i, yi) in l.shape().enumerate() {
            let scale = dy[yi].abs() + (a.row(i).abs() * x.abs())[0] + g[i].abs() + 1e-300;
            prop_assert!((lin[i] - dy[yi]).abs() <= 1e-10 * scale, "row {i}: A x + g = {} vs rates {}", lin[i], dy[yi]);
        }
    }

    /// The vorticity closure's wall values and partials (T_w, Ĩ, J in the local variables).
    #[test]
    fn vorticity_wall_partials_match_differences(
        k in 2usize..=32, r in 0.6..1.6f64, rd in -0.5..0.5f64, a in -1e-2..1e-2f64, ad in -1e-1..1e-1f64,
        gt in -1.0..1.0f64, i_int in -1.0..1.0f64, jr in -1.0..1.0f64, w0 in 1e-4..1e-2f64,
    ) {
        let (k, rho, eta) = (k as f64, 1.0, 0.02);
        let vals = |x: &[f64; 10]| {
            let src = wall_source(k, eta, x[var::R], x[var::RD], x[var::A], x[var::AD], x[var::GT]);
            let w = wall(k, rho, eta, x[var::R], x[var::RD], src, x[var::IINT], x[var::JR], w0, None);
            // J from the wall's normal term kρṘJ/R
            let j = w.normal[1] * x[var::R] / (k * rho * x[var::RD]);
            [w.tw, w.itil, j]
        };
        let x0 = { let mut x = [0.0; 10]; x[var::R] = r; x[var::RD] = rd; x[var::A] = a; x[var::AD] = ad; x[var::GT] = gt; x[var::IINT] = i_int; x[var::JR] = jr; x };
        prop_assume!(rd.abs() > 1e-3);
        let src = wall_source(k, eta, r, rd, a, ad, gt);
        let lin = wall_linear(r, src, &wall_source_partials(k, eta, r, rd, a, gt), i_int, jr, w0);
        let v0 = vals(&x0);
        prop_assert!((lin.tw - v0[0]).abs() <= 1e-12 * v0[0].abs().max(1.0));
        prop_assert!((lin.itil - v0[1]).abs() <= 1e-12 * v0[1].abs().max(1.0));
        for x in [var::R, var::RD, var::A, var::AD, var::GT, var::IINT, var::JR] {
            let h = 1e-4 * x0[x].abs().max(0.1);
            let (mut p, mut m) = (x0, x0);
            p[x] += h;
            m[x] -= h;
            let (vp, vm) = (vals(&p), vals(&m));
            for (c, an) in [lin.d_tw[x], lin.d_itil[x], lin.d_j[x]].into_iter().enumerate() {
                let fd = (vp[c] - vm[c]) / (2.0 * h);
                prop_assert!((an - fd).abs() <= 1e-6 * (an.abs() + fd.abs()) + 1e-8, "var {x} comp {c}: {an} vs {fd}");
            }
        }
    }
}

/// Central differences of the monolithic system's reduced function (f_z, T_w)(z, p).
fn fd_reduced(sys: &Monolithic<'_>, t: f64, z: &[f64], p: &[f64]) -> (DMatrix<f64>, DMatrix<f64>) {
    let (nz, m) = (z.len(), p.len() / 2);
    let eval = |z: &[f64], p: &[f64]| {
        let (mut fz, mut tw) = (vec![0.0; nz], vec![0.0; m]);
        sys.reduced(t, z, p, &mut fz, &mut tw);
        fz.extend(tw);
        fz
    };
    let (mut gz, mut gp) = (DMatrix::zeros(nz + m, nz), DMatrix::zeros(nz + m, 2 * m));
    for (x, out) in [(z, &mut gz), (p, &mut gp)] {
        for j in 0..x.len() {
            let h = 1e-6 * x[j].abs().max(1e-2);
            let (mut xp, mut xm) = (x.to_vec(), x.to_vec());
            xp[j] += h;
            xm[j] -= h;
            let (fp, fm) = if x.len() == nz { (eval(&xp, p), eval(&xm, p)) } else { (eval(z, &xp), eval(z, &xm)) };
            for i in 0..nz + m {
                out[(i, j)] = (fp[i] - fm[i]) / (2.0 * h);
            }
        }
    }
    (gz, gp)
}

proptest! {
    #![proptest_config(config(16))]

    /// The structured Jacobian's pieces of the monolithic vorticity system, exact.
    #[test]
    fn monolithic_reduced_jacobian_matches_differences(
        which in 0usize..7, (t, z) in state(StateLayout::reduced(3).dim()), p in prop::collection::vec(-1e-2..1e-2f64, 6),
    ) {
        let mut scene = scenes()[which].clone();
        scene.modes.max_order = 6;
        scene.vorticity.points = 40;
        let fm = FullModel::from_scene(&scene).unwrap();
        let c = fm.coupling();
        let sys = Monolithic::new(&c, fm.grid.clone());
        let w0 = sys.operators()[0].w0();
        let (nz, m) = (z.len(), 3);
        let (mut gz, mut gp) = (DMatrix::zeros(nz + m, nz), DMatrix::zeros(nz + m, 2 * m));
        reduced_jacobian(&c, t, &z, &p, w0, &mut gz, &mut gp);
        let (fz, fp) = fd_reduced(&sys, t, &z, &p);
        for (an, fd, x, what) in [(&gz, &fz, &z[..], "z"), (&gp, &fp, &p[..], "p")] {
            for i in 0..nz + m {
                let scale = |j: usize| x[j].abs().max(1e-2);
                let row_max = (0..x.len()).map(|j| (an[(i, j)] * scale(j)).abs()).fold(0.0, f64::max)
                    .max((0..nz).map(|j| (gz[(i, j)] * z[j].abs().max(1e-2)).abs()).fold(0.0, f64::max));
                for j in 0..x.len() {
                    let err = (an[(i, j)] - fd[(i, j)]).abs() * scale(j);
                    prop_assert!(err <= 1e-6 * row_max + 1e-9, "∂/∂{what}: ({i},{j}) analytic {} vs fd {}", an[(i, j)], fd[(i, j)]);
                }
            }
        }
    }

    /// ∂/∂R and ∂/∂Ṙ of the vorticity operator rows.
    #[test]
    fn operator_row_derivatives_match_differences(k in 2usize..=32, r in 0.6..1.6f64, rd in -0.5..0.5f64) {
        prop_assume!(rd.abs() > 1e-3);
        let grid = Grid::new(2.0, 60, 10.0).unwrap();
        let op = ModeOperator::new(&grid, k);
        let nu = 0.02;
        let (mut d_r, mut d_rd) = (Rows::default(), Rows::default());
        op.rows_derivatives(r, rd, nu, &mut d_r, &mut d_rd);
        for (v, an) in [(0usize, &d_r), (1, &d_rd)] {
            let h = 1e-6;
            let (mut p, mut m) = (Rows::default(), Rows::default());
            let (rp, rdp, rm, rdm) = if v == 0 { (r + h, rd, r - h, rd) } else { (r, rd + h, r, rd - h) };
            op.rows(rp, rdp, nu, &mut p);
            op.rows(rm, rdm, nu, &mut m);
            for (a, (pp, mm)) in [(&an.lower, (&p.lower, &m.lower)), (&an.diag, (&p.diag, &m.diag)), (&an.upper, (&p.upper, &m.upper))] {
                for i in 0..a.len() {
                    let fd = (pp[i] - mm[i]) / (2.0 * h);
                    prop_assert!((a[i] - fd).abs() <= 1e-6 * (a[i].abs() + fd.abs()) + 1e-6, "var {v} node {i}: {} vs {fd}", a[i]);
                }
            }
        }
    }
}
