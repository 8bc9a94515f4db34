//! The `magbubble` command line. `main.rs` calls [`main_entry`]; each subcommand lives in its
//! own file with its clap `Args` struct and a `run(args) -> anyhow::Result<()>`.

use clap::{Parser, Subcommand};
use std::process::ExitCode;

pub mod accuracy;
mod accuracy_critical;
pub mod coefficients;
pub mod compare;
pub mod convergence;
pub mod figure;
pub mod fit;
pub mod floquet;
pub mod modes;
pub mod population;
pub mod response;
pub mod run;
pub mod scene;
pub mod stability;
pub mod sweep;

#[derive(Debug, Parser)]
#[command(name = "magbubble", version, about = "Oscillations of an encapsulated magnetic microbubble")]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Simulate a scene: writes series.csv and summary.json.
    Run(run::RunArgs),
    /// Print the generated Legendre-coupling coefficients of a field.
    Coefficients(coefficients::CoefficientsArgs),
    /// Write, explain or check scenes.
    #[command(subcommand)]
    Scene(scene::SceneCommand),
    /// Natural frequencies (and the damped linear spectrum) of a scene.
    Modes(modes::ModesArgs),
    /// Floquet stability of the periodic orbit of a driven scene.
    Floquet(floquet::FloquetArgs),
    /// Stability diagrams: critical pressure (or current) against frequency.
    Stability(stability::StabilityArgs),
    /// Join the shards of a sharded stability sweep or grid sweep.
    Merge(stability::MergeArgs),
    /// A grid of runs over scene keys, in parallel: one CSV row per run.
    Sweep(sweep::SweepArgs),
    /// Time-step convergence of the full model (fig 3).
    Convergence(convergence::ConvergenceArgs),
    /// Boundary-layer vs full vorticity model on one scene (fig 4).
    Compare(compare::CompareArgs),
    /// Work–precision: what accuracy costs in time.
    Accuracy(accuracy::AccuracyArgs),
    /// Reproduce the paper's figures from scenes/figures.
    Figure(figure::FigureArgs),
    /// Linear radial response: amplitude, phase, damping by source, σ_s, σ_e per frequency.
    Response(response::ResponseArgs),
    /// A polydisperse population's stability map: per frequency each bin's critical ε_p and
    /// the fraction unstable (population.csv, population_bins.csv).
    Population(population::PopulationArgs),
    /// A population's linear attenuation [dB/cm] and backscatter coefficient (attenuation.csv).
    Attenuation(population::AttenuationArgs),
    /// Fit scene parameters to measured R(t) (and a_k(t)): values, standard errors, correlations.
    Fit(fit::FitArgs),
}

/// Parses the arguments, runs the subcommand, prints the whole error chain on failure.
///
/// A closed stdout (`| head`) ends the command quietly with status 141 (128 + SIGPIPE, what a
/// shell reports for a program killed by a broken pipe); any other write error is an error.
pub fn main_entry() -> ExitCode {
    let cli = Cli::parse();
    let result = dispatch(cli.command).and_then(|()| Ok(crate::output::flush_out()?));
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            let broken_pipe = err
                .chain()
                .any(|e| e.downcast_ref::<crate::output::StdoutError>().is_some_and(|s| s.is_broken_pipe()));
            if broken_pipe {
                return ExitCode::from(141);
            }
            report_error(&err);
            ExitCode::FAILURE
        }
    }
}

/// `error: …` and one `caused by:` line per cause that adds something (a cause whose text is
/// already part of the line above is not repeated).
fn report_error(err: &anyhow::Error) {
    let top = err.to_string();
    noteln!("error: {top}");
    let mut shown = top;
    for cause in err.chain().skip(1) {
        let text = cause.to_string();
        if shown.contains(&text) {
            continue;
        }
        noteln!("  caused by: {text}");
        shown = text;
    }
}

fn dispatch(command: Command) -> anyhow::Result<()> {
    match command {
        Command::Run(a) => run::run(&a),
        Command::Coefficients(a) => coefficients::run(&a),
        Command::Scene(c) => scene::run(&c),
        Command::Modes(a) => modes::run(&a),
        Command::Floquet(a) => floquet::run(&a),
        Command::Stability(a) => stability::run(&a),
        Command::Merge(a) => stability::merge(&a),
        Command::Sweep(a) => sweep::run(&a),
        Command::Convergence(a) => convergence::run(&a),
        Command::Compare(a) => compare::run(&a),
        Command::Accuracy(a) => accuracy::run(&a),
        Command::Figure(a) => figure::run(&a),
        Command::Response(a) => response::run(&a),
        Command::Population(a) => population::run_population(&a),
        Command::Attenuation(a) => population::run_attenuation(&a),
        Command::Fit(a) => fit::run(&a),
    }
}
