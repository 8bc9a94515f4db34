//! `magbubble fit SCENE --data FILE --param KEY[=LOW:HIGH] … [--out DIR] [--plot] [--starts N]`
//! (issue 32): fit.json (parameters with standard errors, correlation, residual_rms,
//! iterations, status, warnings) and fit.csv (t, then per fitted column data, model, residual);
//! `--plot` draws data against model and the residuals (fit.svg/png). The fit runs to the end
//! before anything is written; each file is written atomically.

use crate::api::fit::{fit, Data, FitRequest, ParamSpec};
use crate::api::{Monitor, Scene};
use crate::output::{write_json, CsvWriter, OutputDir};
use crate::plot::{Axis, Figure, Panel, Series};
use anyhow::Context as _;
use std::path::PathBuf;

#[derive(Debug, clap::Args)]
pub struct FitArgs {
    /// The scene file (TOML): the model and the start values.
    pub scene: PathBuf,
    /// Measurements: CSV with t [s], R [m], optional a2, a4, … [m] and sigma_R, sigma_a2, … [m].
    #[arg(long)]
    pub data: PathBuf,
    /// A parameter to fit: a numeric scene key or time_offset, with optional bounds LOW:HIGH
    /// (repeatable).
    #[arg(long = "param", value_name = "KEY[=LOW:HIGH]", required = true)]
    pub params: Vec<String>,
    /// Output directory (default: out/<scene file stem>-fit).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Draw data against model and the residuals (fit.svg, fit.png).
    #[arg(long)]
    pub plot: bool,
    /// Optimise from N start points (the scene's values, then points drawn in the bounds).
    #[arg(long, default_value_t = 1)]
    pub starts: usize,
    /// Override a scene key (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
}

pub fn run(args: &FitArgs) -> anyhow::Result<()> {
    let params = args.params.iter().map(|p| p.parse::<ParamSpec>()).collect::<anyhow::Result<Vec<_>>>()?;
    let scene = Scene::load(&args.scene, &args.set)?;
    let data = Data::read(&args.data)?;
    let mut request = FitRequest::new(data, params);
    request.starts = args.starts;
    for w in &scene.scene().warnings {
        noteln!("warning: {w}");
    }
    #[cfg(unix)]
    let cancel = Some(crate::output::cancel_on_signal());
    #[cfg(not(unix))]
    let cancel = None;
    let report = fit(&scene, &request, &Monitor { cancel, ..Monitor::default() })?;
    let out = args.out.clone().unwrap_or_else(|| super::run::default_out_for(&args.scene, "fit"));
    let dir = OutputDir::create(&out)?;
    if !report.curves.is_empty() {
        let mut header = vec!["t".to_string()];
        for c in &report.curves {
            header.extend([format!("{}_data", c.name), format!("{}_model", c.name), format!("{}_residual", c.name)]);
        }
        let mut csv = CsvWriter::create(&dir.join("fit.csv"), &header)?;
        let mut row = Vec::with_capacity(header.len());
        for (i, &t) in report.t.iter().enumerate() {
            row.clear();
            row.push(t);
            for c in &report.curves {
                row.extend([c.data[i], c.model[i], c.residual[i]]);
            }
            csv.row(&row);
        }
        csv.commit()?;
    }
    write_json(&dir.join("fit.json"), &report)?;
    if args.plot && !report.curves.is_empty() {
        let t_us: Vec<f64> = report.t.iter().map(|t| t * 1e6).collect();
        let mut panels = Vec::new();
        for c in &report.curves {
            let um = |v: &[f64]| v.iter().map(|x| x * 1e6).collect::<Vec<_>>();
            panels.push(
                Panel::new(Axis::linear("t [us]"), Axis::linear(format!("{} [um]", c.name)))
                    .series(Series::points("data", t_us.clone(), um(&c.data)))
                    .series(Series::line("model", t_us.clone(), um(&c.model))),
            );
            panels.push(
                Panel::new(Axis::linear("t [us]"), Axis::linear(format!("{} residual [um]", c.name)))
                    .series(Series::points("model - data", t_us.clone(), um(&c.residual))),
            );
        }
        Figure::stacked(panels).title(format!("fit: {}", args.scene.display())).save(&out, "fit").context("the fit's plot")?;
    }
    for p in &report.parameters {
        outln!("{} = {:e} ± {:e} ({})", p.key, p.value, p.std_error, p.derivative);
    }
    for w in &report.warnings {
        outln!("warning: {w}");
    }
    outln!(
        "status: {}{}; {} iterations, residual rms {:.3} (weighted); wrote {}",
        report.status,
        report.reason.as_ref().map(|r| format!(" ({r})")).unwrap_or_default(),
        report.iterations,
        report.residual_rms,
        out.join("fit.json").display()
    );
    if report.status == "failed" {
        anyhow::bail!("the fit failed: {}", report.reason.clone().unwrap_or_default());
    }
    Ok(())
}
