//! The figures' ladder entry points (analysis/ladder.rs, issue 16 row 5) against the ones they
//! stand in for: `ladder::critical_outcome` against `critical::critical_point` (same outcome,
//! same first unstable mode, critical value within the bracket tolerance) and
//! `ladder::max_multiplier` against `floquet` at 400 Magnus steps (within 1e-6 relative), on
//! figure 6's scene with the coil (dense k ± 2 blocks) at a resonant, a critical and a
//! stable-throughout frequency.

use magbubble::analysis::ladder;
use magbubble::analysis::stability::{critical_point, floquet, Criterion, CriticalOptions, FloquetOptions, StabilityError};
use magbubble::scene::{Scene, SceneTemplate};
use std::path::Path;

fn template() -> SceneTemplate {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/figures/fig06_current.toml");
    SceneTemplate::load(&path, &["field.coil.current=100e3", "modes.max_order=8"]).unwrap()
}

#[test]
fn critical_outcome_matches_critical_point() {
    let base = template();
    let opts = CriticalOptions {
        criterion: Criterion::Floquet,
        lo: 0.0,
        hi: 1.0,
        scan: 8,
        tol: 2e-3,
        relative_tol: false,
        floquet: FloquetOptions::default(),
        series: Default::default(),
    };
    let mut outcomes = Vec::new();
    for f in [0.5e6, 1.0e6, 4.0e6] {
        let at = |p: f64| -> Result<Scene, StabilityError> {
            base.with(&[("drive.frequency_hz", f), ("drive.amplitude", p)]).map_err(|e| StabilityError::Scene(e.to_string()))
        };
        let old = critical_point(&at, &opts).unwrap();
        let (new, mode) = ladder::critical_outcome(&at, &opts).unwrap();
        assert_eq!(new.name(), old.outcome.name(), "at {f:e} Hz");
        assert_eq!(mode, old.mode, "at {f:e} Hz");
        match (new.value(), old.outcome.value()) {
            (Some(a), Some(b)) => assert!((a - b).abs() <= opts.tol, "at {f:e} Hz: {a} vs {b}"),
            (None, None) => {}
            other => panic!("at {f:e} Hz: {other:?}"),
        }
        outcomes.push(new.name());
    }
    // the three kinds of point the test is meant to cover
    assert_eq!(outcomes, ["critical", "critical", "stable_throughout"]);
}

#[test]
fn max_multiplier_within_its_tolerance_of_the_400_step_value() {
    let base = template();
    let opts = FloquetOptions::default();
    for f in [0.5e6, 1.0e6, 4.0e6] {
        let s = base.with(&[("drive.frequency_hz", f)]).unwrap();
        let full = floquet(&s, &opts).unwrap().max_multiplier;
        let cheap = ladder::max_multiplier(&s, &opts).unwrap();
        assert!((cheap - full).abs() <= 1e-6 * full, "at {f:e} Hz: {cheap} vs {full}");
    }
}

/// A violent orbit (benches/population.toml's coil scene, R0 8.68 µm, 500 kHz, ε_p 0.99–1, k ≤
/// 16: R from 4.1 to 17.4 µm) whose fastest mode grows by ~1e32 per period: the rungs of 6–25
/// steps overflow and 50/100/200 steps give 1e88, 1e38, 1e33, far from the O(h⁴) regime. The
/// pair's Richardson value was −7.7e36, read as "stable": `stability --range 0.99:1` reported
/// stable_throughout with the 400-step max|μ| of 4.9e32 beside it. The verdict must agree with
/// the n-step Floquet value.
#[test]
fn a_violent_orbit_is_unstable_on_the_ladder_as_at_full_steps() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("benches/population.toml");
    let base = SceneTemplate::load(&path, &["bubble.radius=8.680044616187811e-6", "drive.frequency_hz=5e5"]).unwrap();
    let opts = CriticalOptions {
        criterion: Criterion::Floquet,
        lo: 0.99,
        hi: 1.0,
        scan: 1,
        tol: 1e-3,
        relative_tol: true,
        floquet: FloquetOptions::default(),
        series: Default::default(),
    };
    let at = |p: f64| -> Result<Scene, StabilityError> {
        base.with(&[("drive.amplitude", p)]).map_err(|e| StabilityError::Scene(e.to_string()))
    };
    let full = floquet(&at(1.0).unwrap(), &opts.floquet).unwrap();
    assert!(full.unstable && full.max_multiplier > 1e20, "the 400-step value: {}", full.max_multiplier);
    let point = critical_point(&at, &opts).unwrap();
    assert_eq!(point.outcome.name(), "unstable_at_bottom", "critical_point: {:?}", point.outcome);
    let (outcome, _) = ladder::critical_outcome(&at, &opts).unwrap();
    assert_eq!(outcome.name(), "unstable_at_bottom");
}
