//! The generated tables: sanity values, band structure, closed forms against every exact value,
//! and the membrane coefficients against FORMULATION §2 / eq 2.29 (typed here, independently).

use magbubble::coefficients::{self as c, Amp, Load, COIL, COIL_H4, DIPOLE, KMAX};
use std::collections::BTreeSet;

fn powers(m: &c::Monomial) -> BTreeSet<(String, i32)> {
    m.powers.iter().map(|(s, p)| (s.to_string(), *p)).collect()
}

fn set(v: &[(&str, i32)]) -> BTreeSet<(String, i32)> {
    v.iter().map(|(s, p)| (s.to_string(), *p)).collect()
}

#[test]
fn coil_zero_order_and_prefactor() {
    assert_eq!(COIL.components.len(), 1);
    let comp = &COIL.components[0];
    // ℋ = μ0 χ_s H2² R0² / (4 a² R²) (appendix A), force ∝ r
    assert_eq!(comp.prefactor.coeff, 0.25);
    assert_eq!(comp.prefactor.coeff_exact, "1/4");
    assert_eq!(powers(&comp.prefactor), set(&[("mu0", 1), ("chi_s", 1), ("H2", 2), ("R0", 2), ("a", -2), ("R", -2)]));
    assert_eq!(comp.r_power, 1);
    assert_eq!(comp.zero_normal, &[(0, 2.0), (2, 2.0)]);
    assert_eq!(comp.zero_tangential, &[(2, 1.0)]);
}

#[test]
fn dipole_zero_order_and_prefactor() {
    let comp = &DIPOLE.components[0];
    // ℋ = −36 μ0 χ_s M² R0² / (z⁸ R²) (appendix B with its dimension corrected)
    assert_eq!(comp.prefactor.coeff, -36.0);
    assert_eq!(powers(&comp.prefactor), set(&[("mu0", 1), ("chi_s", 1), ("M", 2), ("R0", 2), ("z", -8), ("R", -2)]));
    assert_eq!(comp.r_power, 1);
    assert_eq!(comp.zero_normal, &[(0, -2.0 / 3.0), (2, 2.0 / 3.0)]);
    assert_eq!(comp.zero_tangential, &[(2, 1.0 / 3.0)]);
}

#[test]
fn h2_only_fields_couple_k_to_k_and_k_plus_minus_2_only() {
    // every nonzero projection became a coupling: the offsets are the band
    for t in [&COIL, &DIPOLE] {
        let comp = &t.components[0];
        let offsets: BTreeSet<i32> = comp.couplings.iter().map(|c| c.offset).collect();
        assert_eq!(offsets, BTreeSet::from([-2, 0, 2]), "{}", t.name);
        let names: Vec<&str> = comp.couplings.iter().map(|c| c.name).collect();
        assert_eq!(names, ["F1", "F2", "F3", "F4", "F5", "F6", "F1t", "F2t", "F3t", "F4t", "F5t", "F6t"]);
        let f3 = comp.coupling(Load::Normal, Amp::A, 2).expect("F3");
        assert_eq!(f3.name, "F3");
        assert_eq!(f3.values.len(), KMAX + 1);
        // F3 exists from target 0 (M0 ∋ F3(0) a2); F1 from k = 2; F5 from k = 4; tangential from k = 1
        assert!(f3.at(0).is_some() && t.coupling("F1").unwrap().at(1).is_none());
        assert!(t.coupling("F5").unwrap().at(3).is_none() && t.coupling("F5").unwrap().at(4).is_some());
        assert!(t.coupling("F3t").unwrap().at(0).is_none() && t.coupling("F3t").unwrap().at(1).is_some());
    }
}

#[test]
fn general_coil_has_three_components_with_wider_bands() {
    let band = |comp: &c::Component| comp.couplings.iter().map(|c| c.offset.abs()).max().unwrap_or(0);
    let by_amp = |a: &[(&str, i32)]| {
        COIL_H4
            .components
            .iter()
            .find(|comp| a.iter().all(|x| comp.prefactor.powers.contains(x)) && !comp.prefactor.powers.iter().any(|(s, _)| (*s == "H4" || *s == "H2") && !a.iter().any(|(t, _)| t == s)))
            .expect("component")
    };
    assert_eq!(COIL_H4.components.len(), 3);
    let (h22, h24, h44) = (by_amp(&[("H2", 2)]), by_amp(&[("H2", 1), ("H4", 1)]), by_amp(&[("H4", 2)]));
    assert_eq!((band(h22), band(h24), band(h44)), (2, 4, 6));
    assert_eq!((h22.r_power, h24.r_power, h44.r_power), (1, 3, 5));
    // the H2² component of the general coil is the paper's coil
    assert_eq!(h22.zero_normal, COIL.components[0].zero_normal);
    for cp in COIL.components[0].couplings {
        let other = h22.coupling(cp.load, cp.amp, cp.offset).expect("same coupling");
        assert_eq!(cp.exact, other.exact, "{}", cp.name);
    }
}

#[test]
fn closed_forms_reproduce_every_exact_value() {
    let cfg = codegen::Config::new(concat!(env!("CARGO_MANIFEST_DIR"), "/derivations"), "derivations", KMAX);
    let d = codegen::derive(&cfg).expect("derivations generate");
    let mut checked = 0;
    for f in &d.fields {
        let table = c::field(&f.name).expect("table in the build");
        for (comp, built) in f.components.iter().zip(table.components) {
            for (cp, b) in comp.couplings.iter().zip(built.couplings) {
                assert_eq!(cp.name, b.name);
                let text = cp.closed.as_ref().map(|c| c.text()).unwrap_or_default();
                assert_eq!(text, b.closed_form, "{} {}", f.name, cp.name);
                let Some(form) = &cp.closed else {
                    assert_eq!(f.name, "coil_h4", "{} {} has no closed form", f.name, cp.name);
                    continue;
                };
                for (k, v) in cp.values.iter().enumerate() {
                    if let (Some(v), true) = (v, k as i64 >= form.k0) {
                        assert_eq!(&form.eval(k as i64), v, "{} {} k={k}", f.name, cp.name);
                        assert_eq!(b.exact_at(k), Some(codegen::algebra::rat_text(v).as_str()));
                        checked += 1;
                    }
                }
            }
        }
    }
    assert!(checked > 2000, "checked {checked}");
}

// FORMULATION §2 / §4.1 (eq 2.29), written out independently; n = k(k+1).
fn s0(r: f64, r0: f64, c1: f64, c2: f64) -> f64 {
    c1 * (4.0 / r - 4.0 * r0.powi(6) / r.powi(7)) + c2 * (4.0 * r / r0.powi(2) - 4.0 * r0.powi(4) / r.powi(5))
}
fn s1(r: f64, r0: f64, c1: f64, c2: f64, n: f64) -> f64 {
    c1 * (-(2.0 * n - 28.0) * r0.powi(6) / r.powi(8) + (2.0 * n - 4.0) / r.powi(2))
        + c2 * (-(2.0 * n - 20.0) * r0.powi(4) / r.powi(6) + (2.0 * n + 4.0) / r0.powi(2))
}
fn s2(r: f64, r0: f64, c1: f64, c2: f64, n: f64) -> f64 {
    -12.0 * n * c1 * r0.powi(6) / r.powi(8) + c2 * (-8.0 * n * r0.powi(4) / r.powi(6) - 4.0 * n / r0.powi(2))
}
fn s11(r: f64, r0: f64, c1: f64, c2: f64) -> f64 {
    -c1 * (8.0 * r0.powi(6) / r.powi(8) + 4.0 / r.powi(2)) - c2 * (4.0 * r0.powi(4) / r.powi(6) + 8.0 / r0.powi(2))
}
fn s12(r: f64, r0: f64, c1: f64, c2: f64, n: f64) -> f64 {
    c1 * (4.0 * n * r0.powi(6) / r.powi(8) + (4.0 * n - 4.0) / r.powi(2))
        + c2 * ((4.0 * n - 4.0) * r0.powi(4) / r.powi(6) + 4.0 * n / r0.powi(2))
}
fn sigma0(r: f64, r0: f64, c1: f64, c2: f64) -> f64 {
    let l = r / r0;
    2.0 * c1 * (l * l - l.powi(-4)) + 2.0 * c2 * (l.powi(4) - l.powi(-2))
}

fn close(a: f64, b: f64, what: &str) {
    assert!((a - b).abs() <= 1e-12 * b.abs().max(1.0), "{what}: generated {a} vs FORMULATION {b}");
}

#[test]
fn membrane_matches_formulation_section_2() {
    use c::membrane::{paper, tension};
    for &(r, r0) in &[(1.0, 1.0), (1.3, 1.0), (0.7, 1.1), (2.1e-6, 2.0e-6)] {
        for &(c1, c2) in &[(1.0, 0.0), (0.0, 1.0), (0.3, 0.05)] {
            close(paper::s0(r, r0, c1, c2), s0(r, r0, c1, c2), "S0");
            close(tension::s0(r, r0, c1, c2), s0(r, r0, c1, c2), "S0 tension");
            for k in [2.0, 3.0, 4.0, 7.0, 12.0, 32.0] {
                let n = k * (k + 1.0);
                close(paper::s1(r, r0, c1, c2, k), s1(r, r0, c1, c2, n), "S1");
                close(paper::s2(r, r0, c1, c2, k), s2(r, r0, c1, c2, n), "S2");
                close(paper::s11(r, r0, c1, c2, k), s11(r, r0, c1, c2), "S11");
                close(paper::s12(r, r0, c1, c2, k), s12(r, r0, c1, c2, n), "S12");
                // tension form: F_n unchanged, ΔS11 = +2σ0R0²/R⁴, ΔS12 = −nσ0R0²/R⁴
                let sg = sigma0(r, r0, c1, c2) * r0 * r0 / r.powi(4);
                close(tension::s1(r, r0, c1, c2, k), s1(r, r0, c1, c2, n), "S1 tension");
                close(tension::s2(r, r0, c1, c2, k), s2(r, r0, c1, c2, n), "S2 tension");
                close(tension::s11(r, r0, c1, c2, k), s11(r, r0, c1, c2) + 2.0 * sg, "S11 tension");
                close(tension::s12(r, r0, c1, c2, k), s12(r, r0, c1, c2, n) - n * sg, "S12 tension");
            }
        }
    }
}
