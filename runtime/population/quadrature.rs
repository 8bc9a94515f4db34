//! The quadrature of a size distribution (docs/population.md, "Bins"): equal-probability bins
//! in ln R0. Bin i of N covers the quantiles [i/N, (i+1)/N] of the distribution; its node is the
//! bin's median, the quantile (i + ½)/N, and its weight is 1/N.
//!
//! Why this rule and not Gauss–Hermite in ln R0: the population's main output, the fraction
//! unstable at a given ε_p, is the weight of the bins whose critical ε_p lies below it — an
//! integral of a step function of R0. With equal weights its error is at most one bin's weight
//! (1/N) per threshold crossing and halves with each doubling of N, whatever the shape of the
//! critical curve; Gauss–Hermite's spectral accuracy needs a smooth integrand, and its largest
//! weights (≈ 0.4·√(2/N) at the centre) would make that step error far larger. The attenuation
//! integrand σ_e(R0) is a sharp resonance peak, also not smooth on the scale of a few Hermite
//! nodes.

use crate::scene::PopulationBin;

/// The standard normal quantile Φ⁻¹(p) for 0 < p < 1, by Wichura's algorithm AS 241 (Appl.
/// Statist. 37, 477, 1988; relative accuracy about 1e-16) — the two regions that cover
/// p ≥ 1e-11 (`population.bins` ≤ 100 000 needs p ≥ 5e-6).
pub fn normal_quantile(p: f64) -> f64 {
    assert!(p > 1e-11 && p < 1.0 - 1e-11, "normal_quantile: p = {p} outside the covered range");
    let horner = |c: &[f64], x: f64| c.iter().rev().fold(0.0, |acc, &ci| acc * x + ci);
    let q = p - 0.5;
    if q.abs() <= 0.425 {
        const A: [f64; 8] = [
            3.387_132_872_796_366_608,
            1.331_416_678_917_843_774_5e2,
            1.971_590_950_306_551_442_7e3,
            1.373_169_376_550_946_112_5e4,
            4.592_195_393_154_987_145_7e4,
            6.726_577_092_700_870_085_3e4,
            3.343_057_558_358_812_810_5e4,
            2.509_080_928_730_122_672_7e3,
        ];
        const B: [f64; 8] = [
            1.0,
            4.231_333_070_160_091_125_2e1,
            6.871_870_074_920_579_083e2,
            5.394_196_021_424_751_107_7e3,
            2.121_379_430_158_659_586_7e4,
            3.930_789_580_009_271_061e4,
            2.872_908_573_572_194_267_4e4,
            5.226_495_278_852_854_561e3,
        ];
        let r = 0.180625 - q * q;
        return q * horner(&A, r) / horner(&B, r);
    }
    const C: [f64; 8] = [
        1.423_437_110_749_683_577_34,
        4.630_337_846_156_545_295_9,
        5.769_497_221_460_691_405_5,
        3.647_848_324_763_204_605_04,
        1.270_458_252_452_368_382_58,
        2.417_807_251_774_506_117_7e-1,
        2.272_384_498_926_918_458_33e-2,
        7.745_450_142_783_414_076_4e-4,
    ];
    const D: [f64; 8] = [
        1.0,
        2.053_191_626_637_758_821_87,
        1.676_384_830_183_803_849_4,
        6.897_673_349_851_000_045_5e-1,
        1.481_039_764_274_800_745_9e-1,
        1.519_866_656_361_645_719_66e-2,
        5.475_938_084_995_344_946e-4,
        1.050_750_071_644_416_843_24e-9,
    ];
    let tail = if q < 0.0 { p } else { 1.0 - p };
    let r = (-tail.ln()).sqrt() - 1.6;
    let x = horner(&C, r) / horner(&D, r);
    if q < 0.0 {
        -x
    } else {
        x
    }
}

/// The N equal-probability bins of a lognormal distribution (module doc): node i at
/// median · σ_g^{Φ⁻¹((i + ½)/N)}, weight 1/N. One bin is the median itself (Φ⁻¹(½) = 0).
pub fn lognormal_bins(median: f64, geometric_std: f64, n: usize) -> Vec<PopulationBin> {
    let s = geometric_std.ln();
    (0..n)
        .map(|i| {
            let z = normal_quantile((i as f64 + 0.5) / n as f64);
            PopulationBin { radius: median * (s * z).exp(), weight: 1.0 / n as f64 }
        })
        .collect()
}

/// The bins of a `population.file` CSV (header with columns `radius` [m] and `weight`, `#`
/// comments and blank lines skipped): one bin per row, weights normalised to sum 1. Every
/// radius must be finite and > 0, every weight finite and ≥ 0, and not all weights 0.
pub fn read_bins(text: &str) -> Result<Vec<PopulationBin>, String> {
    let mut lines = text.lines().enumerate().filter(|(_, l)| !l.trim().is_empty() && !l.trim_start().starts_with('#'));
    let (_, header) = lines.next().ok_or("is empty (expected a header `radius,weight` and at least one row)")?;
    let names: Vec<&str> = header.split(',').map(str::trim).collect();
    let col = |n: &str| names.iter().position(|&c| c == n).ok_or_else(|| format!("the header `{header}` has no column `{n}` (expected `radius,weight`: radius [m], weight)"));
    let (ir, iw) = (col("radius")?, col("weight")?);
    let mut bins = Vec::new();
    for (i, line) in lines {
        let f: Vec<&str> = line.split(',').map(str::trim).collect();
        let num = |j: usize| -> Result<f64, String> {
            let s = f.get(j).ok_or_else(|| format!("line {}: `{line}` has no column {}", i + 1, j + 1))?;
            s.parse::<f64>().map_err(|_| format!("line {}: `{s}` is not a number", i + 1))
        };
        let (radius, weight) = (num(ir)?, num(iw)?);
        if !(radius.is_finite() && radius > 0.0) {
            return Err(format!("line {}: radius {radius} must be finite and > 0", i + 1));
        }
        if !(weight.is_finite() && weight >= 0.0) {
            return Err(format!("line {}: weight {weight} must be finite and >= 0", i + 1));
        }
        bins.push(PopulationBin { radius, weight });
    }
    if bins.is_empty() {
        return Err("has a header but no rows".into());
    }
    let total: f64 = bins.iter().map(|b| b.weight).sum();
    if !(total > 0.0 && total.is_finite()) {
        return Err(format!("the weights sum to {total}: need at least one weight > 0"));
    }
    for b in &mut bins {
        b.weight /= total;
    }
    Ok(bins)
}
