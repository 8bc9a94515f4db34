//! Rendering a [`Figure`] with plotters to SVG and PNG, atomically (temp file + rename).
//!
//! Data hygiene happens here, once: non-finite points (and non-positive ones on a log axis)
//! are skipped and break a line into pieces; very long lines are thinned with a min/max
//! envelope so a 2000 µs run sampled every nanosecond still gives a small SVG; a panel
//! with nothing drawable is an error, never a panic.

use super::figure::{Figure, Legend, Mark, Panel, Scale, Series};
use super::legend::{self, Placement};
use super::logaxis::{axis_tick_label, LogAxis};
use super::{fonts, PlotError};
use plotters::coord::ranged1d::{AsRangedCoord, Ranged, ValueFormatter};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

mod data;
use data::{drawable_extent, pieces, resolve, staircase, thin};

/// The two files written by [`Figure::save`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Saved {
    pub svg: PathBuf,
    pub png: PathBuf,
}

/// Colour-blind-friendly palette (matplotlib's tab10).
const PALETTE: [(u8, u8, u8); 10] = [
    (31, 119, 180),
    (255, 127, 14),
    (44, 160, 44),
    (214, 39, 40),
    (148, 103, 189),
    (140, 86, 75),
    (227, 119, 194),
    (127, 127, 127),
    (188, 189, 34),
    (23, 190, 207),
];

fn color(i: usize) -> RGBColor {
    let (r, g, b) = PALETTE[i % PALETTE.len()];
    RGBColor(r, g, b)
}

impl Figure {
    /// Writes `dir/stem.svg` and `dir/stem.png` (creating `dir`). Each file is first written
    /// under a temporary name in `dir` and renamed, so a reader never sees a partial image.
    pub fn save(&self, dir: &Path, stem: &str) -> Result<Saved, PlotError> {
        check_stem(stem)?;
        let layout = Layout::of(self)?;
        fonts::register()?;
        let _lock = crate::output::DirLock::acquire(dir)?;
        let size = (self.width.max(200), layout.height);

        let svg = dir.join(format!("{stem}.svg"));
        let mut text = String::new();
        {
            let root = SVGBackend::with_string(&mut text, size).into_drawing_area();
            draw_figure(&root, self, &layout).map_err(|message| PlotError::Render {
                path: svg.clone(),
                message,
            })?;
            root.present().map_err(|e| PlotError::Render {
                path: svg.clone(),
                message: e.to_string(),
            })?;
        }
        let tmp = temp_path(dir, stem, "svg");
        std::fs::write(&tmp, text.as_bytes()).map_err(|source| PlotError::Io {
            path: tmp.clone(),
            source,
        })?;
        rename(&tmp, &svg)?;

        let png = dir.join(format!("{stem}.png"));
        // The bitmap encoder picks the format from the extension: keep `.png` on the temp name.
        let tmp = temp_path(dir, stem, "png");
        let drawn = (|| {
            let root = BitMapBackend::new(&tmp, size).into_drawing_area();
            draw_figure(&root, self, &layout)?;
            root.present().map_err(|e| e.to_string())
        })();
        if let Err(message) = drawn {
            let _ = std::fs::remove_file(&tmp);
            return Err(PlotError::Render { path: png, message });
        }
        rename(&tmp, &png)?;
        Ok(Saved { svg, png })
    }
}

fn check_stem(stem: &str) -> Result<(), PlotError> {
    let reason = if stem.is_empty() {
        Some("it is empty")
    } else if stem.contains(['/', '\\']) {
        Some("it contains a path separator (pass the directory separately)")
    } else if stem.starts_with('.') {
        Some("it starts with a dot")
    } else {
        None
    };
    match reason {
        Some(reason) => Err(PlotError::Stem {
            stem: stem.to_string(),
            reason,
        }),
        None => Ok(()),
    }
}

fn temp_path(dir: &Path, stem: &str, ext: &str) -> PathBuf {
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    dir.join(format!(".{stem}.{}.{n}.tmp.{ext}", std::process::id()))
}

fn rename(from: &Path, to: &Path) -> Result<(), PlotError> {
    std::fs::rename(from, to).map_err(|source| {
        let _ = std::fs::remove_file(from);
        PlotError::Io {
            path: to.to_path_buf(),
            source,
        }
    })
}

/// Ranges of every panel, resolved before any drawing (so all errors come first).
struct Layout {
    ranges: Vec<((f64, f64), (f64, f64))>,
    height: u32,
}

const TITLE_HEIGHT: u32 = 40;

impl Layout {
    fn of(fig: &Figure) -> Result<Self, PlotError> {
        let name = fig.describe();
        if fig.panels.is_empty() {
            return Err(PlotError::Empty {
                figure: name,
                what: "the figure has no panel".into(),
            });
        }
        let mut ranges = Vec::with_capacity(fig.panels.len());
        for (i, panel) in fig.panels.iter().enumerate() {
            let what = format!("panel {} ({} vs {})", i + 1, panel.y.label, panel.x.label);
            for s in &panel.series {
                if s.x.len() != s.y.len() {
                    return Err(PlotError::Length {
                        figure: name.clone(),
                        series: s.name.clone(),
                        x: s.x.len(),
                        y: s.y.len(),
                    });
                }
            }
            let (xs, ys) = drawable_extent(panel);
            let x = resolve(&panel.x, xs, &name, &what)?;
            let y = resolve(&panel.y, ys, &name, &what)?;
            ranges.push((x, y));
        }
        if fig.share_x {
            let lo = ranges.iter().map(|r| r.0 .0).fold(f64::INFINITY, f64::min);
            let hi = ranges
                .iter()
                .map(|r| r.0 .1)
                .fold(f64::NEG_INFINITY, f64::max);
            for r in &mut ranges {
                r.0 = (lo, hi);
            }
        }
        let n = fig.panels.len() as u32;
        let height =
            n * fig.panel_height.max(150) + if fig.title.is_some() { TITLE_HEIGHT } else { 0 };
        Ok(Self { ranges, height })
    }
}

/// Plot-area margins of [`draw_panel`] [px]: around the chart, y and x label areas, a caption.
const MARGIN: i32 = 12;
const Y_LABELS: i32 = 88;
const X_LABELS: i32 = 56;
const CAPTION: i32 = 32;
/// Gap between the plot area and a legend placed outside it [px].
const OUTSIDE_GAP: i32 = 12;

/// The legend entries of a panel: named series with something to draw, named markers in range.
fn legend_entries(panel: &Panel, xr: (f64, f64)) -> Vec<&str> {
    let drawn = |s: &Series| !pieces(s, panel.x.scale, panel.y.scale).is_empty();
    let series = panel.series.iter().filter(|s| !s.name.is_empty() && drawn(s)).map(|s| s.name.as_str());
    let marks = panel.vlines.iter().filter(|v| !v.label.is_empty() && v.x >= xr.0 && v.x <= xr.1);
    series.chain(marks.map(|v| v.label.as_str())).collect()
}

/// Legend placement and the width reserved right of the plot area for each panel. With a shared
/// x axis every panel reserves the same width, so the time axes stay aligned.
fn placements<DB: DrawingBackend>(
    areas: &[DrawingArea<DB, Shift>],
    fig: &Figure,
    layout: &Layout,
) -> Vec<(Placement, i32)> {
    let font: TextStyle = (fonts::FAMILY, 16).into_font().into();
    let boxes: Vec<Option<(usize, i32, i32)>> = fig
        .panels
        .iter()
        .zip(&layout.ranges)
        .zip(areas)
        .map(|((panel, &(xr, _)), area)| {
            let entries = legend_entries(panel, xr);
            let widest = entries
                .iter()
                .map(|t| area.estimate_text_size(t, &font).map_or(9 * t.chars().count() as i32, |d| d.0 as i32))
                .max()?;
            let (w, h) = legend::box_size(entries.len(), widest);
            Some((entries.len(), w, h))
        })
        .collect();
    let plot_size = |i: usize, reserve: i32| {
        let (w, h) = areas[i].dim_in_pixel();
        let caption = if fig.panels[i].title.is_some() { CAPTION } else { 0 };
        (w as i32 - 3 * MARGIN - Y_LABELS - reserve, h as i32 - 2 * MARGIN - X_LABELS - caption)
    };
    let mut reserve = vec![0; fig.panels.len()];
    let mut out = vec![(Placement::None, 0); fig.panels.len()];
    // Twice: reserving a column narrows the plot areas, which can move another panel's legend out.
    for _ in 0..2 {
        for (i, (panel, &(xr, yr))) in fig.panels.iter().zip(&layout.ranges).enumerate() {
            let at = legend::place(panel, xr, yr, plot_size(i, reserve[i]), boxes[i]);
            out[i].0 = at;
            if at == Placement::Outside {
                let w = boxes[i].map_or(0, |b| b.1) + OUTSIDE_GAP;
                reserve[i] = reserve[i].max(w);
            }
        }
        if fig.share_x {
            let widest = reserve.iter().copied().max().unwrap_or(0);
            reserve.iter_mut().for_each(|r| *r = widest);
        }
    }
    for (o, r) in out.iter_mut().zip(reserve) {
        o.1 = r;
    }
    out
}

/// The font size for `text` across `area`: `largest` px, or smaller (down to 12 px) when the
/// text would be wider than the area less its margins — a long run title was cut at both ends
/// ("…marmottant: boundary-layer, linear coupling, marmottant, radau5 — completed 400.0…").
fn fitting_size<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, text: &str, largest: f64) -> f64 {
    let room = area.dim_in_pixel().0.saturating_sub(2 * MARGIN as u32);
    let fits = |px: f64| area.estimate_text_size(text, &(fonts::FAMILY, px).into_font().into()).map_or(true, |(w, _)| w <= room);
    let mut px = largest;
    while px > 12.0 && !fits(px) {
        px -= 1.0;
    }
    px
}

fn draw_figure<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    fig: &Figure,
    layout: &Layout,
) -> Result<(), String> {
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let body = match &fig.title {
        Some(t) => root
            .titled(t, (fonts::FAMILY, fitting_size(root, t, 26.0)).into_font())
            .map_err(|e| e.to_string())?,
        None => root.clone(),
    };
    let areas = body.split_evenly((fig.panels.len(), 1));
    let places = placements(&areas, fig, layout);
    for (((panel, area), &(xr, yr)), &legend) in
        fig.panels.iter().zip(&areas).zip(&layout.ranges).zip(&places)
    {
        let (x0, x1) = xr;
        let (y0, y1) = yr;
        let p = (xr, yr, legend);
        match (panel.x.scale, panel.y.scale) {
            (Scale::Linear, Scale::Linear) => draw_panel(area, panel, p, x0..x1, y0..y1),
            (Scale::Log, Scale::Linear) => {
                draw_panel(area, panel, p, LogAxis { lo: x0, hi: x1 }, y0..y1)
            }
            (Scale::Linear, Scale::Log) => {
                draw_panel(area, panel, p, x0..x1, LogAxis { lo: y0, hi: y1 })
            }
            (Scale::Log, Scale::Log) => draw_panel(
                area,
                panel,
                p,
                LogAxis { lo: x0, hi: x1 },
                LogAxis { lo: y0, hi: y1 },
            ),
        }?;
    }
    Ok(())
}

/// The resolved x and y ranges of a panel, its legend placement and the reserved right column.
type Resolved = ((f64, f64), (f64, f64), (Placement, i32));

fn draw_panel<DB, XS, YS>(
    area: &DrawingArea<DB, Shift>,
    panel: &Panel,
    (xr, yr, (placement, reserve)): Resolved,
    xs: XS,
    ys: YS,
) -> Result<(), String>
where
    DB: DrawingBackend,
    XS: AsRangedCoord<Value = f64>,
    YS: AsRangedCoord<Value = f64>,
    XS::CoordDescType: Ranged<ValueType = f64> + ValueFormatter<f64>,
    YS::CoordDescType: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let err = |e: &dyn std::fmt::Display| e.to_string();
    let mut builder = ChartBuilder::on(area);
    builder
        .margin(MARGIN as u32)
        // Room on the right for the last tick label (and a legend placed outside).
        .margin_right((2 * MARGIN + reserve) as u32)
        .x_label_area_size(X_LABELS as u32)
        .y_label_area_size(Y_LABELS as u32);
    if let Some(t) = &panel.title {
        builder.caption(t, (fonts::FAMILY, fitting_size(area, t, 22.0)).into_font());
    }
    let mut chart = builder.build_cartesian_2d(xs, ys).map_err(|e| err(&e))?;
    // A tick that is zero up to rounding (1.39e-17 on a ±0.1 axis) prints as 0.
    let (x_lin, y_lin) = (panel.x.scale == Scale::Linear, panel.y.scale == Scale::Linear);
    let snap = |v: f64, (lo, hi): (f64, f64), linear: bool| {
        if linear && v.abs() < 1e-9 * lo.abs().max(hi.abs()) {
            0.0
        } else {
            v
        }
    };
    let (xi, yi) = (panel.x.integer, panel.y.integer);
    let xfmt = move |v: &f64| axis_tick_label(snap(*v, xr, x_lin), xi);
    let yfmt = move |v: &f64| axis_tick_label(snap(*v, yr, y_lin), yi);
    chart
        .configure_mesh()
        .x_desc(panel.x.label.as_str())
        .y_desc(panel.y.label.as_str())
        .axis_desc_style((fonts::FAMILY, 20))
        .label_style((fonts::FAMILY, 16))
        .x_label_formatter(&xfmt)
        .y_label_formatter(&yfmt)
        .max_light_lines(4)
        .light_line_style(RGBColor(238, 238, 238))
        .bold_line_style(RGBColor(210, 210, 210))
        .draw()
        .map_err(|e| err(&e))?;

    let mut labelled = false;
    // (label, colour, dashed) of every legend entry, for a legend drawn outside the plot area.
    let mut entries: Vec<(&str, RGBColor, bool)> = Vec::new();
    for (i, s) in panel.series.iter().enumerate() {
        let c = color(s.color.unwrap_or(i));
        let pieces = pieces(s, panel.x.scale, panel.y.scale);
        let mut first = true;
        for piece in pieces {
            let anno = match s.mark {
                Mark::Line => chart.draw_series(LineSeries::new(thin(piece), c.stroke_width(2))),
                Mark::Dashed => {
                    chart.draw_series(DashedLineSeries::new(thin(piece), 8, 6, c.stroke_width(2)))
                }
                Mark::Points => {
                    chart.draw_series(piece.iter().map(|&p| Circle::new(p, 3, c.filled())))
                }
                Mark::LinePoints => {
                    chart
                        .draw_series(piece.iter().map(|&p| Circle::new(p, 3, c.filled())))
                        .map_err(|e| err(&e))?;
                    chart.draw_series(LineSeries::new(thin(piece), c.stroke_width(2)))
                }
                Mark::Steps => {
                    chart
                        .draw_series(piece.iter().map(|&p| Circle::new(p, 3, c.filled())))
                        .map_err(|e| err(&e))?;
                    chart.draw_series(LineSeries::new(staircase(&piece), c.stroke_width(2)))
                }
            }
            .map_err(|e| err(&e))?;
            if first && !s.name.is_empty() {
                labelled = true;
                let dashed = s.mark == Mark::Dashed;
                entries.push((s.name.as_str(), c, dashed));
                anno.label(s.name.as_str()).legend(move |(x, y)| {
                    if dashed {
                        PathElement::new(vec![(x, y), (x + 8, y)], c.stroke_width(2))
                    } else {
                        PathElement::new(vec![(x, y), (x + 22, y)], c.stroke_width(2))
                    }
                });
            }
            first = false;
        }
    }
    for v in panel.vlines.iter().filter(|v| v.x >= xr.0 && v.x <= xr.1) {
        let c = color(v.color);
        let anno = chart
            .draw_series(DashedLineSeries::new(vec![(v.x, yr.0), (v.x, yr.1)], 8, 6, c.stroke_width(2)))
            .map_err(|e| err(&e))?;
        if !v.label.is_empty() {
            labelled = true;
            entries.push((v.label.as_str(), c, true));
            anno.label(v.label.as_str())
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 8, y)], c.stroke_width(2)));
        }
    }
    let position = match placement {
        Placement::Corner(Legend::UpperLeft) => Some(SeriesLabelPosition::UpperLeft),
        Placement::Corner(Legend::LowerRight) => Some(SeriesLabelPosition::LowerRight),
        Placement::Corner(Legend::LowerLeft) => Some(SeriesLabelPosition::LowerLeft),
        Placement::Corner(_) => Some(SeriesLabelPosition::UpperRight),
        Placement::Outside => {
            // plotters clamps legend drawing to the plot area: draw this one on the panel.
            let (xs, ys) = chart.plotting_area().get_pixel_range();
            let (bx, by) = area.get_base_pixel();
            return draw_legend_at(area, (xs.end - bx + OUTSIDE_GAP, ys.start - by), &entries);
        }
        Placement::None => None,
    };
    if let (true, Some(position)) = (labelled, position) {
        chart
            .configure_series_labels()
            .position(position)
            .label_font((fonts::FAMILY, 16))
            .background_style(WHITE.mix(0.85))
            .border_style(RGBColor(160, 160, 160))
            .draw()
            .map_err(|e| err(&e))?;
    }
    Ok(())
}

/// A legend box with its top-left corner at `at` (pixels of `area`), laid out as plotters lays
/// out its own (one [`legend::LINE`] per entry, the line sample left of the text).
fn draw_legend_at<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    (x, y): (i32, i32),
    entries: &[(&str, RGBColor, bool)],
) -> Result<(), String> {
    if entries.is_empty() {
        return Ok(());
    }
    let err = |e: &dyn std::fmt::Display| e.to_string();
    let font: TextStyle = (fonts::FAMILY, 16).into_font().into();
    let mut widest = 0;
    for (t, _, _) in entries {
        widest = widest.max(area.estimate_text_size(t, &font).map_err(|e| err(&e))?.0 as i32);
    }
    let (w, h) = legend::box_size(entries.len(), widest);
    area.draw(&Rectangle::new([(x, y), (x + w, y + h)], WHITE.mix(0.85).filled()))
        .map_err(|e| err(&e))?;
    area.draw(&Rectangle::new([(x, y), (x + w, y + h)], RGBColor(160, 160, 160)))
        .map_err(|e| err(&e))?;
    for (k, (text, c, dashed)) in entries.iter().enumerate() {
        let top = y + 10 + k as i32 * legend::LINE;
        let mid = top + 9;
        let style = c.stroke_width(2);
        let segments: &[(i32, i32)] = if *dashed { &[(0, 8), (14, 22)] } else { &[(0, 22)] };
        for &(a, b) in segments {
            area.draw(&PathElement::new(vec![(x + 10 + a, mid), (x + 10 + b, mid)], style))
                .map_err(|e| err(&e))?;
        }
        area.draw(&Text::new(text.to_string(), (x + 40, top), font.clone()))
            .map_err(|e| err(&e))?;
    }
    Ok(())
}


#[cfg(test)]
mod tests {
    use super::*;

    /// A title that fits keeps its size; the 960-px run title of coil_marmottant (cut at both
    /// ends at 26 px) is set smaller, and then fits.
    #[test]
    fn a_long_title_is_set_smaller_until_it_fits() {
        fonts::register().unwrap();
        let mut svg = String::new();
        let root = SVGBackend::with_string(&mut svg, (960, 400)).into_drawing_area();
        assert_eq!(fitting_size(&root, "fig 12", 26.0), 26.0);
        let long = "coil_marmottant: boundary-layer, linear coupling, marmottant, radau5 — completed 400.00 µs";
        let px = fitting_size(&root, long, 26.0);
        assert!(px < 26.0 && px >= 12.0, "{px}");
        let (w, _) = root.estimate_text_size(long, &(fonts::FAMILY, px).into_font().into()).unwrap();
        assert!(w <= 960 - 2 * MARGIN as u32, "{w}");
        let (w26, _) = root.estimate_text_size(long, &(fonts::FAMILY, 26.0).into_font().into()).unwrap();
        assert!(w26 > 960 - 2 * MARGIN as u32, "the example must be one that did not fit: {w26}");
    }
}
