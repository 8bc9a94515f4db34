//! Nondimensionalization at the edge (FORMULATION §4.5, paper §5.4).
//!
//! A free gas bubble (shell.c1 = c2 = 0, issue 10) has no membrane scale: its units are length
//! R0, time t* = R0 √(ρ/p0), pressure p0 (so ρ̄ = 1, p̄0 = 1, η̄ = 1/Re with Re = R0√(ρp0)/η;
//! P and α are undefined and reported as null). docs/model.md, "A free gas bubble".
//!
//! Units: length R0, time t* = √(ρR0³/(2c1)), pressure 2c1/R0. In these units ρ̄ = 1, R̄0 = 1,
//! c̄1 = 1/2, c̄2 = α/2, η̄ = 1/Re, p̄0 = P/2, with Re = √(2ρc1R0)/η, P = p0R0/c1, α = c2/c1.
//! The equations in `radial` and `boundary_layer` are written dimensionally homogeneous (in
//! ρ, η, c1, c2, R0, p0), so they are evaluated unchanged with these numbers: the integrators
//! see plain O(1) numbers and nothing is rescaled per step.

use serde::Serialize;

use crate::coefficients::membrane;
use crate::scene::{MembraneForm, Scene, ShellLaw};

/// The scales that convert between SI and the model's nondimensional numbers.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Scales {
    /// R0 [m]
    pub length: f64,
    /// t* [s]
    pub time: f64,
    /// 2c1/R0 [Pa]
    pub pressure: f64,
}

impl Scales {
    pub fn from_scene(s: &Scene) -> Self {
        let r0 = s.bubble.radius;
        let c1 = s.shell.c1;
        if c1 == 0.0 {
            let time = crate::scene::time_scale(&s.liquid, r0, &s.shell);
            return Self { length: r0, time, pressure: s.liquid.ambient_pressure };
        }
        Self { length: r0, time: (s.liquid.density * r0.powi(3) / (2.0 * c1)).sqrt(), pressure: 2.0 * c1 / r0 }
    }
}

type S0 = fn(f64, f64, f64, f64) -> f64;
type Sk = fn(f64, f64, f64, f64, f64) -> f64;
/// Ŝ1, Ŝ2, Ŝ11, Ŝ12 of every mode k of `ks` at one R, into `out[m]` in that order.
pub type SModes = fn(f64, f64, f64, f64, &[f64], &mut [[f64; 4]]);

/// The five membrane loads of FORMULATION §4.1, chosen once by the scene's `shell.form`, and
/// their exact R-derivatives (generated alongside them, for the analytic Jacobian).
#[derive(Clone, Copy)]
pub struct Membrane {
    pub s0: S0,
    pub s1: Sk,
    pub s2: Sk,
    pub s11: Sk,
    pub s12: Sk,
    pub s0_dr: S0,
    pub s1_dr: Sk,
    pub s2_dr: Sk,
    pub s11_dr: Sk,
    pub s12_dr: Sk,
    /// The same generated s1, s2, s11, s12, all modes in one call: the four functions are inlined
    /// into one loop, so the powers of R common to them are formed once per call, not four times
    /// per mode through function pointers (the same expressions: bit-identical values).
    pub modes: SModes,
    /// Their R-derivatives s1_dr, s2_dr, s11_dr, s12_dr the same way (the exact Jacobian's).
    pub modes_dr: SModes,
}

/// The [`Membrane`] of one generated module (`coefficients::membrane::<law>::<form>`).
macro_rules! tables {
    ($($m:ident)::+) => {{
        fn modes(r: f64, r0: f64, c1: f64, c2: f64, ks: &[f64], out: &mut [[f64; 4]]) {
            for (o, &k) in out.iter_mut().zip(ks) {
                *o = [
                    $($m)::+::s1(r, r0, c1, c2, k),
                    $($m)::+::s2(r, r0, c1, c2, k),
                    $($m)::+::s11(r, r0, c1, c2, k),
                    $($m)::+::s12(r, r0, c1, c2, k),
                ];
            }
        }
        fn modes_dr(r: f64, r0: f64, c1: f64, c2: f64, ks: &[f64], out: &mut [[f64; 4]]) {
            for (o, &k) in out.iter_mut().zip(ks) {
                *o = [
                    $($m)::+::s1_dr(r, r0, c1, c2, k),
                    $($m)::+::s2_dr(r, r0, c1, c2, k),
                    $($m)::+::s11_dr(r, r0, c1, c2, k),
                    $($m)::+::s12_dr(r, r0, c1, c2, k),
                ];
            }
        }
        Membrane {
            s0: $($m)::+::s0,
            s1: $($m)::+::s1,
            s2: $($m)::+::s2,
            s11: $($m)::+::s11,
            s12: $($m)::+::s12,
            s0_dr: $($m)::+::s0_dr,
            s1_dr: $($m)::+::s1_dr,
            s2_dr: $($m)::+::s2_dr,
            s11_dr: $($m)::+::s11_dr,
            s12_dr: $($m)::+::s12_dr,
            modes,
            modes_dr,
        }
    }};
}

impl std::fmt::Debug for Membrane {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Membrane")
    }
}

impl Membrane {
    /// The tables of the scene's elastic law (`shell.law`) in its `shell.form`. The Skalak
    /// functions take (G_s, C) where Mooney–Rivlin takes (c1, c2): same signature.
    pub fn for_law(law: &ShellLaw, form: MembraneForm) -> Self {
        match (law, form) {
            // a Marmottant law is not a membrane table (effects/lipid.rs): the Mooney–Rivlin
            // tables with zero constants stand in where a table is read (odd-mode frequencies)
            (ShellLaw::MooneyRivlin | ShellLaw::Marmottant(_) | ShellLaw::MarmottantSmooth(_) | ShellLaw::Sarkar(_) | ShellLaw::ChurchHoff { .. } | ShellLaw::TensionCurve(_), form) => Self::new(form),
            (ShellLaw::Skalak { .. }, MembraneForm::Paper) => tables!(membrane::skalak::paper),
            (ShellLaw::Skalak { .. }, MembraneForm::Tension) => tables!(membrane::skalak::tension),
        }
    }

    /// The paper's Mooney–Rivlin tables in `form`.
    pub fn new(form: MembraneForm) -> Self {
        match form {
            MembraneForm::Paper => tables!(membrane::paper),
            MembraneForm::Tension => tables!(membrane::tension),
        }
    }
}

/// Nondimensional parameters of the equations.
#[derive(Debug, Clone, Copy)]
pub struct Params {
    pub rho: f64,
    pub r0: f64,
    pub eta: f64,
    pub c1: f64,
    pub c2: f64,
    pub p0: f64,
    /// p̄_g0: `gas.reference_pressure` or the equilibrium rule p̄0 − p̄v + Ŝ0(R0) (docs/model.md,
    /// "Liquid and gas effects"; FORMULATION audit 7 had p_g0 = p0).
    pub pg0: f64,
    /// p̄_v (0: no vapour term)
    pub pv: f64,
    /// c̄ = c t*/R0 when `liquid.sound_speed` is given (Keller–Miksis).
    pub sound_speed: Option<f64>,
    /// 3κ
    pub three_kappa: f64,
    /// (ε_p p̄0, ω_d t*) when driven; `None`: p∞ = p0, no drive term.
    pub drive: Option<(f64, f64)>,
    pub membrane: Membrane,
    /// The two constants the membrane tables take: (c̄1, c̄2) for Mooney–Rivlin, (Ḡ_s, C) for Skalak.
    pub membrane_args: (f64, f64),
}

impl Params {
    pub fn from_scene(s: &Scene, sc: &Scales) -> Self {
        let p = |v: f64| v / sc.pressure;
        let c = |v: f64| v / (sc.pressure * sc.length);
        let drive = s
            .drive
            .as_ref()
            .filter(|d| d.amplitude != 0.0)
            .map(|d| (d.amplitude * p(s.liquid.ambient_pressure), 2.0 * std::f64::consts::PI * d.frequency_hz * sc.time));
        Self {
            rho: s.liquid.density * sc.length.powi(3) / (sc.pressure * sc.length * sc.time * sc.time),
            r0: 1.0,
            eta: s.liquid.viscosity / (sc.pressure * sc.time),
            c1: c(s.shell.c1),
            c2: c(s.shell.c2),
            p0: p(s.liquid.ambient_pressure),
            pg0: {
                let pg0 = p(s.gas.reference_pressure);
                let lipid = crate::model::effects::lipid::LipidLaw::from_scene(&s.shell.law, sc);
                if s.gas.reference_pressure_given {
                    pg0
                } else if let Some(l) = lipid {
                    // + Ŝ0(R0) = 2σ(R0)/R0 of the Marmottant law (issue 31)
                    pg0 + l.s0(1.0).0
                } else if s.shell.is_free() {
                    pg0
                } else {
                    // + Ŝ0(R0): zero for a membrane unstressed at R0 (the shipped laws)
                    pg0 + (Membrane::new(s.shell.form).s0)(1.0, 1.0, c(s.shell.c1), c(s.shell.c2))
                }
            },
            pv: p(s.gas.vapour_pressure),
            sound_speed: s.liquid.sound_speed.map(|c| c * sc.time / sc.length),
            three_kappa: 3.0 * s.gas.polytropic_exponent,
            drive,
            membrane: Membrane::for_law(&s.shell.law, s.shell.form),
            membrane_args: match s.shell.law {
                ShellLaw::MooneyRivlin => (c(s.shell.c1), c(s.shell.c2)),
                ShellLaw::Skalak { shear_modulus, area_dilatation } => (c(shear_modulus), area_dilatation),
                ShellLaw::Marmottant(_) | ShellLaw::MarmottantSmooth(_) | ShellLaw::Sarkar(_) | ShellLaw::ChurchHoff { .. } | ShellLaw::TensionCurve(_) => (0.0, 0.0),
            },
        }
    }

    /// p∞(t) = p0 (1 + ε_p cos ω_d t).
    #[inline]
    pub fn p_inf(&self, t: f64) -> f64 {
        match self.drive {
            None => self.p0,
            Some((amp, w)) => self.p0 + amp * (w * t).cos(),
        }
    }

    /// Undamped natural frequency of shape mode k without field (FORMULATION §4.4, corrected 3.10):
    /// ω_k² = 12 (c1+c2)(k−1)(k+1)(k+2) / [ρ R0³ (2k² + 2k − 1)].
    pub fn omega_k(&self, k: f64) -> f64 {
        (12.0 * (self.c1 + self.c2) * (k - 1.0) * (k + 1.0) * (k + 2.0)
            / (self.rho * self.r0.powi(3) * (2.0 * k * k + 2.0 * k - 1.0)))
            .sqrt()
    }
}

/// The nondimensional groups of a run (paper §5.4, FORMULATION §4.5), reported in summaries.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Groups {
    /// t* = √(ρR0³/(2c1)) [s]; free bubble: R0 √(ρ/p0)
    pub t_star: f64,
    /// Re = √(2ρc1R0)/η; free bubble: R0 √(ρ p0)/η (= ρ (R0/t*) R0/η in both cases)
    pub reynolds: f64,
    /// P = p0 R0 / c1 (None → null for a free bubble)
    pub p: Option<f64>,
    /// α = c2 / c1 (None → null for a free bubble)
    pub alpha: Option<f64>,
    /// The gas pressure at R0 used [Pa] (issue 10): `gas.reference_pressure` or the equilibrium rule.
    pub p_g0_pa: f64,
    /// "equilibrium" (p0 − p_v + 2γ/R0 + Ŝ0(R0)) or "override" (`gas.reference_pressure` given).
    pub p_g0_rule: &'static str,
    /// R0/(c t*): the Mach number of the velocity scale R0/t*, when Keller–Miksis (c given).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mach: Option<f64>,
    /// Rn = μ0 χ_s H2² R0² / (2 c1 a²), coil field only (reference current and distance).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rn: Option<f64>,
    /// M_n = 12 μ0 χ_s M² R0² / (z⁸ c1), dipole field only (eq 5.7 with χ → χ_s).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mn: Option<f64>,
    /// ω_d t*, when driven.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub omega_d_star: Option<f64>,
}
