//! The smooth piece of the drive a run is integrating, between two stop times (burst edges,
//! file knots), held as a time strictly inside it (the midpoint of its ends: an edge itself
//! could round to either side, e.g. (start + L) − start < L), shared between the drive term
//! that evaluates p_a and the run executor that moves it at every stop time.
//!
//! A step that lands on an edge evaluates its last stage *at* the edge; p_a must take the
//! formula of the piece being integrated there, not the one starting at the edge (the run
//! loop's module doc, "Branches at an edge"). The executor sets the piece at the start of a run
//! and at each stop time ([`crate::integrate::run_loop::Schedule::on_stop_time`]), and clears it
//! at the end; unset, p_a is decided from t ([`super::Waveform::pressure_and_rate`]).

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

/// A time inside the current piece (shared by its clones); unset by default.
#[derive(Debug, Clone)]
pub struct Piece(Arc<AtomicU64>);

impl Default for Piece {
    fn default() -> Self {
        Piece(Arc::new(AtomicU64::new(f64::NAN.to_bits())))
    }
}

impl Piece {
    /// The run now integrates the piece [from, to] (from < to).
    pub fn enter(&self, from: f64, to: f64) {
        self.0.store((0.5 * (from + to)).to_bits(), Ordering::Relaxed);
    }

    /// No run is integrating: p_a is decided from t again.
    pub fn clear(&self) {
        self.0.store(f64::NAN.to_bits(), Ordering::Relaxed);
    }

    /// A time inside the current piece, when a run has set one.
    #[inline]
    pub fn inside(&self) -> Option<f64> {
        let t = f64::from_bits(self.0.load(Ordering::Relaxed));
        (!t.is_nan()).then_some(t)
    }
}
