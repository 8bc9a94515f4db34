//! Issue 15 classes 2, 5, 6: what a scene's keys give together is checked before anything runs
//! — derived quantities that overflow name the key the user set, work that cannot finish within
//! `run.integrator.max_steps` is refused, and so is a series.csv above `run.max_output_bytes`.

use magbubble::scene::{load, SceneError};
use std::path::Path;
use std::process::Command;

fn coil_static(extra: &[&str]) -> Result<magbubble::scene::Scene, SceneError> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/coil_static.toml");
    load(path, extra)
}

/// The scene is refused with exactly one issue, on `key`, whose text contains `needle`.
fn refused_on(extra: &[&str], key: &str, needle: &str) {
    let err = coil_static(extra).expect_err(&format!("{extra:?} should be refused"));
    let msg = err.to_string();
    assert_eq!(err.issues().len(), 1, "{extra:?}: {msg}");
    assert_eq!(err.issues()[0].key, key, "{extra:?}: {msg}");
    assert!(msg.contains(needle), "{extra:?}: expected '{needle}' in {msg}");
}

#[test]
fn overflowing_derived_quantities_name_the_key_that_was_set() {
    refused_on(&["drive.frequency_hz=1e308"], "drive.frequency_hz", "2 pi f t* = inf");
    refused_on(&["liquid.viscosity=1e308"], "liquid.viscosity", "Re = sqrt(2 rho c1 R0)/eta");
    refused_on(&["shell.susceptibility=1e308"], "shell.susceptibility", "magnetic stress");
    refused_on(&["shell.susceptibility=-1e308"], "shell.susceptibility", "magnetic stress");
    refused_on(&["bubble.radius=1e308"], "bubble.radius", "t* = sqrt(rho R0^3/(2 c1)) = inf");
    refused_on(&["bubble.radius=1e-300"], "bubble.radius", "t* = sqrt(rho R0^3/(2 c1)) = 0");
    refused_on(&["liquid.density=1e300"], "liquid.density", "t* =");
    refused_on(&["drive.amplitude=1e308"], "drive.amplitude", "eps_p p0 R0/c1 = inf");
    refused_on(&["gas.polytropic_exponent=1e308"], "gas.polytropic_exponent", "3 kappa > 1000");
    refused_on(&["liquid.ambient_pressure=1e300"], "liquid.ambient_pressure", "P = p0 R0/c1");
    refused_on(&["field.coil.current=1e300"], "field.coil.current", "magnetic stress");
    refused_on(&["bubble.initial.velocity=1e300"], "bubble.initial.velocity", "dR/dt(0) t*/R0");
}

/// Tiny additive loads and rates are exact in double precision (only negligible): the review of
/// the [1e-12, 1e12] limit (issue 15) found these refused as "cannot be evaluated"; they validate
/// and run now.
#[test]
fn tiny_loads_and_rates_are_valid() {
    for set in ["shell.c2=1e-14", "bubble.initial.velocity=1e-20", "shell.thickness=1e-20", "liquid.ambient_pressure=1e-8", "drive.amplitude=1e-15", "field.coil.current=1e-6"] {
        let mut s = coil_static(&[set, "run.duration=1e-7"]).unwrap_or_else(|e| panic!("{set}: {e}"));
        s.run.sample_interval = 1e-8;
        let r = magbubble::model::simulate(&s, &mut |_, _| {}).unwrap();
        assert!(!matches!(r.status, magbubble::model::RunStatus::Failed { .. }), "{set}: {:?}", r.status);
    }
    // A scale is still bounded below: R(0)/R0 = 1e-13.
    refused_on(&["bubble.initial.radius=1e-18"], "bubble.initial.radius", "R(0)/R0 = 1e-13, outside [1e-12, 1e12]");
}

#[test]
fn extreme_but_representable_values_are_accepted() {
    for set in ["drive.frequency_hz=1e9", "liquid.viscosity=10", "shell.susceptibility=-0.5", "bubble.radius=1e-7"] {
        coil_static(&[set]).unwrap_or_else(|e| panic!("{set}: {e}"));
    }
}

#[test]
fn budgets_are_checked_up_front() {
    refused_on(
        &["run.integrator.method=rk4", "run.integrator.dt=1e-20"],
        "run.integrator.dt",
        "takes 1e16 steps, more than run.integrator.max_steps = 50000000",
    );
    // The same step is fine when the budget allows it.
    coil_static(&["run.integrator.method=rk4", "run.integrator.dt=1e-9", "run.integrator.max_steps=200000"]).unwrap();
    refused_on(
        &["run.integrator.method=rk4", "run.integrator.dt=1e-9", "run.integrator.max_steps=1000"],
        "run.integrator.dt",
        "takes 100000 steps",
    );
    refused_on(&["drive.frequency_hz=1e12"], "run.duration", "1e8 periods of the fastest forcing");
}

#[test]
fn output_size_is_refused_with_the_estimate() {
    refused_on(&["run.sample_interval=1e-18"], "run.sample_interval", "1e14 rows of 18 numbers, about 43200.0 TB");
    // A key lifts the limit for who means it.
    coil_static(&["run.sample_interval=1e-11", "run.max_output_bytes=1e12"]).unwrap();
    refused_on(&["run.sample_interval=1e-11"], "run.sample_interval", "above run.max_output_bytes = 1e9");
}

#[test]
fn a_refused_run_creates_nothing_and_exits_at_once() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("o");
    let start = std::time::Instant::now();
    let o = Command::new(env!("CARGO_BIN_EXE_magbubble"))
        .arg("run")
        .arg(Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/coil_static.toml"))
        .arg("--out")
        .arg(&out)
        .args(["--set", "run.sample_interval=1e-18"])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("series.csv would have"));
    assert!(!out.exists());
    // Not a timing assertion on the work: a refused scene does no work at all.
    assert!(start.elapsed().as_secs() < 30);
}
