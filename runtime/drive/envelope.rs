//! Burst envelopes w(u) on u = τ/L ∈ [0, 1] (docs/model.md, "Drives"): zero outside, with their
//! exact derivative dw/du for the drive's time derivative.

/// The shape of a burst's envelope.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Shape {
    /// w = 1.
    Rectangular,
    /// w = sin²(π u).
    Hann,
    /// w = exp(−x²/2), x = (u − ½) L/σ = 8 (u − ½): the burst spans ±4σ about its centre
    /// (truncated there: w = e⁻⁸ = 3.4·10⁻⁴ at the edges), σ = FWHM/(2√(2 ln 2)) with the FWHM
    /// `cycles` carrier periods (so L = 8σ = 3.397 · cycles/f).
    Gaussian,
    /// Tukey (tapered cosine) with taper fraction α ∈ [0, 1]: cosine tapers of length αL/2 at
    /// each end, 1 between (α = 0: rectangular, α = 1: Hann).
    Tukey(f64),
}

/// L/σ of the Gaussian envelope: the burst is truncated at ±4σ.
pub const GAUSS_HALF_WIDTH_SIGMAS: f64 = 4.0;

/// 2√(2 ln 2): FWHM/σ of a Gaussian.
pub fn fwhm_over_sigma() -> f64 {
    2.0 * (2.0 * std::f64::consts::LN_2).sqrt()
}

impl Shape {
    /// The burst length L in carrier periods for `cycles` (the Gaussian's FWHM is `cycles`
    /// periods, its truncated support 8σ).
    pub fn length_in_periods(&self, cycles: f64) -> f64 {
        match self {
            Shape::Gaussian => cycles / fwhm_over_sigma() * 2.0 * GAUSS_HALF_WIDTH_SIGMAS,
            _ => cycles,
        }
    }

    /// (w(u), dw/du) for u ∈ [0, 1].
    pub fn at(&self, u: f64) -> (f64, f64) {
        use std::f64::consts::PI;
        match *self {
            Shape::Rectangular => (1.0, 0.0),
            Shape::Hann => {
                let s = (PI * u).sin();
                (s * s, PI * (2.0 * PI * u).sin())
            }
            Shape::Gaussian => {
                let k = 2.0 * GAUSS_HALF_WIDTH_SIGMAS;
                let x = (u - 0.5) * k;
                let w = (-0.5 * x * x).exp();
                (w, -x * k * w)
            }
            Shape::Tukey(a) => {
                if a <= 0.0 {
                    return (1.0, 0.0);
                }
                let taper = |v: f64| {
                    // rising half-cosine over v ∈ [0, a/2]
                    let s = (PI * v / a).sin();
                    (s * s, PI / a * (2.0 * PI * v / a).sin())
                };
                if u < 0.5 * a {
                    taper(u)
                } else if u > 1.0 - 0.5 * a {
                    let (w, dw) = taper(1.0 - u);
                    (w, -dw)
                } else {
                    (1.0, 0.0)
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// dw/du against a central difference, for every shape, away from the Tukey joints.
    #[test]
    fn derivatives_match_differences() {
        for s in [Shape::Rectangular, Shape::Hann, Shape::Gaussian, Shape::Tukey(0.5), Shape::Tukey(1.0)] {
            for i in 1..40 {
                let u = i as f64 / 40.0 + 0.0031;
                let h = 1e-6;
                let fd = (s.at(u + h).0 - s.at(u - h).0) / (2.0 * h);
                let (_, dw) = s.at(u);
                assert!((fd - dw).abs() < 1e-6 * (1.0 + dw.abs()), "{s:?} u={u}: {dw} vs {fd}");
            }
        }
    }

    /// Tukey(1) is Hann, Tukey(0) is rectangular; the Gaussian's FWHM is `cycles` periods.
    #[test]
    fn limits_and_width() {
        for i in 0..=20 {
            let u = i as f64 / 20.0;
            assert!((Shape::Tukey(1.0).at(u).0 - Shape::Hann.at(u).0).abs() < 1e-15);
            assert_eq!(Shape::Tukey(0.0).at(u), (1.0, 0.0));
        }
        let cycles = 2.0;
        let l = Shape::Gaussian.length_in_periods(cycles);
        // half maximum at the centre ± cycles/2 periods
        let u = 0.5 + 0.5 * cycles / l;
        assert!((Shape::Gaussian.at(u).0 - 0.5).abs() < 1e-12);
        assert!((Shape::Gaussian.at(0.0).0 - (-8.0f64).exp()).abs() < 1e-15);
    }
}
