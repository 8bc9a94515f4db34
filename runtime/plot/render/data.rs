//! The data side of rendering (module doc of [`super`]): which points are drawable (finite,
//! and positive on a log axis), the axis ranges they give, the runs of drawable points a line is
//! drawn in, and the thinning of very long lines to a min/max envelope.

use super::super::figure::{Axis, Panel, Scale, Series};
use super::super::PlotError;

/// Longest polyline drawn as is; longer ones keep a min/max envelope of about this many points.
const MAX_LINE_POINTS: usize = 6000;

pub(super) fn usable(v: f64, scale: Scale) -> bool {
    v.is_finite() && (scale == Scale::Linear || v > 0.0)
}

/// `(min, max)` of an axis' drawable values; `None` when there is none.
pub(super) type Extent = Option<(f64, f64)>;

/// Min/max of the drawable points of a panel, per axis.
pub(super) fn drawable_extent(panel: &Panel) -> (Extent, Extent) {
    let mut xr: Option<(f64, f64)> = None;
    let mut yr: Option<(f64, f64)> = None;
    let grow = |r: &mut Option<(f64, f64)>, v: f64| {
        *r = Some(match *r {
            None => (v, v),
            Some((lo, hi)) => (lo.min(v), hi.max(v)),
        })
    };
    for s in &panel.series {
        for (&x, &y) in s.x.iter().zip(&s.y) {
            if usable(x, panel.x.scale) && usable(y, panel.y.scale) {
                grow(&mut xr, x);
                grow(&mut yr, y);
            }
        }
    }
    (xr, yr)
}

/// The axis range: the user's (checked), or the data's with a 4 % margin.
pub(super) fn resolve(axis: &Axis, data: Extent, figure: &str, what: &str) -> Result<(f64, f64), PlotError> {
    let bad = |reason: String| PlotError::Axis {
        figure: figure.to_string(),
        axis: axis.label.clone(),
        reason,
    };
    if let Some((lo, hi)) = axis.range {
        if !(lo.is_finite() && hi.is_finite() && lo < hi) {
            return Err(bad(format!(
                "range {lo}..{hi} is not an increasing finite interval"
            )));
        }
        if axis.scale == Scale::Log && lo <= 0.0 {
            return Err(bad(format!(
                "a log axis needs a positive range, got {lo}..{hi}"
            )));
        }
        return Ok((lo, hi));
    }
    let Some((lo, hi)) = data else {
        return Err(PlotError::Empty {
            figure: figure.to_string(),
            what: format!("{what} has no finite data point to plot"),
        });
    };
    Ok(match axis.scale {
        Scale::Linear => {
            let span = hi - lo;
            if span > 0.0 && span > 1e-12 * lo.abs().max(hi.abs()) {
                (lo - 0.04 * span, hi + 0.04 * span)
            } else {
                let d = if lo == 0.0 { 1.0 } else { 0.05 * lo.abs() };
                (lo - d, hi + d)
            }
        }
        Scale::Log => {
            let ratio = hi / lo;
            if ratio > 1.0 + 1e-9 {
                let m = ratio.powf(0.04);
                (lo / m, hi * m)
            } else {
                (lo / 2.0, hi * 2.0)
            }
        }
    })
}

/// The runs of consecutive drawable points of a series (a non-drawable point ends a run).
pub(super) fn pieces(s: &Series, xs: Scale, ys: Scale) -> Vec<Vec<(f64, f64)>> {
    let mut out = Vec::new();
    let mut cur = Vec::new();
    for (&x, &y) in s.x.iter().zip(&s.y) {
        if usable(x, xs) && usable(y, ys) {
            cur.push((x, y));
        } else if !cur.is_empty() {
            out.push(std::mem::take(&mut cur));
        }
    }
    if !cur.is_empty() {
        out.push(cur);
    }
    out
}

/// Keeps at most about [`MAX_LINE_POINTS`] points of a polyline: per bucket of consecutive
/// points, the first, the minimum and the maximum in y and the last (in their order), so an
/// oscillation keeps its envelope.
pub(super) fn thin(points: Vec<(f64, f64)>) -> Vec<(f64, f64)> {
    let n = points.len();
    if n <= MAX_LINE_POINTS {
        return points;
    }
    let buckets = MAX_LINE_POINTS / 4;
    let size = n.div_ceil(buckets);
    let mut out = Vec::with_capacity(4 * buckets + 1);
    for chunk in points.chunks(size) {
        let (mut imin, mut imax) = (0, 0);
        for (i, p) in chunk.iter().enumerate() {
            if p.1 < chunk[imin].1 {
                imin = i;
            }
            if p.1 > chunk[imax].1 {
                imax = i;
            }
        }
        let mut idx = [0, imin.min(imax), imin.max(imax), chunk.len() - 1];
        idx.sort_unstable();
        let mut last = usize::MAX;
        for i in idx {
            if i != last {
                out.push(chunk[i]);
                last = i;
            }
        }
    }
    out
}

/// (x0,y0),(x1,y0),(x1,y1),(x2,y1)…: each value holds until the next sample.
pub(super) fn staircase(points: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let mut out = Vec::with_capacity(2 * points.len());
    for w in points.windows(2) {
        out.push(w[0]);
        out.push((w[1].0, w[0].1));
    }
    if let Some(&last) = points.last() {
        out.push(last);
    }
    out
}
