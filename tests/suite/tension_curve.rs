//! `shell.law = "tension-curve"` (issue 31; docs/model.md, "Lipid shells: tension curve"): the
//! radial R(t) against an RK4 of the coated Rayleigh–Plesset equation written here with a PCHIP
//! written here (Fritsch & Carlson 1980 with Fritsch & Butland's interior slopes); a curve
//! sampled from Marmottant's σ(R) reproduces the marmottant law within interpolation error; bad
//! curves are refused naming the key.

use crate::common;
use crate::common::water::*;
use magbubble::model::{simulate, RunStatus};
use magbubble::scene::{load_str, Lipid, Scene, ShellLaw, TensionCurve};

/// A curve with plateaus and a steep rise: buckled (σ = 0) below 0.95, ruptured (0.072) above 1.2.
const KNOTS: [(f64, f64); 7] = [(0.85, 0.0), (0.95, 0.0), (1.0, 0.02), (1.05, 0.05), (1.1, 0.065), (1.2, 0.072), (1.3, 0.072)];

/// The PCHIP of (x, y) at u, from Fritsch & Carlson 1980 / Fritsch & Butland 1984: interior
/// slopes 1/d = (w1/δ_{i−1} + w2/δ_i)/(w1 + w2) where the secants agree in sign (else 0), ends
/// by the three-point formula limited to the first secant's sign and 3|δ|; constant beyond the
/// ends. Hermite cubic p(t) = y0 + d0 h t + (3δ − 2d0 − d1) h t² + (d0 + d1 − 2δ) h t³.
fn pchip(x: &[f64], y: &[f64], u: f64) -> f64 {
    let n = x.len();
    if u <= x[0] {
        return y[0];
    }
    if u >= x[n - 1] {
        return y[n - 1];
    }
    let h = |i: usize| x[i + 1] - x[i];
    let del = |i: usize| (y[i + 1] - y[i]) / h(i);
    let slope = |i: usize| -> f64 {
        if i == 0 || i == n - 1 {
            let (a, b, m0, m1) = if i == 0 { (h(0), h(1), del(0), del(1)) } else { (h(n - 2), h(n - 3), del(n - 2), del(n - 3)) };
            let e = ((2.0 * a + b) * m0 - a * m1) / (a + b);
            return if m0 == 0.0 || e * m0 <= 0.0 { 0.0 } else if m0 * m1 < 0.0 && e.abs() > 3.0 * m0.abs() { 3.0 * m0 } else { e };
        }
        let (d0, d1) = (del(i - 1), del(i));
        if d0 * d1 <= 0.0 {
            return 0.0;
        }
        let (w1, w2) = (2.0 * h(i) + h(i - 1), h(i) + 2.0 * h(i - 1));
        (w1 + w2) / (w1 / d0 + w2 / d1)
    };
    let i = x.iter().rposition(|&k| k <= u).unwrap();
    let (hh, t, dl) = (h(i), (u - x[i]) / h(i), del(i));
    let (d0, d1) = (slope(i), slope(i + 1));
    y[i] + d0 * hh * t + (3.0 * dl - 2.0 * d0 - d1) * hh * t * t + (d0 + d1 - 2.0 * dl) * hh * t * t * t
}

fn curve(knots: &[(f64, f64)]) -> TensionCurve {
    TensionCurve { file: "(test)".into(), area_ratio: knots.iter().map(|k| k.0).collect(), tension: knots.iter().map(|k| k.1).collect() }
}

/// The paper's bubble with the curve's shell, in equilibrium at R0 (p_g0 = p0 + 2σ(A0)/R0).
fn scene(eps_p: f64, f_hz: f64, c: TensionCurve) -> Scene {
    let mut s = common::scene(0, eps_p, f_hz);
    let (x, y) = (c.area_ratio.clone(), c.tension.clone());
    s.gas.reference_pressure = P0 + 2.0 * pchip(&x, &y, 1.0) / common::R0;
    s.shell.law = ShellLaw::TensionCurve(c);
    s
}

/// (t, R) of a run over 3 drive periods.
fn run(s: &mut Scene, f_hz: f64, rtol: f64) -> (Vec<f64>, Vec<f64>) {
    s.run.duration = 3.0 / f_hz;
    s.run.sample_interval = 0.02 / f_hz;
    s.run.integrator.rtol = rtol;
    s.run.integrator.atol = 1e-14;
    let (mut ts, mut rs) = (vec![], vec![]);
    let rep = simulate(s, &mut |t, row| {
        ts.push(t);
        rs.push(row[0]);
    })
    .unwrap();
    assert!(matches!(rep.status, RunStatus::Completed), "{:?}", rep.status);
    (ts, rs)
}

#[test]
fn radial_motion_matches_an_rk4_of_the_equation_with_the_same_interpolant() {
    let (x, y): (Vec<f64>, Vec<f64>) = KNOTS.iter().copied().unzip();
    let f_hz = 1e6;
    for eps in [0.1, 0.3, 1.0] {
        let mut s = scene(eps, f_hz, curve(&KNOTS));
        let (ts, rs) = run(&mut s, f_hz, 1e-11);
        let pg0 = s.gas.reference_pressure;
        let w = 2.0 * std::f64::consts::PI * f_hz;
        // ρ(RR̈ + 3/2Ṙ²) = p_g0(R0/R)^{3κ} − p0(1 + ε_p cos ωt) − 4ηṘ/R − 2σ(R²/R0²)/R
        let rp = |t: f64, v: [f64; 2]| {
            let (r, rd) = (v[0], v[1]);
            let sigma = pchip(&x, &y, (r / common::R0).powi(2));
            let p = pg0 * (common::R0 / r).powf(3.0 * KAPPA) - P0 * (1.0 + eps * (w * t).cos()) - 4.0 * ETA * rd / r - 2.0 * sigma / r;
            [rd, (p / RHO - 1.5 * rd * rd) / r]
        };
        let radii: Vec<f64> = x.iter().map(|j| common::R0 * j.sqrt()).collect();
        let (rref, crossings) = common::rk4_cut_at(&rp, &radii, [common::R0, 0.0], &ts, 2e-11);
        let err = rs.iter().zip(&rref).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max) / common::R0;
        let (lo, hi) = rs.iter().fold((f64::INFINITY, 0.0f64), |(l, h), &r| (l.min(r), h.max(r)));
        eprintln!("eps_p = {eps}: max|ΔR|/R0 = {err:.2e}, {crossings} knot crossings, R/R0 in [{:.4}, {:.4}]", lo / common::R0, hi / common::R0);
        assert!(crossings >= 2, "the orbit crosses knots");
        assert!(err <= 1e-8, "eps_p = {eps}: {err:e}");
    }
}

#[test]
fn a_curve_sampled_from_marmottant_reproduces_the_marmottant_law() {
    let (chi, s0, sr) = (0.5, 0.02, 0.072);
    let l = Lipid { elasticity: chi, buckling_radius: common::R0 / (1.0 + s0 / chi).sqrt(), initial_tension: s0, rupture_tension: sr, smoothing: None };
    let jb = (l.buckling_radius / common::R0).powi(2);
    let jr = jb * (1.0 + sr / chi);
    let sigma = |j: f64| if j < jb { 0.0 } else { (chi * (j / jb - 1.0)).min(sr) };
    let f_hz = 1e6;
    let mut m = common::scene(0, 0.6, f_hz); // buckles every cycle (J < J_b)
    m.shell.law = ShellLaw::Marmottant(l);
    m.gas.reference_pressure = P0 + 2.0 * s0 / common::R0;
    let (_, rm) = run(&mut m, f_hz, 1e-11);
    let jmin = rm.iter().fold(f64::INFINITY, |a, &r| a.min((r / common::R0).powi(2)));
    assert!(jmin < jb - 0.01, "the orbit reaches well into the buckled branch: J_min = {jmin}, J_b = {jb}");
    // knots every h in J on [0.8, 1.3], with J_b and J_r among them: PCHIP is exact except on the
    // two segments beside each kink, where it errs by O(χ h): the run's error falls as h falls
    let err = |h: f64| {
        let mut js: Vec<f64> = (0..).map(|i| 0.8 + h * i as f64).take_while(|&j| j <= 1.3 + 1e-12).filter(|j| (j - jb).abs() > h / 4.0 && (j - jr).abs() > h / 4.0).collect();
        js.extend([jb, jr]);
        js.sort_by(f64::total_cmp);
        let knots: Vec<(f64, f64)> = js.iter().map(|&j| (j, sigma(j))).collect();
        let mut s = scene(0.6, f_hz, curve(&knots));
        let (_, rc) = run(&mut s, f_hz, 1e-11);
        rc.iter().zip(&rm).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max) / common::R0
    };
    let (coarse, fine) = (err(0.01), err(0.0025));
    eprintln!("max|R_curve − R_marmottant|/R0: h = 0.01: {coarse:.2e}, h = 0.0025: {fine:.2e}");
    assert!(fine < coarse / 3.0, "the difference falls with the knot spacing: {coarse:e} → {fine:e}");
    assert!(fine < 1e-4, "{fine:e}");
}

fn ld(dir: &std::path::Path, csv: Option<&str>, extra: &str) -> Result<Scene, String> {
    if let Some(text) = csv {
        std::fs::write(dir.join("c.csv"), text).unwrap();
    }
    let toml = format!("[bubble]\nradius = 10e-6\n[shell]\nc1 = 0.1\nc2 = 0.12\nlaw = \"tension-curve\"\ntension_file = \"c.csv\"\n{extra}");
    let path = dir.join("s.toml");
    std::fs::write(&path, &toml).unwrap();
    magbubble::scene::load(&path, &[] as &[String]).map_err(|e| e.to_string())
}

#[test]
fn bad_curves_are_refused_naming_the_key() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let ok = "area_ratio,tension\n0.9,0\n1.0,0.02\n1.1,0.05\n";
    assert!(ld(d, Some(ok), "").is_ok(), "{:?}", ld(d, Some(ok), ""));
    let cases = [
        ("area_ratio,tension\n0.9,0\n1.1,0.02\n1.0,0.05\n", "strictly increasing"),
        ("area_ratio,tension\n0.9,0\n1.0,0.05\n1.1,0.02\n", "non-monotone"),
        ("area_ratio,tension\n0.9,0\n1.0,NaN\n1.1,0.05\n", "not finite"),
        ("area_ratio,tension\n0.9,0\n1.0,0.02\n", "at least 3"),
        ("area,tension\n0.9,0\n1.0,0.02\n1.1,0.05\n", "no column `area_ratio`"),
        ("area_ratio,sigma\n0.9,0\n1.0,0.02\n1.1,0.05\n", "no column `tension`"),
        ("area_ratio,tension\n0.9,0\n1.0,x\n1.1,0.05\n", "`x` is not a number"),
    ];
    for (csv, want) in cases {
        let e = ld(d, Some(csv), "").unwrap_err();
        assert!(e.contains("shell.tension_file") && e.contains(want), "{want}: {e}");
    }
    std::fs::remove_file(d.join("c.csv")).unwrap();
    let e = ld(d, None, "").unwrap_err();
    assert!(e.contains("shell.tension_file") && e.contains("cannot read"), "{e}");
    // a key of another law, and the curve's key under another law
    let e = ld(d, Some(ok), "elasticity = 0.5\n").unwrap_err();
    assert!(e.contains("shell.elasticity"), "{e}");
    let other = load_str("[bubble]\nradius = 10e-6\n[shell]\nc1 = 0.1\nc2 = 0.12\ntension_file = \"c.csv\"\n", "t", &[] as &[&str]).unwrap_err().to_string();
    assert!(other.contains("shell.tension_file") && other.contains("tension-curve"), "{other}");
    let missing = load_str("[bubble]\nradius = 10e-6\n[shell]\nc1 = 0.1\nc2 = 0.12\nlaw = \"tension-curve\"\n", "t", &[] as &[&str]).unwrap_err().to_string();
    assert!(missing.contains("shell.tension_file") && missing.contains("required"), "{missing}");
}
