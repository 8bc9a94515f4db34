//! The acoustic drive as a pure function of time (docs/model.md, "Drives"): the pressure p_a(t)
//! added to the ambient p0, p∞(t) = p0 + p_a(t), and its exact time derivative (Keller–Miksis).
//!
//! p_a(t) = w(τ/L) Σ_i ε_i p0 cos(ω_i τ + φ_i)   (tones under an envelope), or
//! p_a(t) = s · p_file(t)                        (a measured waveform, [`Samples`]),
//!
//! with τ the time since the current burst's start (τ = t for a continuous drive), L the burst
//! length and w the envelope ([`Shape`]), zero outside the burst. A train repeats the burst every
//! 1/`repeat_hz`. The continuous single-tone drive is ε p0 cos(ω t + φ), evaluated exactly as the
//! model always has (bit-for-bit: `amp * (w * t).cos()` with φ = 0).
//!
//! The burst edges and the file's knots are where p_a or dp_a/dt jumps: [`Waveform::stop_times`]
//! lists them for the integration loop. Between two of them p_a is smooth; a run evaluates it
//! on the piece it is integrating ([`Waveform::pressure_and_rate_on`], the piece held by a
//! [`Piece`]), so a step that lands on an edge sees the left side's formula there. A [`Waveform`] is unit-agnostic: built in SI from a scene
//! ([`Waveform::from_scene`]) and rescaled ([`Waveform::scaled`]) to the model's units.

mod envelope;
mod piece;
mod samples;

pub use envelope::Shape;
pub use piece::Piece;
pub use samples::Samples;

/// One sinusoid ε p_ref cos(ω τ + φ).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tone {
    /// ε: amplitude relative to the waveform's reference pressure (p0).
    pub amplitude: f64,
    /// ω [1/time unit]
    pub omega: f64,
    /// φ [rad]
    pub phase: f64,
}

/// A burst (or a train of bursts): the envelope `shape` over [start + nP, start + nP + length).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Burst {
    pub shape: Shape,
    pub start: f64,
    pub length: f64,
    /// The repetition period P of a train (≥ length); `None`: a single burst.
    pub period: Option<f64>,
}

/// The drive's acoustic pressure p_a(t) (see the module doc).
#[derive(Debug, Clone, PartialEq)]
pub enum Waveform {
    /// Tones (the first is the main one) under an optional burst envelope.
    Tones { p_ref: f64, tones: Vec<Tone>, burst: Option<Burst> },
    /// A measured waveform (already multiplied by `drive.file_scale`).
    File(Samples),
}

/// Why a waveform is not periodic (Floquet needs a period).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum NotPeriodic {
    #[error("drive.envelope = \"{0}\" is a burst, not a periodic drive: Floquet needs a periodic drive; use `stability --method series`, which works with any drive")]
    Burst(&'static str),
    #[error("drive.file is a measured waveform, not a periodic drive: Floquet needs a periodic drive; use `stability --method series`, which works with any drive")]
    File,
}

impl Waveform {
    /// The drive of a scene in SI (time [s], pressure [Pa]); `None` when the scene has none.
    pub fn from_scene(drive: &crate::scene::Drive, p0: f64) -> Option<Waveform> {
        use crate::scene::Envelope as E;
        use std::f64::consts::PI;
        if let Some(f) = &drive.file {
            return Some(Waveform::File(f.samples.scaled(1.0, f.scale)));
        }
        let mut tones = Vec::with_capacity(1 + drive.components.len());
        let main = Tone { amplitude: drive.amplitude, omega: 2.0 * PI * drive.frequency_hz, phase: drive.phase };
        tones.push(main);
        tones.extend(drive.components.iter().map(|c| Tone { amplitude: c.amplitude, omega: 2.0 * PI * c.frequency_hz, phase: c.phase }));
        tones.retain(|t| t.amplitude != 0.0);
        if tones.is_empty() {
            return None;
        }
        let shape = match drive.envelope {
            E::Continuous => None,
            E::Rectangular => Some(Shape::Rectangular),
            E::Hann => Some(Shape::Hann),
            E::Gaussian => Some(Shape::Gaussian),
            E::Tukey => Some(Shape::Tukey(drive.tukey_fraction)),
        };
        let burst = shape.map(|shape| Burst {
            shape,
            start: drive.delay,
            length: shape.length_in_periods(drive.cycles.unwrap_or(f64::NAN)) / drive.frequency_hz,
            period: drive.repeat_hz.map(|f| 1.0 / f),
        });
        Some(Waveform::Tones { p_ref: p0, tones, burst })
    }

    /// The same waveform in other units: t' = t / `time`, p' = p / `pressure` (the model's
    /// t* and pressure scale). Tones keep their relative amplitudes: ε (p0/`pressure`), so the
    /// continuous drive's amplitude is the model's ε_p p̄0, bit for bit.
    pub fn scaled(&self, time: f64, pressure: f64) -> Waveform {
        match self {
            Waveform::Tones { p_ref, tones, burst } => Waveform::Tones {
                p_ref: p_ref / pressure,
                tones: tones.iter().map(|t| Tone { omega: t.omega * time, ..*t }).collect(),
                burst: burst.map(|b| Burst { start: b.start / time, length: b.length / time, period: b.period.map(|p| p / time), ..b }),
            },
            Waveform::File(s) => Waveform::File(s.scaled(1.0 / time, 1.0 / pressure)),
        }
    }

    /// p_a(t).
    #[inline]
    pub fn pressure(&self, t: f64) -> f64 {
        match self {
            Waveform::Tones { p_ref, tones, burst: None } if tones.len() == 1 => {
                let w = tones[0];
                w.amplitude * p_ref * (w.omega * t + w.phase).cos()
            }
            _ => self.pressure_and_rate(t).0,
        }
    }

    /// dp_a/dt (exact; piecewise for a file).
    #[inline]
    pub fn rate(&self, t: f64) -> f64 {
        match self {
            Waveform::Tones { p_ref, tones, burst: None } if tones.len() == 1 => {
                let w = tones[0];
                -(w.amplitude * p_ref) * w.omega * (w.omega * t + w.phase).sin()
            }
            _ => self.pressure_and_rate(t).1,
        }
    }

    /// (p_a(t), dp_a/dt), the piece holding t decided from t itself (right-continuous at an
    /// edge: a burst is closed at its start and open at its end).
    #[inline]
    pub fn pressure_and_rate(&self, t: f64) -> (f64, f64) {
        match self {
            Waveform::File(s) => s.at(t),
            Waveform::Tones { p_ref, tones, burst } => match burst {
                None => tones_at(*p_ref, tones, t, 1.0, 0.0),
                Some(b) => match b.index(t) {
                    None => (0.0, 0.0),
                    Some(n) => b.evaluate(*p_ref, tones, t, n),
                },
            },
        }
    }

    /// (p_a(t), dp_a/dt) on the smooth piece holding the time `inside` (a time strictly
    /// between two stop times, e.g. their midpoint: never an edge, where rounding could pick
    /// either side): the same formula for every t of that piece, its ends included. A step
    /// landing on an edge therefore evaluates its last stage on the side it integrates (Hairer,
    /// Nørsett & Wanner I, II.6), where [`pressure_and_rate`](Self::pressure_and_rate) would
    /// give the next piece's value.
    pub fn pressure_and_rate_on(&self, t: f64, inside: f64) -> (f64, f64) {
        match self {
            Waveform::File(s) => s.at_on(t, inside),
            Waveform::Tones { p_ref, tones, burst } => match burst {
                None => tones_at(*p_ref, tones, t, 1.0, 0.0),
                Some(b) => match b.index(inside) {
                    None => (0.0, 0.0),
                    Some(n) => b.evaluate(*p_ref, tones, t, n),
                },
            },
        }
    }

    /// The times in the open interval (t0, t1) where p_a or its derivative jumps: the burst
    /// edges, the file's knots (sorted, without repeats). The integration loop must not step
    /// over them (the hook it reads through [`crate::model::Model::stop_times`]).
    pub fn stop_times(&self, t0: f64, t1: f64) -> Vec<f64> {
        let mut v: Vec<f64> = match self {
            Waveform::File(s) => s.times().iter().copied().filter(|&t| t > t0 && t < t1).collect(),
            Waveform::Tones { burst: None, .. } => Vec::new(),
            Waveform::Tones { burst: Some(b), .. } => {
                let mut v = Vec::new();
                let mut n = 0u64;
                loop {
                    let s = b.start + b.period.map_or(0.0, |p| n as f64 * p);
                    if s >= t1 {
                        break;
                    }
                    v.extend([s, s + b.length].into_iter().filter(|&t| t > t0 && t < t1));
                    if b.period.is_none() {
                        break;
                    }
                    n += 1;
                }
                v
            }
        };
        v.sort_by(f64::total_cmp);
        v.dedup();
        v
    }

    /// The drive's period, for Floquet: the common period of the tones' frequencies is the
    /// caller's (`analysis::periodic::common_period`); here: an error for a burst, a train or
    /// a file, the tones' angular frequencies otherwise.
    pub fn periodic_omegas(&self) -> Result<Vec<f64>, NotPeriodic> {
        match self {
            Waveform::File(_) => Err(NotPeriodic::File),
            Waveform::Tones { burst: Some(b), .. } => Err(NotPeriodic::Burst(match b.shape {
                Shape::Rectangular => "rectangular",
                Shape::Hann => "hann",
                Shape::Gaussian => "gaussian",
                Shape::Tukey(_) => "tukey",
            })),
            Waveform::Tones { tones, .. } => Ok(tones.iter().map(|t| t.omega).collect()),
        }
    }

    /// A short label for the active-effects list.
    pub fn label(&self) -> String {
        match self {
            Waveform::File(_) => "acoustic drive (file)".into(),
            Waveform::Tones { tones, burst: None, .. } if tones.len() == 1 => "acoustic drive".into(),
            Waveform::Tones { tones, burst, .. } => {
                let n = tones.len();
                let what = if n == 1 { String::new() } else { format!(", {n} tones") };
                match burst {
                    None => format!("acoustic drive{what}"),
                    Some(b) if b.period.is_some() => format!("acoustic drive (burst train{what})"),
                    Some(_) => format!("acoustic drive (burst{what})"),
                }
            }
        }
    }
}

/// Σ_i ε_i p_ref cos(ω_i τ + φ_i) under the envelope value w (and dw/dτ = `dw`), with its
/// τ-derivative.
#[inline]
fn tones_at(p_ref: f64, tones: &[Tone], tau: f64, w: f64, dw: f64) -> (f64, f64) {
    let (mut s, mut ds) = (0.0, 0.0);
    for tone in tones {
        let a = tone.amplitude * p_ref;
        let x = tone.omega * tau + tone.phase;
        let (sin, cos) = sin_cos(x);
        s += a * cos;
        ds -= a * tone.omega * sin;
    }
    (w * s, dw * s + w * ds)
}

/// (sin x, cos x) in one call: glibc's `sincos` shares the argument reduction of the two and
/// returns the same bits as `sin` and `cos` (tested over 10^5 arguments in drive/tests.rs); a
/// Keller–Miksis rhs needs both for p∞ and dp∞/dt (issue 34: 98 + 94 instructions apart,
/// docs/performance.md "Radial runs against APECSS"). Elsewhere the two calls.
#[inline]
pub(crate) fn sin_cos(x: f64) -> (f64, f64) {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    {
        extern "C" {
            fn sincos(x: f64, sin: *mut f64, cos: *mut f64);
        }
        let (mut s, mut c) = (0.0, 0.0);
        // SAFETY: glibc's libm (linked by std) writes the two f64 through the valid pointers.
        unsafe { sincos(x, &mut s, &mut c) };
        (s, c)
    }
    #[cfg(not(all(target_os = "linux", target_env = "gnu")))]
    {
        (x.sin(), x.cos())
    }
}

impl Burst {
    /// τ = t − start − nP, the time since the start of burst n.
    #[inline]
    fn tau(&self, t: f64, n: f64) -> f64 {
        let since = t - self.start;
        match self.period {
            None => since,
            Some(p) => since - n * p,
        }
    }

    /// The index n (as f64) of the burst holding t; `None` outside every burst. Bursts are
    /// closed at the start and open at the end: [start + nP, start + nP + L).
    fn index(&self, t: f64) -> Option<f64> {
        let since = t - self.start;
        if !(since >= 0.0) {
            return None;
        }
        let n = self.period.map_or(0.0, |p| (since / p).floor());
        (self.tau(t, n) < self.length).then_some(n)
    }

    /// The tones under burst n's envelope at t (t may lie at or just past the burst's end:
    /// the envelope's formula continued).
    fn evaluate(&self, p_ref: f64, tones: &[Tone], t: f64, n: f64) -> (f64, f64) {
        let tau = self.tau(t, n);
        let (w, dwdu) = self.shape.at(tau / self.length);
        tones_at(p_ref, tones, tau, w, dwdu / self.length)
    }
}

#[cfg(test)]
mod tests;
