//! The one blow-up classifier of magbubble (FORMULATION §5: a blow-up is a result, reported
//! with the mode and time).

use super::layout::StateLayout;

/// Classifies a nondimensional state y = [R̄, Ṙ̄, (ā_k, ǡ_k, b̄_k)_k] (lengths / R0).
/// Returns the offending mode — "nonfinite", "R" (R ≤ 0), or "a{k}" / "b{k}" when
/// |a_k|/R0 or |b_k|/R0 exceeds `threshold` (the largest such one) — or `None`.
pub fn classify(y: &[f64], orders: &[usize], threshold: f64) -> Option<String> {
    if y.iter().any(|v| !v.is_finite()) {
        return Some("nonfinite".into());
    }
    if y[0] <= 0.0 {
        return Some("R".into());
    }
    let (mut worst, l): (Option<(f64, String)>, _) = (None, StateLayout::reduced(orders.len()));
    for (m, k) in orders.iter().enumerate() {
        for (v, name) in [(y[l.a(m)].abs(), "a"), (y[l.b(m)].abs(), "b")] {
            if v > threshold && worst.as_ref().is_none_or(|w| v > w.0) {
                worst = Some((v, format!("{name}{k}")));
            }
        }
    }
    worst.map(|w| w.1)
}

/// The event function of the blow-up: g(y) = max(max_k max(|a_k|, |b_k|)/R0 − threshold, −R̄),
/// +∞ for a non-finite state. `classify` reports a blow-up exactly when g > 0 (or R̄ = 0); the
/// run executor root-finds g = 0 on the dense output to time the crossing.
pub fn margin(y: &[f64], orders: &[usize], threshold: f64) -> f64 {
    // every component tested, no early exit: a loop the compiler vectorises (called at every
    // sample and step end)
    if !y.iter().fold(true, |ok, v| ok & v.is_finite()) {
        return f64::INFINITY;
    }
    // y is finite here, so a comparison is the maximum (no NaN case of `f64::max` to handle)
    let mut g = -y[0];
    for zk in y[StateLayout::reduced(orders.len()).shape()].chunks_exact(StateLayout::AMPLITUDES) {
        for v in [zk[StateLayout::A].abs() - threshold, zk[StateLayout::B].abs() - threshold] {
            if v > g {
                g = v;
            }
        }
    }
    g
}

/// The credible-range check of a quadratic run (issue 12): the mode "a{k}" with the largest
/// |a_k|/R0 above `bound`, or `None`.
pub fn out_of_range(y: &[f64], orders: &[usize], bound: f64) -> Option<String> {
    let (mut worst, l): (Option<(f64, usize)>, _) = (None, StateLayout::reduced(orders.len()));
    for (m, &k) in orders.iter().enumerate() {
        let v = y[l.a(m)].abs();
        if v > bound && worst.is_none_or(|w| v > w.0) {
            worst = Some((v, k));
        }
    }
    worst.map(|(_, k)| format!("a{k}"))
}

/// Its event function: max_k |a_k|/R0 − bound (positive exactly when [`out_of_range`] reports).
pub fn range_margin(y: &[f64], orders: &[usize], bound: f64) -> f64 {
    let l = StateLayout::reduced(orders.len());
    (0..orders.len()).map(|m| y[l.a(m)].abs() - bound).fold(f64::NEG_INFINITY, f64::max)
}

#[cfg(test)]
mod tests {
    use super::{classify, margin, out_of_range, range_margin};

    #[test]
    fn credible_range_reports_the_largest_a_k_above_the_bound() {
        let orders = [2, 4];
        let mut y = vec![1.0, 0.0, 0.05, 0.0, 0.3, 0.0, 0.0, 0.0];
        assert_eq!(out_of_range(&y, &orders, 0.1), None); // b_k do not count
        assert!(range_margin(&y, &orders, 0.1) < 0.0);
        y[5] = -0.12;
        y[2] = 0.11;
        assert_eq!(out_of_range(&y, &orders, 0.1).as_deref(), Some("a4"));
        assert!((range_margin(&y, &orders, 0.1) - 0.02).abs() < 1e-15);
    }

    #[test]
    fn margin_is_positive_exactly_when_classified() {
        let orders = [2, 4];
        let mut y = vec![1.0, 0.0, 0.01, 0.0, 0.0, 0.0, 0.0, 0.0];
        assert!((margin(&y, &orders, 0.5) - (-0.49)).abs() < 1e-15);
        y[7] = -0.7;
        assert!(margin(&y, &orders, 0.5) > 0.0 && classify(&y, &orders, 0.5).is_some());
        y[7] = 0.0;
        y[0] = -1e-3;
        assert!(margin(&y, &orders, 0.5) > 0.0 && classify(&y, &orders, 0.5).is_some());
        y[1] = f64::NAN;
        assert_eq!(margin(&y, &orders, 0.5), f64::INFINITY);
    }

    #[test]
    fn classifies_modes_radius_and_nan() {
        let orders = [2, 4];
        let mut y = vec![1.0, 0.0, 0.01, 0.0, 0.0, 0.0, 0.0, 0.0];
        assert_eq!(classify(&y, &orders, 0.5), None);
        y[7] = -0.7; // b4
        y[2] = 0.6; // a2
        assert_eq!(classify(&y, &orders, 0.5).as_deref(), Some("b4"));
        y[0] = -1e-3;
        assert_eq!(classify(&y, &orders, 0.5).as_deref(), Some("R"));
        y[3] = f64::NAN;
        assert_eq!(classify(&y, &orders, 0.5).as_deref(), Some("nonfinite"));
    }
}
