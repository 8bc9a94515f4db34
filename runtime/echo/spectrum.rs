//! The echo's spectrum (docs/model.md, "Echo", eq E4): the one-sided amplitude spectrum of a
//! uniformly sampled pressure under a Hann window, in dB re 1 Pa, and the levels the summary
//! reports at f/2, f, 3f/2 and 2f of the drive's main frequency f.
//!
//! A_0 = |X_0|/Σw, A_j = 2|X_j|/Σw (0 < j < N/2), A_{N/2} = |X_{N/2}|/Σw, X the DFT of w·p with
//! the symmetric Hann window w_n = sin²(π n/(N − 1)); a sinusoid of amplitude A on a bin reads A.
//! A line's level is the largest A_j within ±1 bin of its frequency (the Hann scalloping loss is
//! at most 1.42 dB; a line is resolved when the window holds ≳ 4 of its periods).

use realfft::RealFftPlanner;
use serde::Serialize;

/// The floor of the dB scale (A = 0 is written as this level, 1e-30 Pa).
pub const FLOOR_DB: f64 = -600.0;

/// A one-sided amplitude spectrum.
#[derive(Debug, Clone)]
pub struct Spectrum {
    /// Bin frequencies [Hz].
    pub f: Vec<f64>,
    /// Amplitudes [Pa].
    pub amplitude: Vec<f64>,
}

/// 20 log10(A / 1 Pa), floored at [`FLOOR_DB`].
pub fn db(a: f64) -> f64 {
    if a > 0.0 { (20.0 * a.log10()).max(FLOOR_DB) } else { FLOOR_DB }
}

impl Spectrum {
    /// The spectrum of `p` sampled every `dt` seconds (at least 2 samples), over its first
    /// [`fft_length`]`(p.len())` samples (the largest 13-smooth length, for a fast FFT plan; the
    /// samples beyond it, at the window's end, are left out: 6001 → 6000; at most 3.5 % of them
    /// for 100 to 200,000 samples, checked by enumeration).
    pub fn of(p: &[f64], dt: f64) -> Spectrum {
        let p = &p[..fft_length(p.len())];
        let n = p.len();
        if n < 2 {
            return Spectrum { f: Vec::new(), amplitude: Vec::new() };
        }
        let w: Vec<f64> = (0..n).map(|i| (std::f64::consts::PI * i as f64 / (n - 1) as f64).sin().powi(2)).collect();
        let sw: f64 = w.iter().sum();
        let mut planner = RealFftPlanner::<f64>::new();
        let fft = planner.plan_fft_forward(n);
        let mut input: Vec<f64> = p.iter().zip(&w).map(|(x, w)| x * w).collect();
        let mut out = fft.make_output_vec();
        fft.process(&mut input, &mut out).expect("buffer lengths from the plan");
        let amplitude = out
            .iter()
            .enumerate()
            .map(|(j, z)| {
                let edge = j == 0 || (n % 2 == 0 && j == n / 2);
                z.norm() / sw * if edge { 1.0 } else { 2.0 }
            })
            .collect();
        let f = (0..out.len()).map(|j| j as f64 / (n as f64 * dt)).collect();
        Spectrum { f, amplitude }
    }

    /// The level [dB re 1 Pa] of the line at `freq` (the largest bin within ±1 bin); `None`
    /// beyond the Nyquist frequency or for an empty spectrum.
    pub fn line_db(&self, freq: f64) -> Option<f64> {
        let df = *self.f.get(1)?;
        let j = (freq / df).round() as usize;
        if j + 1 >= self.f.len() || freq <= 0.0 {
            return None;
        }
        let a = self.amplitude[j.saturating_sub(1)..=j + 1].iter().copied().fold(0.0, f64::max);
        Some(db(a))
    }
}

/// The largest n' ≤ n whose prime factors are all ≤ 13 (n itself for n < 2).
pub fn fft_length(n: usize) -> usize {
    let smooth = |mut m: usize| {
        for f in [2, 3, 5, 7, 11, 13] {
            while m > 1 && m % f == 0 {
                m /= f;
            }
        }
        m == 1
    };
    (1..=n.max(1)).rev().find(|&m| smooth(m)).unwrap_or(n)
}

/// summary.json's `echo` object.
#[derive(Debug, Clone, Serialize)]
pub struct EchoSummary {
    /// max − min of the first point's echo over the window [Pa].
    pub peak_to_peak_pa: f64,
    /// Line levels [dB re 1 Pa] at f, 2f, f/2, 3f/2 (f = drive.frequency_hz; null without tones).
    pub fundamental_db: Option<f64>,
    pub second_harmonic_db: Option<f64>,
    pub subharmonic_db: Option<f64>,
    pub ultraharmonic_db: Option<f64>,
    /// 20 log10(rms of the shape modes' part of the far-field echo / rms of the first point's
    /// echo) over the window [dB relative to the echo]; null for a spherical bubble (exactly 0).
    pub shape_mode_contribution_db: Option<f64>,
    /// "far" or "near"; the window [s]; the spectrum's window function.
    pub form: &'static str,
    pub window_s: [f64; 2],
    pub spectrum_window: &'static str,
}

/// The summary of a recorded echo over `window` (sample indices from, to), with the drive's
/// main frequency `f0` [Hz] when it has tones.
pub fn summarize(p: &[f64], shape: &[f64], t: &[f64], spectrum: &Spectrum, f0: Option<f64>, form: &'static str) -> EchoSummary {
    let (lo, hi) = p.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &x| (l.min(x), h.max(x)));
    let rms = |v: &[f64]| (v.iter().map(|x| x * x).sum::<f64>() / v.len().max(1) as f64).sqrt();
    let (rs, rp) = (rms(shape), rms(p));
    let line = |m: f64| f0.and_then(|f| spectrum.line_db(m * f));
    EchoSummary {
        peak_to_peak_pa: if p.is_empty() { 0.0 } else { hi - lo },
        fundamental_db: line(1.0),
        second_harmonic_db: line(2.0),
        subharmonic_db: line(0.5),
        ultraharmonic_db: line(1.5),
        shape_mode_contribution_db: (rs > 0.0 && rp > 0.0).then(|| 20.0 * (rs / rp).log10()),
        form,
        window_s: [t.first().copied().unwrap_or(0.0), t.last().copied().unwrap_or(0.0)],
        spectrum_window: "hann (symmetric), amplitude-corrected",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A sinusoid on a bin reads its amplitude; one off-bin reads within the scalloping loss;
    /// an absent line is far below.
    #[test]
    fn reads_amplitudes() {
        let (n, dt) = (4000, 1e-8);
        let f = 1e6; // 40 bins of 25 kHz
        let p: Vec<f64> = (0..n).map(|i| 3.0 * (2.0 * std::f64::consts::PI * f * i as f64 * dt).cos() + 0.5).collect();
        let s = Spectrum::of(&p, dt);
        assert!((s.line_db(f).unwrap() - db(3.0)).abs() < 0.01, "{}", s.line_db(f).unwrap());
        assert!((s.amplitude[0] - 0.5).abs() < 1e-3);
        assert!(s.line_db(0.5 * f).unwrap() < db(3.0) - 80.0);
        let g = 1.0125e6;
        let q: Vec<f64> = (0..n).map(|i| (2.0 * std::f64::consts::PI * g * i as f64 * dt).sin()).collect();
        let l = Spectrum::of(&q, dt).line_db(g).unwrap();
        assert!(l <= 0.01 && l > -1.43, "{l}");
        assert_eq!((fft_length(6001), fft_length(4000), fft_length(17)), (6000, 4000, 16));
    }
}
