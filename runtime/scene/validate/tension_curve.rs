//! `shell.law = "tension-curve"` (issue 31; docs/model.md, "Lipid shells: tension curve"): the
//! CSV of `shell.tension_file` read and checked here, so a bad curve is refused with the scene —
//! before any work, nothing written — naming the key, the file and the line.

use super::super::raw::RawShell;
use super::super::types::TensionCurve;
use super::check::Check;

/// Fewest knots of a curve (PCHIP's end slopes take three points).
pub const MIN_ROWS: usize = 3;
/// Most knots: each is a branch of the run (a one-byte branch code, effects/lipid.rs).
pub const MAX_ROWS: usize = 250;

/// Under another law: `shell.tension_file` would do nothing.
pub(super) fn refuse_key(c: &mut Check, rs: &RawShell, law: &str) {
    if let Some(f) = &rs.tension_file {
        c.push("shell.tension_file", Some(format!("\"{f}\"")), format!("a key of shell.law = \"tension-curve\", but shell.law = \"{law}\": it would do nothing (remove it or set shell.law)"));
    }
}

/// The curve of `shell.tension_file`, every problem pushed to `c` (a placeholder curve then).
pub(super) fn build(c: &mut Check, rs: &RawShell) -> TensionCurve {
    let placeholder = |file: &str| TensionCurve { file: file.to_string(), area_ratio: vec![0.5, 1.0, 1.5], tension: vec![0.0; 3] };
    let Some(file) = &rs.tension_file else {
        c.push("shell.tension_file", None, "required with shell.law = \"tension-curve\" (a CSV with the columns area_ratio, tension [N/m])");
        return placeholder("");
    };
    let parsed = std::fs::read_to_string(file).map_err(|e| format!("cannot read {file}: {e}")).and_then(|t| parse(&t));
    match parsed {
        Ok((area_ratio, tension)) => TensionCurve { file: file.clone(), area_ratio, tension },
        Err(reason) => {
            c.push("shell.tension_file", Some(format!("\"{file}\"")), reason);
            placeholder(file)
        }
    }
}

/// The knots of CSV text: a header naming `area_ratio` and `tension` (other columns ignored;
/// blank lines and `#` lines skipped), at least [`MIN_ROWS`] rows of finite numbers, area_ratio
/// > 0 and strictly increasing, tension non-decreasing (a monolayer's tension does not fall as
/// its area grows; a falling curve would make the spherical state unstable on its own).
pub fn parse(text: &str) -> Result<(Vec<f64>, Vec<f64>), String> {
    let mut lines = text.lines().enumerate().filter(|(_, l)| !l.trim().is_empty() && !l.trim_start().starts_with('#'));
    let (_, header) = lines.next().ok_or("is empty (expected a header `area_ratio,tension` and at least 3 rows)")?;
    let names: Vec<&str> = header.split(',').map(str::trim).collect();
    let col = |n: &str| {
        names.iter().position(|&c| c == n).ok_or_else(|| format!("the header `{header}` has no column `{n}` (expected `area_ratio,tension`: A/A0 [–], sigma [N/m])"))
    };
    let (ia, it) = (col("area_ratio")?, col("tension")?);
    let (mut a, mut s) = (Vec::new(), Vec::new());
    for (i, line) in lines {
        let f: Vec<&str> = line.split(',').map(str::trim).collect();
        let num = |j: usize, name: &str| -> Result<f64, String> {
            let cell = f.get(j).ok_or_else(|| format!("line {}: `{line}` has no {name} column", i + 1))?;
            let v: f64 = cell.parse().map_err(|_| format!("line {}: {name} `{cell}` is not a number", i + 1))?;
            if !v.is_finite() {
                return Err(format!("line {}: {name} = {cell} is not finite", i + 1));
            }
            Ok(v)
        };
        let (x, y) = (num(ia, "area_ratio")?, num(it, "tension")?);
        if x <= 0.0 {
            return Err(format!("line {}: area_ratio = {x} must be > 0", i + 1));
        }
        if let (Some(&px), Some(&py)) = (a.last(), s.last()) {
            if x <= px {
                return Err(format!("line {}: area_ratio = {x} after {px}: area_ratio must be strictly increasing", i + 1));
            }
            if y < py {
                return Err(format!("line {}: tension = {y} after {py}: the tension must not decrease as area_ratio grows (non-monotone curve)", i + 1));
            }
        }
        a.push(x);
        s.push(y);
    }
    if a.len() < MIN_ROWS {
        return Err(format!("has {} data rows: a tension curve needs at least {MIN_ROWS}", a.len()));
    }
    if a.len() > MAX_ROWS {
        return Err(format!("has {} data rows: at most {MAX_ROWS} knots (each is a branch switch of the run)", a.len()));
    }
    Ok((a, s))
}
