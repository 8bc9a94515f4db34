//! A base-10 logarithmic axis with readable ticks. plotters' own log coordinate labels every
//! minor tick when the range spans less than a few decades (overlapping text); this one labels
//! decades, or 1-2-5 multiples, or every multiple, whichever gives a few labels, and draws the
//! 1…9 multiples as light grid lines.

use plotters::coord::ranged1d::{DefaultFormatting, KeyPointHint, Ranged};
use std::ops::Range;

/// `lo..hi`, both positive, `lo < hi` (checked by the caller).
#[derive(Debug, Clone, Copy)]
pub(crate) struct LogAxis {
    pub lo: f64,
    pub hi: f64,
}

impl LogAxis {
    /// Every `m · 10^n` within the range, for the multipliers given, ascending.
    fn multiples(&self, mults: &[f64]) -> Vec<f64> {
        let (n0, n1) = (
            self.lo.log10().floor() as i32,
            self.hi.log10().ceil() as i32,
        );
        let mut out = Vec::new();
        for n in n0..=n1 {
            let p = 10f64.powi(n);
            for &m in mults {
                let v = m * p;
                // Tolerate rounding at the ends (e.g. 1e-3 computed as 0.0010000000000000002).
                if v >= self.lo * (1.0 - 1e-12) && v <= self.hi * (1.0 + 1e-12) {
                    out.push(v);
                }
            }
        }
        out
    }

    /// A few evenly spaced round values for a range narrower than one 1…9 step.
    fn linear_ticks(&self, max: usize) -> Vec<f64> {
        let span = self.hi - self.lo;
        let raw = span / (max.clamp(2, 5) as f64);
        let mag = 10f64.powf(raw.log10().floor());
        let step = [1.0, 2.0, 5.0, 10.0]
            .iter()
            .map(|m| m * mag)
            .find(|&s| s >= raw)
            .unwrap_or(10.0 * mag);
        let mut v = (self.lo / step).ceil() * step;
        let mut out = Vec::new();
        while v <= self.hi && out.len() < max {
            out.push(v);
            v += step;
        }
        out
    }
}

const ALL: [f64; 9] = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0];

impl Ranged for LogAxis {
    type FormatOption = DefaultFormatting;
    type ValueType = f64;

    fn map(&self, v: &f64, limit: (i32, i32)) -> i32 {
        let (l0, l1) = (self.lo.log10(), self.hi.log10());
        let f = if *v > 0.0 {
            (v.log10() - l0) / (l1 - l0)
        } else {
            -10.0
        };
        // Clamp far-away values so the pixel coordinate cannot overflow.
        let f = if f.is_finite() {
            f.clamp(-10.0, 11.0)
        } else {
            -10.0
        };
        limit.0 + ((limit.1 - limit.0) as f64 * f).round() as i32
    }

    fn key_points<H: KeyPointHint>(&self, hint: H) -> Vec<f64> {
        let max = hint.max_num_points();
        if max == 0 {
            return Vec::new();
        }
        if hint.weight().allow_light_points() {
            let all = self.multiples(&ALL);
            if all.len() <= max {
                return all;
            }
        }
        let decades = self.multiples(&[1.0]);
        if decades.len() >= 3 {
            let step = decades.len().div_ceil(max).max(1);
            return decades
                .into_iter()
                .enumerate()
                .filter(|(i, _)| i % step == 0)
                .map(|(_, v)| v)
                .collect();
        }
        for mults in [&[1.0, 2.0, 5.0][..], &ALL[..]] {
            let v = self.multiples(mults);
            if v.len() >= 3 && v.len() <= max {
                return v;
            }
        }
        let v = self.multiples(&[1.0, 2.0, 5.0]);
        if v.len() >= 2 && v.len() <= max {
            return v;
        }
        self.linear_ticks(max)
    }

    fn range(&self) -> Range<f64> {
        self.lo..self.hi
    }
}

/// Compact tick text: `0`, `0.25`, `150`, `1e-5`, `2.5e6`.
/// A tick label; on an integer axis (mode numbers) a tick between whole numbers gets none.
pub(crate) fn axis_tick_label(v: f64, integer: bool) -> String {
    if integer && (v - v.round()).abs() > 1e-9 * v.abs().max(1.0) {
        return String::new();
    }
    if integer {
        return format!("{}", v.round() as i64);
    }
    tick_label(v)
}

pub(crate) fn tick_label(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return if v == 0.0 { "0".into() } else { format!("{v}") };
    }
    let a = v.abs();
    if !(1e-3..1e5).contains(&a) {
        let s = format!("{v:.2e}");
        let (mant, exp) = s.split_once('e').unwrap_or((&s, "0"));
        let mant = mant.trim_end_matches('0').trim_end_matches('.');
        return format!("{mant}e{exp}");
    }
    let s = format!("{v:.4}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    s.to_string()
}

#[cfg(test)]
mod tests {
    use super::*;
    use plotters::coord::ranged1d::BoldPoints;

    #[test]
    fn ticks_are_decades_or_one_two_five() {
        let wide = LogAxis {
            lo: 1e-10,
            hi: 2e-3,
        };
        let t = wide.key_points(BoldPoints(10));
        assert_eq!(t.len(), 8, "{t:?}");
        assert!((t[0] - 1e-10).abs() < 1e-22 && (t[7] - 1e-3).abs() < 1e-15);
        let narrow = LogAxis {
            lo: 1.1e-3,
            hi: 1.1e-2,
        };
        let t = narrow.key_points(BoldPoints(10));
        assert_eq!(t.len(), 3, "{t:?}"); // 2e-3, 5e-3, 1e-2
        let tiny = LogAxis { lo: 1.1, hi: 1.3 };
        let t = tiny.key_points(BoldPoints(10));
        assert!(
            t.len() >= 2 && t.iter().all(|&v| (1.1..=1.3).contains(&v)),
            "{t:?}"
        );
        assert_eq!(wide.map(&1e-10, (0, 100)), 0);
        assert_eq!(wide.map(&2e-3, (0, 100)), 100);
        assert_eq!(wide.map(&0.0, (0, 100)), -1000);
        assert_eq!(wide.map(&f64::NAN, (0, 100)), -1000);
    }

    #[test]
    fn integer_axes_label_whole_numbers_only() {
        assert_eq!(axis_tick_label(8.0, true), "8");
        assert_eq!(axis_tick_label(7.999999999999, true), "8");
        assert_eq!(axis_tick_label(7.5, true), "");
        assert_eq!(axis_tick_label(0.25, true), "");
        assert_eq!(axis_tick_label(7.5, false), super::tick_label(7.5));
    }
}
