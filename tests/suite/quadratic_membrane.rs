//! The second-order membrane loads (issue 12, scope 1: `coefficients::quadratic_membrane` via the
//! runtime term `effects::quadratic_membrane`) against an independent f64 oracle
//! (`support::membrane_loads`): the exact nonlinear loads F_n, F_t on a surface with two finite
//! amplitudes, projected by quadrature, the bilinear coefficient by 8th-order second differences
//! in the two amplitudes. ≤ 1e-8 relative for l, m ≤ 16, both forms, Mooney–Rivlin and Skalak,
//! on a prestressed sphere (R ≠ R0, so the zero-order stress enters).

use crate::support::membrane_loads::{projected, Amp, Law};
use crate::support::shell_energy::{mixed, second, steps};
use magbubble::model::layout::StateLayout;
use magbubble::coefficients::quadratic_membrane::Form;
use magbubble::model::effects::quadratic_membrane::QuadraticMembrane;
use magbubble::model::effects::{At, Loads, Term};

const R: f64 = 1.08;
const R0: f64 = 1.0;
const MODES: usize = 16; // k = 2 … 32

fn term(name: &str, form: Form, args: (f64, f64)) -> QuadraticMembrane {
    let law = QuadraticMembrane::law(name).expect("generated law");
    let orders: Vec<f64> = (1..=MODES).map(|i| 2.0 * i as f64).collect();
    QuadraticMembrane::new(law, form, R0, args, &orders).expect("term")
}

/// The term's loads at a state with the given (mode index, is_b, value) amplitudes:
/// [−P, G_n,j…] and [G_t,j…] indexed by j/2 (entry 0 of the tangential unused).
fn table(t: &QuadraticMembrane, amps: &[(usize, bool, f64)]) -> (Vec<f64>, Vec<f64>) {
    let l = StateLayout::reduced(MODES);
    let mut z = vec![0.0; l.dim()];
    z[l.r()] = R;
    for &(i, b, v) in amps {
        z[if b { l.b(i) } else { l.a(i) }] += v;
    }
    let (mut gn, mut gt) = (vec![0.0; MODES], vec![0.0; MODES]);
    let mut loads = Loads { pressure: 0.0, gn: &mut gn, gt: &mut gt };
    t.add(&At { t: 0.0, z: &z }, &mut loads);
    let p = loads.pressure;
    let mut n = vec![-p];
    n.extend(gn);
    let mut tt = vec![0.0];
    tt.extend(gt);
    (n, tt)
}

/// Bilinear coefficient of u_l v_m from the table (polarization; exact for a bilinear term).
fn table_cross(t: &QuadraticMembrane, l: usize, ub: bool, m: usize, vb: bool) -> (Vec<f64>, Vec<f64>) {
    let (il, im) = (l / 2 - 1, m / 2 - 1);
    if l == m && ub == vb {
        return table(t, &[(il, ub, 1.0)]);
    }
    let (n, tt) = table(t, &[(il, ub, 1.0), (im, vb, 1.0)]);
    let (n1, t1) = table(t, &[(il, ub, 1.0)]);
    let (n2, t2) = table(t, &[(im, vb, 1.0)]);
    let d = |a: &[f64], b: &[f64], c: &[f64]| a.iter().zip(b).zip(c).map(|((x, y), z)| x - y - z).collect::<Vec<f64>>();
    (d(&n, &n1, &n2), d(&tt, &t1, &t2))
}

fn check(law: Law, name: &str, args: (f64, f64)) -> f64 {
    let (paper, tension) = (term(name, Form::Paper, args), term(name, Form::Tension, args));
    let mut worst: f64 = 0.0;
    for (l, m) in [(2, 2), (2, 4), (4, 6), (6, 6), (2, 16), (8, 12), (16, 16)] {
        let jmax = l + m;
        for (ub, vb) in [(false, false), (false, true), (true, false), (true, true)] {
            if l == m && ub && !vb {
                continue; // the same coefficient as (a_l, b_l)
            }
            let amp = |n: usize, b: bool, e: f64| Amp { n, a: if b { 0.0 } else { e }, b: if b { e } else { 0.0 } };
            let step = |n: usize, b: bool| {
                let (ha, hb) = steps(R, n, 0.02);
                if b { hb } else { ha }
            };
            let oracle: Vec<[f64; 3]> = if l == m && ub == vb {
                let f: Vec<Vec<[f64; 3]>> = (0..9).map(|i| projected(law, R, R0, &[amp(l, ub, (i as f64 - 4.0) * step(l, ub))], jmax)).collect();
                (0..=jmax).map(|j| [0, 1, 2].map(|c| second(|e| f[((e / step(l, ub)).round() as i64 + 4) as usize][j][c], step(l, ub)) / 2.0)).collect()
            } else {
                let (hl, hm) = (step(l, ub), step(m, vb));
                let mut f = vec![vec![Vec::new(); 9]; 9];
                for (i, row) in f.iter_mut().enumerate() {
                    for (k, cell) in row.iter_mut().enumerate() {
                        if i == 4 || k == 4 {
                            continue; // the stencil of a mixed first derivative skips the centre lines
                        }
                        *cell = projected(law, R, R0, &[amp(l, ub, (i as f64 - 4.0) * hl), amp(m, vb, (k as f64 - 4.0) * hm)], jmax);
                    }
                }
                let at = |x: f64, y: f64, j: usize, c: usize| f[((x / hl).round() as i64 + 4) as usize][((y / hm).round() as i64 + 4) as usize][j][c];
                (0..=jmax).map(|j| [0, 1, 2].map(|c| mixed(|x, y| at(x, y, j, c), hl, hm))).collect()
            };
            let (pn, pt) = table_cross(&paper, l, ub, m, vb);
            let (_, tt) = table_cross(&tension, l, ub, m, vb);
            for (c, want) in [(0, &pn), (1, &pt), (2, &tt)] {
                let scale = (0..=jmax.min(2 * MODES)).step_by(2).map(|j| want[j / 2].abs()).fold(1e-300, f64::max);
                for j in 0..=jmax {
                    let got = oracle[j][c];
                    let w = if j % 2 == 0 && j / 2 < want.len() && (c == 0 || j > 0) { want[j / 2] } else { 0.0 };
                    let e = (got - w).abs() / scale;
                    assert!(e <= 1e-8, "{name} (l, m, j) = ({l}, {m}, {j}) b = ({ub}, {vb}) load {c}: oracle {got:e} vs table {w:e} (scale {scale:e}: {e:.1e})");
                    worst = worst.max(e);
                }
            }
        }
    }
    worst
}

#[test]
fn mooney_rivlin_second_order_loads_match_the_finite_amplitude_oracle() {
    let worst = check(Law::MooneyRivlin { c1: 0.9, c2: 0.25 }, "mooney_rivlin", (0.9, 0.25));
    eprintln!("Mooney–Rivlin: worst relative difference {worst:.2e}");
}

#[test]
fn skalak_second_order_loads_match_the_finite_amplitude_oracle() {
    let worst = check(Law::Skalak { gs: 0.8, c: 1.7 }, "skalak", (0.8, 1.7));
    eprintln!("Skalak: worst relative difference {worst:.2e}");
}
