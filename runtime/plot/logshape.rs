//! When shape amplitudes go on a log axis, and how (issue 15 "shape modes on a log |a_k| axis
//! when amplitudes span decades or a run blows up").
//!
//! A linear axis shows only the largest curve when the modes of a panel differ by orders of
//! magnitude, and only the last microsecond of a run that blows up (one spike at the end, the
//! growth before it flat at zero). [`wants_log`] decides; [`log_magnitudes`] gives |a| above a
//! floor, so the axis is not stretched over twenty decades by zero crossings.

/// Ratio of amplitudes (two decades) from which a panel is drawn on a log axis.
pub const LOG_SPAN: f64 = 100.0;
/// The floor of [`log_magnitudes`]: the smallest per-curve [`FLOOR_QUANTILE`] quantile of
/// |a| > 0, and never below [`MAX_DECADES`] decades under the largest |a|.
const FLOOR_QUANTILE: f64 = 0.02;
const MAX_DECADES: i32 = 12;

fn max_abs(v: &[f64]) -> f64 {
    v.iter().filter(|x| x.is_finite()).fold(0.0, |m, x| m.max(x.abs()))
}

/// Whether curves (one per mode or run) belong on a log |a| axis: a run blew up, or among the
/// curves that are not identically zero the largest and the smallest maximum |a| differ by
/// [`LOG_SPAN`] or more, or one curve grows or decays by that much (the maxima of |a| over its
/// ten consecutive tenths, zero tenths left out).
pub fn wants_log(curves: &[Vec<f64>], blown_up: bool) -> bool {
    let maxima: Vec<f64> = curves.iter().map(|c| max_abs(c)).filter(|m| *m > 0.0).collect();
    if maxima.is_empty() {
        return false;
    }
    if blown_up {
        return true;
    }
    let spans = |m: &mut dyn Iterator<Item = f64>| {
        let (lo, hi) = m.filter(|v| *v > 0.0).fold((f64::INFINITY, 0.0f64), |(l, h), v| (l.min(v), h.max(v)));
        hi >= LOG_SPAN * lo
    };
    spans(&mut maxima.iter().copied())
        || curves.iter().any(|c| c.len() >= 10 && spans(&mut c.chunks(c.len().div_ceil(10)).map(max_abs)))
}

/// |a| of every curve; values below the common floor (module docs: a mode not excited yet,
/// the bottom of a zero crossing) and non-finite values are gaps, so nothing lies flat on the
/// bottom of the axis looking like data.
pub fn log_magnitudes(curves: &[Vec<f64>]) -> Vec<Vec<f64>> {
    let top = curves.iter().map(|c| max_abs(c)).fold(0.0, f64::max);
    let mut floor = f64::INFINITY;
    for c in curves {
        let mut pos: Vec<f64> = c.iter().filter(|x| x.is_finite() && **x != 0.0).map(|x| x.abs()).collect();
        if pos.is_empty() {
            continue;
        }
        pos.sort_by(f64::total_cmp);
        floor = floor.min(pos[((pos.len() - 1) as f64 * FLOOR_QUANTILE) as usize]);
    }
    let floor = floor.max(top * 10f64.powi(-MAX_DECADES));
    curves
        .iter()
        .map(|c| c.iter().map(|x| if x.is_finite() && x.abs() >= floor { x.abs() } else { f64::NAN }).collect())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wave(amp: f64, n: usize) -> Vec<f64> {
        (0..n).map(|i| amp * (0.3 * i as f64).sin()).collect()
    }

    #[test]
    fn decades_apart_or_growing_or_blown_up_is_log() {
        assert!(!wants_log(&[wave(1.0, 100), wave(0.5, 100)], false));
        assert!(wants_log(&[wave(1.0, 100), wave(1e-3, 100)], false));
        assert!(wants_log(&[wave(1.0, 100)], true));
        assert!(!wants_log(&[vec![0.0; 10]], true), "nothing to draw on a log axis");
        let growing: Vec<f64> = (0..100).map(|i| 1e-6 * (0.2 * i as f64).exp() * (i as f64).cos()).collect();
        let decaying: Vec<f64> = growing.iter().rev().copied().collect();
        assert!(wants_log(&[growing], false));
        assert!(wants_log(&[decaying], false));
    }

    #[test]
    fn magnitudes_have_a_floor_near_the_smallest_amplitude() {
        let m = log_magnitudes(&[wave(1.0, 1000), wave(1e-4, 1000), vec![0.0, f64::NAN]]);
        let floor = m[1].iter().cloned().fold(f64::INFINITY, f64::min);
        assert!(floor > 1e-8 && floor < 1e-4, "{floor}");
        assert!(m[2][0].is_nan() && m[2][1].is_nan(), "zeros and NaN are gaps");
        assert!(m.iter().flatten().filter(|v| v.is_finite()).all(|v| *v >= floor));
        assert!(m[1].iter().filter(|v| v.is_nan()).count() < 30, "only the bottoms of zero crossings are cut");
        assert!((m[0].iter().cloned().fold(0.0, f64::max) - 1.0).abs() < 1e-3);
    }
}
