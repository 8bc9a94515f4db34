//! Boundary-layer closure against the full vorticity model on one scene (paper §5.1, fig 4):
//! per output column (R, a_k, b_k), the maximum and mean absolute differences of two time
//! series sampled at the same times, and the same relative to the full model's max |x|.

use serde::Serialize;

/// Differences of one column.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ColumnDiff {
    pub name: String,
    /// max_t |x_bl − x_full| [m]
    pub max_abs_diff: f64,
    /// mean_t |x_bl − x_full| [m]
    pub mean_abs_diff: f64,
    /// max_t |x_full| [m] (the scale of the relative numbers)
    pub max_abs_full: f64,
    /// max_abs_diff / max_abs_full (R: of R − R0 excluded; relative to max |R| itself)
    pub max_rel_diff: f64,
    /// mean_abs_diff / max_abs_full
    pub mean_rel_diff: f64,
}

/// Compares two series of rows (same columns, same sample times). Rows beyond the shorter
/// series are ignored (e.g. when one run blew up earlier).
pub fn compare_rows(names: &[String], bl: &[Vec<f64>], full: &[Vec<f64>]) -> Vec<ColumnDiff> {
    let n = bl.len().min(full.len());
    names
        .iter()
        .enumerate()
        .map(|(c, name)| {
            let (mut max_d, mut sum_d, mut max_f) = (0.0f64, 0.0f64, 0.0f64);
            for i in 0..n {
                let d = (bl[i][c] - full[i][c]).abs();
                max_d = max_d.max(d);
                sum_d += d;
                max_f = max_f.max(full[i][c].abs());
            }
            let mean_d = if n > 0 { sum_d / n as f64 } else { f64::NAN };
            let rel = |x: f64| if max_f > 0.0 { x / max_f } else { f64::NAN };
            ColumnDiff {
                name: name.clone(),
                max_abs_diff: max_d,
                mean_abs_diff: mean_d,
                max_abs_full: max_f,
                max_rel_diff: rel(max_d),
                mean_rel_diff: rel(mean_d),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn differences_of_known_series() {
        let names = vec!["R".to_string(), "a2".to_string()];
        let full = vec![vec![1.0, 0.0], vec![1.0, 2.0], vec![1.0, -4.0]];
        let bl = vec![vec![1.0, 1.0], vec![1.0, 2.0], vec![1.0, -1.0]];
        let d = compare_rows(&names, &bl, &full);
        assert_eq!(d[0].max_abs_diff, 0.0);
        assert_eq!(d[1].max_abs_diff, 3.0);
        assert!((d[1].mean_abs_diff - 4.0 / 3.0).abs() < 1e-15);
        assert_eq!(d[1].max_abs_full, 4.0);
        assert!((d[1].max_rel_diff - 0.75).abs() < 1e-15);
    }
}
