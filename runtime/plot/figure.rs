//! The description of a figure: plain data, no plotters types. A [`Figure`] is one or more
//! [`Panel`]s stacked vertically; a panel has two [`Axis`] and several named [`Series`].
//! Rendering (SVG + PNG) lives in `render.rs`.

/// Linear or base-10 logarithmic axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Scale {
    #[default]
    Linear,
    Log,
}

/// One axis: its label (with the unit, e.g. `"t [µs]"`), its scale and an optional fixed range.
#[derive(Debug, Clone, PartialEq)]
pub struct Axis {
    pub label: String,
    pub scale: Scale,
    /// `None`: fitted to the finite data (plus a small margin).
    pub range: Option<(f64, f64)>,
    /// Only whole numbers are labelled (mode numbers k; issue 15 "integer ticks").
    pub integer: bool,
}

impl Axis {
    pub fn linear(label: impl Into<String>) -> Self {
        Self {
            label: label.into(),
            scale: Scale::Linear,
            range: None,
            integer: false,
        }
    }
    pub fn log(label: impl Into<String>) -> Self {
        Self {
            label: label.into(),
            scale: Scale::Log,
            range: None,
            integer: false,
        }
    }
    /// Linear when `log` is false, logarithmic otherwise.
    pub fn with_scale(label: impl Into<String>, log: bool) -> Self {
        if log {
            Self::log(label)
        } else {
            Self::linear(label)
        }
    }
    /// Label whole numbers only (a mode-number axis).
    pub fn integer(mut self) -> Self {
        self.integer = true;
        self
    }
    pub fn range(mut self, lo: f64, hi: f64) -> Self {
        self.range = Some((lo, hi));
        self
    }
}

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mark {
    /// A polyline; non-finite points break it into pieces (a visible gap).
    Line,
    /// A dashed polyline (reference lines: slopes, |μ| = 1 …).
    Dashed,
    /// Markers only (scatter).
    Points,
    /// Polyline with a marker at every point.
    LinePoints,
    /// A staircase: the value holds from each x to the next (e.g. first unstable mode vs f),
    /// with a marker at every sample.
    Steps,
}

/// One named curve. `x` and `y` must have the same length; non-finite points (and
/// non-positive ones on a log axis) are skipped when drawing.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Legend text; empty: no legend entry.
    pub name: String,
    pub x: Vec<f64>,
    pub y: Vec<f64>,
    pub mark: Mark,
    /// Palette index; `None`: the series' position in its panel.
    pub color: Option<usize>,
}

impl Series {
    pub fn new(name: impl Into<String>, x: Vec<f64>, y: Vec<f64>, mark: Mark) -> Self {
        Self {
            name: name.into(),
            x,
            y,
            mark,
            color: None,
        }
    }
    pub fn line(name: impl Into<String>, x: Vec<f64>, y: Vec<f64>) -> Self {
        Self::new(name, x, y, Mark::Line)
    }
    pub fn dashed(name: impl Into<String>, x: Vec<f64>, y: Vec<f64>) -> Self {
        Self::new(name, x, y, Mark::Dashed)
    }
    pub fn points(name: impl Into<String>, x: Vec<f64>, y: Vec<f64>) -> Self {
        Self::new(name, x, y, Mark::Points)
    }
    pub fn line_points(name: impl Into<String>, x: Vec<f64>, y: Vec<f64>) -> Self {
        Self::new(name, x, y, Mark::LinePoints)
    }
    pub fn steps(name: impl Into<String>, x: Vec<f64>, y: Vec<f64>) -> Self {
        Self::new(name, x, y, Mark::Steps)
    }
    pub fn color(mut self, index: usize) -> Self {
        self.color = Some(index);
        self
    }
}

/// Where the legend goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Legend {
    /// The first corner of the plot area (upper right, upper left, lower right, lower left)
    /// whose legend box covers no drawn data; outside the plot area, on the right, when every
    /// corner would hide data (issue 15 "legends placed off the data"; `legend.rs`).
    #[default]
    Auto,
    UpperRight,
    UpperLeft,
    LowerRight,
    LowerLeft,
    /// No legend even when series have names.
    Hidden,
}

/// A vertical dashed line across a panel at `x` (e.g. the blow-up time of a run), with a
/// legend entry when `label` is not empty.
#[derive(Debug, Clone, PartialEq)]
pub struct VLine {
    pub x: f64,
    pub label: String,
    /// Palette index.
    pub color: usize,
}

/// One chart: two axes and its series.
#[derive(Debug, Clone, PartialEq)]
pub struct Panel {
    pub title: Option<String>,
    pub x: Axis,
    pub y: Axis,
    pub series: Vec<Series>,
    pub legend: Legend,
    /// Vertical markers drawn over the full height of the panel.
    pub vlines: Vec<VLine>,
}

impl Panel {
    pub fn new(x: Axis, y: Axis) -> Self {
        Self {
            title: None,
            x,
            y,
            series: Vec::new(),
            legend: Legend::default(),
            vlines: Vec::new(),
        }
    }
    /// Adds a vertical dashed marker at `x` (palette colour 3, red).
    pub fn vline(mut self, x: f64, label: impl Into<String>) -> Self {
        self.vlines.push(VLine {
            x,
            label: label.into(),
            color: 3,
        });
        self
    }
    pub fn title(mut self, title: impl Into<String>) -> Self {
        self.title = Some(title.into());
        self
    }
    pub fn legend(mut self, legend: Legend) -> Self {
        self.legend = legend;
        self
    }
    pub fn series(mut self, series: Series) -> Self {
        self.series.push(series);
        self
    }
    pub fn push(&mut self, series: Series) {
        self.series.push(series);
    }
}

/// A figure: panels stacked top to bottom, rendered to `stem.svg` and `stem.png`.
#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    pub title: Option<String>,
    pub panels: Vec<Panel>,
    /// All panels use the union of their x ranges (e.g. R(t) above a_2(t)).
    pub share_x: bool,
    /// Image width in pixels.
    pub width: u32,
    /// Height of one panel in pixels (the title adds a little).
    pub panel_height: u32,
}

impl Figure {
    pub const DEFAULT_WIDTH: u32 = 960;
    pub const DEFAULT_PANEL_HEIGHT: u32 = 540;

    pub fn new(panels: Vec<Panel>) -> Self {
        Self {
            title: None,
            panels,
            share_x: false,
            width: Self::DEFAULT_WIDTH,
            panel_height: Self::DEFAULT_PANEL_HEIGHT,
        }
    }
    /// A figure with one panel.
    pub fn single(panel: Panel) -> Self {
        Self::new(vec![panel])
    }
    /// Panels stacked vertically that share their x axis.
    pub fn stacked(panels: Vec<Panel>) -> Self {
        let mut f = Self::new(panels);
        f.share_x = true;
        f.panel_height = 400;
        f
    }
    pub fn title(mut self, title: impl Into<String>) -> Self {
        self.title = Some(title.into());
        self
    }
    /// The name used in error messages.
    pub(crate) fn describe(&self) -> String {
        match &self.title {
            Some(t) => t.clone(),
            None => self
                .panels
                .first()
                .map(|p| format!("{} vs {}", p.y.label, p.x.label))
                .unwrap_or_else(|| "(untitled)".into()),
        }
    }
}
