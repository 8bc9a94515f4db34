//! The figure registry and the time-series recipe (with a synthetic simulator, so this test
//! checks the pipeline, not the physics).

use magbubble::plot::paper::{
    self, make_stability, make_time_series, Analyzer, CriticalRow, FigureError, ModeRow, Recipe,
    RunOutput, Simulator, Sweep,
};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

fn scenes() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/figures")
}

#[test]
fn the_registry_lists_figures_3_to_16_each_with_a_shipped_scene() {
    let numbers: Vec<u32> = paper::FIGURES.iter().map(|f| f.number).collect();
    assert_eq!(numbers, (3..=16).collect::<Vec<_>>());
    for f in paper::FIGURES {
        let path = scenes().join(f.scene);
        let text =
            std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        assert!(
            text.starts_with(&format!("# Figure {}", f.number)),
            "{} does not open with its comment",
            f.scene
        );
        text.parse::<toml::Table>()
            .unwrap_or_else(|e| panic!("{}: {e}", f.scene));
        assert!(!f.shows.is_empty());
        let variants = match f.recipe {
            Recipe::TimeSeries(s) => s.variants,
            Recipe::Stability(s) => s.families,
            _ => &[],
        };
        for v in variants {
            for o in v.overrides {
                assert!(
                    o.contains('='),
                    "figure {}: override `{o}` is not key=value",
                    f.number
                );
            }
        }
    }
    assert!(paper::find(2).is_none() && paper::find(17).is_none());
    assert_eq!(paper::find(7).unwrap().stem(), "fig07");
}

/// Returns damped sines whose a_2 amplitude grows with a number read from the overrides.
struct Synthetic {
    calls: Mutex<Vec<Vec<String>>>,
}

impl Simulator for Synthetic {
    fn simulate(&self, scene: &Path, overrides: &[String]) -> Result<RunOutput, String> {
        assert!(scene.is_file());
        self.calls.lock().unwrap().push(overrides.to_vec());
        let n = 2000;
        let t: Vec<f64> = (0..n).map(|i| i as f64 * 1e-8).collect();
        let rows = t
            .iter()
            .map(|&t| {
                let w = 2.0 * std::f64::consts::PI * 1e6 * t;
                vec![
                    10e-6 * (1.0 + 0.1 * w.sin()),
                    1e-7 * (0.5 * w).sin(),
                    0.0,
                    2e-8 * w.cos(),
                    0.0,
                ]
            })
            .collect();
        Ok(RunOutput {
            columns: ["R", "a2", "b2", "a4", "b4"].map(String::from).to_vec(),
            t_s: t,
            rows,
            status: "completed".into(),
            blow_up: overrides
                .iter()
                .any(|o| o.contains("moment=10.0"))
                .then(|| ("a4".to_string(), 1.5e-5)),
            wall_seconds: 0.01,
        })
    }
}

#[test]
fn a_time_series_figure_runs_every_curve_and_writes_csv_images_and_note() {
    let dir = tempfile::tempdir().unwrap();
    let sim = Synthetic {
        calls: Mutex::new(Vec::new()),
    };
    for n in [15, 16] {
        let fig = paper::find(n).unwrap();
        let Recipe::TimeSeries(spec) = &fig.recipe else {
            panic!("figure {n} is a time series")
        };
        let seen = Mutex::new(Vec::new());
        let report = make_time_series(fig, spec, &scenes(), dir.path(), true, &sim, &|l: &str| {
            seen.lock().unwrap().push(l.to_string())
        })
        .unwrap();
        assert_eq!(seen.lock().unwrap().len(), spec.variants.len());
        assert_eq!(report.runs.len(), spec.variants.len());
        let stem = fig.stem();
        for ext in ["csv", "svg", "png", "md"] {
            assert!(
                dir.path().join(format!("{stem}.{ext}")).is_file(),
                "{stem}.{ext} missing"
            );
        }
        let csv = std::fs::read_to_string(dir.path().join(format!("{stem}.csv"))).unwrap();
        assert!(
            csv.starts_with("variant,t_s,R_m,a2_m,b2_m,a4_m,b4_m\n"),
            "{}",
            &csv[..60]
        );
        assert_eq!(csv.lines().count(), 1 + 2000 * spec.variants.len());
        let md = std::fs::read_to_string(dir.path().join(format!("{stem}.md"))).unwrap();
        assert!(
            md.contains("total wall time") && md.contains("--quick"),
            "{md}"
        );
    }
    assert!(dir.path().join("fig15_phase.png").is_file());
    let svg = std::fs::read_to_string(dir.path().join("fig16.svg")).unwrap();
    // A curve blew up: the shape panels are |a_k| on a log axis (issue 15 "What people look at").
    assert!(svg.contains("|a₄| [µm]") && svg.contains("M = 10 A m² (a4 blew up at 15.0 µs)"));
    // Quick mode appends the CI overrides after the curve's own.
    let calls = sim.calls.lock().unwrap();
    assert!(calls
        .iter()
        .all(|c| c.iter().any(|o| o == "modes.max_order=4")));
    // the curves run in parallel, so the calls come in any order: find fig 16's M = 10 curve
    // and check the quick overrides come after its own
    let m10 = calls.iter().find(|c| c.contains(&"field.dipole.moment=10.0".to_string())).expect("fig 16's M = 10 curve ran");
    let own = m10.iter().position(|o| o == "field.dipole.moment=10.0").unwrap();
    let quick = m10.iter().position(|o| o == "modes.max_order=4").unwrap();
    assert!(own < quick, "{m10:?}");
}

#[test]
fn a_missing_scene_and_a_failing_run_are_errors_that_name_the_figure() {
    let dir = tempfile::tempdir().unwrap();
    let fig = paper::find(12).unwrap();
    let Recipe::TimeSeries(spec) = &fig.recipe else {
        unreachable!()
    };
    let sim = Synthetic {
        calls: Mutex::new(Vec::new()),
    };
    let err =
        make_time_series(fig, spec, dir.path(), dir.path(), true, &sim, &|_: &str| {}).unwrap_err();
    assert!(
        matches!(err, FigureError::MissingScene { figure: 12, .. }),
        "{err}"
    );

    struct Failing;
    impl Simulator for Failing {
        fn simulate(&self, _: &Path, _: &[String]) -> Result<RunOutput, String> {
            Err("shell.c1 = -1: must be positive".into())
        }
    }
    let err = make_time_series(
        fig,
        spec,
        &scenes(),
        dir.path(),
        true,
        &Failing,
        &|_: &str| {},
    )
    .unwrap_err();
    let text = err.to_string();
    assert!(
        text.contains("figure 12") && text.contains("χ = 1") && text.contains("shell.c1"),
        "{text}"
    );
}

/// A V-shaped critical curve around 2 MHz, lowered by a number in the overrides; ω_k ∝ k^1.5.
struct SyntheticAnalyzer;

impl Analyzer for SyntheticAnalyzer {
    fn modes(&self, _: &Path, _: &[String], kmax: usize) -> Result<(Vec<ModeRow>, f64), String> {
        let rows = (2..=kmax).map(|k| ModeRow {
            k,
            omega_rad_s: 1e6 * (k as f64).powf(1.5),
            omega_nondim: 0.1 * (k as f64).powf(1.5),
        });
        Ok((rows.collect(), 1e-7))
    }
    fn critical(
        &self,
        _: &Path,
        overrides: &[String],
        sweep: &Sweep,
    ) -> Result<Vec<CriticalRow>, String> {
        let shift = overrides.len() as f64 * 0.01;
        Ok(sweep
            .freqs_hz
            .iter()
            .map(|&f| {
                let c = 0.05 + shift + ((f - 2e6) / 4e6).abs();
                // Nothing unstable for figure 9's current sweep: an empty diagram, not an error.
                let ok = c < sweep.range.1 && !sweep.vary.contains("current");
                CriticalRow {
                    frequency_hz: f,
                    critical: if ok { c } else { f64::NAN },
                    outcome: if ok { "critical" } else { "stable_throughout" }.into(),
                    mode: ok.then_some(2 + 2 * (f / 1e6) as usize),
                }
            })
            .collect())
    }
    fn max_multiplier(
        &self,
        _: &Path,
        _: &[String],
        _: &str,
        freqs_hz: &[f64],
    ) -> Result<Vec<f64>, String> {
        Ok(freqs_hz
            .iter()
            .map(|f| 0.9 + 0.2 * (f / 1e6).sin().abs())
            .collect())
    }
}

#[test]
fn a_stability_figure_writes_every_panel_it_asks_for() {
    let dir = tempfile::tempdir().unwrap();
    for n in [5, 6, 7, 9, 10] {
        let fig = paper::find(n).unwrap();
        let Recipe::Stability(spec) = &fig.recipe else {
            panic!("figure {n} is a stability figure")
        };
        let report = make_stability(
            fig,
            spec,
            &scenes(),
            dir.path(),
            true,
            &SyntheticAnalyzer,
            &|_: &str| {},
        )
        .unwrap();
        assert_eq!(report.runs.len(), 2, "--quick keeps two families");
        let stem = fig.stem();
        let csv = std::fs::read_to_string(dir.path().join(format!("{stem}.csv"))).unwrap();
        assert_eq!(csv.lines().count(), 1 + 2 * spec.quick_freqs.2, "{csv}");
        let want: &[&str] = match n {
            5 => &["", "_mode"],
            6 => &["", "_omega", "_mu"],
            7 => &["", "_omega"],
            _ => &[""],
        };
        for suffix in want {
            assert!(
                dir.path().join(format!("{stem}{suffix}.png")).is_file(),
                "{stem}{suffix}.png missing"
            );
        }
    }
    let svg = std::fs::read_to_string(dir.path().join("fig07.svg")).unwrap();
    assert!(
        svg.contains("ω_d t* [–]"),
        "figure 7 uses the nondimensional frequency"
    );
    let svg = std::fs::read_to_string(dir.path().join("fig09.svg")).unwrap();
    assert!(
        svg.contains("no critical value in [0, 400]"),
        "figure 9 says nothing went unstable"
    );
    let svg = std::fs::read_to_string(dir.path().join("fig10.svg")).unwrap();
    assert!(
        svg.contains("f2 = 0.5 MHz"),
        "figure 10 has its panel titles"
    );
}

#[test]
fn an_unknown_figure_is_a_clear_error_and_list_names_every_figure() {
    let bin = env!("CARGO_BIN_EXE_magbubble");
    let out = std::process::Command::new(bin).args(["figure", "17"]).output().unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("no figure 17"));
    let out = std::process::Command::new(bin).args(["figure", "twelve"]).output().unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("expected a number 3–16"));
    let out = std::process::Command::new(bin).args(["figure", "list"]).output().unwrap();
    assert!(out.status.success());
    let list = String::from_utf8_lossy(&out.stdout);
    assert_eq!(list.lines().count(), 14, "{list}");
    assert!(list.contains("fig12_chi.toml"));
}
