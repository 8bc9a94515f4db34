//! The exact algebra under the tables: Legendre series, division by 1 − x², projections, fits.

use codegen::algebra::legendre::{self, Basis};
use codegen::algebra::{rat, ratio, Poly, Rat};
use codegen::derive::fit::fit_rational;
use codegen::derive::project::{project, Amp, Load};

#[test]
fn series_operations_match_the_recurrences() {
    // x P_3 = (4 P_4 + 3 P_2)/7
    let mut p3 = vec![rat(0); 4];
    p3[3] = rat(1);
    assert_eq!(legendre::mul_x(&p3), vec![rat(0), rat(0), ratio(3, 7), rat(0), ratio(4, 7)]);
    // P_4' = 7 P_3 + 3 P_1
    let mut p4 = vec![rat(0); 5];
    p4[4] = rat(1);
    assert_eq!(legendre::derivative(&p4), vec![rat(0), rat(3), rat(0), rat(7)]);
    // (1 − x²) G / (1 − x²) = G
    let g: Vec<Rat> = (0..9).map(|i| ratio(i * i - 3, i + 2)).collect();
    let n = legendre::poly_times(&[rat(1), rat(0), rat(-1)], &g);
    assert_eq!(legendre::div_one_minus_x2(&n).unwrap(), g);
    assert!(legendre::div_one_minus_x2(&g).is_err(), "G is not divisible by 1 − x²");
}

#[test]
fn mode_shapes_project_onto_themselves() {
    let mut basis = Basis::default();
    for k in [2usize, 5, 16] {
        // a_k P_k → 1 on P_k; b_k P^1_k = −s P_k' b_k → 1 on P^1_k
        let a = Poly::var("#a").mul(&Poly::var("#P0"));
        let b = Poly::var("#b").mul(&Poly::var("#s")).mul(&Poly::var("#P1")).neg();
        let pa = project(&a, Load::Normal, k, &mut basis).unwrap();
        let pb = project(&b, Load::Tangential, k, &mut basis).unwrap();
        let unit = |s: &Vec<Rat>| s.iter().enumerate().all(|(j, v)| *v == if j == k { rat(1) } else { rat(0) });
        assert!(pa.values().all(unit) && pa.keys().all(|(amp, _)| *amp == Some(Amp::A)));
        assert!(pb.values().all(unit) && pb.keys().all(|(amp, _)| *amp == Some(Amp::B)));
    }
}

#[test]
fn rational_fit_recovers_and_rejects() {
    let f = |k: i64| ratio(-13 * k * k - 13 * k + 6, (2 * k - 1) * (2 * k + 3));
    let pts: Vec<(i64, Rat)> = (2..40).map(|k| (k, f(k))).collect();
    let form = fit_rational(&pts).expect("found");
    assert_eq!(form.text(), "(-13*k^2 - 13*k + 6)/((2*k - 1)*(2*k + 3))");
    // one wrong value beyond the fit window: no form verifies
    let mut bad = pts.clone();
    bad[30].1 += rat(1);
    assert!(fit_rational(&bad).map_or(true, |c| (2..40).all(|k| c.eval(k) == bad[(k - 2) as usize].1)));
}
