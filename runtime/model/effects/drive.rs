//! The far-field pressure p∞(t) = p0 + p_a(t) (FORMULATION §4.1; the drive p_a of docs/model.md,
//! "Drives", evaluated by [`Waveform`]), entering the radial balance as −p∞. During a run p_a is
//! evaluated on the piece being integrated ([`Piece`], set by the run executor at the drive's
//! stop times), so a step landing on a burst edge sees its own side there. Without a drive
//! (absent or ε_p = 0) it is the constant p0 and the term is not listed as an effect ("no drive
//! term").

use super::{At, LoadJacobian, Loads, PressureRate, Term};
use crate::drive::{Piece, Waveform};

#[derive(Debug, Clone)]
pub struct FarField {
    /// p̄0
    pub p0: f64,
    /// p_a in the model's units, when driven.
    pub wave: Option<Waveform>,
    /// The piece of a piecewise drive a run is integrating (unset: decided from t).
    pub piece: Piece,
}

impl FarField {
    /// p∞(t).
    #[inline]
    pub fn p_inf(&self, t: f64) -> f64 {
        match &self.wave {
            None => self.p0,
            Some(w) => self.p0 + self.piece.inside().map_or_else(|| w.pressure(t), |s| w.pressure_and_rate_on(t, s).0),
        }
    }
    /// dp∞/dt (for a radial form that needs the pressure's time derivative, e.g. Keller–Miksis).
    pub fn p_inf_dt(&self, t: f64) -> f64 {
        self.wave.as_ref().map_or(0.0, |w| self.piece.inside().map_or_else(|| w.rate(t), |s| w.pressure_and_rate_on(t, s).1))
    }
}

impl Term for FarField {
    fn name(&self) -> &'static str {
        "far field"
    }
    fn label(&self) -> Option<String> {
        self.wave.as_ref().map(Waveform::label)
    }
    #[inline]
    fn add(&self, at: &At<'_>, loads: &mut Loads<'_>) {
        loads.pressure -= self.p_inf(at.t);
    }
    fn add_jacobian(&self, _at: &At<'_>, _jac: &mut LoadJacobian) {}
    fn add_pressure_gradient(&self, _at: &At<'_>, _dp: &mut [f64; 2]) {}
    /// q = −dp∞/dt (the driving pressure's time derivative in the radiation term).
    fn add_rate(&self, at: &At<'_>, rate: &mut PressureRate) -> bool {
        rate.q -= self.p_inf_dt(at.t);
        true
    }
    /// p∞ and dp∞/dt from one evaluation of the waveform (one sincos for a tone: issue 34);
    /// the same expressions as [`add`](Term::add) and [`add_rate`](Term::add_rate), so the same
    /// bits (the single-tone `pressure` and `rate` are `tones_at`'s sums without the zeros).
    #[inline]
    fn add_with_rate(&self, at: &At<'_>, loads: &mut Loads<'_>, rate: &mut PressureRate) -> bool {
        let (p, dp) = match &self.wave {
            None => (0.0, 0.0),
            Some(w) => match self.piece.inside() {
                None => w.pressure_and_rate(at.t),
                Some(s) => w.pressure_and_rate_on(at.t, s),
            },
        };
        loads.pressure -= if self.wave.is_some() { self.p0 + p } else { self.p0 };
        rate.q -= dp;
        true
    }
}
