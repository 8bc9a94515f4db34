//! Where a legend goes when the panel asks for [`Legend::Auto`] (issue 15 "legends placed off
//! the data"): the first corner of the plot area whose legend box covers no drawn data, else
//! a column outside the plot area, on the right.
//!
//! The test is done on a coarse occupancy grid of the plot area (cells of [`CELL`] pixels):
//! every drawn segment is walked in steps of at most [`CELL`]/2 pixels and marks its cells (a
//! marker its neighbours too); a corner is free when no marked cell lies within its box grown
//! by [`PAD`] pixels. The box size is the one plotters draws: the widest label, the 30-pixel
//! line sample and a 10-pixel margin on each side, one 20-pixel line per entry (font 16).

use super::figure::{Legend, Mark, Panel, Scale};

/// Occupancy cell size [px].
const CELL: i32 = 6;
/// Clearance kept between the legend box and the data [px].
const PAD: i32 = 4;
/// Distance of plotters' corner legends from the plot edges [px].
const INSET: i32 = 5;
/// Height of one legend line at font 16 (plotters: 1.25 × the font size) [px].
pub(crate) const LINE: i32 = 20;

/// Where the legend of a panel is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Placement {
    /// No legend (hidden, or no named series).
    None,
    /// Inside the plot area at this corner (never `Auto` or `Hidden`).
    Corner(Legend),
    /// In a column right of the plot area.
    Outside,
}

/// Width and height [px] of the legend box for `n` entries whose widest label is `text_w` wide.
pub(crate) fn box_size(n: usize, text_w: i32) -> (i32, i32) {
    (text_w + 30 + 20, (n.max(1) as i32 - 1) * LINE + 18 + 20)
}

/// Maps a value to [0, 1] along an axis range (log or linear); `None` when not drawable.
fn frac(v: f64, (lo, hi): (f64, f64), scale: Scale) -> Option<f64> {
    let f = match scale {
        Scale::Linear => (v - lo) / (hi - lo),
        Scale::Log if v > 0.0 => (v.log10() - lo.log10()) / (hi.log10() - lo.log10()),
        Scale::Log => return None,
    };
    f.is_finite().then_some(f)
}

/// Cells of the plot area (`w` × `h` px) covered by the panel's series and markers.
struct Grid {
    cols: i32,
    rows: i32,
    marked: Vec<bool>,
}

impl Grid {
    fn new(w: i32, h: i32) -> Self {
        let (cols, rows) = ((w / CELL).max(1) + 1, (h / CELL).max(1) + 1);
        Self { cols, rows, marked: vec![false; (cols * rows) as usize] }
    }
    fn mark(&mut self, px: f64, py: f64, radius: i32) {
        let (c, r) = ((px / CELL as f64).floor() as i32, (py / CELL as f64).floor() as i32);
        for dc in -radius..=radius {
            for dr in -radius..=radius {
                let (c, r) = (c + dc, r + dr);
                if (0..self.cols).contains(&c) && (0..self.rows).contains(&r) {
                    self.marked[(r * self.cols + c) as usize] = true;
                }
            }
        }
    }
    /// Whether any marked cell meets the pixel rectangle [x0, x1] × [y0, y1].
    fn any_in(&self, x0: i32, y0: i32, x1: i32, y1: i32) -> bool {
        let (c0, c1) = ((x0 / CELL).max(0), (x1 / CELL).min(self.cols - 1));
        let (r0, r1) = ((y0 / CELL).max(0), (y1 / CELL).min(self.rows - 1));
        (r0..=r1).any(|r| (c0..=c1).any(|c| self.marked[(r * self.cols + c) as usize]))
    }
}

/// The legend placement of `panel` drawn on a plot area of `plot` = (w, h) px with the resolved
/// ranges `xr`, `yr`; `legend` = (entries, box w, box h) or `None` without named entries.
pub(crate) fn place(
    panel: &Panel,
    xr: (f64, f64),
    yr: (f64, f64),
    plot: (i32, i32),
    legend: Option<(usize, i32, i32)>,
) -> Placement {
    let Some((_, bw, bh)) = legend else { return Placement::None };
    let corners = [Legend::UpperRight, Legend::UpperLeft, Legend::LowerRight, Legend::LowerLeft];
    match panel.legend {
        Legend::Hidden => return Placement::None,
        Legend::Auto => {}
        fixed => return Placement::Corner(fixed),
    }
    let (w, h) = plot;
    if bw + 2 * INSET > w || bh + 2 * INSET > h {
        return Placement::Outside;
    }
    let grid = occupancy(panel, xr, yr, plot);
    for corner in corners {
        let x0 = match corner {
            Legend::UpperLeft | Legend::LowerLeft => INSET,
            _ => w - bw - INSET,
        };
        let y0 = match corner {
            Legend::UpperLeft | Legend::UpperRight => INSET,
            _ => h - bh - INSET,
        };
        if !grid.any_in(x0 - PAD, y0 - PAD, x0 + bw + PAD, y0 + bh + PAD) {
            return Placement::Corner(corner);
        }
    }
    Placement::Outside
}

fn occupancy(panel: &Panel, xr: (f64, f64), yr: (f64, f64), (w, h): (i32, i32)) -> Grid {
    let mut grid = Grid::new(w, h);
    let to_px = |x: f64, y: f64| -> Option<(f64, f64)> {
        let fx = frac(x, xr, panel.x.scale)?;
        let fy = frac(y, yr, panel.y.scale)?;
        // Points far outside the range are clamped just outside the area (they mark nothing).
        let c = |f: f64| f.clamp(-0.1, 1.1);
        Some((c(fx) * w as f64, (1.0 - c(fy)) * h as f64))
    };
    for s in &panel.series {
        let pts: Vec<Option<(f64, f64)>> = s.x.iter().zip(&s.y).map(|(&x, &y)| to_px(x, y)).collect();
        let joined = !matches!(s.mark, Mark::Points);
        let radius = if matches!(s.mark, Mark::Line | Mark::Dashed) { 0 } else { 1 };
        for (i, p) in pts.iter().enumerate() {
            let Some((px, py)) = *p else { continue };
            grid.mark(px, py, radius);
            let next = if joined { pts.get(i + 1).copied().flatten() } else { None };
            if let Some((qx, qy)) = next {
                // A staircase goes right first, then up or down.
                let path: &[(f64, f64)] = if s.mark == Mark::Steps {
                    &[(px, py), (qx, py), (qx, qy)]
                } else {
                    &[(px, py), (qx, qy)]
                };
                for seg in path.windows(2) {
                    walk(&mut grid, seg[0], seg[1]);
                }
            }
        }
    }
    for v in &panel.vlines {
        if let Some(fx) = frac(v.x, xr, panel.x.scale) {
            walk(&mut grid, (fx * w as f64, 0.0), (fx * w as f64, h as f64));
        }
    }
    grid
}

/// Marks the cells along a segment, in steps of at most half a cell.
fn walk(grid: &mut Grid, (ax, ay): (f64, f64), (bx, by): (f64, f64)) {
    let len = (bx - ax).abs().max((by - ay).abs());
    let n = ((2.0 * len / CELL as f64).ceil() as usize).clamp(1, 4000);
    for k in 1..=n {
        let t = k as f64 / n as f64;
        grid.mark(ax + t * (bx - ax), ay + t * (by - ay), 0);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plot::figure::{Axis, Series};

    fn panel(x: Vec<f64>, y: Vec<f64>) -> Panel {
        Panel::new(Axis::linear("x"), Axis::linear("y")).series(Series::line("s", x, y))
    }

    #[test]
    fn a_rising_line_leaves_the_upper_left_corner_free() {
        let p = panel(vec![0.0, 1.0], vec![0.0, 1.0]);
        let at = place(&p, (0.0, 1.0), (0.0, 1.0), (800, 400), Some((1, 120, 38)));
        assert_eq!(at, Placement::Corner(Legend::UpperLeft));
    }

    #[test]
    fn a_filled_area_puts_the_legend_outside() {
        let x: Vec<f64> = (0..2000).map(|i| i as f64 / 1999.0).collect();
        let y: Vec<f64> = x.iter().map(|t| 0.5 + 0.5 * (400.0 * t).sin()).collect();
        let p = panel(x, y);
        let at = place(&p, (0.0, 1.0), (0.0, 1.0), (800, 400), Some((1, 120, 38)));
        assert_eq!(at, Placement::Outside);
        let fixed = p.clone().legend(Legend::LowerLeft);
        assert_eq!(place(&fixed, (0.0, 1.0), (0.0, 1.0), (800, 400), Some((1, 120, 38))), Placement::Corner(Legend::LowerLeft));
        assert_eq!(place(&p, (0.0, 1.0), (0.0, 1.0), (800, 400), None), Placement::None);
    }

    #[test]
    fn a_marker_line_counts_as_data() {
        // Data only in the lower half; a vertical marker at the right edge blocks the right corners.
        let p = panel(vec![0.0, 1.0], vec![0.0, 0.1]).vline(0.97, "blow-up");
        let at = place(&p, (0.0, 1.0), (0.0, 1.0), (800, 400), Some((2, 120, 58)));
        assert_eq!(at, Placement::Corner(Legend::UpperLeft));
    }
}
