//! One row of a grid: the typed result of one run ([`GridRow`]) and its CSV fields, both ways.

/// How a run of a grid ended (the CSV's `status`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GridStatus {
    Completed,
    /// A shape mode exceeded the blow-up threshold, or R left (0, ∞) (a result, FORMULATION §5).
    BlowUp,
    /// The integrator gave up, or the model could not be assembled (`note` says why).
    Failed,
    /// A quadratic run left the credible range (issue 12; `note` has the mode and time).
    OutOfCredibleRange,
}

impl GridStatus {
    /// The CSV spelling: `completed`, `blow_up`, `failed`.
    pub fn as_str(self) -> &'static str {
        match self {
            GridStatus::Completed => "completed",
            GridStatus::BlowUp => "blow_up",
            GridStatus::Failed => "failed",
            GridStatus::OutOfCredibleRange => "out_of_credible_range",
        }
    }

    fn parse(s: &str) -> Option<GridStatus> {
        [GridStatus::Completed, GridStatus::BlowUp, GridStatus::Failed, GridStatus::OutOfCredibleRange].into_iter().find(|g| g.as_str() == s)
    }
}

/// A run's time series as `run` writes it to `series.csv`: `columns` = `t, R, a2, b2, …` (SI
/// units), `values` row-major (`rows() × columns.len()`).
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    pub columns: Vec<String>,
    pub values: Vec<f64>,
}

impl Series {
    /// Number of output samples.
    pub fn rows(&self) -> usize {
        self.values.len().checked_div(self.columns.len()).unwrap_or(0)
    }

    /// Reads a `series.csv` back (the values read back exactly: the writer prints shortest
    /// round-trip digits).
    pub fn parse(text: &str) -> Option<Series> {
        let mut lines = text.lines();
        let columns: Vec<String> = lines.next()?.split(',').map(str::to_string).collect();
        let mut values = Vec::new();
        for line in lines {
            let before = values.len();
            for cell in line.split(',') {
                values.push(cell.parse::<f64>().ok()?);
            }
            if values.len() - before != columns.len() {
                return None;
            }
        }
        Some(Series { columns, values })
    }
}

/// The result of one run of a grid (one CSV row). Lengths in m, times in s.
#[derive(Debug, Clone, PartialEq)]
pub struct GridRow {
    /// The point's index in the grid (first axis slowest).
    pub index: usize,
    /// The point's value of each grid key, as set (`--set` text), in axis order.
    pub values: Vec<String>,
    pub status: GridStatus,
    /// Time and mode (`a2`, `R`, …) of a blow-up; `None` unless `status` is `BlowUp`.
    pub t_blow_up: Option<f64>,
    pub blow_up_mode: Option<String>,
    /// Time of the last output sample (NaN when the run never started).
    pub t_end: f64,
    /// Smallest and largest R over the output samples (NaN without a sample).
    pub r_min: f64,
    pub r_max: f64,
    /// The largest max |a_k|, |b_k| and its column (`a2`…); `None` without shape modes.
    pub max_shape: Option<(String, f64)>,
    /// max |x| over the samples per mode column (`a2`, `b2`, … of the grid's largest
    /// `modes.max_order`); `None` for a mode this point does not have.
    pub max_abs: Vec<(String, Option<f64>)>,
    /// Integrator work, as `summary.json`'s `steps`, `rejected_steps`, `rhs_evaluations`.
    pub steps: u64,
    pub rejected_steps: u64,
    pub rhs_evaluations: u64,
    /// Why a run failed (empty otherwise); commas and line breaks become `;`.
    pub note: String,
    /// Wall time of the run [s]: the one field that is not deterministic.
    pub wall_seconds: f64,
    /// The run's series, when asked for ([`super::GridOptions::return_series`]).
    pub series: Option<Series>,
}

/// The result columns before the mode columns.
const HEAD: [&str; 8] = ["status", "t_blow_up", "blow_up_mode", "t_end", "R_min", "R_max", "max_shape", "max_shape_mode"];
/// The result columns after the mode columns (`wall_seconds` last).
const TAIL: [&str; 5] = ["steps", "rejected_steps", "rhs_evaluations", "note", "wall_seconds"];

/// The result columns of a grid whose largest mode set is `orders`.
pub fn result_header(orders: &[usize]) -> Vec<String> {
    let mut h: Vec<String> = HEAD.iter().map(|s| s.to_string()).collect();
    for k in orders {
        h.push(format!("max_a{k}"));
        h.push(format!("max_b{k}"));
    }
    h.extend(TAIL.iter().map(|s| s.to_string()));
    h
}

/// The mode columns (`a2`, `b2`, …) of `orders`.
pub(super) fn mode_columns(orders: &[usize]) -> Vec<String> {
    orders.iter().flat_map(|k| [format!("a{k}"), format!("b{k}")]).collect()
}

fn num(x: f64) -> String {
    format!("{x:e}")
}

fn opt(x: Option<f64>) -> String {
    x.map(num).unwrap_or_default()
}

impl GridRow {
    /// The CSV fields after `index` (grid values, then the result columns).
    pub fn fields(&self) -> Vec<String> {
        let mut f = self.values.clone();
        f.push(self.status.as_str().into());
        f.push(opt(self.t_blow_up));
        f.push(self.blow_up_mode.clone().unwrap_or_default());
        f.extend([num(self.t_end), num(self.r_min), num(self.r_max)]);
        f.push(opt(self.max_shape.as_ref().map(|m| m.1)));
        f.push(self.max_shape.as_ref().map(|m| m.0.clone()).unwrap_or_default());
        f.extend(self.max_abs.iter().map(|(_, v)| opt(*v)));
        f.extend([self.steps.to_string(), self.rejected_steps.to_string(), self.rhs_evaluations.to_string()]);
        f.push(self.note.replace([',', '\n', '\r'], ";"));
        f.push(num(self.wall_seconds));
        f
    }

    /// The row of CSV `fields` (as [`GridRow::fields`] writes them) of a grid with `naxes` keys
    /// and mode set `orders`; `None` if they do not parse.
    pub fn from_fields(index: usize, fields: &[String], naxes: usize, orders: &[usize]) -> Option<GridRow> {
        let modes = mode_columns(orders);
        if fields.len() != naxes + HEAD.len() + modes.len() + TAIL.len() {
            return None;
        }
        let (values, rest) = fields.split_at(naxes);
        let f = |i: usize| rest[i].as_str();
        let float = |i: usize| f(i).parse::<f64>().ok();
        let some = |i: usize| if f(i).is_empty() { Some(None) } else { float(i).map(Some) };
        let text = |i: usize| Some(f(i).to_string()).filter(|s| !s.is_empty());
        let m = HEAD.len() + modes.len();
        let max_shape = match (some(6)?, text(7)) {
            (Some(v), Some(name)) => Some((name, v)),
            _ => None,
        };
        let mut max_abs = Vec::with_capacity(modes.len());
        for (j, name) in modes.into_iter().enumerate() {
            max_abs.push((name, some(HEAD.len() + j)?));
        }
        Some(GridRow {
            index,
            values: values.to_vec(),
            status: GridStatus::parse(f(0))?,
            t_blow_up: some(1)?,
            blow_up_mode: text(2),
            t_end: float(3)?,
            r_min: float(4)?,
            r_max: float(5)?,
            max_shape,
            max_abs,
            steps: f(m).parse().ok()?,
            rejected_steps: f(m + 1).parse().ok()?,
            rhs_evaluations: f(m + 2).parse().ok()?,
            note: f(m + 3).to_string(),
            wall_seconds: float(m + 4)?,
            series: None,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fields_read_back_to_the_same_row() {
        let row = GridRow {
            index: 3,
            values: vec!["1e6".into(), "vorticity".into()],
            status: GridStatus::BlowUp,
            t_blow_up: Some(1.2345678901234567e-5),
            blow_up_mode: Some("a4".into()),
            t_end: 1.2345678901234567e-5,
            r_min: 0.1 + 0.2,
            r_max: f64::NAN,
            max_shape: Some(("b2".into(), 3e-9)),
            max_abs: vec![("a2".into(), Some(1e-8)), ("b2".into(), None)],
            steps: 12,
            rejected_steps: 1,
            rhs_evaluations: 99,
            note: "a, b\nc".into(),
            wall_seconds: 0.5,
            series: None,
        };
        let fields = row.fields();
        assert_eq!(fields.len(), 2 + result_header(&[2]).len());
        let back = GridRow::from_fields(3, &fields, 2, &[2]).unwrap();
        assert!(back.r_max.is_nan());
        assert_eq!(back.note, "a; b;c");
        assert_eq!(GridRow { r_max: 0.0, note: String::new(), ..back }, GridRow { r_max: 0.0, note: String::new(), ..row });
        assert!(GridRow::from_fields(3, &fields[1..], 2, &[2]).is_none());
        let s = Series::parse("t,R\n0e0,1e-5\n1e-8,1.1e-5\n").unwrap();
        assert_eq!((s.rows(), s.values[3]), (2, 1.1e-5));
        assert!(Series::parse("t,R\n0e0\n").is_none());
    }
}
