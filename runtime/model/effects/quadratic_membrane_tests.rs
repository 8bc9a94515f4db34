//! Tests of [`super::QuadraticMembrane`]'s SIMD paths (quadratic_membrane.rs).

use super::*;
use crate::coefficients::quadratic_membrane::Form;

/// The AVX factors, row sums and the Jacobian assembled with them are the portable ones bit
/// for bit.
#[cfg(target_arch = "x86_64")]
#[test]
fn avx_jacobian_is_the_portable_one() {
    if !std::arch::is_x86_feature_detected!("avx") {
        return;
    }
    let v = |i: usize, s: f64| ((i as f64) * s + 0.2).sin();
    for np in 1..=MAXP {
        let c: Vec<f64> = (0..PRODUCTS * np).map(|i| if i % 5 == 3 { 0.0 } else { v(i, 0.91) * 1e3 }).collect();
        let (p, d): (Vec<f64>, Vec<f64>) = (0..np).map(|i| (v(i, 1.3), -v(i, 0.4) * 1e-3)).unzip();
        let (a, b) = row_sums(&c, &p, &d);
        // SAFETY: AVX checked above.
        let (x, y) = unsafe { row_sums_avx(&c, &p, &d) };
        assert_eq!(a.map(f64::to_bits), x.map(f64::to_bits), "{np} prefactors");
        assert_eq!(b.map(f64::to_bits), y.map(f64::to_bits), "{np} prefactors");
    }
    let modes = 6;
    let z: Vec<f64> = (0..crate::model::layout::StateLayout::reduced(modes).dim()).map(|i| if i == 0 { 1.1 } else { 0.05 * v(i, 2.1) }).collect();
    let at = At { t: 0.0, z: &z };
    for np in 1..=MAXP {
        let p: Vec<f64> = (0..np).map(|i| v(i, 0.77) * 3.0).collect();
        let len = modes * PRODUCTS * np;
        let (mut l0, mut r0, mut l1, mut r1) = (vec![0.0; len], vec![0.0; len], vec![1.0; len], vec![1.0; len]);
        factors_portable(&at, &p, &mut l0, &mut r0);
        factors(&at, &p, &mut l1, &mut r1);
        assert_eq!(l0.iter().map(|x| x.to_bits()).collect::<Vec<_>>(), l1.iter().map(|x| x.to_bits()).collect::<Vec<_>>(), "{np} prefactors");
        assert_eq!(r0, r1, "{np} prefactors");
    }
    let orders: Vec<f64> = (1..=modes).map(|i| 2.0 * i as f64).collect();
    for (name, form) in [("mooney_rivlin", Form::Paper), ("mooney_rivlin", Form::Tension), ("skalak", Form::Paper)] {
        let t = QuadraticMembrane::new(QuadraticMembrane::law(name).unwrap(), form, 1.0, (0.9, 0.3), &orders).unwrap();
        let (p, d) = t.prefactors(at.r());
        let np = t.monos.len();
        let (mut avx, mut portable) = (LoadJacobian::new(modes), LoadJacobian::new(modes));
        t.add_jacobian(&at, &mut avx);
        t.jacobian_with(&at, &mut portable, |c| row_sums(c, &p[..np], &d[..np]));
        for (x, y) in [(&avx.pressure, &portable.pressure), (&avx.gn, &portable.gn), (&avx.gt, &portable.gt)] {
            assert_eq!(x.iter().map(|v| v.to_bits()).collect::<Vec<_>>(), y.iter().map(|v| v.to_bits()).collect::<Vec<_>>(), "{name} {form:?}");
        }
    }
}
