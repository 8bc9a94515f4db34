//! The frame mapping of the second-order model (issue 12; runtime effects/quadratic_frame.rs,
//! docs/model.md "One frame for the state"): the state's a_n are Eulerian amplitudes
//! (r = f(θ) = R + Σ a_n P_n(cos θ)), b_n the material displacement (θ = Θ + Σ b_n P¹_n/R), and
//! the membrane's material-frame loads are mapped to them.
//!
//! * An independent oracle: the exact membrane loads on the material parametrisation
//!   r(Θ) = f(θ(Θ)) of a surface given by its Eulerian (R, a) and its b, the normal load
//!   projected on P_j(cos θ) by quadrature (the tangential one at the material angle), the
//!   bilinear coefficients by 8th-order second differences, against linear + quadratic membrane
//!   + frame mapping: ≤ 1e-8 relative, both laws and both forms.
//! * Label invariance: a shape energy (surface tension as a membrane law, Helfrich bending)
//!   depends on the shape only, so after the mapping its normal loads on the Eulerian
//!   amplitudes must not depend on b at all: every a·b and b·b coefficient vanishes (the tables
//!   alone have them); and a run of a bending-only shell does not depend on the initial b to
//!   O(ε³).

use crate::support::membrane_loads::{loads_on, mode, normalise_projections, Law};
use crate::support::shell_energy::{gauss_legendre, mixed, second, steps};
use magbubble::model::layout::StateLayout;
use magbubble::coefficients::quadratic_membrane::Form;
use magbubble::model::effects::membrane::MembraneTerm;
use magbubble::model::effects::quadratic_bending::QuadraticBending;
use magbubble::model::effects::quadratic_frame::FrameMap;
use magbubble::model::effects::quadratic_membrane::QuadraticMembrane;
use magbubble::model::effects::second_order::{FirstOrder, MaterialLoads, SecondOrderTerm};
use magbubble::model::effects::shell::{bending_table, surface_tension_table, OneConstant, Table};
use magbubble::model::effects::{At, Loads, Term};
use magbubble::model::params::Membrane;
use magbubble::scene::{MembraneForm, ShellLaw};

const R: f64 = 1.08;
const R0: f64 = 1.0;
const MODES: usize = 16; // k = 2 … 32
const PAIRS: [(usize, usize); 7] = [(2, 2), (2, 4), (4, 6), (6, 6), (2, 16), (8, 12), (16, 16)];

fn orders() -> Vec<f64> {
    (1..=MODES).map(|i| 2.0 * i as f64).collect()
}

/// Ordinary terms plus the frame mapping (undriven, ḃ⁽¹⁾ = 0: these loads hold no rate).
struct Stack {
    ordinary: Vec<Box<dyn Term>>,
    frame: Option<FrameMap>,
}

impl Stack {
    /// [−P, G_n,j…] and [0, G_t,j…] indexed by j/2 at a state with the given
    /// (mode index, is_b, value) amplitudes.
    fn loads(&self, amps: &[(usize, bool, f64)]) -> (Vec<f64>, Vec<f64>) {
        let l = StateLayout::reduced(MODES);
        let mut z = vec![0.0; l.dim()];
        z[l.r()] = R;
        for &(i, b, v) in amps {
            z[if b { l.b(i) } else { l.a(i) }] += v;
        }
        let (mut gn, mut gt) = (vec![0.0; MODES], vec![0.0; MODES]);
        let mut l = Loads { pressure: 0.0, gn: &mut gn, gt: &mut gt };
        let at = At { t: 0.0, z: &z };
        for t in &self.ordinary {
            t.add(&at, &mut l);
        }
        if let Some(f) = &self.frame {
            let zero = [0.0; MODES];
            let (p, gn, gt) = f.lagrangian_loads(0.0, &z);
            let material = MaterialLoads { pressure: p, gn: &gn[..MODES], gt: &gt[..MODES] };
            f.add(&at, &FirstOrder { rdd: 0.0, add: &zero, bd: &zero, material }, &mut l);
        }
        let mut n = vec![-l.pressure];
        n.extend(gn);
        let mut tt = vec![0.0];
        tt.extend(gt);
        (n, tt)
    }
}

/// The step of an amplitude of mode n (a or b).
fn step(n: usize, b: bool) -> f64 {
    let (ha, hb) = steps(R, n, 0.02);
    if b {
        hb
    } else {
        ha
    }
}

/// Bilinear coefficient of u_l v_m of a smooth function of the two amplitudes, component-wise:
/// ½ ∂² for u = v, ∂²/∂u∂v otherwise (8th-order differences).
fn cross<const C: usize>(f: impl Fn(f64, f64) -> Vec<[f64; C]>, same: bool, hl: f64, hm: f64, len: usize) -> Vec<[f64; C]> {
    if same {
        let v: Vec<Vec<[f64; C]>> = (0..9).map(|i| f((i as f64 - 4.0) * hl, 0.0)).collect();
        (0..len).map(|j| std::array::from_fn(|c| second(|e| v[((e / hl).round() as i64 + 4) as usize][j][c], hl) / 2.0)).collect()
    } else {
        let mut v = vec![vec![Vec::new(); 9]; 9];
        for (i, row) in v.iter_mut().enumerate() {
            for (k, cell) in row.iter_mut().enumerate() {
                if i != 4 && k != 4 {
                    *cell = f((i as f64 - 4.0) * hl, (k as f64 - 4.0) * hm);
                }
            }
        }
        let at = |x: f64, y: f64, j: usize, c: usize| v[((x / hl).round() as i64 + 4) as usize][((y / hm).round() as i64 + 4) as usize][j][c];
        (0..len).map(|j| std::array::from_fn(|c| mixed(|x, y| at(x, y, j, c), hl, hm))).collect()
    }
}

/// The model's bilinear coefficient of (u_l, v_m), [normal, tangential] per target j/2.
fn model_cross(s: &Stack, l: usize, ub: bool, m: usize, vb: bool) -> Vec<[f64; 2]> {
    let (il, im) = (l / 2 - 1, m / 2 - 1);
    let same = l == m && ub == vb;
    let f = |x: f64, y: f64| {
        let (n, t) = s.loads(&[(il, ub, x), (im, vb, y)]);
        n.iter().zip(&t).map(|(a, b)| [*a, *b]).collect::<Vec<_>>()
    };
    cross(f, same, step(l, ub), step(m, vb), MODES + 1)
}

fn one_constant(table: Table, value: f64) -> OneConstant {
    OneConstant { name: "shape energy", label: String::new(), table, value, r0: R0, orders: orders() }
}

/// Every a·b and b·b coefficient of the mapped normal loads of a shape energy vanishes; returns
/// (worst mapped / largest unmapped, largest unmapped a·b coefficient).
fn label_independence(lin: &OneConstant, quad: impl Fn() -> Box<dyn Term>) -> (f64, f64) {
    let mapped = Stack { ordinary: vec![Box::new(lin.clone()), quad()], frame: FrameMap::new(vec![Box::new(lin.clone())], &orders()) };
    let unmapped = Stack { ordinary: vec![Box::new(lin.clone()), quad()], frame: None };
    let (mut worst, mut biggest): (f64, f64) = (0.0, 0.0);
    for (l, m) in PAIRS {
        // the pair's scale: its largest unmapped a·b coefficient (b·b ones vanish for a shape energy)
        let scale = model_cross(&unmapped, l, false, m, true).iter().map(|x| x[0].abs()).fold(0.0, f64::max);
        biggest = biggest.max(scale);
        for (ub, vb) in [(false, true), (true, false), (true, true)] {
            if l == m && ub && !vb {
                continue; // the same coefficient as (a_l, b_l)
            }
            let (got, raw) = (model_cross(&mapped, l, ub, m, vb), model_cross(&unmapped, l, ub, m, vb));
            let floor = scale;
            for (j, x) in got.iter().enumerate() {
                let e = x[0].abs() / floor;
                assert!(e <= 1e-8, "(l, m, j) = ({l}, {m}, {}) b = ({ub}, {vb}): mapped {:e}, unmapped {:e}", 2 * j, x[0], raw[j][0]);
                worst = worst.max(e);
            }
        }
    }
    (worst, biggest)
}

#[test]
fn shape_energies_do_not_depend_on_the_material_labels_after_the_mapping() {
    let gamma = 0.7;
    let lin = one_constant(surface_tension_table(), gamma);
    let law = QuadraticMembrane::law("surface_tension").expect("generated law");
    let (worst, raw) = label_independence(&lin, || Box::new(QuadraticMembrane::new(law, Form::Tension, R0, (gamma, 0.0), &orders()).expect("term")));
    eprintln!("surface tension: mapped a·b, b·b ≤ {worst:.1e} of the largest unmapped ({raw:.3e})");
    assert!(raw > 1e-2 * gamma, "the material-frame table has a·b terms to cancel");
    let kb = 0.03;
    let lin = one_constant(bending_table(), kb);
    let (worst, raw) = label_independence(&lin, || Box::new(QuadraticBending::new(kb, R0, &orders()).expect("term")));
    eprintln!("bending: mapped a·b, b·b ≤ {worst:.1e} of the largest unmapped ({raw:.3e})");
    assert!(raw > 1e-2 * kb, "the material-frame table has a·b terms to cancel");
}

/// Oracle: [normal on P_j(cos θ), paper F_t on P¹_j(cos Θ), tension F_t on P¹_j(cos Θ)] of the
/// surface with Eulerian amplitudes (n, a_n, b_n) on the sphere of radius R.
fn eulerian_projection(law: Law, amps: &[(usize, f64, f64)], jmax: usize) -> Vec<[f64; 3]> {
    let nmax = amps.iter().map(|m| m.0).max().unwrap_or(0);
    let nodes = gauss_legendre(3 * (nmax + jmax) + 80);
    let mut out = vec![[0.0; 3]; jmax + 1];
    for &(x, w) in &nodes {
        let th = x.acos();
        // θ(Θ) and its Θ-derivatives
        let (mut t, mut t1, mut t2) = (th, 1.0, 0.0);
        for &(n, _, b) in amps {
            let f = mode(n, th);
            t += b / R * f[1];
            t1 += b / R * f[2];
            t2 += b / R * f[3];
        }
        // r(Θ) = f(θ(Θ)), f(θ) = R + Σ a_n P_n(cos θ)
        let (mut f0, mut f1, mut f2) = (R, 0.0, 0.0);
        for &(n, a, _) in amps {
            let g = mode(n, t);
            f0 += a * g[0];
            f1 += a * g[1];
            f2 += a * g[2];
        }
        let g = [f0, f1 * t1, f2 * t1 * t1 + f1 * t2, t, t1, t2];
        let (fnn, fp, ft) = loads_on(law, R0, g, th);
        let measure = t.sin() * t1 / th.sin();
        for (j, o) in out.iter_mut().enumerate() {
            let (pe, pm) = (mode(j, t), mode(j, th));
            o[0] += w * fnn * pe[0] * measure;
            o[1] += w * fp * pm[1];
            o[2] += w * ft * pm[1];
        }
    }
    normalise_projections(&mut out);
    out
}

fn membrane_stack(law: &ShellLaw, form: Form, name: &str, args: (f64, f64)) -> Stack {
    let mform = match form {
        Form::Paper => MembraneForm::Paper,
        Form::Tension => MembraneForm::Tension,
    };
    let lin = || MembraneTerm { law: Membrane::for_law(law, mform), r0: R0, c1: args.0, c2: args.1, orders: orders() };
    let quad = QuadraticMembrane::new(QuadraticMembrane::law(name).expect("law"), form, R0, args, &orders()).expect("term");
    Stack { ordinary: vec![Box::new(lin()), Box::new(quad)], frame: FrameMap::new(vec![Box::new(lin())], &orders()) }
}

/// Worst relative difference oracle − model over the pairs, combinations and targets, and the
/// largest change the mapping makes to a coefficient (relative to the same scale).
fn oracle_check(law: Law, shell: ShellLaw, name: &str, args: (f64, f64)) -> (f64, f64) {
    let stacks = |frame: bool| {
        let s = [Form::Paper, Form::Tension].map(|f| membrane_stack(&shell, f, name, args));
        s.map(|x| if frame { x } else { Stack { frame: None, ..x } })
    };
    let ([paper, tension], [paper0, tension0]) = (stacks(true), stacks(false));
    let (mut worst, mut share): (f64, f64) = (0.0, 0.0);
    for (l, m) in PAIRS {
        let jmax = l + m;
        for (ub, vb) in [(false, false), (false, true), (true, false), (true, true)] {
            if l == m && ub && !vb {
                continue;
            }
            let amp = |n: usize, b: bool, e: f64| (n, if b { 0.0 } else { e }, if b { e } else { 0.0 });
            let f = |x: f64, y: f64| eulerian_projection(law, &[amp(l, ub, x), amp(m, vb, y)], jmax);
            let oracle = cross(f, l == m && ub == vb, step(l, ub), step(m, vb), jmax + 1);
            let (pn, tt) = (model_cross(&paper, l, ub, m, vb), model_cross(&tension, l, ub, m, vb));
            let (pn0, tt0) = (model_cross(&paper0, l, ub, m, vb), model_cross(&tension0, l, ub, m, vb));
            // load c: 0 normal on P_j, 1 paper F_t on P¹_j, 2 tension F_t on P¹_j
            let pick = |p: &[[f64; 2]], t: &[[f64; 2]], c: usize, j: usize| -> f64 {
                if j % 2 == 1 || j / 2 > MODES || (c > 0 && j == 0) {
                    return 0.0;
                }
                match c {
                    0 => p[j / 2][0],
                    1 => p[j / 2][1],
                    _ => t[j / 2][1],
                }
            };
            for c in 0..3 {
                let scale = (0..=jmax).map(|j| pick(&pn, &tt, c, j).abs()).fold(1e-300, f64::max);
                for j in 0..=jmax {
                    let want = pick(&pn, &tt, c, j);
                    let e = (oracle[j][c] - want).abs() / scale;
                    assert!(e <= 1e-8, "{name} (l, m, j) = ({l}, {m}, {j}) b = ({ub}, {vb}) load {c}: oracle {:e} vs model {want:e} ({e:.1e})", oracle[j][c]);
                    worst = worst.max(e);
                    share = share.max((want - pick(&pn0, &tt0, c, j)).abs() / scale);
                }
            }
        }
    }
    (worst, share)
}

#[test]
fn mapped_membrane_loads_match_the_eulerian_projection_oracle() {
    let (worst, share) = oracle_check(Law::MooneyRivlin { c1: 0.9, c2: 0.25 }, ShellLaw::MooneyRivlin, "mooney_rivlin", (0.9, 0.25));
    eprintln!("Mooney–Rivlin: worst relative difference {worst:.2e}; the mapping changes a coefficient by up to {share:.3} of its scale");
    assert!(share > 1e-2, "the mapping is not negligible here");
    let (worst, share) = oracle_check(Law::Skalak { gs: 0.8, c: 1.7 }, ShellLaw::Skalak { shear_modulus: 0.8, area_dilatation: 1.7 }, "skalak", (0.8, 1.7));
    eprintln!("Skalak: worst relative difference {worst:.2e}; the mapping changes a coefficient by up to {share:.3} of its scale");
}

/// A bending-only shell (c1 = c2 = 0, k_b, γ), undriven, k ≤ 4, a_2(0) = εR0 and b_2(0) = βεR0.
fn bending_shell(eps: f64, beta: f64) -> magbubble::scene::Scene {
    let r0 = 10e-6;
    let a = format!("bubble.initial.a={{2 = {:e}}}", eps * r0);
    let b = format!("bubble.initial.b={{2 = {:e}, 4 = {:e}}}", beta * eps * r0, -0.5 * beta * eps * r0);
    magbubble::scene::load(
        "scenes/no_field.toml",
        &[
            "shell.c1=0.0",
            "shell.c2=0.0",
            "shell.bending_modulus=1e-13",
            "shell.surface_tension=0.072",
            "drive.amplitude=0.0",
            "modes.max_order=4",
            "modes.coupling=\"quadratic\"",
            "run.duration=3e-6",
            "run.sample_interval=1e-8",
            "run.integrator.rtol=1e-11",
            "run.integrator.atol=1e-15",
            &a,
            &b,
        ],
    )
    .expect("scene")
}

/// max over the samples of |run(b) − run(0)| in R, a_2, a_4 (units of R0).
fn label_difference(eps: f64) -> [f64; 3] {
    let rows = |s: &magbubble::scene::Scene| {
        let mut v: Vec<Vec<f64>> = Vec::new();
        magbubble::model::simulate(s, &mut |_, row| v.push(row.to_vec())).expect("runs");
        v
    };
    let (x, y) = (rows(&bending_shell(eps, 1.0)), rows(&bending_shell(eps, 0.0)));
    assert_eq!(x.len(), y.len());
    assert_eq!(x[0].len(), 5, "R, a2, b2, a4, b4");
    [0, 1, 3].map(|c| x.iter().zip(&y).map(|(p, q)| (p[c] - q[c]).abs()).fold(0.0, f64::max) / 10e-6)
}

#[test]
fn a_bending_shell_does_not_depend_on_the_initial_b_to_second_order() {
    let m = magbubble::model::Model::from_scene(&bending_shell(1e-3, 1.0)).expect("model");
    assert!(m.equations().has("quadratic frame") && m.equations().has("quadratic bending"));
    let (d0, d1, d2) = (label_difference(8e-3), label_difference(4e-3), label_difference(2e-3));
    eprintln!("ε = 8e-3: {d0:?}");
    let ratio: Vec<f64> = d1.iter().zip(&d2).map(|(a, b)| a / b).collect();
    eprintln!("initial b changes R, a2, a4 by {d1:?} (ε = 4e-3), {d2:?} (ε = 2e-3): ratios {ratio:.3?}");
    for r in &ratio[1..] {
        assert!((6.5..9.5).contains(r), "O(ε³): ratio {r}");
    }
}

/// The term alone: its exact Jacobian against central differences of its loads at finite
/// amplitudes and a nonzero ḃ⁽¹⁾ (a linear function of z here, with its gradient), every row.
#[test]
fn frame_term_jacobian_matches_differences() {
    use magbubble::model::effects::second_order::FirstOrderGradient;
    use magbubble::model::effects::shell::ShellViscosity;
    use crate::support::load_jacobian::{assert_load_jacobian_matches_fd, finite_state, flat_loads};
    use magbubble::model::effects::LoadJacobian;
    let modes = 6;
    let orders: Vec<f64> = (1..=modes).map(|i| 2.0 * i as f64).collect();
    let n = StateLayout::reduced(modes).dim();
    let mr = || MembraneTerm { law: Membrane::for_law(&ShellLaw::MooneyRivlin, MembraneForm::Tension), r0: R0, c1: 0.9, c2: 0.3, orders: orders.clone() };
    let bend = || OneConstant { name: "bending", label: String::new(), table: bending_table(), value: 0.02, r0: R0, orders: orders.clone() };
    let visc = || ShellViscosity { kappa_s: 0.3, mu_s: 0.2, r0: R0, orders: orders.clone() };
    let sets: Vec<(&str, Vec<Box<dyn Term>>)> = vec![
        ("membrane", vec![Box::new(mr())]),
        ("bending + viscosity", vec![Box::new(bend()), Box::new(visc())]),
        ("all", vec![Box::new(mr()), Box::new(bend()), Box::new(visc())]),
    ];
    // ḃ⁽¹⁾_m = Σ_j g[m][j] z_j
    let g: Vec<f64> = (0..modes * n).map(|i| 0.3 * (0.7 * i as f64).cos()).collect();
    let bd = |z: &[f64]| (0..modes).map(|m| (0..n).map(|j| g[m * n + j] * z[j]).sum()).collect::<Vec<f64>>();
    for (label, set) in sets {
        let t = FrameMap::new(set, &orders).expect("term");
        let y = finite_state(modes);
        let eval = |z: &[f64]| {
            flat_loads(modes, |l| {
                let (zero, b) = (vec![0.0; modes], bd(z));
                let (p, gn0, gt0) = t.lagrangian_loads(0.0, z);
                let material = MaterialLoads { pressure: p, gn: &gn0[..modes], gt: &gt0[..modes] };
                t.add(&At { t: 0.0, z }, &FirstOrder { rdd: 0.0, add: &zero, bd: &b, material }, l);
            })
        };
        let mut jac = LoadJacobian::new(modes);
        let (zero, zn, b) = (vec![0.0; modes], vec![0.0; n], bd(&y));
        let zm = vec![0.0; modes * n];
        let (p, gn0, gt0) = t.lagrangian_loads(0.0, &y);
        let material = MaterialLoads { pressure: p, gn: &gn0[..modes], gt: &gt0[..modes] };
        let mut j0 = LoadJacobian::new(modes);
        t.lagrangian_jacobian(0.0, &y, &mut j0);
        let first = FirstOrder { rdd: 0.0, add: &zero, bd: &b, material };
        t.add_jacobian(&At { t: 0.0, z: &y }, &first, &FirstOrderGradient { drdd: &zn, dadd: &zm, dbd: &g, material: &j0 }, &mut jac);
        assert_load_jacobian_matches_fd(&jac, &y, eval, label);
    }
}
