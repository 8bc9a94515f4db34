//! The plotting layer: every kind of figure renders to SVG + PNG, survives NaN/∞, and fails
//! with a clear error (never a panic) when there is nothing to draw.
//! Set `MAGBUBBLE_PLOT_KEEP=DIR` to keep the rendered files for a look.

use magbubble::plot::kinds::{self, Curve, TimeSeries};
use magbubble::plot::{series_plot, stability_plot, Axis, Figure, Panel, PlotError, Series};
use std::path::{Path, PathBuf};

fn out_dir(name: &str) -> (Option<tempfile::TempDir>, PathBuf) {
    match std::env::var_os("MAGBUBBLE_PLOT_KEEP") {
        Some(d) => (None, PathBuf::from(d).join(name)),
        None => {
            let t = tempfile::tempdir().unwrap();
            let p = t.path().to_path_buf();
            (Some(t), p)
        }
    }
}

/// Both files exist, the PNG is a real image of some size, and the SVG carries every text.
fn assert_rendered(dir: &Path, stem: &str, texts: &[&str]) {
    let png = std::fs::read(dir.join(format!("{stem}.png"))).unwrap();
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n", "{stem}.png is not a PNG");
    assert!(png.len() > 10_000, "{stem}.png is only {} bytes", png.len());
    let svg = std::fs::read_to_string(dir.join(format!("{stem}.svg"))).unwrap();
    assert!(
        svg.starts_with("<svg"),
        "{stem}.svg does not start with <svg"
    );
    for t in texts {
        let escaped = t
            .replace('&', "&amp;")
            .replace('<', "&lt;")
            .replace('>', "&gt;")
            .replace('\'', "&apos;");
        assert!(svg.contains(&escaped), "{stem}.svg lacks the text `{t}`");
    }
    // No temporary file left behind.
    let leftovers: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().contains(".tmp."))
        .collect();
    assert!(leftovers.is_empty(), "temporary files left: {leftovers:?}");
}

fn damped_run(label: &str, amp: f64, n: usize) -> TimeSeries {
    let t: Vec<f64> = (0..n).map(|i| i as f64 * 1e-8).collect();
    let r = t
        .iter()
        .map(|&t| 10e-6 * (1.0 + 0.1 * (2e6 * std::f64::consts::PI * t).sin()))
        .collect();
    let a2 = t
        .iter()
        .map(|&t| amp * 1e-7 * (1e6 * t).sin() * (t / 2e-5).exp())
        .collect();
    let a4 = t.iter().map(|&t| amp * 3e-8 * (3e6 * t).cos()).collect();
    TimeSeries {
        label: label.into(),
        t_s: t,
        radius_m: r,
        shapes: vec![("a_2".into(), a2), ("a_4".into(), a4)],
        blow_up: None,
    }
}

#[test]
fn every_kind_of_figure_renders() {
    let (_keep, dir) = out_dir("kinds");
    let runs = [
        damped_run("χ = 1", 1.0, 3000),
        damped_run("χ = 5", 2.0, 3000),
    ];
    kinds::time_series("time series", &runs)
        .save(&dir, "ts")
        .unwrap();
    assert_rendered(&dir, "ts", &["t [µs]", "R [µm]", "χ = 5: a₂"]);

    let x: Vec<f64> = (0..400).map(|i| (i as f64 * 0.05).sin()).collect();
    let y: Vec<f64> = (0..400)
        .map(|i| (i as f64 * 0.05).cos() * (1.0 + 0.001 * i as f64))
        .collect();
    kinds::phase_portrait(
        "phase",
        "a₂ [µm]",
        "ȧ₂ [m/s]",
        &[Curve::new("f2 = 1.777 f1", x, y)],
    )
    .save(&dir, "phase")
    .unwrap();
    assert_rendered(&dir, "phase", &["ȧ₂ [m/s]"]);

    let k: Vec<f64> = (2..=32).map(|k| k as f64).collect();
    let fam = |s: f64| {
        Curve::new(
            format!("I = {s} kA"),
            k.clone(),
            k.iter().map(|k| s * k.powf(1.5)).collect(),
        )
    };
    kinds::omega_vs_k("modes", "ω_k [rad/s]", &[fam(1.0), fam(2.0)], true)
        .save(&dir, "omega")
        .unwrap();
    assert_rendered(&dir, "omega", &["mode number k", "I = 2 kA"]);

    let f: Vec<f64> = (1..=40).map(|i| i as f64 * 0.15).collect();
    let eps = |n: f64| {
        f.iter()
            .map(|f| 0.05 + (f - 2.0).powi(2) / n)
            .collect::<Vec<_>>()
    };
    let mut gappy = eps(20.0);
    gappy[7] = f64::NAN; // a frequency with no critical pressure found
    let curves = [
        Curve::new("12 modes", f.clone(), eps(10.0)),
        Curve::new("16 modes", f.clone(), gappy),
    ];
    kinds::stability_diagram("stability", "f_d [MHz]", "critical ε_p", &curves, true)
        .save(&dir, "stab")
        .unwrap();
    assert_rendered(&dir, "stab", &["critical ε_p", "16 modes"]);

    let modes: Vec<f64> = f.iter().map(|f| 2.0 * (1.0 + f).floor()).collect();
    kinds::first_unstable_mode(
        "first unstable",
        "f_d [MHz]",
        &[Curve::new("", f.clone(), modes)],
    )
    .save(&dir, "mode")
    .unwrap();
    assert_rendered(&dir, "mode", &["first unstable mode k"]);

    let mu: Vec<f64> = f
        .iter()
        .map(|f| 0.8 + 0.5 * (f * 2.0).sin().abs())
        .collect();
    kinds::max_multiplier(
        "Floquet",
        "f_d [MHz]",
        &[Curve::new("I = 100 kA", f.clone(), mu)],
        false,
    )
    .save(&dir, "mu")
    .unwrap();
    assert_rendered(&dir, "mu", &["max |μ|", "|μ| = 1"]);

    let times = vec![1e-3, 3e-3, 1e-2, 3e-2];
    let wp = [
        Curve::new("rk4", times.clone(), vec![1e-3, 1e-5, 1e-7, 1e-9]),
        Curve::new("radau5", times.clone(), vec![1e-4, 1e-7, 1e-10, 0.0]), // 0: off a log axis, skipped
    ];
    let evals = vec![Curve::new("rk4", vec![1e3, 2e3, 4e3, 8e3], vec![1e-3, 1e-5, 1e-7, 1e-9])];
    kinds::work_precision("work–precision", "error [–]", &[("rhs evaluations", evals), ("wall time [s]", wp.to_vec())])
        .save(&dir, "wp")
        .unwrap();
    assert_rendered(&dir, "wp", &["rhs evaluations", "wall time [s]", "radau5"]);

    let dt = vec![1e-2, 5e-3, 2.5e-3, 1.25e-3];
    let e: Vec<f64> = dt.iter().map(|d: &f64| 3.0 * d.powi(2)).collect();
    kinds::convergence(
        "convergence",
        "Δt' [–]",
        "error [–]",
        &[Curve::new("e_s", dt, e)],
        &[1, 2],
    )
    .save(&dir, "conv")
    .unwrap();
    assert_rendered(&dir, "conv", &["Δt' [–]", "slope 2"]);
}

#[test]
fn nan_and_infinite_points_are_skipped_not_fatal() {
    let (_keep, dir) = out_dir("nan");
    let x: Vec<f64> = (0..200).map(|i| i as f64).collect();
    let y: Vec<f64> = x
        .iter()
        .map(|&v| {
            if (50.0..60.0).contains(&v) {
                f64::NAN
            } else if v == 100.0 {
                f64::INFINITY
            } else {
                v.sin()
            }
        })
        .collect();
    let fig = Figure::single(
        Panel::new(Axis::linear("x [–]"), Axis::log("y [–]"))
            .series(Series::line(
                "sin, log y: negatives skipped",
                x.clone(),
                y.clone(),
            ))
            .series(Series::steps("steps", x.clone(), y.clone()))
            .series(Series::points("points", x, y)),
    );
    fig.save(&dir, "nan").unwrap();
    assert_rendered(&dir, "nan", &["y [–]"]);
}

#[test]
fn a_panel_with_nothing_drawable_is_an_error() {
    let (_keep, dir) = out_dir("empty");
    let all_nan = Series::line("nan", vec![1.0, 2.0], vec![f64::NAN, f64::NAN]);
    let fig =
        Figure::single(Panel::new(Axis::linear("t [s]"), Axis::linear("R [m]")).series(all_nan));
    let err = fig.save(&dir, "x").unwrap_err();
    assert!(matches!(err, PlotError::Empty { .. }), "{err}");
    assert!(
        err.to_string().contains("R [m]"),
        "the error names the panel: {err}"
    );

    let no_series = Figure::single(Panel::new(Axis::linear("t [s]"), Axis::linear("R [m]")));
    assert!(matches!(
        no_series.save(&dir, "y").unwrap_err(),
        PlotError::Empty { .. }
    ));
    assert!(matches!(
        Figure::new(vec![]).save(&dir, "z").unwrap_err(),
        PlotError::Empty { .. }
    ));

    let negative_on_log = Figure::single(
        Panel::new(Axis::log("t [s]"), Axis::linear("R [m]")).series(Series::line(
            "",
            vec![-1.0, 0.0],
            vec![1.0, 2.0],
        )),
    );
    assert!(matches!(
        negative_on_log.save(&dir, "w").unwrap_err(),
        PlotError::Empty { .. }
    ));

    let ragged = Figure::single(
        Panel::new(Axis::linear("t"), Axis::linear("R")).series(Series::line(
            "bad",
            vec![1.0, 2.0],
            vec![1.0],
        )),
    );
    assert!(matches!(
        ragged.save(&dir, "v").unwrap_err(),
        PlotError::Length { x: 2, y: 1, .. }
    ));

    let ok = Figure::single(
        Panel::new(Axis::linear("t"), Axis::linear("R")).series(Series::line(
            "",
            vec![1.0],
            vec![1.0],
        )),
    );
    assert!(matches!(
        ok.save(&dir, "a/b").unwrap_err(),
        PlotError::Stem { .. }
    ));
    let bad_range = Figure::single(
        Panel::new(Axis::log("t").range(0.0, 1.0), Axis::linear("R")).series(Series::line(
            "",
            vec![1.0],
            vec![1.0],
        )),
    );
    assert!(matches!(
        bad_range.save(&dir, "r").unwrap_err(),
        PlotError::Axis { .. }
    ));
    // Nothing half-written was left behind by the failures.
    let names: Vec<_> = std::fs::read_dir(&dir)
        .map(|d| d.filter_map(|e| e.ok()).map(|e| e.file_name()).collect())
        .unwrap_or_default();
    assert!(names.is_empty(), "files written by failed saves: {names:?}");
}

#[test]
fn a_single_point_and_a_constant_series_get_a_usable_range() {
    let (_keep, dir) = out_dir("flat");
    let fig = Figure::single(
        Panel::new(Axis::linear("t [µs]"), Axis::linear("R [µm]")).series(Series::line_points(
            "flat",
            vec![0.0, 1.0, 2.0],
            vec![10.0, 10.0, 10.0],
        )),
    );
    fig.save(&dir, "flat").unwrap();
    let one = Figure::single(
        Panel::new(Axis::log("f [MHz]"), Axis::log("ε_p")).series(Series::points(
            "one",
            vec![1.0],
            vec![0.3],
        )),
    );
    one.save(&dir, "one").unwrap();
    assert_rendered(&dir, "one", &["ε_p"]);
}

#[test]
fn long_series_are_thinned_to_a_small_svg() {
    let (_keep, dir) = out_dir("long");
    let n = 400_000;
    let t: Vec<f64> = (0..n).map(|i| i as f64 * 5e-9).collect();
    let r: Vec<f64> = t
        .iter()
        .map(|&t| 10e-6 * (1.0 + 0.2 * (2e6 * std::f64::consts::PI * t).sin()))
        .collect();
    let run = TimeSeries {
        label: String::new(),
        t_s: t,
        radius_m: r.clone(),
        shapes: vec![("a_2".into(), r)],
        blow_up: None,
    };
    kinds::time_series("long", &[run])
        .save(&dir, "long")
        .unwrap();
    let svg = std::fs::metadata(dir.join("long.svg")).unwrap().len();
    assert!(svg < 2_000_000, "SVG of a 400k-point run is {svg} bytes");
}

#[test]
fn series_csv_is_read_and_plotted() {
    let (_keep, dir) = out_dir("csv");
    std::fs::create_dir_all(&dir).unwrap();
    let csv = dir.join("series.csv");
    let mut text =
        String::from("# magbubble run\nt [s],R [m],Rdot [m/s],a_2 [m],adot_2 [m/s],b_2 [m]\n");
    for i in 0..500 {
        let t = i as f64 * 2e-8;
        let a = if i == 250 {
            "NaN".to_string()
        } else {
            format!("{}", 1e-7 * (3e6 * t).sin())
        };
        text += &format!(
            "{t},{},{},{a},0,{}\n",
            10e-6 * (1.0 + 0.1 * (6e6 * t).cos()),
            0.0,
            1e-8
        );
    }
    std::fs::write(&csv, text).unwrap();
    let saved = series_plot(&csv, &dir).unwrap();
    assert_eq!(saved.png, dir.join("series.png"));
    assert_rendered(&dir, "series", &["R [µm]", "a₂"]);

    let table = magbubble::plot::SeriesTable::read(&csv).unwrap();
    assert_eq!(table.orders('a'), vec![2]);
    assert_eq!(table.shape('A', 2).unwrap().len(), 500);
    let r = table.radius_m().unwrap();
    assert!((r[0] - 11e-6).abs() < 1e-12);

    // the reduced thermal model's bubble pressure gets a panel of its own
    let mut text = String::from("t,R,p_b\n");
    for i in 0..200 {
        let t = i as f64 * 1e-8;
        text += &format!("{t:e},{:e},{:e}\n", 5e-6 * (1.0 + 0.1 * (1e6 * t).sin()), 101325.0 * (1.0 + 0.3 * (1e6 * t).cos()));
    }
    std::fs::write(dir.join("thermal.csv"), text).unwrap();
    series_plot(&dir.join("thermal.csv"), &dir).unwrap();
    assert_rendered(&dir, "series", &["R [µm]", "p_b [kPa]"]);
    let svg = std::fs::read_to_string(dir.join("series.svg")).unwrap();
    assert!(!svg.contains("shape amplitude"), "a radial run has no shape panel");

    std::fs::write(dir.join("bad.csv"), "t,R\n0,1\n1,2,3\n").unwrap();
    let err = series_plot(&dir.join("bad.csv"), &dir).unwrap_err();
    assert!(matches!(err, PlotError::Csv { line: 3, .. }), "{err}");
    std::fs::write(dir.join("nor.csv"), "t,x\n0,1\n").unwrap();
    let err = series_plot(&dir.join("nor.csv"), &dir).unwrap_err();
    assert!(err.to_string().contains("radius"), "{err}");
}

#[test]
fn stability_csvs_are_plotted_with_their_modes() {
    let (_keep, dir) = out_dir("stability_csv");
    std::fs::create_dir_all(&dir).unwrap();
    let header = "index,drive.frequency_hz,critical,outcome,stable,unstable,mode,max_multiplier_stable,max_multiplier_unstable,orbit_multiple,evaluations,note\n";
    let mut fams = Vec::new();
    for (n, shift) in [(12, 0.0), (16, 0.02)] {
        let mut text = String::from(header);
        for i in 0..10 {
            let f = 0.5e6 + i as f64 * 0.5e6;
            let (crit, outcome, mode) = if i == 7 {
                ("nan".to_string(), "stable_throughout", "")
            } else {
                (
                    format!("{}", 0.1 + shift + 0.02 * i as f64),
                    "critical",
                    "a4",
                )
            };
            text += &format!("{i},{f:e},{crit},{outcome},0,0,{mode},0.99,1.01,1,12,\"no orbit at 0.7, unstable\"\n");
        }
        let path = dir.join(format!("stability_modes.max_order={n}.csv"));
        std::fs::write(&path, text).unwrap();
        fams.push((format!("{n} modes"), path));
    }
    let saved = stability_plot(&fams, &dir, "stability", "critical ε_p", false).unwrap();
    assert_eq!(saved.len(), 2);
    assert_rendered(
        &dir,
        "stability",
        &["f_d [MHz]", "critical ε_p", "16 modes"],
    );
    assert_rendered(&dir, "stability_mode", &["first unstable mode k"]);
}

/// `magbubble run ARGS --out OUT` from the repository root; its summary.json.
fn run_summary(args: &[&str], out: &std::path::Path) -> serde_json::Value {
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_magbubble"))
        .args(args)
        .arg("--out")
        .arg(out)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap()
}

/// A run's plot is titled with its scene, its model and how it ended (issue 29 item 14), not
/// with the output folder's name.
#[test]
fn run_plot_title_names_scene_model_and_stop() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("whatever_folder");
    let summary = run_summary(&["run", "scenes/coil_static.toml", "--set", "modes.coupling=\"quadratic\"", "--plot"], &out);
    let c = &summary["status"]["out_of_credible_range"];
    let title = magbubble::plot::run_title(&summary).unwrap();
    let expected = format!(
        "coil_static (1 override): boundary-layer, quadratic coupling, mooney-rivlin, radau5 — {} left |a|/R0 ≤ 0.1 at {:.2} µs",
        c["mode"].as_str().unwrap(),
        c["t"].as_f64().unwrap() * 1e6
    );
    assert_eq!(title, expected);
    let svg = std::fs::read_to_string(out.join("series.svg")).unwrap();
    assert!(svg.contains("coil_static (1 override)"), "the plot's title is not the scene's");
    assert!(!svg.contains("whatever_folder"), "the plot is still titled with the folder");
    // a Keller–Miksis bubble
    let title = magbubble::plot::run_title(&run_summary(&["run", "scenes/keller_miksis.toml"], &dir.path().join("km"))).unwrap();
    assert!(title.starts_with("keller_miksis: Keller–Miksis, "), "{title}");
    assert!(title.contains(" — completed ") || title.contains(" — blow-up of "), "{title}");
    // a free bubble has no shell law
    let title = magbubble::plot::run_title(&run_summary(&["run", "scenes/free_bubble.toml"], &dir.path().join("fb"))).unwrap();
    assert!(title.contains(", free bubble, ") && !title.contains("mooney"), "{title}");
    assert!(!title.contains("thermal"), "a polytropic gas is not named: {title}");
    // the reduced thermal model is named
    let title = magbubble::plot::run_title(&run_summary(&["run", "scenes/hard/reduced_collapse.toml", "--set", "run.duration=1e-7"], &dir.path().join("rc"))).unwrap();
    assert!(title.contains(", free bubble, reduced thermal, "), "{title}");
}
