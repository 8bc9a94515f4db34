//! `[population]` → [`Population`] (docs/population.md): the distribution resolved into its
//! bins here, so a bad file, a bad weight or a bin thinner than its shell is refused when the
//! scene is loaded, before anything is written.

use super::super::raw::RawPopulation;
use super::super::schema::{self, fmt_num};
use super::super::types::*;
use super::Check;
use crate::population::quadrature::{lognormal_bins, read_bins};
use std::path::PathBuf;

pub(super) fn build(c: &mut Check, raw: Option<RawPopulation>, bubble: &Bubble, shell: &Shell) -> Option<Population> {
    let rp = raw?;
    let lognormal_keys = [
        ("population.median_radius", rp.median_radius.map(fmt_num)),
        ("population.geometric_std", rp.geometric_std.map(fmt_num)),
        ("population.bins", rp.bins.map(|b| b.to_string())),
    ];
    let (distribution, bins) = match c.choice("population.distribution", rp.distribution.as_deref()) {
        "lognormal" => {
            if let Some(f) = &rp.file {
                c.push("population.file", Some(format!("\"{f}\"")), "does nothing with distribution = \"lognormal\" (set distribution = \"file\")");
            }
            let median_radius = c.float_or("population.median_radius", rp.median_radius, bubble.radius);
            let geometric_std = c.float("population.geometric_std", rp.geometric_std);
            let n = c.int("population.bins", rp.bins);
            let ok = median_radius > 0.0 && geometric_std >= 1.0 && geometric_std.is_finite() && (1..=100_000).contains(&n);
            let bins = if ok { lognormal_bins(median_radius, geometric_std, n as usize) } else { Vec::new() };
            (Distribution::Lognormal { median_radius, geometric_std }, bins)
        }
        "file" => {
            for (key, v) in lognormal_keys {
                if let Some(v) = v {
                    c.push(key, Some(v), "does nothing with distribution = \"file\" (the file's rows are the bins)");
                }
            }
            let Some(path) = rp.file.clone() else {
                c.push("population.file", None, "required with distribution = \"file\"");
                return None;
            };
            let bins = match std::fs::read_to_string(&path).map_err(|e| format!("cannot read {path}: {e}")).and_then(|t| read_bins(&t)) {
                Ok(b) => b,
                Err(reason) => {
                    c.push("population.file", Some(format!("\"{path}\"")), reason);
                    Vec::new()
                }
            };
            (Distribution::File { path: PathBuf::from(path) }, bins)
        }
        other => unreachable!("schema choice {other}"),
    };
    let concentration_per_ml = rp.concentration.map(|v| {
        c.range("population.concentration", v);
        v
    });
    let scale_with_radius: Vec<String> =
        rp.scale_with_radius.as_deref().unwrap_or("").split(',').map(str::trim).filter(|k| !k.is_empty()).map(String::from).collect();
    for key in &scale_with_radius {
        let why = match crate::scene::numeric_param(key) {
            Err(e) => Some(e),
            Ok(p) if p.kind != schema::Kind::Float => Some(format!("`{key}` is not a real number")),
            Ok(_) if key == "bubble.radius" || key.starts_with("population.") => Some(format!("`{key}` cannot be scaled (bubble.radius is the bin's radius itself)")),
            Ok(_) => None,
        };
        if let Some(why) = why {
            c.push("population.scale_with_radius", Some(format!("\"{key}\"")), why);
        }
    }
    // a bin thinner than its shell is no bubble (issue 33, bad input)
    if !shell.is_free() && bubble.radius > 0.0 {
        let scaled = scale_with_radius.iter().any(|k| k == "shell.thickness");
        for (i, b) in bins.iter().enumerate() {
            let thickness = if scaled { shell.thickness * b.radius / bubble.radius } else { shell.thickness };
            if thickness >= b.radius {
                c.push(
                    "population",
                    Some(fmt_num(b.radius)),
                    format!("bin {i} (radius {} m): the shell thickness {} m is not below the radius", fmt_num(b.radius), fmt_num(thickness)),
                );
                break;
            }
        }
    }
    Some(Population { distribution, bins, concentration_per_ml, scale_with_radius })
}
