//! The quadratic (second-order) free-bubble tables (codegen → `coefficients::quadratic`, issue 12)
//! against an independent f64 oracle (`support::potential_flow`): the dynamic condition on a
//! surface with two finite amplitudes, the potential solved numerically on the exact surface,
//! and the bilinear coefficient from second differences in the two amplitudes (8th-order
//! stencils). ≤ 1e-8 relative for l, m ≤ 16.

use crate::support::potential_flow::{Flow, Mode, Oracle};
use crate::support::shell_energy::{mixed, second};
use magbubble::coefficients::quadratic::FREE_BUBBLE;

const FLOW: Flow = Flow { rho: 1.1, gamma: 0.7, pg: 1.3, kappa: 1.4, p_inf: 0.9, radial: [1.05, 0.3, -0.2] };
const AMP_L: [f64; 3] = [0.8, -0.5, 0.9];
const AMP_M: [f64; 3] = [-0.6, 0.4, 0.3];

fn symbol(s: &str) -> Option<f64> {
    Some(match s {
        "rho" => FLOW.rho,
        "gamma" => FLOW.gamma,
        "pg" => FLOW.pg,
        "kappa" => FLOW.kappa,
        "R" => FLOW.radial[0],
        "Rd" => FLOW.radial[1],
        "Rdd" => FLOW.radial[2],
        _ => return None,
    })
}

/// ∂²F_j/∂ε_l∂ε_m (l ≠ m) or ∂²F_j/∂ε² (l = m) from the tables, and the sum of the magnitudes
/// of its terms (the scale of the comparison). F = s_j × (table load), s_0 = +1, s_j = −1.
fn predicted(j: usize, l: usize, m: usize) -> (f64, f64) {
    let s = if j == 0 { 1.0 } else { -1.0 };
    let (mut sum, mut scale) = (0.0, 0.0);
    for t in FREE_BUBBLE {
        let pre = t.prefactor_at(symbol).expect("known symbols");
        let (x, y) = (t.first.order(), t.second.order());
        let parts = if l == m {
            vec![2.0 * t.value(j, l, l) * AMP_L[x] * AMP_L[y]]
        } else {
            vec![t.value(j, l, m) * AMP_L[x] * AMP_M[y], t.value(j, m, l) * AMP_M[x] * AMP_L[y]]
        };
        for p in parts {
            sum += s * pre * p;
            scale += (pre * p).abs();
        }
    }
    (sum, scale)
}

fn check_pair(l: usize, m: usize) -> f64 {
    let jmax = l + m;
    let oracle = Oracle::new(jmax + 6);
    let mode = |n: usize, amp: [f64; 3], e: f64| Mode { n, amp: amp.map(|v| v * e) };
    // steps on the scale the response varies on, R/(k+1)
    let (hl, hm) = (0.02 * FLOW.radial[0] / (l as f64 + 1.0), 0.02 * FLOW.radial[0] / (m as f64 + 1.0));
    let mut worst: f64 = 0.0;
    let per_j: Vec<Vec<f64>> = if l == m {
        // ∂²/∂ε² of every F_j at once: evaluate the projections on the stencil
        let cache = std::cell::RefCell::new(std::collections::BTreeMap::new());
        let f = |e: f64, j: usize| {
            let key = (e * 1e12).round() as i64;
            let v = cache.borrow_mut().entry(key).or_insert_with(|| oracle.residual(&FLOW, &[mode(l, AMP_L, e)], jmax)).clone();
            v[j]
        };
        (0..=jmax).map(|j| vec![second(|e| f(e, j), hl)]).collect()
    } else {
        let cache = std::cell::RefCell::new(std::collections::BTreeMap::new());
        let f = |el: f64, em: f64, j: usize| {
            let key = ((el * 1e12).round() as i64, (em * 1e12).round() as i64);
            let v = cache.borrow_mut().entry(key).or_insert_with(|| oracle.residual(&FLOW, &[mode(l, AMP_L, el), mode(m, AMP_M, em)], jmax)).clone();
            v[j]
        };
        (0..=jmax).map(|j| vec![mixed(|a, b| f(a, b, j), hl, hm)]).collect()
    };
    for j in (l.abs_diff(m)..=jmax).step_by(2) {
        let (want, scale) = predicted(j, l, m);
        let got = per_j[j][0];
        let e = (got - want).abs() / scale;
        assert!(e <= 1e-8, "(l, m, j) = ({l}, {m}, {j}): oracle {got:e} vs tables {want:e} (relative to {scale:e}: {e:.1e})");
        worst = worst.max(e);
    }
    // the selection rules: nothing on the targets outside |l − m| ≤ j ≤ l + m (odd j included)
    for j in 0..l.abs_diff(m) {
        assert!(per_j[j][0].abs() <= 1e-8 * predicted(l.abs_diff(m), l, m).1, "({l}, {m}) leaks onto j = {j}: {:e}", per_j[j][0]);
    }
    worst
}

#[test]
fn quadratic_tables_match_the_finite_amplitude_oracle_for_l_m_le_16() {
    let mut worst: f64 = 0.0;
    for (l, m) in [(2, 2), (2, 4), (4, 6), (6, 6), (2, 16), (8, 12), (16, 16)] {
        let e = check_pair(l, m);
        eprintln!("(l, m) = ({l}, {m}): worst relative difference {e:.2e}");
        worst = worst.max(e);
    }
    eprintln!("worst over all pairs and targets: {worst:.2e}");
}
