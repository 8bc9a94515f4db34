//! One test per kind of scene error, each checking the message names the key, the value and
//! what is allowed.

use magbubble::scene::{load_str, SceneError};

const NO_SET: &[&str] = &[];

/// Loads `text` (with overrides) and returns the full error message; fails if it loads.
fn error_of(text: &str, overrides: &[&str]) -> (SceneError, String) {
    match load_str(text, "test.toml", overrides) {
        Ok(scene) => panic!("scene should be invalid, got {scene:?}"),
        Err(e) => {
            let msg = e.to_string();
            (e, msg)
        }
    }
}

#[test]
fn unknown_key_is_named_with_its_section_and_a_suggestion() {
    let (e, msg) = error_of("[shell]\nc3 = 0.1\n", NO_SET);
    assert_eq!(e.issues().len(), 1, "{msg}");
    assert!(msg.contains("`shell.c3`"), "{msg}");
    assert!(msg.contains("unknown key; [shell] accepts c1, c2"), "{msg}");
    assert!(
        msg.contains("did you mean `c1`?") || msg.contains("did you mean `c2`?"),
        "{msg}"
    );
}

#[test]
fn unknown_section_is_rejected() {
    let (_, msg) = error_of("[bubbel]\nradius = 1e-5\n", NO_SET);
    assert!(msg.contains("`bubbel`: unknown section"), "{msg}");
    assert!(msg.contains("did you mean `bubble`?"), "{msg}");
}

#[test]
fn wrong_type_names_expected_and_found() {
    let (_, msg) = error_of("[shell]\nc1 = \"stiff\"\n", NO_SET);
    assert!(
        msg.contains("`shell.c1` = \"stiff\": expected a number, found a string"),
        "{msg}"
    );
    let (_, msg) = error_of("[modes]\nmax_order = 16.0\n", NO_SET);
    assert!(
        msg.contains("`modes.max_order` = 16.0: expected an integer, found a float"),
        "{msg}"
    );
}

#[test]
fn out_of_range_names_value_and_range() {
    let (_, msg) = error_of("[shell]\nc1 = -0.1\n", NO_SET);
    assert!(msg.contains("`shell.c1` = -0.1: must be >= 0"), "{msg}");
    let (_, msg) = error_of("[liquid]\nviscosity = nan\n", NO_SET);
    assert!(
        msg.contains("`liquid.viscosity` = NaN: must be > 0"),
        "{msg}"
    );
}

#[test]
fn bad_choice_lists_the_options() {
    let (_, msg) = error_of("[modes]\nviscous = \"laminar\"\n", NO_SET);
    assert!(
        msg.contains(
            "`modes.viscous` = \"laminar\": must be one of \"boundary-layer\", \"vorticity\""
        ),
        "{msg}"
    );
}

#[test]
fn max_order_must_be_even_and_at_most_kmax() {
    let (_, msg) = error_of("[modes]\nmax_order = 15\n", NO_SET);
    assert!(
        msg.contains("`modes.max_order` = 15: must be an even integer in 0..=64 (KMAX)"),
        "{msg}"
    );
    let (_, msg) = error_of("[modes]\nmax_order = 66\n", NO_SET);
    assert!(msg.contains("`modes.max_order` = 66"), "{msg}");
}

#[test]
fn odd_initial_mode_is_rejected() {
    let (_, msg) = error_of("[bubble.initial]\na = { 3 = 1e-8 }\n", NO_SET);
    assert!(
        msg.contains("`bubble.initial.a.3` = 1e-8: odd mode k = 3 not simulated"),
        "{msg}"
    );
}

#[test]
fn initial_mode_above_max_order_is_rejected() {
    let (_, msg) = error_of(
        "[modes]\nmax_order = 4\n[bubble.initial]\nb = { 6 = 1e-9 }\n",
        NO_SET,
    );
    assert!(
        msg.contains("`bubble.initial.b.6` = 1e-9: a key for k = 6 > modes.max_order = 4"),
        "{msg}"
    );
    let (_, msg) = error_of("[bubble.initial]\na = { x = 1e-9, 0 = 1e-9 }\n", NO_SET);
    assert!(msg.contains("`bubble.initial.a.x`"), "{msg}");
    assert!(
        msg.contains("`bubble.initial.a.0` = 1e-9: k = 0 is the radial mode"),
        "{msg}"
    );
}

#[test]
fn initial_amplitude_beyond_blow_up_threshold_is_rejected() {
    let (_, msg) = error_of("[bubble.initial]\na = { 2 = 6e-6 }\n", NO_SET);
    assert!(msg.contains("`bubble.initial.a.2` = 6e-6: |a_2(0)|/R0 = 0.6 already exceeds run.blow_up_threshold = 0.5"), "{msg}");
}

#[test]
fn zero_or_negative_duration_is_rejected() {
    for d in ["0.0", "-1e-6"] {
        let (_, msg) = error_of(&format!("[run]\nduration = {d}\n"), NO_SET);
        assert!(
            msg.contains(&format!("`run.duration` = {}: must be > 0", d)),
            "{msg}"
        );
    }
}

#[test]
fn sample_interval_and_dt_may_not_exceed_duration() {
    let (e, msg) = error_of(
        "[run]\nduration = 1e-6\nsample_interval = 2e-6\nintegrator = { dt = 5e-6 }\n",
        NO_SET,
    );
    assert_eq!(e.issues().len(), 2, "{msg}");
    assert!(
        msg.contains("`run.sample_interval` = 2e-6: must not exceed run.duration = 1e-6"),
        "{msg}"
    );
    assert!(
        msg.contains("`run.integrator.dt` = 5e-6: must not exceed run.duration = 1e-6"),
        "{msg}"
    );
}

#[test]
fn rtol_out_of_range_is_rejected() {
    let (_, msg) = error_of("[run.integrator]\nrtol = 0.5\n", NO_SET);
    assert!(
        msg.contains("`run.integrator.rtol` = 0.5: must be in [1e-14, 0.1]"),
        "{msg}"
    );
    let (_, msg) = error_of("[run.integrator]\nrtol = 0.0\n", NO_SET);
    assert!(
        msg.contains("`run.integrator.rtol` = 0.0: must be in [1e-14, 0.1]"),
        "{msg}"
    );
}

#[test]
fn missing_required_key_names_its_section() {
    let (_, msg) = error_of("[field.coil]\nturns = 1000\n", NO_SET);
    assert!(
        msg.contains("`field.coil.current`: required when [field.coil] is present"),
        "{msg}"
    );
    let (_, msg) = error_of("[drive]\nfrequency_hz = 1e6\n", NO_SET);
    assert!(
        msg.contains("`drive.amplitude`: required when [drive] is present"),
        "{msg}"
    );
    let (_, msg) = error_of("[field.coil]\ncurrent = { amplitude = 1e5 }\n", NO_SET);
    assert!(
        msg.contains("`field.coil.current.frequency_hz`: required"),
        "{msg}"
    );
}

#[test]
fn coil_and_dipole_together_are_rejected() {
    let (_, msg) = error_of(
        "[field.coil]\ncurrent = 1e5\n[field.dipole]\nmoment = 1.0\n",
        NO_SET,
    );
    assert!(
        msg.contains("`field`: give at most one of [field.coil] and [field.dipole]"),
        "{msg}"
    );
}

#[test]
fn dipole_inside_the_bubble_is_rejected() {
    let (_, msg) = error_of("[field.dipole]\nmoment = 1.0\ndistance = 5e-6\n", NO_SET);
    assert!(
        msg.contains("`field.dipole.distance` = 5e-6: must exceed bubble.radius = 1e-5"),
        "{msg}"
    );
}

#[test]
fn toml_syntax_error_carries_line_and_column() {
    let text = "[bubble]\nradius = 10e-6\n[shell]\nc1 = = 0.1\n";
    match load_str(text, "bad.toml", NO_SET) {
        Err(SceneError::Syntax {
            line,
            column,
            ref message,
            ..
        }) => {
            assert_eq!(line, 4, "{message}");
            assert_eq!(column, 6, "{message}");
        }
        other => panic!("expected a syntax error, got {other:?}"),
    }
    let msg = load_str(text, "bad.toml", NO_SET).unwrap_err().to_string();
    assert!(msg.starts_with("bad.toml:4:6: TOML syntax error"), "{msg}");
}

#[test]
fn bad_set_path_is_named() {
    let (_, msg) = error_of("", &["shell.c9=0.2"]);
    assert!(
        msg.contains("`shell.c9` = 0.2: --set: no such key in the scene schema"),
        "{msg}"
    );
    let (_, msg) = error_of("", &["drive.amplitude"]);
    assert!(msg.contains("--set expects key.path=value"), "{msg}");
}

#[test]
fn bad_set_value_is_named() {
    let (_, msg) = error_of("", &["drive.amplitude=0.3.4"]);
    assert!(
        msg.contains("`drive.amplitude` = 0.3.4: --set: not a TOML value"),
        "{msg}"
    );
    // A bare word is a string, then rejected by type.
    let (_, msg) = error_of("", &["drive.amplitude=high"]);
    assert!(
        msg.contains("`drive.amplitude` = \"high\": expected a number, found a string"),
        "{msg}"
    );
}

#[test]
fn set_through_a_scalar_is_rejected() {
    let (_, msg) = error_of(
        "[field.coil]\ncurrent = 1e5\n",
        &["field.coil.current.amplitude=2e5"],
    );
    assert!(
        msg.contains("`field.coil.current` is a float in the scene, not a table"),
        "{msg}"
    );
}

#[test]
fn every_problem_is_reported_not_just_the_first() {
    let text =
        "[shell]\nc1 = -1.0\nc3 = 2.0\n[run]\nduration = 0.0\n[bubble.initial]\na = { 3 = 1e-9 }\n";
    let (e, msg) = error_of(text, &["liquid.density=\"heavy\""]);
    let keys: Vec<&str> = e.issues().iter().map(|i| i.key.as_str()).collect();
    for k in [
        "shell.c1",
        "shell.c3",
        "run.duration",
        "bubble.initial.a.3",
        "liquid.density",
    ] {
        assert!(keys.contains(&k), "{k} missing from {msg}");
    }
    assert_eq!(e.issues().len(), 5, "{msg}");
    assert!(
        msg.starts_with("test.toml: invalid scene, 5 problems:"),
        "{msg}"
    );
}

#[test]
fn unreadable_file_is_an_error_not_a_panic() {
    let e = magbubble::scene::load("/nonexistent/scene.toml", NO_SET).unwrap_err();
    assert!(
        e.to_string()
            .contains("cannot read scene file /nonexistent/scene.toml"),
        "{e}"
    );
}
