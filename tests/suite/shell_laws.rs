//! The shell laws of derivations/shell/ against independent references (issue 11):
//! * the generated tables against an f64 energy/dissipation oracle (support::shell_energy:
//!   Gauss–Legendre quadrature on the perturbed surface, finite differences), ≤ 1e-9 for k ≤ 32;
//! * the small-strain and linear-order statements: Skalak K = G_s(1 + 2C), Laplace/Lamb for γ,
//!   (k−1)k(k+1)(k+2) k_b/R⁴ for the Helfrich bending energy, 4κ_sṘ/R² for the dilatational
//!   viscosity.

use crate::support::shell_energy::{first, mixed, second, steps, Point, Surface};
use magbubble::coefficients::membrane::{self, bending, mooney_rivlin, skalak, surface_tension, viscous};

const KS: std::ops::RangeInclusive<usize> = 2..=32;
const TOL: f64 = 1e-9;

/// The finite-difference step factor (scanned in docs/derivation-notes.md; env SHELL_ORACLE_STEP
/// overrides it for the scan).
fn step_factor(default: f64) -> f64 {
    std::env::var("SHELL_ORACLE_STEP").ok().and_then(|v| v.parse().ok()).unwrap_or(default)
}
const STEP: f64 = 3e-2;
/// Surface tension: all of its energy is prestress (E = γA), so the round-off of the differences
/// is larger and the optimum step is larger (scan in docs/derivation-notes.md).
const STEP_TENSION: f64 = 1e-1;

/// The five tension-form loads of one law at (R, R0, k).
#[derive(Clone, Copy, Debug)]
struct Loads {
    s0: f64,
    s1: f64,
    s2: f64,
    s11: f64,
    s12: f64,
}

fn rel(a: f64, b: f64, scale: f64) -> f64 {
    (a - b).abs() / scale.max(b.abs())
}

/// Compares the oracle's energy derivatives with the tables; returns the worst relative error.
fn check_energy(what: &str, energy: &dyn Fn(&Point, f64) -> f64, loads: &dyn Fn(f64, usize) -> Loads, r: f64, r0: f64, step: f64) -> f64 {
    let mut worst: f64 = 0.0;
    let surface = |r: f64, k: usize, a: f64, b: f64| Surface { r, r0, k, a, b, rd: 0.0, ad: 0.0, bd: 0.0 };
    // radial: ∂E/∂R = 2R² S0
    let de = first(|h| surface(r + h, 2, 0.0, 0.0).integrate(energy), 1e-3 * r);
    let l = loads(r, 2);
    // parameters are O(1): a zero S0 (R = R0, bending) is compared absolutely
    let e = rel(de, 2.0 * r * r * l.s0, 1.0);
    assert!(e <= TOL, "{what} R={r}: dE/dR {de:e} vs 2R²S0 {:e} ({e:.1e})", 2.0 * r * r * l.s0);
    worst = worst.max(e);
    for k in KS {
        let l = loads(r, k);
        let (kk, nn) = (k as f64, (k * (k + 1)) as f64);
        let norm = 2.0 / (2.0 * kk + 1.0);
        let (ha, hb) = steps(r, k, step_factor(step));
        let en = |a: f64, b: f64| surface(r, k, a, b).integrate(energy);
        let eaa = second(|a| en(a, 0.0), ha);
        let ebb = second(|b| en(0.0, b), hb);
        let eab = mixed(en, ha, hb);
        let kaa = norm * (r * r * l.s1 + 2.0 * r * l.s0);
        let kab = norm * (r * r * l.s2 - nn * r * l.s0);
        let kba = nn * norm * (r * r * l.s11 - r * l.s0);
        let kbb = nn * norm * r * r * l.s12;
        // the scale of the mode's stiffness (a zero entry is compared absolutely on it)
        let scale = kaa.abs().max(kbb.abs() / nn).max(kab.abs()).max(1e-300);
        for (name, oracle, table) in [("E_aa", eaa, kaa), ("E_ab vs S2", eab, kab), ("E_ab vs S11", eab, kba), ("E_bb", ebb, kbb)] {
            let sc = if name == "E_bb" { scale * nn } else { scale };
            let e = (oracle - table).abs() / sc.max(table.abs());
            assert!(e <= TOL, "{what} R={r} k={k}: {name} oracle {oracle:e} vs tables {table:e} ({e:.1e})");
            worst = worst.max(e);
        }
    }
    worst
}

fn hyper(w: impl Fn(f64, f64) -> f64 + Copy, r0: f64) -> impl Fn(&Point, f64) -> f64 {
    move |p: &Point, th: f64| w(p.lambda1, p.lambda2) * r0 * r0 * th.sin()
}

#[test]
fn skalak_tension_form_is_the_first_variation_of_its_energy() {
    let r0 = 1.0;
    for &(gs, c) in &[(1.0, 0.0), (1.0, 0.5), (0.7, 5.0)] {
        let w = move |l1: f64, l2: f64| {
            let i1 = l1 * l1 + l2 * l2 - 2.0;
            let i2 = (l1 * l2).powi(2) - 1.0;
            gs / 4.0 * (i1 * i1 + 2.0 * i1 - 2.0 * i2 + c * i2 * i2)
        };
        let loads = |r: f64, k: usize| {
            let kf = k as f64;
            use skalak::tension as t;
            Loads { s0: t::s0(r, r0, gs, c), s1: t::s1(r, r0, gs, c, kf), s2: t::s2(r, r0, gs, c, kf), s11: t::s11(r, r0, gs, c, kf), s12: t::s12(r, r0, gs, c, kf) }
        };
        for r in [1.0, 1.1, 0.93] {
            let worst = check_energy("skalak", &hyper(w, r0), &loads, r, r0, STEP);
            eprintln!("skalak Gs={gs} C={c} R={r}: worst {worst:.1e}");
        }
    }
}

#[test]
fn mooney_rivlin_tension_form_is_the_first_variation_of_its_energy() {
    let r0 = 1.0;
    let (c1, c2) = (0.5, 0.6);
    let w = move |l1: f64, l2: f64| {
        c1 * (l1 * l1 + l2 * l2 + (l1 * l2).powi(-2) - 3.0) + c2 * (l1.powi(-2) + l2.powi(-2) + (l1 * l2).powi(2) - 3.0)
    };
    let loads = |r: f64, k: usize| {
        let kf = k as f64;
        use mooney_rivlin::tension as t;
        Loads { s0: t::s0(r, r0, c1, c2), s1: t::s1(r, r0, c1, c2, kf), s2: t::s2(r, r0, c1, c2, kf), s11: t::s11(r, r0, c1, c2, kf), s12: t::s12(r, r0, c1, c2, kf) }
    };
    for r in [1.0, 1.1] {
        let worst = check_energy("mooney-rivlin", &hyper(w, r0), &loads, r, r0, STEP);
        eprintln!("mooney-rivlin R={r}: worst {worst:.1e}");
    }
}

#[test]
fn surface_tension_and_bending_are_the_first_variation_of_their_shape_energies() {
    let r0 = 1.0;
    let gamma = 0.3;
    let loads = |r: f64, k: usize| {
        let kf = k as f64;
        use surface_tension::tension as t;
        Loads { s0: t::s0(r, r0, gamma), s1: t::s1(r, r0, gamma, kf), s2: t::s2(r, r0, gamma, kf), s11: t::s11(r, r0, gamma, kf), s12: t::s12(r, r0, gamma, kf) }
    };
    let area = move |p: &Point, _: f64| gamma * p.area;
    for r in [1.0, 1.2] {
        let worst = check_energy("surface tension", &area, &loads, r, r0, STEP_TENSION);
        eprintln!("surface tension R={r}: worst {worst:.1e}");
    }
    let kb = 0.2;
    let loads = |r: f64, k: usize| {
        let kf = k as f64;
        use bending::tension as t;
        Loads { s0: t::s0(r, r0, kb), s1: t::s1(r, r0, kb, kf), s2: t::s2(r, r0, kb, kf), s11: t::s11(r, r0, kb, kf), s12: t::s12(r, r0, kb, kf) }
    };
    let helfrich = move |p: &Point, _: f64| kb / 2.0 * (p.kappa1 + p.kappa2).powi(2) * p.area;
    for r in [1.0, 0.8] {
        let worst = check_energy("bending", &helfrich, &loads, r, r0, STEP);
        eprintln!("bending R={r}: worst {worst:.1e}");
    }
}

#[test]
fn linear_order_statements_of_the_issue_hold() {
    let r0 = 1.3;
    for r in [1.3, 1.0, 1.7] {
        for k in KS {
            let kf = k as f64;
            let n = kf * (kf + 1.0);
            let close = |a: f64, b: f64, what: &str| assert!((a - b).abs() <= 1e-12 * b.abs().max(1e-300), "{what} k={k} R={r}: {a:e} vs {b:e}");
            // Lamb: (k−1)(k+2)γ/R² on a_k, Laplace 2γ/R, nothing on b_k or tangential (tension form)
            close(surface_tension::tension::s1(r, r0, 0.07, kf), (kf - 1.0) * (kf + 2.0) * 0.07 / (r * r), "Lamb");
            close(surface_tension::tension::s0(r, r0, 0.07), 2.0 * 0.07 / r, "Laplace");
            for v in [surface_tension::tension::s2(r, r0, 0.07, kf), surface_tension::tension::s11(r, r0, 0.07, kf), surface_tension::tension::s12(r, r0, 0.07, kf)] {
                assert_eq!(v, 0.0);
            }
            // Helfrich bending: (k−1)k(k+1)(k+2) k_b/R⁴, no radial load, nothing else
            close(bending::paper::s1(r, r0, 2e-19, kf), (kf - 1.0) * kf * (kf + 1.0) * (kf + 2.0) * 2e-19 / r.powi(4), "bending");
            assert_eq!(bending::paper::s0(r, r0, 2e-19), 0.0);
            assert_eq!(bending::paper::s2(r, r0, 2e-19, kf), 0.0);
            // dilatational viscosity: radial 4κ_sṘ/R², and ∂S0/∂Ṙ
            close(viscous::tension::s0(r, r0, 0.4, 0.0, 2e-9), 4.0 * 2e-9 * 0.4 / (r * r), "4κsṘ/R²");
            assert_eq!(viscous::tension::s0(r, r0, 0.4, 3e-9, 0.0), 0.0, "no shear viscosity in the radial load");
            assert_eq!(viscous::tension::s1d(r, r0, 0.4, 3e-9, 0.0, kf), 0.0, "no shear viscosity on ȧ_k");
            let _ = n;
        }
        // Skalak small strain: dS0/dR at R0 = 4K/R0², K = G_s(1 + 2C)
    }
    for &(gs, c) in &[(0.05, 0.0), (0.05, 1.0), (0.05, 1e3)] {
        let r0 = 2e-6;
        let h = 1e-6 * r0;
        let ds0 = (skalak::paper::s0(r0 + h, r0, gs, c) - skalak::paper::s0(r0 - h, r0, gs, c)) / (2.0 * h);
        let k_mod = gs * (1.0 + 2.0 * c);
        assert!((ds0 - 4.0 * k_mod / (r0 * r0)).abs() <= 1e-8 * ds0.abs(), "Skalak C={c}: dS0/dR {ds0:e} vs 4K/R0² {:e}", 4.0 * k_mod / (r0 * r0));
        // no prestress at R0 (to rounding: the terms cancel in f64)
        assert!(skalak::paper::s0(r0, r0, gs, c).abs() <= 1e-14 * gs * (1.0 + c) / r0, "Skalak S0(R0) = {:e}", skalak::paper::s0(r0, r0, gs, c));
    }
}

#[test]
fn viscous_loads_are_the_derivatives_of_the_rayleigh_dissipation() {
    let (r0, mu, kap) = (1.0, 0.3, 0.8);
    let diss = move |p: &Point, _: f64| 0.5 * (kap * (p.d1 + p.d2).powi(2) + mu * (p.d1 - p.d2).powi(2)) * p.area;
    let mut worst: f64 = 0.0;
    for r in [1.0, 1.15] {
        for rd in [0.0, 0.37] {
            let s = |k: usize, a: f64, b: f64, ad: f64, bd: f64, rdv: f64| Surface { r, r0, k, a, b, rd: rdv, ad, bd }.integrate(diss);
            // radial: ∂D/∂Ṙ = 2R² S0 (exact for a quadratic D: a 2-point difference is exact)
            if rd != 0.0 {
                let dd = (s(2, 0.0, 0.0, 0.0, 0.0, rd * 1.5) - s(2, 0.0, 0.0, 0.0, 0.0, rd * 0.5)) / rd;
                let t = 2.0 * r * r * viscous::tension::s0(r, r0, rd, mu, kap);
                assert!(rel(dd, t, 0.0) <= TOL, "viscous R={r}: dD/dṘ {dd:e} vs 2R²S0 {t:e}");
            }
            for k in KS {
                let kf = k as f64;
                let nn = kf * (kf + 1.0);
                let norm = 2.0 / (2.0 * kf + 1.0);
                use viscous::tension as t;
                let (s0, s1, s2, s11, s12) = (t::s0(r, r0, rd, mu, kap), t::s1(r, r0, rd, mu, kap, kf), t::s2(r, r0, rd, mu, kap, kf), t::s11(r, r0, rd, mu, kap, kf), t::s12(r, r0, rd, mu, kap, kf));
                let (s1d, s2d, s11d, s12d) = (t::s1d(r, r0, rd, mu, kap, kf), t::s2d(r, r0, rd, mu, kap, kf), t::s11d(r, r0, rd, mu, kap, kf), t::s12d(r, r0, rd, mu, kap, kf));
                let (ha, hb) = steps(r, k, step_factor(STEP));
                // rate–rate: D is quadratic in the rates, exactly
                let q = |ad: f64, bd: f64| s(k, 0.0, 0.0, ad, bd, rd);
                let daa = q(1.0, 0.0) + q(-1.0, 0.0) - 2.0 * q(0.0, 0.0);
                let dbb = q(0.0, 1.0) + q(0.0, -1.0) - 2.0 * q(0.0, 0.0);
                let dab = (q(1.0, 1.0) - q(1.0, -1.0) - q(-1.0, 1.0) + q(-1.0, -1.0)) / 4.0;
                // rate–amplitude: ∂/∂q of ∂D/∂q̇ (the latter exact by a 2-point difference)
                let dqa = |a: f64, b: f64| (s(k, a, b, 1.0, 0.0, rd) - s(k, a, b, -1.0, 0.0, rd)) / 2.0;
                let dqb = |a: f64, b: f64| (s(k, a, b, 0.0, 1.0, rd) - s(k, a, b, 0.0, -1.0, rd)) / 2.0;
                let d_ad_a = first(|a| dqa(a, 0.0), ha);
                let d_ad_b = first(|b| dqa(0.0, b), hb);
                let d_bd_a = first(|a| dqb(a, 0.0), ha);
                let d_bd_b = first(|b| dqb(0.0, b), hb);
                let scale = (norm * r * r * s1d).abs().max((nn * norm * r * r * s12d).abs() / nn);
                let checks = [
                    ("D_ȧȧ", daa, norm * r * r * s1d, 1.0),
                    ("D_ȧḃ vs S2d", dab, norm * r * r * s2d, 1.0),
                    ("D_ȧḃ vs S11d", dab, nn * norm * r * r * s11d, 1.0),
                    ("D_ḃḃ", dbb, nn * norm * r * r * s12d, nn),
                    ("D_ȧa", d_ad_a, norm * (r * r * s1 + 2.0 * r * s0), 1.0),
                    ("D_ȧb", d_ad_b, norm * (r * r * s2 - nn * r * s0), nn),
                    ("D_ḃa", d_bd_a, nn * norm * (r * r * s11 - r * s0), 1.0),
                    ("D_ḃb", d_bd_b, nn * norm * r * r * s12, nn),
                ];
                for (name, oracle, table, weight) in checks {
                    let sc = scale * weight * if rd == 0.0 { 1.0 } else { 1.0 + rd };
                    let e = (oracle - table).abs() / sc.max(table.abs());
                    assert!(e <= TOL, "viscous R={r} Ṙ={rd} k={k}: {name} oracle {oracle:e} vs tables {table:e} ({e:.1e})");
                    worst = worst.max(e);
                }
            }
        }
    }
    eprintln!("viscous vs Rayleigh dissipation: worst {worst:.1e}");
}

#[test]
fn the_laws_are_listed_and_mooney_rivlin_keeps_its_names() {
    assert_eq!(membrane::LAWS, &["bending", "marmottant", "mooney_rivlin", "skalak", "surface_tension", "viscous"]);
    assert_eq!(skalak::SYMBOLS, &["Gs", "C"]);
    assert_eq!(viscous::ARGS, "r, r0, rd, mu_s, kappa_s");
    // the historical path is the same function
    assert_eq!(membrane::paper::s1(1.1, 1.0, 0.1, 0.2, 4.0), mooney_rivlin::paper::s1(1.1, 1.0, 0.1, 0.2, 4.0));
}
