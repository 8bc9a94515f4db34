//! Issue 13 part 5: the critical ε_p in the accuracy study (analysis/critical_accuracy.rs,
//! `accuracy --critical`). Small ladders on a k ≤ 2 scene at 1 MHz.

use super::common;
use magbubble::analysis::critical_accuracy::{critical_accuracy, CriticalAccuracyOptions};
use std::process::Command;

#[test]
fn errors_fall_along_each_ladder_and_the_closure_gap_is_reported() {
    let mut s = common::scene(2, 0.1, 1e6);
    s.vorticity.stretching = 20.0;
    s.vorticity.y_max = 3.0;
    let mut o = CriticalAccuracyOptions::quick(1e6);
    o.mode_ladder = vec![2];
    o.mode_reference = 4;
    let mut seen = 0;
    let r = critical_accuracy(&s, &o, &mut |_| seen += 1).unwrap();
    assert_eq!(seen, r.references.len() + r.rungs.len());
    assert_eq!(r.references.iter().map(|x| x.ladder).collect::<Vec<_>>(), ["magnus", "modes", "grid", "sdirk"]);
    for x in r.references.iter().chain(&r.rungs) {
        assert_eq!(x.outcome, "critical", "{x:?}");
        assert!(x.critical > 0.0 && x.critical < 1.0, "{x:?}");
    }
    let errors = |ladder: &str| -> Vec<f64> { r.rungs.iter().filter(|x| x.ladder == ladder).map(|x| x.error).collect() };
    // Refining a numerical setting brings ε_c to its reference: strictly falling errors, each
    // above the bracket tolerance (each midpoint is within tol/2 of its boundary, so a smaller
    // error would measure the search, not the setting).
    for ladder in ["magnus", "grid", "sdirk"] {
        let e = errors(ladder);
        assert!(e.len() >= 2 && e.windows(2).all(|w| w[1] < w[0]), "{ladder}: {e:?}");
        assert!(e.iter().all(|&x| x > o.tol), "{ladder}: {e:?}");
    }
    // The closure's modelling error is far above the numerical ones of the finest rungs.
    let gap = errors("closure")[0];
    assert!(gap > 10.0 * errors("grid").last().unwrap(), "closure gap {gap}");
    // The full-model reference is searched once for both of its ladders.
    let (g, d) = (&r.references[2], &r.references[3]);
    assert_eq!((g.critical, g.wall_seconds), (d.critical, d.wall_seconds));
}

#[test]
fn the_cli_refuses_what_has_no_meaning_with_critical() {
    let run = |extra: &[&str]| {
        let out = Command::new(env!("CARGO_BIN_EXE_magbubble"))
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .args(["accuracy", "scenes/no_field.toml", "--quick", "--out", "/nonexistent/never-written"])
            .args(extra)
            .output()
            .unwrap();
        assert!(!out.status.success());
        String::from_utf8_lossy(&out.stderr).into_owned()
    };
    assert!(run(&["--critical=-1e6"]).contains("--critical -1000000: the drive frequency must be finite and > 0"));
    assert!(run(&["--critical", "1e6", "--duration", "1e-6"]).contains("--duration has no meaning with --critical"));
}
