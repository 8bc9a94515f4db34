//! Natural frequencies (corrected eq 3.10, FORMULATION §4.4).
use crate::common;
use magbubble::analysis::frequencies::natural_frequencies;

fn closed_form_nondim(k: f64, alpha: f64) -> f64 {
    // (ω_k t*)² = 6(1+α)(k−1)(k+1)(k+2)/(2k²+2k−1)
    (6.0 * (1.0 + alpha) * (k - 1.0) * (k + 1.0) * (k + 2.0) / (2.0 * k * k + 2.0 * k - 1.0)).sqrt()
}

#[test]
fn no_field_matches_the_closed_form_and_collapses_in_r0() {
    let alpha = common::C2 / common::C1;
    let mut first: Option<Vec<f64>> = None;
    for r0 in [5e-6, 10e-6, 20e-6] {
        let mut s = common::scene(16, 0.0, 1e6);
        s.bubble.radius = r0;
        s.bubble.initial.radius = r0;
        let f = natural_frequencies(&s, 16).unwrap();
        assert_eq!(f.shape.len(), 15);
        let ks: Vec<usize> = f.shape.iter().map(|m| m.k).collect();
        assert_eq!(ks, (2..=16).collect::<Vec<_>>());
        for m in &f.shape {
            let expect = closed_form_nondim(m.k as f64, alpha);
            assert!((m.omega_nondim - expect).abs() < 1e-10 * expect, "k={} {} vs {}", m.k, m.omega_nondim, expect);
            // SI: ω² = 12(c1+c2)(k−1)(k+1)(k+2)/[ρR0³(2k²+2k−1)]
            let k = m.k as f64;
            let si = (12.0 * (common::C1 + common::C2) * (k - 1.0) * (k + 1.0) * (k + 2.0)
                / (1000.0 * r0.powi(3) * (2.0 * k * k + 2.0 * k - 1.0)))
                .sqrt();
            assert!((m.omega_rad_s - si).abs() < 1e-9 * si);
        }
        let nd: Vec<f64> = f.shape.iter().map(|m| m.omega_nondim).collect();
        if let Some(prev) = &first {
            for (a, b) in prev.iter().zip(&nd) {
                assert!((a - b).abs() < 1e-12 * a);
            }
        } else {
            first = Some(nd);
        }
    }
}

#[test]
fn radial_frequency_is_the_linearised_one() {
    // ω0² = [3κ p0 + R0 Ŝ0'(R0)]/(ρR0²), Ŝ0'(R0) = 24(c1+c2)/R0² (from Ŝ0 of §4.1).
    let s = common::scene(4, 0.0, 1e6);
    let f = natural_frequencies(&s, 4).unwrap();
    let r0 = common::R0;
    let w2 = (3.0 * 1.4 * 101325.0 + 24.0 * (common::C1 + common::C2) / r0) / (1000.0 * r0 * r0);
    assert!((f.radial.omega_rad_s - w2.sqrt()).abs() < 1e-6 * w2.sqrt(), "{} vs {}", f.radial.omega_rad_s, w2.sqrt());
}

/// The coil lowers every ω_k by a small relative shift δ_k that is, to first order, linear in the
/// magnetic loads: they scale with ℋ ∝ H² ∝ I² (a static current), and the mode couplings
/// k → k ± 2 move the eigenvalues only at second order (∝ I⁴). So δ_k(I)/δ_k(I/2) = 4 up to a
/// relative O(δ_k) — asserted within 10 max δ_k (measured δ_k ≈ 1e-4 … 2e-4 at 100 kA). A shift
/// that did not come from the I²-scaled loads, or a coupling wrongly on the diagonal, breaks it.
#[test]
fn a_coil_field_shifts_every_mode_only_slightly() {
    let plain = natural_frequencies(&common::scene(8, 0.0, 1e6), 8).unwrap();
    let shifts_at = |current: f64| {
        let mut s = common::scene(8, 0.0, 1e6);
        s.field = Some(common::coil(current));
        let with = natural_frequencies(&s, 8).unwrap();
        plain
            .shape
            .iter()
            .zip(&with.shape)
            .map(|(p, w)| {
                assert_eq!(p.k, w.k);
                // Odd k get their couplings from the same tables (MagneticLoads::odd): they shift too.
                assert!(w.field_couplings, "k = {}", w.k);
                (p.omega_nondim - w.omega_nondim) / p.omega_nondim
            })
            .collect::<Vec<f64>>()
    };
    let (full, half) = (shifts_at(100e3), shifts_at(50e3));
    let largest = full.iter().copied().fold(0.0, f64::max);
    for (i, (f, h)) in full.iter().zip(&half).enumerate() {
        let k = plain.shape[i].k;
        let ratio = f / h;
        eprintln!("k={k}: δ(100 kA) {f:.4e}, δ(50 kA) {h:.4e}, ratio {ratio:.6}");
        assert!(*f > 0.0 && *h > 0.0, "k = {k}: the field lowers ω_k ({f:e}, {h:e})");
        assert!((ratio / 4.0 - 1.0).abs() < 10.0 * largest, "k = {k}: δ(I)/δ(I/2) = {ratio}, not 4 (ℋ ∝ I²)");
    }
    // The odd shifts (odd couplings) fall in line with the even ones (even couplings): the
    // relative lowering decreases monotonically over k = 2, 3, …, 8.
    assert!(full.windows(2).all(|w| w[0] > w[1] && w[1] > 0.0), "{full:?}");
}

#[test]
fn odd_modes_beyond_the_tables_are_refused_with_a_field() {
    let mut s = common::scene(8, 0.0, 1e6);
    s.field = Some(common::coil(100e3));
    let e = natural_frequencies(&s, 65).unwrap_err().to_string();
    assert!(e.contains("k = 65") && e.contains("k ≤ 64"), "{e}");
    // Without a field the odd frequencies need no table: k = 65 is computed.
    s.field = None;
    let f = natural_frequencies(&s, 65).unwrap();
    assert_eq!(f.shape.last().map(|m| m.k), Some(65));
}

/// `modes` lists odd k too (issue 13 part 6), but says which k the time-domain commands evolve:
/// `evolved` is true exactly for the orders in `run`'s series (the even set up to max_order).
#[test]
fn modes_json_says_which_orders_run_evolves() {
    let s = common::scene(6, 0.0, 1e6);
    let f = magbubble::api::modes::frequencies(&s, Some(6), "test").unwrap();
    let j = serde_json::to_value(magbubble::api::modes::Modes::Frequencies(f)).unwrap();
    let header = magbubble::output::series_header(&s);
    for m in j["shape"].as_array().unwrap() {
        let k = m["k"].as_u64().unwrap();
        let in_series = header.contains(&format!("a{k}"));
        assert_eq!(m["evolved"].as_bool().unwrap(), in_series, "k = {k}: {m}");
    }
    assert_eq!(j["shape"].as_array().unwrap().len(), 5);
}
