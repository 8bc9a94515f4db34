//! DEV STAND-IN: replaced by the generated tables (helper H1, branch `codegen`).
//!
//! Same API as docs/architecture.md. The membrane functions are FORMULATION §4.1; the coil
//! and dipole couplings are the paper's appendix A/B formulas (NOT reliable, FORMULATION §0),
//! used here only so that the model can be developed before the generated tables land.
//! This file must never reach `main`.
#![allow(dead_code)]

use std::sync::LazyLock;

pub const KMAX: usize = 64;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Load {
    Normal,
    Tangential,
}
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Amp {
    A,
    B,
}

#[derive(Debug)]
pub struct Monomial {
    pub coeff: f64,
    pub coeff_exact: &'static str,
    pub powers: &'static [(&'static str, i32)],
    pub text: &'static str,
}

#[derive(Debug)]
pub struct Coupling {
    pub name: &'static str,
    pub load: Load,
    pub amp: Amp,
    pub offset: i32,
    pub values: &'static [Option<f64>],
    pub exact: &'static [Option<&'static str>],
    pub closed_form: &'static str,
}

#[derive(Debug)]
pub struct Component {
    pub prefactor: Monomial,
    pub r_power: i32,
    pub zero_normal: &'static [(usize, f64)],
    pub zero_tangential: &'static [(usize, f64)],
    pub couplings: &'static [Coupling],
}

#[derive(Debug)]
pub struct FieldTable {
    pub name: &'static str,
    pub spec: &'static str,
    pub components: &'static [Component],
}

fn leak<T>(v: Vec<T>) -> &'static [T] {
    Box::leak(v.into_boxed_slice())
}

fn coupling(
    name: &'static str,
    load: Load,
    amp: Amp,
    offset: i32,
    kmin: usize,
    f: fn(f64) -> f64,
) -> Coupling {
    let values: Vec<Option<f64>> = (0..=KMAX)
        .map(|k| (k >= kmin && k % 2 == 0).then(|| f(k as f64)))
        .collect();
    Coupling {
        name,
        load,
        amp,
        offset,
        values: leak(values),
        exact: leak(vec![None; KMAX + 1]),
        closed_form: "dev stand-in",
    }
}

fn appendix_a() -> Vec<Coupling> {
    use Amp::*;
    use Load::*;
    let d1 = |k: f64| (2.0 * k - 1.0) * (2.0 * k + 3.0);
    let _ = d1;
    vec![
        coupling("F1", Normal, A, 0, 2, |k| (-13.0 * k * k - 13.0 * k + 6.0) / ((2.0 * k - 1.0) * (2.0 * k + 3.0))),
        coupling("F2", Normal, B, 0, 2, |k| 10.0 * k * k * (k * k + 2.0 * k + 1.0) / ((2.0 * k - 1.0) * (2.0 * k + 3.0))),
        coupling("F3", Normal, A, 2, 0, |k| -3.0 * (k.powi(3) + 7.0 * k * k + 14.0 * k + 8.0) / ((2.0 * k + 3.0) * (2.0 * k + 5.0))),
        coupling("F4", Normal, B, 2, 0, |k| 3.0 * (k.powi(4) + 10.0 * k.powi(3) + 35.0 * k * k + 50.0 * k + 24.0) / ((2.0 * k + 3.0) * (2.0 * k + 5.0))),
        coupling("F5", Normal, A, -2, 4, |k| -3.0 * k * (2.0 * k.powi(3) - 5.0 * k * k + 8.0 * k - 5.0) / ((2.0 * k - 1.0) * (2.0 * k - 3.0))),
        coupling("F6", Normal, B, -2, 4, |k| 3.0 * k * (2.0 * k.powi(4) - k.powi(3) - 16.0 * k * k + 25.0 * k - 10.0) / ((2.0 * k - 1.0) * (2.0 * k - 3.0))),
        coupling("F1t", Tangential, A, 0, 2, |k| 5.0 * (2.0 * k * k + 2.0 * k - 3.0) / ((2.0 * k - 1.0) * (2.0 * k + 3.0))),
        coupling("F2t", Tangential, B, 0, 2, |k| 3.0 * (k * k + k + 3.0) / ((2.0 * k - 1.0) * (2.0 * k + 3.0))),
        coupling("F3t", Tangential, A, 2, 2, |k| 3.0 * (k * k + 6.0 * k + 8.0) / ((2.0 * k + 3.0) * (2.0 * k + 5.0))),
        coupling("F4t", Tangential, B, 2, 2, |k| -3.0 * k * (k.powi(3) + 9.0 * k * k + 26.0 * k + 24.0) / ((2.0 * k + 3.0) * (2.0 * k + 5.0))),
        coupling("F5t", Tangential, A, -2, 4, |k| 3.0 * (k * k - 4.0 * k + 3.0) / ((2.0 * k - 1.0) * (2.0 * k - 3.0))),
        coupling("F6t", Tangential, B, -2, 4, |k| 3.0 * (k.powi(3) - 6.0 * k * k + 11.0 * k - 6.0) / ((2.0 * k - 1.0) * (2.0 * k - 3.0))),
    ]
}

fn appendix_b() -> Vec<Coupling> {
    use Amp::*;
    use Load::*;
    vec![
        coupling("F1", Normal, A, 0, 2, |k| (k * k - 2.0) / (4.0 * k * k + 4.0 * k - 3.0)),
        coupling("F2", Normal, B, 0, 2, |k| -k * (k.powi(3) + 2.0 * k * k - k - 3.0) / (4.0 * k * k + 4.0 * k - 3.0)),
        coupling("F3", Normal, A, 2, 0, |k| -(k.powi(3) + 7.0 * k * k + 14.0 * k + 8.0) / (4.0 * k * k + 16.0 * k + 15.0)),
        coupling("F4", Normal, B, 2, 0, |k| (k.powi(4) + 10.0 * k.powi(3) + 35.0 * k * k + 50.0 * k + 24.0) / (4.0 * k * k + 16.0 * k + 15.0)),
        coupling("F5", Normal, A, -2, 4, |k| -k * (k * k - 2.0 * k + 1.0) / (4.0 * k * k - 8.0 * k + 3.0)),
        coupling("F6", Normal, B, -2, 4, |k| k * (k.powi(3) - 2.0 * k * k - k + 2.0) / (4.0 * k * k - 8.0 * k + 3.0)),
        coupling("F1t", Tangential, A, 0, 2, |k| -(2.0 * k * k + 2.0 * k + 1.0) / (4.0 * k * k + 4.0 * k - 3.0)),
        coupling("F2t", Tangential, B, 0, 2, |k| (k * k + k + 3.0) / (4.0 * k * k + 4.0 * k - 3.0)),
        coupling("F3t", Tangential, A, 2, 2, |k| (2.0 * k.powi(3) + 13.0 * k * k + 26.0 * k + 16.0) / (8.0 * k.powi(3) + 36.0 * k * k + 46.0 * k + 15.0)),
        coupling("F4t", Tangential, B, 2, 2, |k| -(2.0 * k.powi(4) + 23.0 * k.powi(3) + 89.0 * k * k + 138.0 * k + 72.0) / (8.0 * k.powi(3) + 36.0 * k * k + 46.0 * k + 15.0)),
        coupling("F5t", Tangential, A, -2, 4, |k| (k * k - 6.0 * k + 7.0) / (4.0 * k * k - 8.0 * k + 3.0)),
        coupling("F6t", Tangential, B, -2, 4, |k| (k.powi(3) - 6.0 * k * k + 15.0 * k - 14.0) / (4.0 * k * k - 8.0 * k + 3.0)),
    ]
}

/// Paper coil (appendix A): ℋ = μ0 χ_s H2² R0² / (4 a² R²), m = 1, ℋ0 = 2ℋR, ℋ2 = 2ℋR, ℋ¹2 = ℋR.
pub static COIL: LazyLock<FieldTable> = LazyLock::new(|| FieldTable {
    name: "coil",
    spec: "dev stand-in (appendix A)",
    components: leak(vec![Component {
        prefactor: Monomial {
            coeff: 0.25,
            coeff_exact: "1/4",
            powers: &[("mu0", 1), ("chi_s", 1), ("H2", 2), ("R0", 2), ("a", -2), ("R", -2)],
            text: "mu0*chi_s*H2^2*R0^2/(4*a^2*R^2)",
        },
        r_power: 1,
        zero_normal: &[(0, 2.0), (2, 2.0)],
        zero_tangential: &[(2, 1.0)],
        couplings: leak(appendix_a()),
    }]),
});

/// Same as COIL in the stand-in (no H4 components).
pub static COIL_H4: LazyLock<FieldTable> = LazyLock::new(|| FieldTable {
    name: "coil_h4",
    spec: "dev stand-in (appendix A, H4 dropped)",
    components: COIL.components,
});

/// Dipole (appendix B shapes, prefactor made dimensionally consistent for the stand-in):
/// ℋ = 36 μ0 χ_s M² R0² / (z⁸ R²), m = 1.
pub static DIPOLE: LazyLock<FieldTable> = LazyLock::new(|| FieldTable {
    name: "dipole",
    spec: "dev stand-in (appendix B)",
    components: leak(vec![Component {
        prefactor: Monomial {
            coeff: 36.0,
            coeff_exact: "36",
            powers: &[("mu0", 1), ("chi_s", 1), ("M", 2), ("R0", 2), ("z", -8), ("R", -2)],
            text: "36*mu0*chi_s*M^2*R0^2/(z^8*R^2)",
        },
        r_power: 1,
        zero_normal: &[(0, 2.0 / 3.0), (2, -2.0 / 3.0)],
        zero_tangential: &[(2, -1.0 / 3.0)],
        couplings: leak(appendix_b()),
    }]),
});

/// Membrane loads, FORMULATION §4.1 (ε-scaled: c_i in N/m).
pub mod membrane {
    pub mod paper {
        pub fn s0(r: f64, r0: f64, c1: f64, c2: f64) -> f64 {
            c1 * (4.0 / r - 4.0 * r0.powi(6) / r.powi(7)) + c2 * (4.0 * r / (r0 * r0) - 4.0 * r0.powi(4) / r.powi(5))
        }
        pub fn s1(r: f64, r0: f64, c1: f64, c2: f64, k: f64) -> f64 {
            let n = k * (k + 1.0);
            c1 * (-(2.0 * n - 28.0) * r0.powi(6) / r.powi(8) + (2.0 * n - 4.0) / (r * r))
                + c2 * (-(2.0 * n - 20.0) * r0.powi(4) / r.powi(6) + (2.0 * n + 4.0) / (r0 * r0))
        }
        pub fn s2(r: f64, r0: f64, c1: f64, c2: f64, k: f64) -> f64 {
            let n = k * (k + 1.0);
            -12.0 * n * c1 * r0.powi(6) / r.powi(8) + c2 * (-8.0 * n * r0.powi(4) / r.powi(6) - 4.0 * n / (r0 * r0))
        }
        pub fn s11(r: f64, r0: f64, c1: f64, c2: f64, _k: f64) -> f64 {
            -c1 * (8.0 * r0.powi(6) / r.powi(8) + 4.0 / (r * r)) - c2 * (4.0 * r0.powi(4) / r.powi(6) + 8.0 / (r0 * r0))
        }
        pub fn s12(r: f64, r0: f64, c1: f64, c2: f64, k: f64) -> f64 {
            let n = k * (k + 1.0);
            c1 * (4.0 * n * r0.powi(6) / r.powi(8) + (4.0 * n - 4.0) / (r * r))
                + c2 * ((4.0 * n - 4.0) * r0.powi(4) / r.powi(6) + 4.0 * n / (r0 * r0))
        }
    }
    pub mod tension {
        fn sigma0(r: f64, r0: f64, c1: f64, c2: f64) -> f64 {
            let l = r / r0;
            2.0 * c1 * (l * l - l.powi(-4)) + 2.0 * c2 * (l.powi(4) - l.powi(-2))
        }
        pub fn s0(r: f64, r0: f64, c1: f64, c2: f64) -> f64 {
            super::paper::s0(r, r0, c1, c2)
        }
        pub fn s1(r: f64, r0: f64, c1: f64, c2: f64, k: f64) -> f64 {
            super::paper::s1(r, r0, c1, c2, k)
        }
        pub fn s2(r: f64, r0: f64, c1: f64, c2: f64, k: f64) -> f64 {
            super::paper::s2(r, r0, c1, c2, k)
        }
        pub fn s11(r: f64, r0: f64, c1: f64, c2: f64, k: f64) -> f64 {
            super::paper::s11(r, r0, c1, c2, k) + 2.0 * sigma0(r, r0, c1, c2) * r0 * r0 / r.powi(4)
        }
        pub fn s12(r: f64, r0: f64, c1: f64, c2: f64, k: f64) -> f64 {
            let n = k * (k + 1.0);
            super::paper::s12(r, r0, c1, c2, k) - n * sigma0(r, r0, c1, c2) * r0 * r0 / r.powi(4)
        }
    }
}
