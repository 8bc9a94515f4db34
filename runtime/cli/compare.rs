//! `magbubble compare SCENE [--out DIR] [--set key=value]…`: the scene with the boundary-layer
//! closure and with the full vorticity model (paper §5.1, fig 4). Prints the maximum and mean
//! differences of R and every a_k, b_k; writes `DIR/compare.csv` (t and both series of every
//! column) and `DIR/compare.json` (the differences and both run reports), atomically; with
//! `--plot` `DIR/compare.{svg,png}` (R and the largest a_k of both runs, and their difference).

use crate::analysis::compare::run_both;
use crate::output::{write_json, OutputDir};
use crate::plot::study::compare_figure;
use crate::scene;
use anyhow::Context;
use std::path::PathBuf;

/// Arguments of `magbubble compare`.
#[derive(Debug, clap::Args)]
pub struct CompareArgs {
    /// The scene file (TOML); `modes.viscous` is ignored (both closures are run).
    pub scene: PathBuf,
    /// Output directory (default: out/<scene file stem>-compare).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Override a scene key, e.g. --set drive.amplitude=0.3 (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Also draw both series and their difference (compare.svg/.png).
    #[arg(long)]
    pub plot: bool,
}

pub fn run(args: &CompareArgs) -> anyhow::Result<()> {
    let scene = scene::load(&args.scene, &args.set).with_context(|| format!("loading {}", args.scene.display()))?;
    let runs = run_both(&scene)?;
    let (rep_bl, rep_full, diffs) = (&runs.report_bl, &runs.report_full, &runs.diffs);
    outln!("boundary layer: {:?}; full ({:?}): {:?}", rep_bl.status, runs.scheme, rep_full.status);
    outln!("{:>6} {:>14} {:>14} {:>14} {:>10} {:>10}", "column", "max |diff| m", "mean |diff| m", "max |full| m", "max rel", "mean rel");
    for d in diffs {
        outln!(
            "{:>6} {:>14.4e} {:>14.4e} {:>14.4e} {:>10} {:>10}",
            d.name,
            d.max_abs_diff,
            d.mean_abs_diff,
            d.max_abs_full,
            rel_cell(d.max_rel_diff, d.max_abs_diff),
            rel_cell(d.mean_rel_diff, d.mean_abs_diff)
        );
    }
    let out = args.out.clone().unwrap_or_else(|| super::run::default_out_for(&args.scene, "compare"));
    let dir = OutputDir::create(&out)?;
    runs.write_csv(&dir.join("compare.csv"))?;
    #[derive(serde::Serialize)]
    struct Summary<'a> {
        differences: &'a [crate::analysis::compare::ColumnDiff],
        boundary_layer: &'a crate::model::RunReport,
        vorticity: &'a crate::model::RunReport,
    }
    write_json(&dir.join("compare.json"), &Summary { differences: diffs, boundary_layer: rep_bl, vorticity: rep_full })?;
    if args.plot {
        let blow_up = |s: &crate::model::RunStatus| match s {
            crate::model::RunStatus::BlowUp { t, mode } => Some((mode.clone(), *t)),
            _ => None,
        };
        let title = format!("boundary layer vs full vorticity: {}", args.scene.display());
        compare_figure(&title, &runs.names, &runs.t, &runs.bl, &runs.full, [blow_up(&rep_bl.status), blow_up(&rep_full.status)])
            .save(dir.path(), "compare")
            .context("writing the compare plot")?;
        outln!("plotted {}", dir.join("compare.svg").display());
    } else {
        // an earlier run's plot would sit beside the new data (issue 29 item 9)
        for stale in crate::plot::remove_stale_plots(dir.path(), &["compare"]) {
            noteln!("removed {} (an earlier run's plot; --plot draws a new one)", stale.display());
        }
    }
    outln!("wrote {}", out.display());
    Ok(())
}

/// A relative difference for the table: `0` when both runs are identical in that column (a mode
/// identically zero in both, where diff/max|full| is 0/0), `—` when the full run is identically
/// zero but the boundary-layer run is not (no scale to be relative to).
fn rel_cell(rel: f64, abs_diff: f64) -> String {
    if rel.is_finite() {
        format!("{rel:.3e}")
    } else if abs_diff == 0.0 {
        "0".to_string()
    } else {
        "—".to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::rel_cell;

    #[test]
    fn zero_columns_print_zero_not_nan() {
        assert_eq!(rel_cell(f64::NAN, 0.0), "0");
        assert_eq!(rel_cell(f64::NAN, 1e-9), "—");
        assert_eq!(rel_cell(0.25, 1.0), "2.500e-1");
    }
}
