//! Issue 29 items 1–2: the time-series criterion over the default range 0:1 (ε_p = 0 removes
//! the drive, docs/scenes.md) and with every mode that starts at zero seeded, so that it agrees
//! with Floquet on the shipped scenes within its stated detection limit (docs/stability.md).
use magbubble::analysis::bisect::Outcome;
use magbubble::analysis::stability::*;
use magbubble::scene::{Scene, SceneTemplate};

fn opts(criterion: Criterion, lo: f64, tol: f64) -> CriticalOptions {
    CriticalOptions { criterion, lo, hi: 1.0, scan: 8, tol, relative_tol: false, floquet: Default::default(), series: Default::default() }
}

fn at(t: &SceneTemplate, f: f64) -> impl Fn(f64) -> Result<Scene, StabilityError> + '_ {
    move |p: f64| t.with(&[("drive.frequency_hz", f), ("drive.amplitude", p)]).map_err(|e| StabilityError::Scene(e.to_string()))
}

#[test]
fn the_default_range_starts_at_zero_drive_and_works() {
    let t = SceneTemplate::load("scenes/no_field.toml", &["modes.max_order=4"]).unwrap();
    let scene_at = at(&t, 1e6);
    // ε_p = 0 removes the drive: alone, the scene cannot be judged, and the message says why
    let zero = scene_at(0.0).unwrap();
    assert!(zero.drive.is_none());
    let e = series_unstable(&zero, &SeriesOptions::default()).unwrap_err().to_string();
    assert!(e.contains("nothing periodic") && e.contains("drive.amplitude = 0"), "{e}");
    assert!(check_scene(&zero, Criterion::Series).is_err());
    // as the lower end of a range, it is watched over the upper end's period
    check_range(&zero, &scene_at(1.0).unwrap(), Criterion::Series).unwrap();
    let v = series_unstable(&zero, &SeriesOptions { period_s: Some(1e-6), ..Default::default() }).unwrap();
    assert!(!v.unstable, "{v:?}");
    let c = critical_point(&scene_at, &opts(Criterion::Series, 0.0, 1e-2)).unwrap();
    assert!(matches!(c.outcome, Outcome::Critical { .. }), "{:?}", c.outcome);
    // neither end periodic: an error that names the range
    let flat = |_: f64| -> Result<Scene, StabilityError> { Ok(zero.clone()) };
    let e = critical_point(&flat, &opts(Criterion::Series, 0.0, 1e-2)).unwrap_err().to_string();
    assert!(e.contains("either end of the range"), "{e}");
}

/// The series criterion flags |μ| per drive period above growth^(4/periods) (module doc of
/// `series_unstable`); the bracket it returns must be consistent with Floquet both ways.
fn agree(path: &str, f: f64, max_order: usize) -> (f64, f64) {
    let t = SceneTemplate::load(path, &[format!("modes.max_order={max_order}")]).unwrap();
    let scene_at = at(&t, f);
    let fl = critical_point(&scene_at, &opts(Criterion::Floquet, 0.0, 1e-3)).unwrap();
    let se = critical_point(&scene_at, &opts(Criterion::Series, 0.0, 1e-2)).unwrap();
    let (a, b) = (fl.outcome.value().expect("floquet bracket"), se.outcome.value().expect("series bracket"));
    let Outcome::Critical { stable, unstable, .. } = se.outcome else { unreachable!() };
    let mu = |p: f64| floquet(&scene_at(p).unwrap(), &FloquetOptions::default()).unwrap().max_multiplier_per_drive_period;
    let limit = 2f64.powf(4.0 / SeriesOptions::default().periods as f64);
    let (mu_s, mu_u) = (mu(stable), mu(unstable));
    eprintln!("{path} at {f:e} Hz, N = {max_order}: Floquet ε_c = {a:.4} ({}), series ε_c = {b:.4} ({}); Floquet |μ| at the series bracket {mu_s:.5} / {mu_u:.5} (limit {limit:.5})", fl.mode, se.mode);
    assert!(mu_s <= limit, "{path}: series called {stable} stable but Floquet |μ| = {mu_s} > {limit}");
    assert!(mu_u > 1.0, "{path}: series called {unstable} unstable but Floquet |μ| = {mu_u}");
    (a, b)
}

#[test]
fn series_and_floquet_agree_on_the_shipped_scenes() {
    // the case: series gave 0.763 (a2) with a2 alone seeded, Floquet 0.490 (a4)
    let (a, b) = agree("scenes/no_field.toml", 1e6, 4);
    assert!((a - b).abs() < 0.02, "{a} vs {b}");
    // every shipped scene with a drive and shape modes the Floquet analysis takes
    for path in ["scenes/coil_static.toml", "scenes/dipole.toml", "scenes/skalak.toml", "scenes/free_bubble.toml", "scenes/coil_ac_current.toml", "scenes/coil_oscillating_distance.toml", "scenes/coil_h4.toml", "scenes/keller_miksis.toml"] {
        agree(path, 1e6, 4);
    }
}
