//! The quadrature against the generated triple products and the plain sums; the kernels'
//! clones bit for bit.

use super::*;
use crate::coefficients::quadratic_lookup::ppp;

/// C(j, l, m) = (2j + 1)/2 ∫ P_l P_m P_j from the generated exact table.
fn projection(j: usize, l: usize, m: usize) -> f64 {
    ppp(l, m, j) * (2.0 * j as f64 + 1.0) / 2.0
}

/// (2j + 1)/2 ∫ P_l P_m P_j by the Adams–Neumann closed form (any parities): with
/// 2s = l + m + j even, 2/(2s + 1) · A(s − l) A(s − m) A(s − j)/A(s), A(k) = (2k)!/(2^k k!)².
fn adams(j: usize, l: usize, m: usize) -> f64 {
    let s2 = l + m + j;
    if s2 % 2 == 1 || j > l + m || l > m + j || m > l + j {
        return 0.0;
    }
    let s = s2 / 2;
    let a = |k: usize| (1..=k).fold(1.0, |acc, i| acc * (2 * i - 1) as f64 / (2 * i) as f64);
    (2.0 * j as f64 + 1.0) / 2.0 * 2.0 / (2 * s + 1) as f64 * a(s - l) * a(s - m) * a(s - j) / a(s)
}

/// The rule integrates P_l P_m P_j exactly (to rounding) for every l, m, j of the mode set:
/// the generated triple products at k ≤ 32 even (half the nodes), the closed form at k ≤ 12
/// all (every node).
#[test]
fn the_rule_gives_the_generated_triple_products() {
    for orders in [(1..=16).map(|i| 2 * i).collect::<Vec<usize>>(), (1..=12).collect()] {
        let even = orders.iter().all(|k| k % 2 == 0);
        let outputs: Vec<(usize, usize)> = std::iter::once(0).chain(orders.iter().copied()).map(|j| (0, j)).collect();
        let one = [Monomial { set: 0, power: 0, first: (0, 0), second: (1, 0), mono: 0, value: 1.0 }];
        let g = GaussProduct::new(&orders, &outputs, 2, 1, &one).expect("k ≤ 32");
        let n = orders.len();
        let mut worst: f64 = 0.0;
        for l in 0..n {
            for m in 0..n {
                let mut amp = vec![0.0; 2 * n];
                (amp[l], amp[n + m]) = (1.0, 1.0);
                let mut out = vec![0.0; outputs.len()];
                g.eval(&[1.0], &amp, &mut out);
                for (&(_, j), got) in outputs.iter().zip(&out) {
                    let want = if even { projection(j, orders[l], orders[m]) } else { adams(j, orders[l], orders[m]) };
                    worst = worst.max((got - want).abs());
                }
            }
        }
        // rounding of a sum over ≤ 49 nodes of O(1) terms
        assert!(worst <= 1e-14, "orders {orders:?}: worst |Δ C| {worst:e}");
    }
    // and the rule is the smallest exact one: one node fewer misses the top degree
    let cube = |n: usize| {
        let (x, w) = gauss_legendre(n);
        x.iter().zip(&w).map(|(&x, &w)| w * legendre(32, x).powi(3)).sum::<f64>() * 65.0 / 2.0
    };
    let exact = projection(32, 32, 32);
    assert!((adams(32, 32, 32) - exact).abs() <= 1e-15, "the closed form against the table");
    assert!((cube(49) - exact).abs() <= 1e-14, "49 nodes: {} against {exact}", cube(49));
    assert!((cube(48) - exact).abs() > 1e-6, "48 nodes: {} against {exact}", cube(48));
}

/// The four steps equal the plain sum Σ_{l,m} C · v p L_l^a L_m^b L_j^c x_l y_m, with powers
/// of L_j from −1 to 3, symmetric and asymmetric kinds, two output sets and three prefactors.
#[test]
fn eval_is_the_plain_sum() {
    let orders: Vec<usize> = (1..=8).map(|i| 2 * i).collect();
    let n = orders.len();
    let mut outputs: Vec<(usize, usize)> = std::iter::once(0).chain(orders.iter().copied()).map(|j| (0, j)).collect();
    outputs.extend(orders.iter().map(|&j| (1, j)));
    let mut terms = Vec::new();
    for (i, (set, power, fk, fa, sk, sa)) in [(0, 0, 0, 0, 0, 1), (0, 1, 0, 2, 1, 0), (0, 2, 1, 1, 1, 1), (1, -1, 1, 3, 1, 0), (1, 0, 0, 1, 1, 2), (1, 3, 0, 0, 1, 0), (0, 0, 1, 0, 0, 0), (1, -1, 0, 0, 0, 2)].into_iter().enumerate() {
        terms.push(Monomial { set, power, first: (fk, fa), second: (sk, sa), mono: i % 3, value: 0.5 + 0.37 * i as f64 * if i % 2 == 0 { 1.0 } else { -1.0 } });
    }
    let g = GaussProduct::new(&orders, &outputs, 2, 3, &terms).expect("k ≤ 16");
    let p = [1.3, -0.7, 2.1];
    let amp: Vec<f64> = (0..2 * n).map(|i| ((i as f64) * 0.77).sin() * 1e-2).collect();
    let mut out = vec![0.25; outputs.len()];
    g.eval(&p, &amp, &mut out);
    let big = |k: usize| (k * (k + 1)) as f64;
    for (o, &(set, j)) in outputs.iter().enumerate() {
        let (mut want, mut scale) = (0.25, 0.25f64);
        for t in terms.iter().filter(|t| t.set == set && !(t.power < 0 && j == 0)) {
            for l in 0..n {
                for m in 0..n {
                    let v = projection(j, orders[l], orders[m]) * t.value * p[t.mono] * big(orders[l]).powi(t.first.1 as i32) * big(orders[m]).powi(t.second.1 as i32) * big(j).powi(t.power) * amp[t.first.0 * n + l] * amp[t.second.0 * n + m];
                    want += v;
                    scale += v.abs();
                }
            }
        }
        assert!((out[o] - want).abs() <= 1e-14 * scale, "output {o} ({set}, {j}): {} against {want} (scale {scale:e})", out[o]);
    }
}

/// The AVX and AVX-512 kernels give the portable one's result bit for bit (k ≤ 16: 2 blocks of
/// nodes, k ≤ 32: 4 blocks).
#[test]
fn the_clones_are_the_portable_kernel_bit_for_bit() {
    for kmax in [16usize, 32] {
        let orders: Vec<usize> = (1..=kmax / 2).map(|i| 2 * i).collect();
        let n = orders.len();
        let outputs: Vec<(usize, usize)> = std::iter::once(0).chain(orders.iter().copied()).map(|j| (0, j)).chain(orders.iter().map(|&j| (1, j))).collect();
        let terms: Vec<Monomial> = (0..24)
            .map(|i| Monomial { set: i % 2, power: (i % 4) as i32 - 1, first: (i % 2, (i % 3) as u32), second: ((i / 2) % 2, (i % 4) as u32), mono: i % 2, value: ((i as f64) * 1.3).cos() })
            .collect();
        let g = GaussProduct::new(&orders, &outputs, 2, 2, &terms).expect("k ≤ 32");
        assert_eq!(g.blocks, kmax / 8, "k ≤ {kmax}: 3k/2 + 1 nodes, half of them");
        let amp: Vec<f64> = (0..2 * n).map(|i| ((i as f64) * 0.41).cos() * 1e-3).collect();
        let p = [0.9, -1.7];
        let mut dispatched = vec![0.5; outputs.len()];
        g.eval(&p, &amp, &mut dispatched);
        let mut s = vec![0.0; g.scratch_len()];
        let (k, coef, rows) = g.split(&mut s);
        g.prepare(&p, &amp, k, coef);
        let mut portable = vec![0.5; outputs.len()];
        g.steps_portable(k, coef, rows, &mut portable);
        #[allow(unused_mut)]
        let mut clones = vec![("dispatched", dispatched)];
        #[cfg(target_arch = "x86_64")]
        {
            if std::arch::is_x86_feature_detected!("avx") {
                let mut avx = vec![0.5; outputs.len()];
                // SAFETY: AVX checked just above; the slices as `eval` lays them out.
                unsafe {
                    match g.blocks {
                        2 => g.steps_avx::<2, 4>(&p, &amp, k, coef, rows, &mut avx),
                        _ => g.steps_avx::<4, 8>(&p, &amp, k, coef, rows, &mut avx),
                    }
                }
                clones.push(("AVX", avx));
            }
            if std::arch::is_x86_feature_detected!("avx512f") {
                let mut avx = vec![0.5; outputs.len()];
                // SAFETY: AVX-512F checked just above; as above.
                unsafe {
                    match g.blocks {
                        2 => g.steps_avx512::<2, 2>(&p, &amp, k, coef, rows, &mut avx),
                        _ => g.steps_avx512::<4, 4>(&p, &amp, k, coef, rows, &mut avx),
                    }
                }
                clones.push(("AVX-512", avx));
            }
        }
        assert!(portable.iter().any(|&x| x != 0.5), "k ≤ {kmax}: no load");
        for (name, c) in &clones {
            for (a, b) in portable.iter().zip(c) {
                assert_eq!(a.to_bits(), b.to_bits(), "k ≤ {kmax} {name}: {a} against {b}");
            }
        }
    }
}
