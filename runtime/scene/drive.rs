//! The validated `[drive]` and `[echo]` (docs/model.md, "Drives"): p∞(t) = p0 + p_a(t), p_a given by tones
//! under an envelope or by a measured waveform; evaluated by [`crate::drive::Waveform`].

use crate::drive::Samples;
use serde::Serialize;
use std::path::PathBuf;

/// The acoustic drive. The continuous single tone p0 (1 + ε_p cos(2π f t + φ)) is the paper's.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Drive {
    /// ε_p (dimensionless); 0 with a file drive
    pub amplitude: f64,
    /// f_d [Hz]; ω_d = 2π f_d (FORMULATION: "ω_d = 1 MHz" is a frequency)
    pub frequency_hz: f64,
    /// φ [rad]
    pub phase: f64,
    pub envelope: Envelope,
    /// Burst length in carrier periods (the Gaussian's FWHM); `Some` exactly when bursting.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cycles: Option<f64>,
    /// Start of the (first) burst [s].
    pub delay: f64,
    /// Taper fraction of the Tukey envelope.
    pub tukey_fraction: f64,
    /// Pulse-repetition frequency of a train of bursts [Hz].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub repeat_hz: Option<f64>,
    /// Further tones under the same envelope.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub components: Vec<Component>,
    /// A measured waveform instead of the tones.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub file: Option<DriveFile>,
}

impl Drive {
    /// The continuous cosine p0 (1 + ε_p cos 2π f t) (the paper's drive; every other key default).
    pub fn cosine(amplitude: f64, frequency_hz: f64) -> Drive {
        Drive {
            amplitude,
            frequency_hz,
            phase: 0.0,
            envelope: Envelope::Continuous,
            cycles: None,
            delay: 0.0,
            tukey_fraction: 0.5,
            repeat_hz: None,
            components: Vec::new(),
            file: None,
        }
    }

    /// Whether the drive is periodic (continuous tones, no file).
    pub fn is_continuous(&self) -> bool {
        self.envelope == Envelope::Continuous && self.file.is_none()
    }
}

/// `drive.envelope`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Envelope {
    Continuous,
    Rectangular,
    Hann,
    Gaussian,
    Tukey,
}

/// One of `drive.components`: ε cos(2π f τ + φ).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Component {
    pub amplitude: f64,
    pub frequency_hz: f64,
    pub phase: f64,
}

/// `drive.file` and `drive.file_scale`, read at validation.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DriveFile {
    /// The path as resolved (relative paths: against the scene file's directory).
    pub path: PathBuf,
    pub scale: f64,
    #[serde(skip)]
    pub samples: Samples,
}

/// `[echo]`: where the scattered pressure is recorded (docs/model.md, "Echo").
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Echo {
    /// r [m] from the bubble's centre
    pub distance: f64,
    /// θ [deg] from the symmetry axis, one column each
    pub angles_deg: Vec<f64>,
    /// [t0, t1] [s] of the spectrum (`None`: the whole run)
    #[serde(skip_serializing_if = "Option::is_none")]
    pub window: Option<[f64; 2]>,
}
