//! Shell-viscous shape loads (issue 11 part 3): the Kelvin–Voigt shell's loads on the shape modes,
//! G_n ∋ S1 a + S2 b + S1D ȧ + S2D ḃ, G_t ∋ S11 a + S12 b + S11D ȧ + S12D ḃ (tension form,
//! derivations/shell/viscous.rs), wired through the boundary-layer closure, which solves (NS)
//! for ḃ exactly (runtime/model/boundary_layer.rs `apply_bdot_loads`). Checked against
//!
//! * the closed forms of the rate coefficients at rest (S1D = 4κ_s/R², S2D = −2nκ_s/R²,
//!   S11D = −2κ_s/R², S12D = [nκ_s + (n−2)μ_s]/R², n = k(k+1));
//! * the dispersion relation: at rest, e^{st} turns S_ij into S_ij + s S_ijD in the (N, TS, NS)
//!   determinant of runtime/model/dispersion.rs; with φ = δ_k/R (the boundary layer) its roots
//!   must be the eigenvalues of the model's linear mode system A (written out here, and equal
//!   to `LinearMode::determinant` when the viscosity is off);
//! * a free decay of a_2 in a run (Prony fit) against the same eigenvalue;
//! * the exact Jacobian (off equilibrium, driven, with a field and Keller–Miksis) against
//!   finite differences.

use crate::support::jacobian::assert_jacobian_matches_fd_step;
use crate::support::prony::prony;
use magbubble::analysis::dispersion::{LinearMode, C64};
use magbubble::model::effects::{BdotLoads, LoadJacobian};
use magbubble::model::layout::StateLayout;
use magbubble::model::Model;
use magbubble::scene;

const KS: f64 = 4e-9; // κ_s [kg/s]
const MU: f64 = 1e-8; // μ_s [Pa s m]

fn scene_text(ks: f64, mu: f64) -> String {
    format!(
        "[bubble]\nradius = 10e-6\ninitial = {{ a = {{ 2 = 1e-9 }} }}\n[shell]\ndilatational_viscosity = {ks:e}\n\
         shear_viscosity = {mu:e}\n[modes]\nmax_order = 6\n[run]\nduration = 20e-6\nsample_interval = 2e-8\n"
    )
}

fn model(ks: f64, mu: f64) -> Model {
    let s = scene::load_str(&scene_text(ks, mu), "shell viscosity (test)", &[] as &[&str]).unwrap();
    Model::from_scene(&s).unwrap()
}

/// (N, TS, NS) determinant with s-dependent loads G = (S + sSD)·(a, b) (module doc).
#[allow(clippy::too_many_arguments)]
fn det(k: f64, rho: f64, eta: f64, r: f64, s: C64, phi: C64, sn: [f64; 4], st: [f64; 4]) -> C64 {
    let one = C64::new(1.0, 0.0);
    let c = (k + 1.0) / (rho * r);
    // sn = (S1, S1D, S2, S2D), st = (S11, S11D, S12, S12D)
    let (g1, g2) = (s * sn[1] + sn[0], s * sn[3] + sn[2]);
    let (t1, t2) = (s * st[1] + st[0], s * st[3] + st[2]);
    let m = [
        [s * s + (s * (2.0 * eta * (k + 2.0) / r) + g1) * c, g2 * c, (one - phi * (2.0 * (k + 1.0))) * (c * k * eta / r)],
        [s * (-2.0 * (k + 2.0) / (k + 1.0)) + t1 * (r / eta), t2 * (r / eta), one + phi * 2.0],
        [s / (k + 1.0), s, -phi],
    ];
    m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
        + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
}

/// Per mode: (S1, S1D, S2, S2D), (S11, S11D, S12, S12D) at rest at R0 from the model's terms, δ_k,
/// and the eigenvalues of the mode's 3×3 block of A.
fn per_mode(m: &Model) -> Vec<(f64, [f64; 4], [f64; 4], f64, Vec<C64>)> {
    let bl = m.boundary_layer().unwrap();
    let eq = bl.equations();
    let nm = bl.modes().len();
    let l = StateLayout::reduced(nm);
    let z = (0..l.dim()).map(|i| if i == l.r() { 1.0 } else { 0.0 }).collect::<Vec<_>>();
    let mut lj = LoadJacobian::new(nm);
    eq.load_jacobian(0.0, &z, &mut lj);
    let (mut cn, mut ct, mut cnr, mut ctr) = (vec![0.0; nm], vec![0.0; nm], vec![0.0; nm], vec![0.0; nm]);
    eq.bdot_loads(0.0, &z, &mut BdotLoads { cn: &mut cn, ct: &mut ct, cn_r: &mut cnr, ct_r: &mut ctr });
    let (a, _) = bl.linear_modes(0.0, 1.0, 0.0, 0.0);
    (0..nm)
        .map(|j| {
            let (ia, iad, ib) = (l.a(j), l.adot(j), l.b(j));
            let (gn, gt) = (lj.gn_row(j), lj.gt_row(j));
            let block = a.view((StateLayout::x_a(j), StateLayout::x_a(j)), (3, 3)).clone_owned();
            let eig = block.complex_eigenvalues().iter().map(|e| C64::new(e.re, e.im)).collect();
            (bl.modes()[j].k, [gn[ia], gn[iad], gn[ib], cn[j]], [gt[ia], gt[iad], gt[ib], ct[j]], bl.delta(j, 1.0), eig)
        })
        .collect()
}

#[test]
fn rate_coefficients_at_rest_are_the_closed_forms() {
    let m = model(KS, MU);
    let (rho, ts) = (m.equations().params().rho, m.time_scale());
    // nondimensional κ_s, μ_s: units p* R0 t* with p* = 2c1/R0 (c1 = 0.1 N/m)
    let unit = 2.0 * 0.1 * ts;
    let (ks, mu) = (KS / unit, MU / unit);
    assert!((rho - 1.0).abs() < 1e-15);
    let base = per_mode(&model(0.0, 0.0));
    for ((k, sn, st, _, _), (_, sn0, st0, _, _)) in per_mode(&m).into_iter().zip(base) {
        let n = k * (k + 1.0);
        let want_n = [sn0[0], 4.0 * ks, sn0[2], -2.0 * n * ks];
        let want_t = [st0[0], -2.0 * ks, st0[2], n * ks + (n - 2.0) * mu];
        for (x, w) in sn.iter().zip(want_n).chain(st.iter().zip(want_t)) {
            assert!((x - w).abs() <= 1e-13 * (1.0 + w.abs()), "k = {k}: {sn:?} {st:?} vs {want_n:?} {want_t:?}");
        }
    }
}

#[test]
fn linear_spectrum_solves_the_dispersion_relation_with_shell_viscosity() {
    let (m, m0) = (model(KS, MU), model(0.0, 0.0));
    let p = *m.equations().params();
    for ((k, sn, st, delta, eig), (_, sn0, st0, delta0, eig0)) in per_mode(&m).into_iter().zip(per_mode(&m0)) {
        let phi = C64::new(delta, 0.0);
        // the transcription against dispersion.rs without viscosity
        let lm = LinearMode { k: k as usize, rho: p.rho, eta: p.eta, r0: 1.0, s1: sn0[0], s2: sn0[2], s11: st0[0], s12: st0[2] };
        let s_test = C64::new(-0.3, 2.0);
        let (mine, theirs) = (det(k, p.rho, p.eta, 1.0, s_test, C64::new(delta0, 0.0), sn0, st0), lm.determinant(s_test, C64::new(delta0, 0.0)));
        assert!((mine - theirs).norm() <= 1e-12 * theirs.norm(), "transcription: {mine} vs {theirs}");
        for s in &eig {
            let (d, scale) = (det(k, p.rho, p.eta, 1.0, *s, phi, sn, st).norm(), det(k, p.rho, p.eta, 1.0, *s * 1.01, phi, sn, st).norm());
            assert!(d <= 1e-9 * scale, "k = {k}: det at eigenvalue {s} is {d:e} (at 1.01 s: {scale:e})");
        }
        // the viscosity matters: the oscillatory pair moves
        let osc = |e: &[C64]| *e.iter().max_by(|a, b| a.im.partial_cmp(&b.im).unwrap()).unwrap();
        let (w, w0) = (osc(&eig), osc(&eig0));
        eprintln!("k = {k}: s = {w:.6} with κ_s, μ_s; {w0:.6} without (units 1/t*)");
        assert!((w.re - w0.re).abs() > 0.05 * w0.re.abs(), "k = {k}: decay {} vs {}", w.re, w0.re);
    }
}

#[test]
fn free_decay_of_a2_matches_the_linear_spectrum() {
    let m = model(KS, MU);
    let s = scene::load_str(&scene_text(KS, MU), "shell viscosity (test)", &["run.integrator.rtol=1e-10", "run.integrator.atol=1e-16"]).unwrap();
    let mut a2 = Vec::new();
    let rep = magbubble::model::simulate(&s, &mut |_, row| a2.push(row[1])).unwrap();
    assert_eq!(rep.status, magbubble::model::RunStatus::Completed);
    let want = per_mode(&m)[0].4.iter().copied().max_by(|a, b| a.im.partial_cmp(&b.im).unwrap()).unwrap() / m.time_scale();
    let roots = prony(&a2, s.run.sample_interval, 3);
    let got = *roots.iter().min_by(|a, b| (**a - want).norm().partial_cmp(&(**b - want).norm()).unwrap()).unwrap();
    eprintln!("a2 free decay: Prony {got:.6e} 1/s, linear spectrum {want:.6e} 1/s, rel {:.1e}", (got - want).norm() / want.norm());
    assert!((got - want).norm() < 1e-4 * want.norm(), "{got} vs {want}");
}

#[test]
fn shell_viscous_jacobian_matches_finite_differences() {
    let base = "[bubble]\nradius = 10e-6\n[shell]\ndilatational_viscosity = 2e-9\nshear_viscosity = 5e-9\n\
                [drive]\namplitude = 0.3\nfrequency_hz = 1e6\n[modes]\nmax_order = 6\n";
    for extra in ["", "[field.coil]\ncurrent = 1e6\n", "[liquid]\nsound_speed = 1500.0\n[field.coil]\ncurrent = 1e6\n", "[liquid]\nsound_speed = 1500.0\n"] {
        let s = scene::load_str(&format!("{base}{extra}"), "shell viscosity (test)", &[] as &[&str]).unwrap();
        let m = Model::from_scene(&s).unwrap();
        assert!(m.equations().has_bdot_loads());
        assert_jacobian_matches_fd_step(m.system(), extra, 1e-5);
    }
}

/// `modes --damped` with shell viscosity takes the eigenvalues of A's mode blocks (the
/// stiffness-only determinant cannot carry the ȧ, ḃ loads); without it that route must agree
/// with the determinant's roots, which it replaces only when the viscosity is on.
#[test]
fn damped_spectrum_includes_the_shell_viscosity() {
    use magbubble::model::vorticity::scene::damped_spectrum;
    for (ks, mu) in [(0.0, 0.0), (KS, MU)] {
        let s = scene::load_str(&scene_text(ks, mu), "shell viscosity (test)", &[] as &[&str]).unwrap();
        let m = Model::from_scene(&s).unwrap();
        let ts = m.time_scale();
        let d = damped_spectrum(&s).unwrap();
        for (mode, (k, _, _, _, eig)) in d.shape.iter().zip(per_mode(&m)) {
            let top = eig.iter().copied().max_by(|a, b| a.im.total_cmp(&b.im)).unwrap() / ts;
            assert_eq!(mode.k as f64, k);
            let (e1, e2) = ((mode.decay_per_s + top.re).abs() / top.re.abs(), (mode.omega_rad_s - top.im).abs() / top.im);
            eprintln!("κ_s = {ks:e}, k = {k}: decay {:.6e} 1/s, ω {:.6e} rad/s (vs A: {e1:.1e}, {e2:.1e})", mode.decay_per_s, mode.omega_rad_s);
            assert!(e1 < 1e-8 && e2 < 1e-8, "k = {k}: {mode:?} vs {top}");
        }
    }
}
