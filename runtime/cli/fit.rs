//! `magbubble fit SCENE --data FILE --param KEY[=LOW:HIGH] … [--out DIR] [--plot] [--starts N]`
//! (issue 32): fit.json (parameters with standard errors, correlation, residual_rms,
//! iterations, status, warnings) and fit.csv (t, then per fitted column data, model, residual);
//! `--plot` draws data against model and the residuals (fit.svg/png). The fit runs to the end
//! before anything is written; each file is written atomically.

use crate::api::fit::{fit, fit_attenuation, AttenuationFitRequest, Data, FitRequest, ParamSpec, Spectrum};
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
    #[arg(long, required_unless_present = "attenuation", conflicts_with = "attenuation")]
    pub data: Option<PathBuf>,
    /// A measured attenuation spectrum instead: CSV with f [Hz], attenuation_db_per_cm, optional
    /// sigma [dB/cm]; the suspension is the scene's [population] (population.concentration) or
    /// monodisperse at bubble.radius with --concentration.
    #[arg(long, value_name = "FILE")]
    pub attenuation: Option<PathBuf>,
    /// Bubbles per mL of a monodisperse suspension (a scene without [population]; --attenuation).
    #[arg(long, value_name = "N", requires = "attenuation")]
    pub concentration: Option<f64>,
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
    if let Some(path) = &args.attenuation {
        return spectrum(args, &scene, params, path);
    }
    let data = Data::read(args.data.as_ref().expect("clap: --data or --attenuation"))?;
    let mut request = FitRequest::new(data, params);
    request.starts = args.starts;
    let report = fit(&scene, &request, &start(&scene))?;
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
    summary(&report, &out)
}

/// The parameters, warnings and status on stdout; a failed fit is an error (after fit.json).
fn summary(report: &crate::api::fit::FitReport, out: &std::path::Path) -> anyhow::Result<()> {
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

/// `--attenuation`: fit.json as for R(t), fit.csv with f, data, model, residual; --plot draws
/// the spectrum against the model and the residuals.
fn spectrum(args: &FitArgs, scene: &Scene, params: Vec<ParamSpec>, path: &std::path::Path) -> anyhow::Result<()> {
    let data = Spectrum::read(path)?;
    let mut request = AttenuationFitRequest::new(data, params, args.concentration);
    request.starts = args.starts;
    let report = fit_attenuation(scene, &request, &start(scene))?;
    let out = args.out.clone().unwrap_or_else(|| super::run::default_out_for(&args.scene, "fit"));
    let dir = OutputDir::create(&out)?;
    if let Some(c) = report.curves.first() {
        let mut csv = CsvWriter::create(&dir.join("fit.csv"), &["f", "data", "model", "residual"].map(String::from))?;
        for (i, &f) in report.t.iter().enumerate() {
            csv.row(&[f, c.data[i], c.model[i], c.residual[i]]);
        }
        csv.commit()?;
    }
    write_json(&dir.join("fit.json"), &report)?;
    if let (true, Some(c)) = (args.plot, report.curves.first()) {
        let mhz: Vec<f64> = report.t.iter().map(|f| f * 1e-6).collect();
        let panels = vec![
            Panel::new(Axis::linear("f [MHz]"), Axis::linear("attenuation [dB/cm]"))
                .series(Series::points("data", mhz.clone(), c.data.clone()))
                .series(Series::line("model", mhz.clone(), c.model.clone())),
            Panel::new(Axis::linear("f [MHz]"), Axis::linear("residual [dB/cm]")).series(Series::points("model - data", mhz, c.residual.clone())),
        ];
        Figure::stacked(panels).title(format!("attenuation fit: {}", args.scene.display())).save(&out, "fit").context("the fit's plot")?;
    }
    summary(&report, &out)
}

/// The scene's warnings printed, and the monitor of a fit that stops on Ctrl-C.
fn start(scene: &Scene) -> Monitor<'static> {
    for w in &scene.scene().warnings {
        noteln!("warning: {w}");
    }
    #[cfg(unix)]
    let cancel = Some(crate::output::cancel_on_signal());
    #[cfg(not(unix))]
    let cancel = None;
    Monitor { cancel, ..Monitor::default() }
}
