//! Figures of the two studies of the full vorticity model: `magbubble convergence --plot`
//! (error against the step and against the work, log–log) and `magbubble compare --plot`
//! (both closures' series and their difference). Plain vectors in, SI units (issue 15
//! "`convergence --plot` and `compare --plot`").

use super::figure::{Axis, Figure, Panel, Series};
use super::kinds::{convergence, mode_name, time_series_panels, Curve, TimeSeries};
use super::logshape::{log_magnitudes, wants_log};

/// One rung of a convergence ladder: step Δt′ [–], e_s, e_f [–], wall time [s].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConvergencePoint {
    pub dt: f64,
    pub e_s: f64,
    pub e_f: f64,
    /// The run's work: steps of the scheme (wall times of millisecond runs are noise).
    pub steps: f64,
}

/// Two panels: e_s and e_f against Δt′ with a dashed slope-`order` guide (the scheme's
/// expected order), and the same errors against the work of each run (its steps).
pub fn convergence_figure(title: &str, points: &[ConvergencePoint], order: u32) -> Figure {
    let pick = |f: fn(&ConvergencePoint) -> f64, x: fn(&ConvergencePoint) -> f64| -> (Vec<f64>, Vec<f64>) {
        (points.iter().map(x).collect(), points.iter().map(f).collect())
    };
    let curves = |x: fn(&ConvergencePoint) -> f64| {
        let (xs, es) = pick(|p| p.e_s, x);
        let (_, ef) = pick(|p| p.e_f, x);
        [
            Curve::new("e_s (shape amplitudes)", xs.clone(), es),
            Curve::new("e_f (vorticity at the end)", xs, ef),
        ]
    };
    let by_step = convergence("", "Δt′ [–]", "relative L2 error [–]", &curves(|p| p.dt), &[order]);
    let mut work = Panel::new(Axis::log("steps (work)"), Axis::log("relative L2 error [–]"))
        .title("error against work");
    for (i, c) in curves(|p| p.steps).into_iter().enumerate() {
        work.push(Series::line_points(c.label, c.x, c.y).color(i));
    }
    let mut step = by_step.panels.into_iter().next().expect("convergence() has one panel");
    step.title = Some("error against the time step".into());
    let mut fig = Figure::new(vec![step, work]).title(title);
    fig.panel_height = 460;
    fig
}

/// The columns drawn by [`compare_figure`]: R and the (at most three) a_k with the largest
/// max |a_k| of the full run, in mode order; identically zero columns are left out.
fn compare_columns(names: &[String], full: &[Vec<f64>], bl: &[Vec<f64>]) -> Vec<usize> {
    let max_of = |rows: &[Vec<f64>], c: usize| rows.iter().filter_map(|r| r.get(c)).fold(0.0f64, |m, v| m.max(v.abs()));
    let mut shapes: Vec<(usize, f64)> = names
        .iter()
        .enumerate()
        .filter(|(_, n)| n.starts_with('a') && n[1..].bytes().all(|b| b.is_ascii_digit()) && n.len() > 1)
        .map(|(c, _)| (c, max_of(full, c).max(max_of(bl, c))))
        .filter(|&(_, m)| m > 0.0)
        .collect();
    shapes.sort_by(|a, b| b.1.total_cmp(&a.1));
    shapes.truncate(3);
    shapes.sort_by_key(|s| s.0);
    names.iter().position(|n| n == "R").into_iter().chain(shapes.into_iter().map(|s| s.0)).collect()
}

/// `a2` → `a_2` (the shape names of [`mode_name`]).
fn shape_label(name: &str) -> String {
    if name.len() > 1 && name.starts_with(['a', 'b']) {
        format!("{}_{}", &name[..1], &name[1..])
    } else {
        name.to_string()
    }
}

/// Stacked panels sharing t: R and up to three a_k of the boundary-layer closure and of the
/// full vorticity model, then their difference (full − boundary layer; |difference| on a log
/// axis when it spans decades). `blow_ups`: the blow-up (mode, t [s]) of each run, if any.
pub fn compare_figure(
    title: &str,
    names: &[String],
    t: &[f64],
    bl: &[Vec<f64>],
    full: &[Vec<f64>],
    blow_ups: [Option<(String, f64)>; 2],
) -> Figure {
    let columns = compare_columns(names, full, bl);
    let col = |rows: &[Vec<f64>], c: usize| -> Vec<f64> { rows.iter().map(|r| r.get(c).copied().unwrap_or(f64::NAN)).collect() };
    let r = names.iter().position(|n| n == "R");
    let shapes: Vec<String> = columns.iter().filter(|&&c| Some(c) != r).map(|&c| shape_label(&names[c])).collect();
    let run = |label: &str, rows: &[Vec<f64>], blow_up: Option<(String, f64)>| TimeSeries {
        label: label.into(),
        t_s: t.to_vec(),
        radius_m: r.map_or_else(Vec::new, |c| col(rows, c)),
        shapes: columns.iter().filter(|&&c| Some(c) != r).map(|&c| (shape_label(&names[c]), col(rows, c))).collect(),
        blow_up,
    };
    let [b0, b1] = blow_ups;
    let runs = [run("boundary layer", bl, b0), run("full vorticity", full, b1)];
    let shape_refs: Vec<&str> = shapes.iter().map(String::as_str).collect();
    let mut fig = time_series_panels(title, &runs, r.is_some(), &shape_refs);
    let mut diffs: Vec<Vec<f64>> = columns
        .iter()
        .map(|&c| col(full, c).iter().zip(col(bl, c)).map(|(f, b)| (f - b) * 1e6).collect())
        .collect();
    let log = wants_log(&diffs, false);
    let y = if log {
        diffs = log_magnitudes(&diffs);
        Axis::log("|full − boundary layer| [µm]")
    } else {
        Axis::linear("full − boundary layer [µm]")
    };
    let mut p = Panel::new(Axis::linear("t [µs]"), y).title("difference");
    let t_us: Vec<f64> = t.iter().map(|v| v * 1e6).collect();
    for (i, (&c, d)) in columns.iter().zip(diffs).enumerate() {
        p.push(Series::line(mode_name(&shape_label(&names[c])), t_us.clone(), d).color(2 + i));
    }
    fig.panels.push(p);
    fig.panel_height = 300;
    fig
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn compare_draws_r_and_the_three_largest_modes() {
        let names: Vec<String> = ["R", "a2", "b2", "a4", "b4", "a6", "b6", "a8", "b8"].iter().map(|s| s.to_string()).collect();
        let row = vec![1e-5, 1e-8, 0.0, 1e-9, 0.0, 0.0, 0.0, 1e-7, 0.0];
        let full = vec![row.clone(); 3];
        let cols = compare_columns(&names, &full, &full);
        assert_eq!(cols, vec![0, 1, 3, 7], "R, a2, a4, a8; a6 is identically zero");
        assert_eq!(shape_label("a12"), "a_12");
    }
}
