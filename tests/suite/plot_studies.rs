//! The plots people look at (issue 15): legends placed off the data, |a_k| on a log axis with
//! the blow-up marked for `run --plot`, and `convergence --plot` / `compare --plot`.

use magbubble::plot::{Axis, Figure, Panel, Series};
use std::path::Path;
use std::process::Command;

fn magbubble() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_magbubble"));
    c.current_dir(env!("CARGO_MANIFEST_DIR"));
    c
}

/// (x, y) of the `<text>` whose content is `label`.
fn text_at(svg: &str, label: &str) -> (f64, f64) {
    let end = svg
        .find(&format!(">\n{label}\n</text>"))
        .unwrap_or_else(|| panic!("no text `{label}` in the SVG"));
    let start = svg[..end].rfind("<text ").unwrap();
    let attr = |name: &str| -> f64 {
        let tag = &svg[start..end];
        let i = tag.find(&format!(" {name}=\"")).unwrap() + name.len() + 3;
        tag[i..].split('"').next().unwrap().parse().unwrap()
    };
    (attr("x"), attr("y"))
}

/// Largest x of the polylines drawn in a palette colour (the data, not the axes).
fn data_right_edge(svg: &str) -> f64 {
    svg.split("<polyline ")
        .skip(1)
        .filter(|p| p.contains("stroke=\"#1F77B4\""))
        .filter_map(|p| p.split("points=\"").nth(1)?.split('"').next())
        .flat_map(|pts| pts.split_whitespace().filter_map(|xy| xy.split(',').next()?.parse::<f64>().ok()).collect::<Vec<_>>())
        .fold(f64::NEG_INFINITY, f64::max)
}

fn render(dir: &Path, stem: &str, y: Vec<f64>) -> String {
    let x: Vec<f64> = (0..y.len()).map(|i| i as f64 / (y.len() - 1) as f64).collect();
    let p = Panel::new(Axis::linear("x [–]"), Axis::linear("y [–]")).series(Series::line("the data", x, y));
    Figure::single(p).save(dir, stem).unwrap();
    std::fs::read_to_string(dir.join(format!("{stem}.svg"))).unwrap()
}

#[test]
fn legends_go_where_the_data_is_not() {
    let tmp = tempfile::tempdir().unwrap();
    // Rising: the upper-right corner holds data, the upper-left does not.
    let svg = render(tmp.path(), "rising", vec![0.0, 1.0]);
    let (x, y) = text_at(&svg, "the data");
    assert!(x < 300.0 && y < 200.0, "rising line: legend at ({x}, {y}), expected upper left");
    // Falling: the first corner tried, upper right, is free.
    let svg = render(tmp.path(), "falling", vec![1.0, 0.0]);
    let (x, y) = text_at(&svg, "the data");
    assert!(x > 600.0 && y < 200.0, "falling line: legend at ({x}, {y}), expected upper right");
    // An oscillation filling the plot: no corner is free, the legend goes right of the data.
    let fill: Vec<f64> = (0..3000).map(|i| (0.05 * i as f64).sin()).collect();
    let svg = render(tmp.path(), "filled", fill);
    let (x, _) = text_at(&svg, "the data");
    let edge = data_right_edge(&svg);
    assert!(x > edge, "filled plot: legend text at x = {x}, data up to x = {edge}");
}

#[test]
fn a_blown_up_run_is_plotted_on_a_log_axis_with_the_blow_up_marked() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("h4");
    let o = magbubble()
        .args(["run", "scenes/coil_h4.toml", "--set", "drive.amplitude=0.5", "--plot", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(summary.contains("blow_up"), "this scene is expected to blow up: {summary}");
    let svg = std::fs::read_to_string(out.join("series.svg")).unwrap();
    for text in ["|shape amplitude| [µm]", "R [µm]", "t [µs]", "blow-up of a₁₆ at"] {
        assert!(svg.contains(text), "series.svg lacks `{text}`");
    }
    // A run that decays over decades is logarithmic too; one that does not stays linear.
    let decayed = tmp.path().join("nf");
    let o = magbubble().args(["run", "scenes/no_field.toml", "--plot", "--out"]).arg(&decayed).output().unwrap();
    assert!(o.status.success());
    let svg = std::fs::read_to_string(decayed.join("series.svg")).unwrap();
    assert!(svg.contains("|shape amplitude| [µm]") && svg.contains("identically 0 (not drawn)"));
    assert!(!svg.contains("blow-up"));
    let short = tmp.path().join("short");
    let o = magbubble()
        .args(["run", "scenes/no_field.toml", "--set", "run.duration=1e-6", "--plot", "--out"])
        .arg(&short)
        .output()
        .unwrap();
    assert!(o.status.success());
    let svg = std::fs::read_to_string(short.join("series.svg")).unwrap();
    assert!(svg.contains(">\nshape amplitude [µm]\n<"), "a 1 µs run spans less than two decades: linear");
}

fn assert_png(path: &Path) {
    let png = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    assert!(png.len() > 10_000, "{} is only {} bytes", path.display(), png.len());
}

#[test]
fn convergence_and_compare_plot() {
    let tmp = tempfile::tempdir().unwrap();
    let small = ["--set", "modes.max_order=4", "--set", "vorticity.points=101"];
    let conv = tmp.path().join("conv");
    let o = magbubble()
        .args(["convergence", "scenes/figures/fig03_convergence.toml", "--duration", "2e-6", "--reference-dt", "5e-4"])
        .args(["--multiples", "2,4,8", "--plot", "--out"])
        .arg(&conv)
        .args(small)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_png(&conv.join("convergence.png"));
    let svg = std::fs::read_to_string(conv.join("convergence.svg")).unwrap();
    for text in ["Δt′ [–]", "steps (work)", "relative L2 error [–]", "e_s (shape amplitudes)", "slope 2", "error against work"] {
        assert!(svg.contains(text), "convergence.svg lacks `{text}`");
    }
    // the work is the steps: halving Δt′ doubles it exactly (issue 29 item 14: wall times of
    // millisecond runs zig-zag)
    let report: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(conv.join("convergence.json")).unwrap()).unwrap();
    let steps: Vec<u64> = report["rows"].as_array().unwrap().iter().map(|r| r["steps"].as_u64().unwrap()).collect();
    assert_eq!(steps.len(), 3);
    assert!(steps.windows(2).all(|w| w[0] == 2 * w[1]), "steps {steps:?}");
    let cmp = tmp.path().join("cmp");
    let o = magbubble()
        .args(["compare", "scenes/figures/fig04_compare.toml", "--set", "run.duration=5e-6", "--plot", "--out"])
        .arg(&cmp)
        .args(small)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_png(&cmp.join("compare.png"));
    let svg = std::fs::read_to_string(cmp.join("compare.svg")).unwrap();
    for text in ["boundary layer", "full vorticity", "difference", "R [µm]", "a₂ [µm]", "full − boundary layer"] {
        assert!(svg.contains(text), "compare.svg lacks `{text}`");
    }
    // Without --plot nothing is drawn.
    let plain = tmp.path().join("plain");
    let o = magbubble()
        .args(["compare", "scenes/figures/fig04_compare.toml", "--set", "run.duration=1e-6", "--out"])
        .arg(&plain)
        .args(small)
        .output()
        .unwrap();
    assert!(o.status.success());
    assert!(!plain.join("compare.svg").exists());
}

/// A command run without `--plot` into a folder that holds its earlier plot removes that plot
/// (issue 29 item 9: it would describe other data): accuracy and stability, as run does.
#[test]
fn a_rerun_without_plot_removes_the_stale_plot() {
    let tmp = tempfile::tempdir().unwrap();
    let acc = tmp.path().join("acc");
    let cases: [(&[&str], &std::path::Path, &[&str]); 2] = [
        (&["accuracy", "scenes/free_bubble.toml", "--quick"], &acc, &["work_precision"]),
        (&["stability", "scenes/no_field.toml", "--freq", "1e6", "--set", "modes.max_order=2"], &tmp.path().join("st"), &["stability"]),
    ];
    for (args, out, stems) in cases {
        let o = magbubble().args(args).arg("--plot").arg("--out").arg(out).output().unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        for s in stems {
            assert!(out.join(format!("{s}.svg")).is_file(), "{s}.svg not drawn");
        }
        let o = magbubble().args(args).arg("--out").arg(out).output().unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        for s in stems {
            assert!(!out.join(format!("{s}.svg")).exists() && !out.join(format!("{s}.png")).exists(), "{s} plot survived");
        }
        assert!(String::from_utf8_lossy(&o.stderr).contains("an earlier run's plot"));
    }
}
