//! The library API: the one entry point of the command line (`crate::cli`) and of the Python
//! binding (`python/src`). Each command is a function over typed inputs that returns a typed
//! result; nothing here parses command-line text, prints, or draws, and nothing crosses as CSV
//! or JSON text (files are written only where a caller passes an output directory, and the
//! JSON a command prints is the `serde` serialisation of its typed result).
//!
//! | command        | file              | entry point                                   | result |
//! |----------------|-------------------|-----------------------------------------------|--------|
//! | scene          | [`scene`]         | [`Scene::load`], [`Scene::from_toml`], [`Scene::with_overrides`] | [`Scene`] |
//! | run            | [`run`]           | [`run::run`] (in memory), [`run::stream`] (row sink) | [`RunResult`], [`RunOutcome`] |
//! | modes          | [`modes`]         | [`modes::modes`]                              | [`modes::Modes`] |
//! | floquet        | [`floquet`]       | [`floquet::floquet`]                          | [`floquet::FloquetResult`] |
//! | stability      | [`stability`]     | [`stability::stability`]                      | [`stability::StabilityOutput`] |
//! | sweep          | [`sweep`]         | [`sweep::sweep`] (rows streamed to a sink)    | [`sweep::SweepSummary`] |
//! | accuracy       | [`accuracy`]      | [`accuracy::study`], [`accuracy::critical`]   | the analysis reports |
//! | coefficients   | [`coefficients`]  | [`coefficients::coefficients`]                | [`coefficients::Coefficients`] |
//! | population     | [`population`]    | [`population::population`]                   | [`population::PopulationOutput`] |
//! | attenuation    | [`attenuation`]   | [`attenuation::attenuation`]                  | [`attenuation::AttenuationOutput`] |
//! | fit            | [`fit`]           | [`fit::fit`]                                  | [`fit::FitReport`] |
//! | response       | [`response`]      | [`response::response`], [`response::table`]   | [`response::Response`] |
//! | (run's echo)   | [`echo`]          | [`RunOutcome::echo`](run::RunOutcome)         | [`echo::Echo`] |
//!
//! A table of results (a sweep's rows, a stability diagram's) is also available as typed
//! columns ([`table::Table`], [`sweep::SweepTable`]), what Python turns into a DataFrame.
//!
//! Long calls take a [`Monitor`] ([`common`]): `progress(done, total)` is reported through it
//! and `cancelled()` is polled, so the CLI draws indicatif bars and stops on SIGINT, and Python
//! shows tqdm and stops on Ctrl-C. Errors are `anyhow::Error` chains with context (which file,
//! which key, which value, why); a blow-up or a failed integration is a status, not an error.
//!
//! ## Adding a command (e.g. `response`, `fit`, `population`)
//!
//! 1. Write `runtime/api/<command>.rs`: a typed request (plain fields: numbers, enums, paths,
//!    an [`api::Scene`](Scene); no command-line text), a typed result that derives or
//!    implements `Serialize` (its serialisation is what `--json` prints and what Python turns
//!    into a dict), and `pub fn <command>(scene: &Scene, request, monitor: &Monitor) ->
//!    anyhow::Result<Result>`. The physics stays in `crate::analysis` / `crate::model`.
//! 2. Add `pub mod <command>;` below and a row to the table above.
//! 3. `runtime/cli/<command>.rs`: clap arguments → the request, the result → text and files.
//! 4. `python/src/calls.rs`: a `#[pyfunction]` that builds the request from Python values,
//!    runs it in `worker::run` (GIL released, progress, Ctrl-C) and converts the result with
//!    `pythonize` or to numpy arrays; `python/magbubble/__init__.py` wraps it.

pub mod accuracy;
// population (issue 33)
pub mod attenuation;
pub mod population;
pub mod coefficients;
pub mod common;
pub mod fit;
pub mod echo;
pub mod floquet;
pub mod modes;
pub mod response;
pub mod run;
pub mod scene;
pub mod stability;
pub mod sweep;
pub mod table;

pub use common::Monitor;
pub use run::{RunOutcome, RunResult, Summary};
pub use scene::Scene;
