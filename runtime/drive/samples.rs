//! A measured drive waveform: knots (t_i, p_i) read from a CSV file with columns `t` [s] and
//! `p` [Pa], interpolated linearly between knots and zero outside [t_0, t_{n−1}]
//! (docs/model.md, "Drives"). The interpolation error on a segment of length h is at most
//! h² max|p''| / 8 (and h max|p''| / 2 in dp/dt); the knots are stop times of the integration
//! loop, where dp/dt jumps.

use std::path::Path;

/// Knots of a piecewise-linear pressure (strictly increasing times, finite values, ≥ 2 knots).
#[derive(Debug, Clone, PartialEq)]
pub struct Samples {
    t: Vec<f64>,
    p: Vec<f64>,
}

impl Samples {
    /// Knots from columns; the reason (for the `drive.file` issue) when they are not usable.
    pub fn new(t: Vec<f64>, p: Vec<f64>) -> Result<Samples, String> {
        if t.len() != p.len() {
            return Err(format!("{} times but {} pressures", t.len(), p.len()));
        }
        if t.len() < 2 {
            return Err(format!("has {} data row(s); a waveform needs at least 2", t.len()));
        }
        for (i, (&ti, &pi)) in t.iter().zip(&p).enumerate() {
            if !ti.is_finite() || !pi.is_finite() {
                return Err(format!("data row {}: t = {ti}, p = {pi} is not finite", i + 1));
            }
        }
        if let Some(i) = t.windows(2).position(|w| w[1] <= w[0]) {
            return Err(format!(
                "column t is not strictly increasing: data row {} has t = {:e} after t = {:e}",
                i + 2,
                t[i + 1],
                t[i]
            ));
        }
        Ok(Samples { t, p })
    }

    /// Reads a CSV file: a header naming the columns `t` and `p` (others ignored), then numbers;
    /// blank lines and lines starting with `#` are skipped.
    pub fn read(path: &Path) -> Result<Samples, String> {
        let text = std::fs::read_to_string(path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
        Self::parse(&text)
    }

    /// [`Samples::read`] from text.
    pub fn parse(text: &str) -> Result<Samples, String> {
        let mut lines = text.lines().enumerate().filter(|(_, l)| !l.trim().is_empty() && !l.trim_start().starts_with('#'));
        let (_, header) = lines.next().ok_or("is empty (expected a header `t,p` and at least 2 data rows)")?;
        let names: Vec<&str> = header.split(',').map(str::trim).collect();
        let col = |n: &str| names.iter().position(|&c| c == n).ok_or_else(|| format!("the header `{header}` has no column `{n}` (expected `t,p`: t [s], p [Pa])"));
        let (it, ip) = (col("t")?, col("p")?);
        let (mut t, mut p) = (Vec::new(), Vec::new());
        for (i, line) in lines {
            let f: Vec<&str> = line.split(',').map(str::trim).collect();
            let num = |j: usize| -> Result<f64, String> {
                let s = f.get(j).ok_or_else(|| format!("line {}: `{line}` has no column {}", i + 1, j + 1))?;
                s.parse::<f64>().map_err(|_| format!("line {}: `{s}` is not a number", i + 1))
            };
            t.push(num(it)?);
            p.push(num(ip)?);
        }
        Samples::new(t, p)
    }

    /// The same knots with times × `time` and pressures × `pressure`.
    pub fn scaled(&self, time: f64, pressure: f64) -> Samples {
        Samples { t: self.t.iter().map(|x| x * time).collect(), p: self.p.iter().map(|x| x * pressure).collect() }
    }

    pub fn times(&self) -> &[f64] {
        &self.t
    }

    pub fn pressures(&self) -> &[f64] {
        &self.p
    }

    /// (p(t), dp/dt): linear between knots (the right segment's slope at a knot), zero outside.
    pub fn at(&self, t: f64) -> (f64, f64) {
        let n = self.t.len();
        if !(t >= self.t[0] && t <= self.t[n - 1]) {
            return (0.0, 0.0);
        }
        // the segment [t_i, t_{i+1}] holding t (the last one for t = t_{n−1})
        let i = (self.t.partition_point(|&x| x <= t).max(1) - 1).min(n - 2);
        let (t0, t1, p0, p1) = (self.t[i], self.t[i + 1], self.p[i], self.p[i + 1]);
        let slope = (p1 - p0) / (t1 - t0);
        (p0 + slope * (t - t0), slope)
    }

    /// (p(t), dp/dt) on the piece holding the time `inside` (strictly between two knots, or
    /// outside the file: zero), its linear formula at any t of that piece, its knots included.
    pub fn at_on(&self, t: f64, inside: f64) -> (f64, f64) {
        let n = self.t.len();
        if !(inside >= self.t[0] && inside < self.t[n - 1]) {
            return (0.0, 0.0);
        }
        let i = self.t.partition_point(|&x| x <= inside) - 1;
        let (t0, t1, p0, p1) = (self.t[i], self.t[i + 1], self.p[i], self.p[i + 1]);
        let slope = (p1 - p0) / (t1 - t0);
        (p0 + slope * (t - t0), slope)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interpolates_and_is_zero_outside() {
        let s = Samples::parse("# measured\nt,p\n0,0\n1e-6,2\n3e-6,-2\n").unwrap();
        let near = |a: (f64, f64), b: (f64, f64)| (a.0 - b.0).abs() < 1e-12 && (a.1 - b.1).abs() < 1e-6;
        assert!(near(s.at(0.5e-6), (1.0, 2e6)), "{:?}", s.at(0.5e-6));
        assert!(near(s.at(2e-6), (0.0, -2e6)), "{:?}", s.at(2e-6));
        assert!(near(s.at(3e-6), (-2.0, -2e6)), "{:?}", s.at(3e-6));
        assert_eq!(s.at(-1e-9), (0.0, 0.0));
        assert_eq!(s.at(3.1e-6), (0.0, 0.0));
    }

    #[test]
    fn refuses_bad_files() {
        let err = |t: &str| Samples::parse(t).unwrap_err();
        assert!(err("").contains("empty"));
        assert!(err("t,p\n0,1\n").contains("at least 2"));
        assert!(err("t,q\n0,1\n1,2\n").contains("no column `p`"));
        assert!(err("t,p\n0,1\n1,NaN\n").contains("not finite"));
        assert!(err("t,p\n0,1\n2,1\n1,1\n").contains("not strictly increasing"));
        assert!(err("t,p\n0,1\n1,x\n").contains("`x` is not a number"));
    }
}
