//! The integration tests, one binary (one link for a clean build): each module is one former
//! test file. Shared helpers: `common` (hand-built scenes), `support` (Prony fit).

mod common;
mod support;

mod blow_up_time;
mod accuracy;
mod cli_run;
mod equations_jacobian;
mod cli_run_real;
mod cli_signal;
mod cli_streams;
mod codegen_algebra;
mod codegen_errors;
mod codegen_golden;
mod cost_snapshots;
mod codegen_tables;
mod coefficients_crosscheck;
mod coil_h4;
mod docs_examples;
mod figures;
mod floquet_cli;
mod floquet_mathieu;
mod floquet_orbits;
mod floquet_periodic;
mod hard_cases;
mod integrators;
mod liquid_gas;
mod modes_damped;
mod modes_frequencies;
mod physics_bl;
mod plot;
mod plot_figures;
mod scene_derived;
mod scene_errors;
mod scene_files;
mod scene_load;
mod shell_laws;
mod shell_runtime;
mod stability_args;
mod stability_criteria;
mod stability_series_window;
mod stability_sweep;
mod vorticity_linear;
mod vorticity_scene;
mod vorticity_structured;
mod vorticity_study;
