//! Floquet and time-series criteria agree on the critical ε_p (docs/stability.md).
use crate::common;
use magbubble::analysis::stability::*;

fn opts(criterion: Criterion, tol: f64) -> CriticalOptions {
    CriticalOptions { criterion, lo: 0.0, hi: 1.0, scan: 8, tol, relative_tol: false, floquet: Default::default(), series: Default::default() }
}

#[test]
fn floquet_and_time_series_agree_within_the_bisection_tolerance() {
    for f in [0.8e6, 1.0e6, 1.2e6] {
        let at = move |p: f64| -> Result<magbubble::scene::Scene, StabilityError> { Ok(common::scene(8, p, f)) };
        let fl = critical_point(&at, &opts(Criterion::Floquet, 1e-3)).unwrap();
        let se = critical_point(&at, &opts(Criterion::Series, 1e-2)).unwrap();
        let (a, b) = (fl.outcome.value().expect("floquet bracket"), se.outcome.value().expect("series bracket"));
        eprintln!("f = {f:e}: Floquet ε_p* = {a:.4} ({}), series ε_p* = {b:.4} ({})", fl.mode, se.mode);
        assert!(fl.max_multiplier_stable <= 1.0 && fl.max_multiplier_unstable > 1.0);
        // The series criterion sees growth only above its detection limit: the late and early
        // windows are periods/4 drive periods apart, so it flags |μ| ≥ growth^(4/periods)
        // (2^(1/100) = 1.0069 with the default 400 periods). Consistency, both ways, at the series bracket ends:
        let magbubble::analysis::bisect::Outcome::Critical { stable, unstable, .. } = se.outcome else { unreachable!() };
        let mu = |p: f64| floquet(&common::scene(8, p, f), &FloquetOptions::default()).unwrap().max_multiplier;
        let limit = 2f64.powf(4.0 / SeriesOptions::default().periods as f64);
        let (mu_s, mu_u) = (mu(stable), mu(unstable));
        eprintln!("   Floquet max|μ| at the series bracket: {mu_s:.5} (stable end), {mu_u:.5} (unstable end); limit {limit:.5}");
        assert!(mu_s <= limit, "series called {stable} stable but Floquet |μ| = {mu_s}");
        assert!(mu_u > 1.0, "series called {unstable} unstable but Floquet |μ| = {mu_u}");
        assert!(b >= a - 1e-2, "the series criterion cannot see instability below the Floquet boundary");
        assert!((a - b).abs() <= 1e-2, "Floquet {a} vs series {b} beyond the series tolerance");
    }
}

#[test]
fn paper_variant_and_orbit_differ_near_twice_the_radial_resonance() {
    // FORMULATION audit 14: the paper's substitution ignores the radial resonance (f0 ≈ 0.49 MHz),
    // so at f_d = 1 MHz its critical pressure is far above the orbit's.
    let at = |p: f64| -> Result<magbubble::scene::Scene, StabilityError> { Ok(common::scene(8, p, 1e6)) };
    let orbit = critical_point(&at, &opts(Criterion::Floquet, 1e-3)).unwrap();
    let mut o = opts(Criterion::Floquet, 1e-3);
    o.floquet.variant = Variant::Paper;
    let paper = critical_point(&at, &o).unwrap();
    eprintln!("orbit {:?} / paper {:?}", orbit.outcome, paper.outcome);
    let a = orbit.outcome.value().unwrap();
    assert!(paper.outcome.value().map_or(true, |b| b > a + 0.05));
}
