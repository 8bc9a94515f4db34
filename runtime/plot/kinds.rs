//! One function per kind of output magbubble produces. Each takes plain vectors in SI units
//! (s, m, Hz, rad/s) and returns a [`Figure`] (call `.save(dir, stem)`); the axes show
//! researcher units (µs, µm, MHz) and say so in their labels.

use super::figure::{Axis, Figure, Legend, Panel, Series};
use super::logshape::{log_magnitudes, wants_log};

/// One simulated run for time-series figures (SI units).
#[derive(Debug, Clone, PartialEq)]
pub struct TimeSeries {
    /// Legend text of the run (e.g. `"χ = 1"`); may be empty for a single run.
    pub label: String,
    pub t_s: Vec<f64>,
    pub radius_m: Vec<f64>,
    /// (`"a_2"`, values in m), (`"b_2"`, …) …
    pub shapes: Vec<(String, Vec<f64>)>,
    /// When the run stopped at a blow-up: the mode and the time [s] (marked on the plot).
    pub blow_up: Option<(String, f64)>,
}

/// A named curve (x, y) in the units the caller states in the axis labels.
#[derive(Debug, Clone, PartialEq)]
pub struct Curve {
    pub label: String,
    pub x: Vec<f64>,
    pub y: Vec<f64>,
}

impl Curve {
    pub fn new(label: impl Into<String>, x: Vec<f64>, y: Vec<f64>) -> Self {
        Self {
            label: label.into(),
            x,
            y,
        }
    }
}

fn scaled(v: &[f64], s: f64) -> Vec<f64> {
    v.iter().map(|x| x * s).collect()
}

/// Pretty mode name: `a_2` → `a₂`, `b_12` → `b₁₂`.
pub fn mode_name(name: &str) -> String {
    const SUB: [char; 10] = ['₀', '₁', '₂', '₃', '₄', '₅', '₆', '₇', '₈', '₉'];
    match name.split_once('_') {
        Some((head, digits))
            if !digits.is_empty() && digits.bytes().all(|b| b.is_ascii_digit()) =>
        {
            let sub: String = digits.bytes().map(|b| SUB[(b - b'0') as usize]).collect();
            format!("{head}{sub}")
        }
        _ => name.to_string(),
    }
}

/// R(t) above the shape amplitudes (a_k, b_k) of one or several runs, sharing the time axis.
/// Legends go where the data is not ([`Legend::Auto`]).
/// With one run the legend names the modes; with several, runs × modes (`χ = 1: a₂`).
pub fn time_series(title: &str, runs: &[TimeSeries]) -> Figure {
    time_series_select(title, runs, &[])
}

/// As [`time_series`], with only the named shape columns (`&["a_2", "a_4"]`); empty: all.
/// The shape panel shows |a_k| on a log axis when a run blew up or the amplitudes span two
/// decades or more ([`wants_log`]); a blow-up is marked by a dashed vertical line. Modes that
/// are identically zero are not drawn (the panel title names them).
pub fn time_series_select(title: &str, runs: &[TimeSeries], shapes: &[&str]) -> Figure {
    let t_axis = || Axis::linear("t [µs]");
    let mut top = Panel::new(t_axis(), Axis::linear("R [µm]"));
    let several = runs.len() > 1;
    let mut names = Vec::new();
    let mut values = Vec::new();
    let mut times = Vec::new();
    let mut zero = Vec::new();
    for (i, run) in runs.iter().enumerate() {
        let t = scaled(&run.t_s, 1e6);
        let label = if several { run.label.clone() } else { String::new() };
        top.push(Series::line(label, t.clone(), scaled(&run.radius_m, 1e6)).color(i));
        for (name, v) in run.shapes.iter().filter(|(n, _)| shapes.is_empty() || shapes.contains(&n.as_str())) {
            if v.iter().all(|x| *x == 0.0) {
                zero.push(mode_name(name));
                continue;
            }
            names.push(match (several, run.label.is_empty()) {
                (true, false) => format!("{}: {}", run.label, mode_name(name)),
                _ => mode_name(name),
            });
            values.push(scaled(v, 1e6));
            times.push(t.clone());
        }
    }
    let blown = runs.iter().any(|r| r.blow_up.is_some());
    let log = wants_log(&values, blown);
    let mut bottom = if log {
        values = log_magnitudes(&values);
        Panel::new(t_axis(), Axis::log("|shape amplitude| [µm]"))
    } else {
        Panel::new(t_axis(), Axis::linear("shape amplitude [µm]"))
    };
    for (color, ((name, t), v)) in names.into_iter().zip(times).zip(values).enumerate() {
        bottom.push(Series::line(name, t, v).color(color));
    }
    if !zero.is_empty() && !bottom.series.is_empty() {
        zero.dedup();
        bottom = bottom.title(format!("{} identically 0 (not drawn)", zero.join(", ")));
    }
    for (i, run) in runs.iter().enumerate() {
        if let Some((mode, tb)) = &run.blow_up {
            let label = format!("blow-up of {} at {:.2} µs", mode_name(&shape_name(mode)), tb * 1e6);
            top = top.vline(tb * 1e6, "");
            bottom = bottom.vline(tb * 1e6, if several { format!("{}: {label}", run.label) } else { label });
            if several {
                top.vlines.last_mut().expect("just pushed").color = i;
                bottom.vlines.last_mut().expect("just pushed").color = i;
            }
        }
    }
    if bottom.series.is_empty() {
        // A radial-only run (modes.max_order = 0) has no shape panel.
        return Figure::single(top).title(title);
    }
    Figure::stacked(vec![top, bottom]).title(title)
}

/// `a16` → `a_16` (the output column names of `model::simulate`); other names unchanged.
fn shape_name(mode: &str) -> String {
    match mode.split_at_checked(1) {
        Some((h, d)) if !d.is_empty() && d.bytes().all(|b| b.is_ascii_digit()) => format!("{h}_{d}"),
        _ => mode.to_string(),
    }
}

/// Phase portrait of one or several trajectories, e.g. a₂ [µm] against ȧ₂ [m/s]: `x` and `y`
/// are in the units of the labels given.
pub fn phase_portrait(title: &str, x_label: &str, y_label: &str, curves: &[Curve]) -> Figure {
    let mut p = Panel::new(Axis::linear(x_label), Axis::linear(y_label));
    for (i, c) in curves.iter().enumerate() {
        p.push(Series::line(c.label.clone(), c.x.clone(), c.y.clone()).color(i));
    }
    Figure::single(p).title(title)
}

/// Natural frequencies against the mode number k, one curve per family (static current, c1 …).
/// `curves`: x = k, y = ω_k in the unit named by `y_label` (e.g. `"ω_k [rad/s]"`, `"ω_k t* [–]"`).
pub fn omega_vs_k(title: &str, y_label: &str, curves: &[Curve], log_y: bool) -> Figure {
    let mut p = Panel::new(
        Axis::linear("mode number k [–]").integer(),
        Axis::with_scale(y_label, log_y),
    );
    for (i, c) in curves.iter().enumerate() {
        p.push(Series::line_points(c.label.clone(), c.x.clone(), c.y.clone()).color(i));
    }
    Figure::single(p).title(title)
}

/// A stability diagram: the critical value (ε_p, or I0 for fig 9) against frequency, one curve
/// per family. Points that found no critical value (NaN) leave a gap.
pub fn stability_diagram(
    title: &str,
    x_label: &str,
    y_label: &str,
    curves: &[Curve],
    log_y: bool,
) -> Figure {
    let mut p = Panel::new(Axis::linear(x_label), Axis::with_scale(y_label, log_y));
    for (i, c) in curves.iter().enumerate() {
        p.push(Series::line_points(c.label.clone(), c.x.clone(), c.y.clone()).color(i));
    }
    Figure::single(p).title(title)
}

/// First unstable mode number against the driving frequency (fig 5b), as a staircase.
pub fn first_unstable_mode(title: &str, x_label: &str, curves: &[Curve]) -> Figure {
    let mut p = Panel::new(Axis::linear(x_label), Axis::linear("first unstable mode k [–]").integer());
    for (i, c) in curves.iter().enumerate() {
        p.push(Series::steps(c.label.clone(), c.x.clone(), c.y.clone()).color(i));
    }
    Figure::single(p).title(title)
}

/// Largest Floquet multiplier modulus against frequency (fig 6c), with the |μ| = 1 line.
pub fn max_multiplier(title: &str, x_label: &str, curves: &[Curve], log_y: bool) -> Figure {
    let mut p = Panel::new(Axis::linear(x_label), Axis::with_scale("max |μ| [–]", log_y));
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for (i, c) in curves.iter().enumerate() {
        for &x in c.x.iter().filter(|x| x.is_finite()) {
            lo = lo.min(x);
            hi = hi.max(x);
        }
        p.push(Series::line_points(c.label.clone(), c.x.clone(), c.y.clone()).color(i));
    }
    if lo < hi {
        p.push(Series::dashed("|μ| = 1", vec![lo, hi], vec![1.0, 1.0]).color(7));
    }
    Figure::single(p).title(title)
}

/// Work–precision, one curve per integrator (y = error [–]): one panel per work measure `(axis label, curves)`, error against work, log–log: a count
/// that does not vary from run to run (rhs evaluations, Floquet evaluations) first, then the
/// wall time a user waits (issue 29 item 14: on millisecond runs the wall time alone zig-zags).
pub fn work_precision(title: &str, error_label: &str, work: &[(&str, Vec<Curve>)]) -> Figure {
    let panels = work
        .iter()
        .map(|(label, curves)| {
            let mut p = Panel::new(Axis::log(*label), Axis::log(error_label));
            for (i, c) in curves.iter().enumerate() {
                p.push(Series::line_points(c.label.clone(), c.x.clone(), c.y.clone()).color(i));
            }
            p
        })
        .collect();
    Figure::new(panels).title(title)
}

/// Convergence: error against the step (e.g. Δt' [–]), log–log, with dashed reference lines
/// of slope p for each order in `orders`, drawn through half the error of the finest point of
/// the first curve (so they run just below the data instead of hiding it).
pub fn convergence(
    title: &str,
    step_label: &str,
    error_label: &str,
    curves: &[Curve],
    orders: &[u32],
) -> Figure {
    let mut p = Panel::new(Axis::log(step_label), Axis::log(error_label));
    for (i, c) in curves.iter().enumerate() {
        p.push(Series::line_points(c.label.clone(), c.x.clone(), c.y.clone()).color(i));
    }
    let usable = |x: f64, y: f64| x.is_finite() && y.is_finite() && x > 0.0 && y > 0.0;
    if let Some(c) = curves.first() {
        let pts: Vec<(f64, f64)> =
            c.x.iter()
                .zip(&c.y)
                .map(|(&x, &y)| (x, y))
                .filter(|&(x, y)| usable(x, y))
                .collect();
        let lo = pts.iter().map(|p| p.0).fold(f64::INFINITY, f64::min);
        let hi = pts.iter().map(|p| p.0).fold(f64::NEG_INFINITY, f64::max);
        if let Some(&(x0, y0)) = pts.iter().find(|p| p.0 == lo) {
            if lo < hi {
                for (j, &q) in orders.iter().enumerate() {
                    let y = |x: f64| 0.5 * y0 * (x / x0).powi(q as i32);
                    p.push(
                        Series::dashed(format!("slope {q}"), vec![lo, hi], vec![y(lo), y(hi)])
                            .color(7 + j),
                    );
                }
            }
        }
    }
    Figure::single(p).title(title)
}

/// Stacked panels sharing the time axis: R(t) (when `radius`), then one panel per shape
/// column named in `shapes` (`"a_2"`, `"a_4"`), each with one curve per run. A shape panel is
/// |a_k| on a log axis when a run blew up or the curves span two decades ([`wants_log`]);
/// each run's blow-up time is a dashed vertical line in its colour on every panel.
pub fn time_series_panels(
    title: &str,
    runs: &[TimeSeries],
    radius: bool,
    shapes: &[&str],
) -> Figure {
    let t_axis = || Axis::linear("t [µs]");
    let mut panels = Vec::new();
    let legend = if runs.len() > 1 {
        Legend::Auto
    } else {
        Legend::Hidden
    };
    if radius {
        let mut p = Panel::new(t_axis(), Axis::linear("R [µm]")).legend(legend);
        for (i, run) in runs.iter().enumerate() {
            p.push(
                Series::line(
                    run.label.clone(),
                    scaled(&run.t_s, 1e6),
                    scaled(&run.radius_m, 1e6),
                )
                .color(i),
            );
        }
        panels.push(p);
    }
    let blown = runs.iter().any(|r| r.blow_up.is_some());
    for shape in shapes {
        let curves: Vec<(usize, &TimeSeries, Vec<f64>)> = runs
            .iter()
            .enumerate()
            .filter_map(|(i, run)| {
                let (_, v) = run.shapes.iter().find(|(n, _)| n == shape)?;
                Some((i, run, scaled(v, 1e6)))
            })
            .collect();
        let mut values: Vec<Vec<f64>> = curves.iter().map(|c| c.2.clone()).collect();
        let name = mode_name(shape);
        let y = if wants_log(&values, blown) {
            values = log_magnitudes(&values);
            Axis::log(format!("|{name}| [µm]"))
        } else {
            Axis::linear(format!("{name} [µm]"))
        };
        let mut p = Panel::new(t_axis(), y).legend(legend);
        for ((i, run, _), v) in curves.into_iter().zip(values) {
            p.push(Series::line(run.label.clone(), scaled(&run.t_s, 1e6), v).color(i));
        }
        panels.push(p);
    }
    for p in &mut panels {
        for (i, run) in runs.iter().enumerate() {
            if let Some((_, tb)) = &run.blow_up {
                p.vlines.push(super::VLine { x: tb * 1e6, label: String::new(), color: i });
            }
        }
    }
    Figure::stacked(panels).title(title)
}

/// dy/dt by central differences (one-sided at the ends); NaN where a neighbour is not finite.
pub fn derivative(t: &[f64], y: &[f64]) -> Vec<f64> {
    let n = t.len().min(y.len());
    (0..n)
        .map(|i| {
            let (a, b) = (i.saturating_sub(1), (i + 1).min(n.saturating_sub(1)));
            if a == b {
                return f64::NAN;
            }
            (y[b] - y[a]) / (t[b] - t[a])
        })
        .collect()
}
