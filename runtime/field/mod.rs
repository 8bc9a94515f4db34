//! Magnetic fields: the scene's coil or dipole → the symbol values the generated load tables
//! are written in (`mu0`, `chi_s`, `H2`, `H4`, `a`, `R0`, `M`, `z`; `R` is the state), and
//! their time dependence. [`loads`] turns a table plus these values into the magnetic loads
//! M0, M_n,k, M_t,k of FORMULATION §4.1 (eq 2.40).
//!
//! Time dependence (paper §5.5–5.6): the coil current is static `I` or `I0 cos 2π f2 t`, and the
//! coil distance may oscillate, a(t) = a (1 + β cos 2π f3 t). Every H_2n ∝ I/a (eq 2.31), so a
//! component ∝ H^p a^q scales with (I(t)/I)^p (a/a(t))^p (a(t)/a)^q. A dipole is static.

pub mod appendix;
pub mod coil;
pub mod dipole;
pub mod loads;

use crate::coefficients::{FieldTable, COIL, COIL_H4, DIPOLE};
use crate::scene::{Current, Field, Shell};

/// μ0 = 4π·10⁻⁷ H/m (the pre-2019 exact value; the SI-2019 value differs by 5·10⁻¹⁰ relative).
pub const MU0: f64 = 4.0e-7 * std::f64::consts::PI;

/// Errors building a field from a scene (the scene validator should make these unreachable).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FieldError {
    #[error("generated table `{table}` uses symbol `{symbol}`, which field `{field}` does not define")]
    UnknownSymbol { table: &'static str, symbol: String, field: &'static str },
    #[error("field.{key} = {value}: must be finite and positive")]
    NonPositive { key: &'static str, value: f64 },
}

/// How the field strength varies in time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TimeLaw {
    /// Static current (or dipole), fixed distance: the loads' time factor is 1, computed once.
    Static,
    /// I(t)/I_ref = cos(ω2 t) (or 1), a(t)/a_ref = 1 + β cos(ω3 t) (or 1); ω in rad/s.
    Varying { current_omega: Option<f64>, distance: Option<(f64, f64)> },
}

/// A field source resolved from the scene: its table, its reference symbol values (SI) and
/// its time law.
#[derive(Debug, Clone)]
pub struct FieldSource {
    pub table: &'static FieldTable,
    /// "coil" or "dipole"
    pub kind: &'static str,
    /// Symbol values at the reference state (I = I or I0, a = mean distance), SI units.
    pub symbols: Vec<(&'static str, f64)>,
    pub law: TimeLaw,
    /// Human-readable effect name, e.g. "coil field (static current)".
    pub label: String,
    /// Paper's nondimensional magnetic group: Rn (coil, §5.4) or M_n (dipole, eq 5.7, χ → χ_s).
    pub group: (&'static str, f64),
}

impl FieldSource {
    /// Resolves the scene's field. `r0` [m] is the bubble's reference radius (for the groups).
    pub fn from_scene(field: &Field, shell: &Shell, r0: f64) -> Result<Self, FieldError> {
        let chi_s = shell.thickness * shell.susceptibility; // χ_s = ε χ (FORMULATION §1, audit 1)
        match field {
            Field::Coil(c) => coil::source(c, chi_s, r0, shell.c1),
            Field::Dipole(d) => dipole::source(d, chi_s, r0, shell.c1),
        }
    }

    /// Reference value of a symbol, if defined.
    pub fn symbol(&self, name: &str) -> Option<f64> {
        self.symbols.iter().find(|(n, _)| *n == name).map(|&(_, v)| v)
    }

    pub fn is_static(&self) -> bool {
        matches!(self.law, TimeLaw::Static)
    }

    /// (I(t)/I_ref, a(t)/a_ref) at time t [s].
    pub fn ratios(&self, t: f64) -> (f64, f64) {
        match self.law {
            TimeLaw::Static => (1.0, 1.0),
            TimeLaw::Varying { current_omega, distance } => (
                current_omega.map_or(1.0, |w| (w * t).cos()),
                distance.map_or(1.0, |(beta, w)| 1.0 + beta * (w * t).cos()),
            ),
        }
    }
}

/// The table a coil uses: with `include_h4` the H2·H4 and H4² components are kept.
pub(crate) fn coil_table(include_h4: bool) -> &'static FieldTable {
    if include_h4 {
        &COIL_H4
    } else {
        &COIL
    }
}

pub(crate) fn dipole_table() -> &'static FieldTable {
    &DIPOLE
}

pub(crate) fn current_law(current: &Current) -> (f64, Option<f64>) {
    match *current {
        Current::Static { value } => (value, None),
        Current::Cosine { amplitude, frequency_hz } => {
            (amplitude, Some(2.0 * std::f64::consts::PI * frequency_hz))
        }
    }
}

