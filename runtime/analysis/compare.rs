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

/// Errors assembling the two models of a comparison.
#[derive(Debug, thiserror::Error)]
pub enum CompareError {
    #[error("assembling the boundary-layer model: {0}")]
    BoundaryLayer(#[from] crate::model::ModelError),
    #[error("assembling the full (vorticity) model: {0}")]
    Full(#[from] crate::model::vorticity::scene::FullModelError),
    #[error("the two runs sampled different times ({bl} s vs {full} s at sample {index})")]
    TimeMismatch { index: usize, bl: f64, full: f64 },
}

/// One scene run with both closures, sampled at the same times (the shorter run sets `t`).
#[derive(Debug)]
pub struct ClosureRuns {
    /// Output columns: R, a2, b2, …
    pub names: Vec<String>,
    /// Sample times [s] common to both runs.
    pub t: Vec<f64>,
    pub bl: Vec<Vec<f64>>,
    pub full: Vec<Vec<f64>>,
    pub report_bl: crate::model::RunReport,
    pub report_full: crate::model::RunReport,
    pub scheme: crate::scene::VorticityScheme,
    pub diffs: Vec<ColumnDiff>,
}

/// Runs `scene` with the boundary-layer closure and with the full vorticity model
/// (`modes.viscous` of the scene is ignored) and compares the common samples.
pub fn run_both(scene: &crate::scene::Scene) -> Result<ClosureRuns, CompareError> {
    let mut scene = scene.clone();
    scene.modes.viscous = crate::scene::Viscous::BoundaryLayer;
    let bl = crate::model::Model::from_scene(&scene)?;
    let full = crate::model::vorticity::scene::FullModel::from_scene(&scene)?;
    let record = |t: &mut Vec<f64>, rows: &mut Vec<Vec<f64>>, ti: f64, row: &[f64]| {
        t.push(ti);
        rows.push(row.to_vec());
    };
    let (mut t, mut rows_bl) = (vec![], vec![]);
    let report_bl = bl.run(&scene.run, &mut |ti, row| record(&mut t, &mut rows_bl, ti, row));
    let (mut t_full, mut rows_full) = (vec![], vec![]);
    let report_full = full.run(&scene.run, &mut |ti, row| record(&mut t_full, &mut rows_full, ti, row));
    let mut n = rows_bl.len().min(rows_full.len());
    let tol = |ti: f64| 1e-9 * scene.run.sample_interval.max(ti.abs());
    if let Some(i) = (0..n).find(|&i| (t[i] - t_full[i]).abs() > tol(t[i])) {
        // the last row of a run that stopped (blow-up) is at the located crossing, off the
        // sample grid: it has no partner in the other run and is left out of the comparison
        let stop_row = i + 1 == n && (i + 1 == t.len() || i + 1 == t_full.len());
        if !stop_row {
            return Err(CompareError::TimeMismatch { index: i, bl: t[i], full: t_full[i] });
        }
        n = i;
    }
    t.truncate(n);
    rows_bl.truncate(n);
    rows_full.truncate(n);
    let names = bl.state_names();
    let diffs = compare_rows(&names, &rows_bl, &rows_full);
    Ok(ClosureRuns { names, t, bl: rows_bl, full: rows_full, report_bl, report_full, scheme: full.scheme, diffs })
}

impl ClosureRuns {
    /// Writes `t, R_bl, R_full, a2_bl, a2_full, …` (SI) atomically.
    pub fn write_csv(&self, path: &std::path::Path) -> Result<(), crate::output::OutputError> {
        let mut header = vec!["t".to_string()];
        for name in &self.names {
            header.push(format!("{name}_bl"));
            header.push(format!("{name}_full"));
        }
        let mut csv = crate::output::CsvWriter::create(path, &header)?;
        let mut line = vec![0.0; header.len()];
        for (i, &t) in self.t.iter().enumerate() {
            line[0] = t;
            for c in 0..self.names.len() {
                line[1 + 2 * c] = self.bl[i][c];
                line[2 + 2 * c] = self.full[i][c];
            }
            csv.row(&line);
        }
        csv.commit()
    }
}
