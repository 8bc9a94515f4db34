//! The second-order bending and shell-viscous loads (issue 12, scope 1; runtime terms
//! effects/quadratic_bending.rs and effects/quadratic_shell_viscosity.rs, tables from codegen's
//! `vary` and `rate` at the bilinear order) against an independent f64 oracle
//! (`support::surface_jets`: the exact nonlinear loads on a surface with two finite amplitudes —
//! bending by the classical Helfrich shape equation, viscosity by the Kelvin–Voigt stress written
//! out — projected by quadrature). The bilinear coefficient of u_l v_m comes from 8th-order second
//! differences in the two amplitudes (the loads are exactly linear in a rate, so a rate's
//! difference is exact). ≤ 1e-8 relative for l, m ≤ 16, on a sphere R ≠ R0.

use crate::support::shell_energy::{mixed, second, steps};
use crate::support::surface_jets::{bending, projected, viscous, Mode};
use magbubble::model::layout::StateLayout;
use magbubble::model::effects::quadratic_bending::QuadraticBending;
use magbubble::model::effects::quadratic_shell_viscosity::QuadraticShellViscosity;
use magbubble::model::effects::second_order::{FirstOrder, MaterialLoads, SecondOrderTerm};
use magbubble::model::effects::{At, Loads, Term};

const R: f64 = 1.08;
const R0: f64 = 1.0;
const MODES: usize = 16; // k = 2 … 32
const PAIRS: [(usize, usize); 7] = [(2, 2), (2, 4), (4, 6), (6, 6), (2, 16), (8, 12), (16, 16)];

/// Amplitude kinds: a, ȧ, b, ḃ.
#[derive(Clone, Copy, Debug, PartialEq)]
enum K {
    A,
    Ad,
    B,
    Bd,
}

fn orders() -> Vec<f64> {
    (1..=MODES).map(|i| 2.0 * i as f64).collect()
}

fn with(n: usize, k: K, v: f64) -> Mode {
    let mut m = Mode { n, ..Mode::default() };
    match k {
        K::A => m.a = v,
        K::Ad => m.ad = v,
        K::B => m.b = v,
        K::Bd => m.bd = v,
    }
    m
}

/// The runtime loads [−P, G_n,j…], [G_t,j…] (index j/2) at R, Ṙ with the given amplitudes.
fn runtime(eval: &dyn Fn(&[f64], &[f64], &mut Loads<'_>), rd: f64, amps: &[(usize, K, f64)]) -> (Vec<f64>, Vec<f64>) {
    let l = StateLayout::reduced(MODES);
    let mut z = vec![0.0; l.dim()];
    let mut bd = vec![0.0; MODES];
    (z[l.r()], z[l.rdot()]) = (R, rd);
    for &(n, k, v) in amps {
        let m = n / 2 - 1;
        match k {
            K::A => z[l.a(m)] += v,
            K::Ad => z[l.adot(m)] += v,
            K::B => z[l.b(m)] += v,
            K::Bd => bd[n / 2 - 1] += v,
        }
    }
    let (mut gn, mut gt) = (vec![0.0; MODES], vec![0.0; MODES]);
    let mut loads = Loads { pressure: 0.0, gn: &mut gn, gt: &mut gt };
    eval(&z, &bd, &mut loads);
    let p = loads.pressure;
    let mut n = vec![-p];
    n.extend(gn);
    let mut t = vec![0.0];
    t.extend(gt);
    (n, t)
}

/// Bilinear coefficient of u_l v_m in the runtime loads (polarization; exact for bilinear loads).
fn runtime_cross(eval: &dyn Fn(&[f64], &[f64], &mut Loads<'_>), rd: f64, l: usize, u: K, m: usize, v: K) -> (Vec<f64>, Vec<f64>) {
    if l == m && u == v {
        return runtime(eval, rd, &[(l, u, 1.0)]);
    }
    let (n, t) = runtime(eval, rd, &[(l, u, 1.0), (m, v, 1.0)]);
    let (n1, t1) = runtime(eval, rd, &[(l, u, 1.0)]);
    let (n2, t2) = runtime(eval, rd, &[(m, v, 1.0)]);
    let d = |a: &[f64], b: &[f64], c: &[f64]| a.iter().zip(b).zip(c).map(|((x, y), z)| x - y - z).collect::<Vec<f64>>();
    (d(&n, &n1, &n2), d(&t, &t1, &t2))
}

/// The oracle's bilinear coefficient of u_l v_m (second differences of the projected loads).
fn oracle_cross(load: &dyn Fn(&[Mode], f64) -> (f64, f64), l: usize, u: K, m: usize, v: K) -> Vec<[f64; 2]> {
    let jmax = l + m;
    let step = |n: usize, k: K| {
        let (ha, hb) = steps(R, n, 0.02);
        if matches!(k, K::A | K::Ad) { ha } else { hb }
    };
    let proj = |modes: &[Mode]| projected(l.max(m), jmax, |th| load(modes, th));
    if l == m && u == v {
        let h = step(l, u);
        let f: Vec<Vec<[f64; 2]>> = (0..9).map(|i| proj(&[with(l, u, (i as f64 - 4.0) * h)])).collect();
        return (0..=jmax).map(|j| [0, 1].map(|c| second(|e| f[((e / h).round() as i64 + 4) as usize][j][c], h) / 2.0)).collect();
    }
    let (hl, hm) = (step(l, u), step(m, v));
    let mut f = vec![vec![Vec::new(); 9]; 9];
    for (i, row) in f.iter_mut().enumerate() {
        for (k, cell) in row.iter_mut().enumerate() {
            if i == 4 || k == 4 {
                continue; // the mixed first-derivative stencil skips the centre lines
            }
            *cell = proj(&[with(l, u, (i as f64 - 4.0) * hl), with(m, v, (k as f64 - 4.0) * hm)]);
        }
    }
    let at = |x: f64, y: f64, j: usize, c: usize| f[((x / hl).round() as i64 + 4) as usize][((y / hm).round() as i64 + 4) as usize][j][c];
    (0..=jmax).map(|j| [0, 1].map(|c| mixed(|x, y| at(x, y, j, c), hl, hm))).collect()
}

/// One coefficient's comparison: name, oracle per target, runtime (normal, tangential).
type Case = (String, Vec<[f64; 2]>, (Vec<f64>, Vec<f64>));

/// Worst relative difference over the cases of one pair, targets j ≤ l + m, normal and
/// tangential: relative to the coefficient's own largest value, and at least to 1e-3 of the
/// pair's largest coefficient (a coefficient that vanishes, e.g. bending's b·b, is then checked
/// against the second differences' round-off on the pair's scale).
fn compare_pair(cases: &[Case]) -> f64 {
    let floor = 1e-3 * cases.iter().flat_map(|(_, _, (n, t))| n.iter().chain(t)).fold(0.0f64, |m, x| m.max(x.abs()));
    cases.iter().map(|(what, oracle, w)| compare(what, oracle, w, floor)).fold(0.0, f64::max)
}

fn compare(what: &str, oracle: &[[f64; 2]], (wn, wt): &(Vec<f64>, Vec<f64>), floor: f64) -> f64 {
    let mut worst: f64 = 0.0;
    for (c, want) in [(0, wn), (1, wt)] {
        let scale = want.iter().map(|x| x.abs()).chain(oracle.iter().map(|o| o[c].abs())).fold(floor.max(1e-300), f64::max);
        for (j, o) in oracle.iter().enumerate() {
            let w = if j % 2 == 0 && j / 2 < want.len() && (c == 0 || j > 0) { want[j / 2] } else { 0.0 };
            let e = (o[c] - w).abs() / scale;
            assert!(e <= 1e-8, "{what} j = {j} load {c}: oracle {:e} vs table {w:e} (scale {scale:e}: {e:.1e})", o[c]);
            worst = worst.max(e);
        }
    }
    worst
}

#[test]
fn bending_second_order_loads_match_the_finite_amplitude_oracle() {
    let kb = 0.7;
    let t = QuadraticBending::new(kb, R0, &orders()).expect("generated bending table");
    let eval = |z: &[f64], _: &[f64], l: &mut Loads<'_>| t.add(&At { t: 0.0, z }, l);
    let load = |modes: &[Mode], th: f64| (bending(kb, R, modes, th), 0.0);
    let mut worst: f64 = 0.0;
    for (l, m) in PAIRS {
        let mut cases: Vec<Case> = Vec::new();
        for (u, v) in [(K::A, K::A), (K::A, K::B), (K::B, K::A), (K::B, K::B)] {
            if l == m && u == K::B && v == K::A {
                continue; // the same coefficient as (a_l, b_l)
            }
            cases.push((format!("bending ({l}, {m}) {u:?}·{v:?}"), oracle_cross(&load, l, u, m, v), runtime_cross(&eval, 0.0, l, u, m, v)));
        }
        worst = worst.max(compare_pair(&cases));
    }
    eprintln!("bending: worst relative difference {worst:.2e}");
}

#[test]
fn shell_viscous_second_order_loads_match_the_finite_amplitude_oracle() {
    let (mu, kappa) = (0.6, 1.3);
    let t = QuadraticShellViscosity::new(mu, kappa, R0, &orders()).expect("generated viscous table");
    let eval = |z: &[f64], bd: &[f64], l: &mut Loads<'_>| {
        let add = vec![0.0; MODES];
        t.add(&At { t: 0.0, z }, &FirstOrder { rdd: 0.0, add: &add, bd, material: MaterialLoads::NONE }, l)
    };
    let mut worst: f64 = 0.0;
    for (l, m) in PAIRS {
        // Ṙ·u_l·v_m (static amplitudes, Ṙ = 1) and u_l·v̇_m (Ṙ = 0), both orders of the pair
        let mut cases: Vec<(f64, usize, K, usize, K)> = Vec::new();
        for (u, v) in [(K::A, K::A), (K::A, K::B), (K::B, K::A), (K::B, K::B)] {
            if !(l == m && u == K::B && v == K::A) {
                cases.push((1.0, l, u, m, v));
            }
        }
        let orders = if l == m { vec![(l, m)] } else { vec![(l, m), (m, l)] };
        for (p, q) in orders {
            for u in [K::A, K::B] {
                for v in [K::Ad, K::Bd] {
                    cases.push((0.0, p, u, q, v));
                }
            }
        }
        let mut results: Vec<Case> = Vec::new();
        for (rd, p, u, q, v) in cases {
            let load = |modes: &[Mode], th: f64| viscous(mu, kappa, R, rd, R0, modes, th);
            results.push((format!("viscous Ṙ = {rd} ({p}, {q}) {u:?}·{v:?}"), oracle_cross(&load, p, u, q, v), runtime_cross(&eval, rd, p, u, q, v)));
        }
        worst = worst.max(compare_pair(&results));
    }
    eprintln!("shell viscosity: worst relative difference {worst:.2e}");
}
