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
    let args: Vec<std::ffi::OsString> = std::env::args_os().collect();
    let command = parse_run(&args).unwrap_or_else(|| Cli::parse_from(&args).command);
    let result = dispatch(command).and_then(|()| Ok(crate::output::flush_out()?));
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

/// `magbubble run …` parsed by a command tree holding `run`'s arguments alone; `None` for any
/// other command and for anything `run`'s parser refuses or answers itself (`--help`, an unknown
/// or missing argument), which the whole tree then parses, so its messages are the ones shown.
/// Building the whole tree (every subcommand's arguments) is 0.36 M instructions, a third of a
/// one-step run (issue 34, docs/performance.md "Start-up"); `run` is the command scripts call
/// thousands of times. tests: `cli::tests::run_fast_path_is_the_full_parse`.
fn parse_run(args: &[std::ffi::OsString]) -> Option<Command> {
    use clap::{Args as _, FromArgMatches as _};
    if args.get(1).is_none_or(|a| a != "run") {
        return None;
    }
    let tree = clap::Command::new("magbubble").subcommand(run::RunArgs::augment_args(clap::Command::new("run")));
    let matches = tree.try_get_matches_from(args).ok()?;
    let (_, sub) = matches.subcommand()?;
    run::RunArgs::from_arg_matches(sub).ok().map(Command::Run)
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The `run` fast path gives what the whole tree parses, or leaves the case to it.
    #[test]
    fn run_fast_path_is_the_full_parse() {
        let cases: &[&[&str]] = &[
            &["magbubble", "run", "a.toml"],
            &["magbubble", "run", "a.toml", "--out", "o", "--set", "drive.amplitude=0.3", "--set", "run.duration=1e-6"],
            &["magbubble", "run", "--plot", "a.toml", "--set=x=1"],
            &["magbubble", "run", "--", "--odd.toml"],
        ];
        for argv in cases {
            let args: Vec<std::ffi::OsString> = argv.iter().map(Into::into).collect();
            let fast = parse_run(&args).unwrap_or_else(|| panic!("{argv:?}: the fast path declined"));
            let full = Cli::try_parse_from(&args).unwrap().command;
            assert_eq!(format!("{fast:?}"), format!("{full:?}"), "{argv:?}");
        }
        let declined: &[&[&str]] = &[
            &["magbubble"],
            &["magbubble", "run"],
            &["magbubble", "run", "--help"],
            &["magbubble", "run", "a.toml", "--bogus"],
            &["magbubble", "modes", "a.toml"],
            &["magbubble", "--version"],
        ];
        for argv in declined {
            let args: Vec<std::ffi::OsString> = argv.iter().map(Into::into).collect();
            assert!(parse_run(&args).is_none(), "{argv:?}");
        }
    }
}
