//! Second-order (quadratic) mode coupling of a free bubble in an inviscid liquid (issue 12).
//!
//! The engine, not a spec, states the potential flow (as it computes the ponderomotive force of a
//! field spec): the surface r = f(θ, t) = R + ζ, ζ = Σ_n a_n P_n(cos θ) (Eulerian shape
//! amplitudes), the potential φ = −R²Ṙ/r + Σ_n c_n r^{−(n+1)} P_n + Σ_j d_j r^{−(j+1)} P_j
//! (c first, d second order, φ → 0 at infinity), and on the surface
//!
//! * the kinematic condition  ∂f/∂t = φ_r − φ_θ f_θ / r²,
//! * the dynamic (Bernoulli + Laplace) condition
//!   ρ(φ_t + ½|∇φ|²) + p_g(V) − γ(κ1 + κ2) − p∞ = 0,
//!
//! with the exact curvatures of the surface of revolution r = f(θ), the polytropic gas at the
//! exact volume V = (2π/3)∫(R+ζ)³ dx, p_g = p_g(R)(V_R/V)^κ. Both conditions are expanded to
//! second order in the amplitudes (order symbol `e`) for one pair of modes (l, m), exactly
//! (rationals, polynomials in x = cos θ), and projected on P_j (weight (2j+1)/2). Order by order:
//! the first-order kinematic condition on P_n gives c_n, the second-order one on P_j gives d_j;
//! the dynamic condition on P_j at second order, with c, d, ċ, ḋ substituted, is the quadratic
//! load. Its bilinear part in (mode l, mode m) is what the tables hold.
//!
//! Sign convention (docs/model.md §4.1): the first-order dynamic condition on P_j is
//! −(ρR/(j+1))[ä_j + 3Ṙȧ_j/R − (j−1)R̈a_j/R] − G_n,j (checked here), so the quadratic load adds
//! Q_j = −F⁽²⁾_j to G_n,j; on P_0 the zero-order part is −ρ(RR̈ + 3/2Ṙ²) + P, so Q_0 = +F⁽²⁾_0 adds
//! to the radial pressure balance P.
//!
//! Viscous stresses are not part of this derivation (docs/model.md, "Quadratic mode coupling").

use crate::algebra::legendre::legendre_poly;
use crate::algebra::{rat, Mono, Poly, Rat};
use num_traits::Zero;
use std::collections::BTreeMap;

/// The order-counting symbol; terms beyond e² are dropped.
const E: &str = "e";
/// cos θ (a plain symbol: no trigonometric normalization).
const X: &str = "x";
/// P_j of the target mode (the second-order potential d_j r^{−(j+1)} P_j), projected as δ.
const PJ: &str = "PJ";

/// Keep terms up to e².
fn trunc(p: Poly) -> Poly {
    let mut out = Poly::zero();
    for (m, c) in p.terms {
        if m.power(E) <= 2 {
            out = out.add(&Poly::term(m, c));
        }
    }
    out
}

/// a·b to e², without forming the products beyond it.
fn mul(a: &Poly, b: &Poly) -> Poly {
    let (a, b) = ([0, 1, 2].map(|n| part(a, n)), [0, 1, 2].map(|n| part(b, n)));
    let mut out = Poly::zero();
    for i in 0..3 {
        for k in 0..3 - i {
            if !a[i].is_zero() && !b[k].is_zero() {
                out = out.add(&a[i].mul(&b[k]));
            }
        }
    }
    out
}

/// The terms of p with e^n (e kept).
fn part(p: &Poly, n: i32) -> Poly {
    Poly { terms: p.terms.iter().filter(|(m, _)| m.power(E) == n).map(|(m, c)| (m.clone(), c.clone())).collect() }
}

fn v(name: &str) -> Poly {
    Poly::var(name)
}

fn c(n: i64) -> Poly {
    Poly::constant(rat(n))
}

fn cr(r: Rat) -> Poly {
    Poly::constant(r)
}

/// R^p.
fn rp(p: i32) -> Poly {
    Poly::term(Mono::var("R", p), rat(1))
}

/// The part of p with e^n, e removed.
fn order(p: &Poly, n: i32) -> Poly {
    let mut out = Poly::zero();
    for (m, c) in &p.terms {
        if m.power(E) == n {
            out = out.add(&Poly::term(m.with(E, 0), c.clone()));
        }
    }
    out
}

/// P_n(x) as a polynomial in x.
fn legendre(n: usize) -> Poly {
    let mut p = Poly::zero();
    for (i, c) in legendre_poly(n).iter().enumerate() {
        if !c.is_zero() {
            p = p.add(&Poly::term(Mono::var(X, i as i32), c.clone()));
        }
    }
    p
}

/// The symbols of one mode: amplitude, rate, acceleration.
#[derive(Clone, Copy, Debug)]
pub struct ModeSyms {
    pub n: usize,
    pub a: &'static str,
    pub ad: &'static str,
    pub add: &'static str,
}

pub const MODE_L: (&str, &str, &str) = ("al", "adl", "addl");
pub const MODE_M: (&str, &str, &str) = ("am", "adm", "addm");

fn mode(n: usize, s: (&'static str, &'static str, &'static str)) -> ModeSyms {
    ModeSyms { n, a: s.0, ad: s.1, add: s.2 }
}

/// Time derivative along the motion (R → Ṙ → R̈, a → ȧ → ä of both modes).
fn rate(p: &Poly) -> Poly {
    let chain = [("R", "Rd"), ("Rd", "Rdd"), ("al", "adl"), ("adl", "addl"), ("am", "adm"), ("adm", "addm")];
    let mut out = Poly::zero();
    for (s, ds) in chain {
        if p.has(s) {
            out = out.add(&p.diff(s).mul(&v(ds)));
        }
    }
    if p.has("Rdd") || p.has("addl") || p.has("addm") {
        // a jerk would be needed: not expected at second order (the d_j contain no acceleration)
        panic!("rate of an acceleration");
    }
    out
}

/// Normalized projection on P_j, (2j+1)/2 ∫ p P_j dx, of a polynomial in x.
#[derive(Default)]
pub struct Projector {
    moments: BTreeMap<(i32, usize), Rat>,
}

impl Projector {
    fn moment(&mut self, n: i32, j: usize) -> Rat {
        if let Some(m) = self.moments.get(&(n, j)) {
            return m.clone();
        }
        let mut s = Rat::zero();
        for (i, c) in legendre_poly(j).iter().enumerate() {
            let p = n as usize + i;
            if p % 2 == 0 && !c.is_zero() {
                s += c * rat(2) / rat(p as i64 + 1);
            }
        }
        let m = s * rat(2 * j as i64 + 1) / rat(2);
        self.moments.insert((n, j), m.clone());
        m
    }
    pub fn project(&mut self, p: &Poly, j: usize) -> Poly {
        let mut out = Poly::zero();
        for (m, c) in &p.terms {
            if m.power(PJ) == 1 {
                // the second-order potential's own P_j: orthogonal to every other P_j'
                assert_eq!(m.power(X), 0, "P_j times a function of x");
                out = out.add(&Poly::term(m.with(PJ, 0), c.clone()));
                continue;
            }
            let n = m.power(X);
            assert!(n >= 0, "negative power of cos θ");
            let w = self.moment(n, j);
            if !w.is_zero() {
                out = out.add(&Poly::term(m.with(X, 0), c * w));
            }
        }
        out
    }
}

/// (R + ζ)^q to second order, ζ = e·z (z first order without e).
fn surface_power(q: i32, z: &Poly) -> Poly {
    let u = z.mul(&rp(-1)).mul(&v(E));
    let qq = rat(q as i64);
    let second = cr(qq.clone() * (qq.clone() - rat(1)) / rat(2));
    rp(q).mul(&c(1).add(&u.scale(&qq)).add(&mul(&u, &u).mul(&second)))
}

/// First-order potential coefficient c_n of one mode, from the kinematic condition on P_n.
pub fn first_order_potential(md: ModeSyms, proj: &mut Projector) -> Poly {
    let (z, pn) = (v(md.a).mul(&legendre(md.n)), legendre(md.n));
    let n1 = md.n as i32 + 1;
    // ∂f/∂t − φ_r at r = R + e z, with φ = −R²Ṙ/r + e c r^{−(n+1)} P_n, order e
    let dfdt = v("Rd").add(&v(md.ad).mul(&pn).mul(&v(E)));
    let phi_r = v("Rd").mul(&rp(2)).mul(&surface_power(-2, &z)).sub(&v("cn").mul(&pn).mul(&surface_power(-(n1 + 1), &z)).scale(&rat(n1 as i64)).mul(&v(E)));
    let k1 = proj.project(&order(&trunc(dfdt.sub(&phi_r)), 1), md.n);
    solve_linear(&k1, "cn")
}

/// Solve p(u) = α u + β = 0 for u.
fn solve_linear(p: &Poly, u: &str) -> Poly {
    let alpha = p.diff(u);
    let beta = p.sub(&alpha.mul(&v(u)));
    let (m, c) = alpha.single().expect("the unknown's coefficient is a monomial");
    let inv = Poly::term(m.pow(-1), num_traits::Inv::inv(c.clone()));
    beta.mul(&inv).neg()
}

/// Substitute symbol `s` by `value`.
fn subst(p: &Poly, s: &str, value: &Poly) -> Poly {
    let mut out = Poly::zero();
    for (m, c) in &p.terms {
        let pw = m.power(s);
        let base = Poly::term(m.with(s, 0), c.clone());
        out = out.add(&if pw == 0 { base } else { base.mul(&value.powi(pw as u32)) });
    }
    out
}

/// The second-order parts on P_j of one pair (l, m): (F⁽²⁾_j with every unknown eliminated).
/// Also returns the first-order dynamic condition of mode l on P_l (for the sign check).
pub struct PairExpansion {
    /// (j, F⁽²⁾_j) for every j allowed by the selection rules.
    pub f2: Vec<(usize, Poly)>,
    pub f1_l: Poly,
    pub f0: Poly,
}

pub fn expand_pair(l: usize, m: usize, proj: &mut Projector) -> PairExpansion {
    let (ml, mm) = (mode(l, MODE_L), mode(m, MODE_M));
    let (pl, pm, pj) = (legendre(l), legendre(m), v(PJ));
    let (dpl, dpm) = (pl.diff(X), pm.diff(X));
    let e = v(E);
    let z = v(ml.a).mul(&pl).add(&v(mm.a).mul(&pm));
    let g = v(ml.a).mul(&dpl).add(&v(mm.a).mul(&dpm)).mul(&e);
    let dg = v(ml.a).mul(&dpl.diff(X)).add(&v(mm.a).mul(&dpm.diff(X))).mul(&e);
    let f = rp(1).add(&z.mul(&e));
    let s2 = c(1).sub(&v(X).powi(2));
    // first-order potential of each mode (solved), and its rate
    let cn = |md: ModeSyms, proj: &mut Projector| {
        let generic = first_order_potential(mode(md.n, ("a", "ad", "add")), proj);
        subst(&subst(&generic, "a", &v(md.a)), "ad", &v(md.ad))
    };
    let (cl, cm) = (cn(ml, proj), cn(mm, proj));
    let (l1, m1) = (l as i32 + 1, m as i32 + 1);
    // second-order potential d̃_j (R/r)^{j+1} P_j (d̃ its value at r = R; J stands for j until projected)
    let jp1 = v("J").add(&c(1));
    // φ pieces at the surface; H = Σ c_n r^{−(n+1)} P_n' (φ_θ = −sinθ·e·H)
    let phi1 = |cl: &Poly, cm: &Poly, shift: i32, weight: bool| {
        let wl = if weight { -(l1 as i64) } else { 1 };
        let wm = if weight { -(m1 as i64) } else { 1 };
        v("cl").mul(&pl).mul(&surface_power(-(l1 + shift), &z)).scale(&rat(wl)).add(&v("cm").mul(&pm).mul(&surface_power(-(m1 + shift), &z)).scale(&rat(wm)))
            .pipe(|p| subst(&subst(&p, "cl", cl), "cm", cm))
            .mul(&e)
    };
    let phi_r = v("Rd").mul(&rp(2)).mul(&surface_power(-2, &z)).add(&phi1(&cl, &cm, 1, true)).sub(&v("d").mul(&pj).mul(&jp1).mul(&rp(-1)).mul(&e).mul(&e));
    let h = v("cl").mul(&dpl).mul(&rp(-l1)).add(&v("cm").mul(&dpm).mul(&rp(-m1))).pipe(|p| subst(&subst(&p, "cl", &cl), "cm", &cm)).mul(&e);
    // kinematic: ∂f/∂t − φ_r + (1 − x²) H g / r²   (φ_θ f_θ = (−s e H)(−s g))
    let dfdt = v("Rd").add(&v(ml.ad).mul(&pl).add(&v(mm.ad).mul(&pm)).mul(&e));
    let kin = trunc(dfdt.sub(&phi_r).add(&mul(&mul(&h, &g), &s2).mul(&rp(-2))));
    // dynamic: ρ(φ_t + ½(φ_r² + (1 − x²)H²/r²)) + p_g(V) − γ(κ1 + κ2) − p∞
    let phi0_t = v("Rd").powi(2).mul(&rp(1)).scale(&rat(-2)).sub(&v("Rdd").mul(&rp(2))).mul(&surface_power(-1, &z));
    let cdl = rate(&cl);
    let cdm = rate(&cm);
    let phi_t = phi0_t.add(&phi1(&cdl, &cdm, 0, false)).add(&v("dd").add(&v("d").mul(&jp1).mul(&v("Rd")).mul(&rp(-1))).mul(&pj).mul(&e).mul(&e));
    let grad2 = mul(&phi_r, &phi_r).add(&mul(&mul(&h, &h), &s2).mul(&rp(-2)));
    let kinetic = trunc(phi_t.add(&grad2.scale(&crate::algebra::ratio(1, 2)))).mul(&v("rho"));
    // curvatures of r = f(θ), f_θ = −sinθ g, f_θθ = −x g + (1 − x²) g'
    let g2s = mul(&mul(&g, &g), &s2);
    let w_inv_half = surface_power(-1, &z).mul(&c(1).sub(&g2s.mul(&rp(-2)).scale(&crate::algebra::ratio(1, 2))));
    let w_inv_3half = surface_power(-3, &z).mul(&c(1).sub(&g2s.mul(&rp(-2)).scale(&crate::algebra::ratio(3, 2))));
    let f_tt = v(X).mul(&g).neg().add(&mul(&s2, &dg));
    let k1n = trunc(mul(&f, &f).add(&g2s.scale(&rat(2))).sub(&mul(&f, &f_tt)));
    let kappa1 = mul(&k1n, &trunc(w_inv_3half));
    let kappa2 = mul(&mul(&f.add(&mul(&v(X), &g)), &surface_power(-1, &z)), &trunc(w_inv_half));
    let laplace = kappa1.add(&kappa2).mul(&v("gamma"));
    // gas at the exact volume: V/V_R = proj_0[f³]/R³, p_g = pg (1 − κ (V/V_R − 1)) to second order
    let vol = proj.project(&trunc(mul(&mul(&f, &f), &f)), 0).mul(&rp(-3));
    let gas = v("pg").mul(&c(1).sub(&v("kappa").mul(&vol.sub(&c(1)))));
    let dynamic = trunc(kinetic.add(&gas).sub(&laplace).sub(&v("pinf")));
    let (kin2, dyn2) = (order(&kin, 2), order(&dynamic, 2));
    let mut f2 = Vec::new();
    for j in (l.abs_diff(m)..=l + m).step_by(2) {
        let at_j = |p: &Poly| subst(p, "J", &c(j as i64));
        let d = solve_linear(&at_j(&proj.project(&kin2, j)), "d");
        let fj = at_j(&proj.project(&dyn2, j));
        f2.push((j, subst(&subst(&fj, "dd", &rate(&d)), "d", &d)));
    }
    let f1_l = proj.project(&order(&dynamic, 1), l);
    let f0 = proj.project(&order(&dynamic, 0), 0);
    PairExpansion { f2, f1_l, f0 }
}


/// Which time derivative of a mode amplitude a product holds: a, ȧ or ä.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Amp2 {
    A,
    Ad,
    Add,
}

impl Amp2 {
    fn of(sym: &str) -> Option<(char, Amp2)> {
        Some(match sym {
            "al" => ('l', Amp2::A),
            "adl" => ('l', Amp2::Ad),
            "addl" => ('l', Amp2::Add),
            "am" => ('m', Amp2::A),
            "adm" => ('m', Amp2::Ad),
            "addm" => ('m', Amp2::Add),
            _ => return None,
        })
    }
    pub fn text(self) -> &'static str {
        match self {
            Amp2::A => "a",
            Amp2::Ad => "adot",
            Amp2::Add => "addot",
        }
    }
}

/// One quadratic term: Σ_{l,m} value(j, l, m) · prefactor · first_l · second_m on target j, with
/// value = s_j C(j, l, m) N(l, m, j) / D(l, m, j), C the coefficient of P_j in P_l P_m
/// (Adams), D = (l+1)(m+1)(j+1) or 1, s_0 = +1 (radial balance P), s_j = −1 for j ≥ 2 (G_n,j).
/// The first amplitude belongs to mode l, the second to mode m; for a symmetric term (same
/// derivative on both) value(j, l, m) = value(j, m, l) and the sum over ordered pairs counts
/// each product once per order.
#[derive(Clone, Debug)]
pub struct QuadTerm {
    pub first: Amp2,
    pub second: Amp2,
    /// Monomial in rho, gamma, R, Rd (Ṙ), Rdd (R̈), pg (the gas pressure at R), kappa.
    pub prefactor: Mono,
    pub denominator: bool,
    pub numerator: super::fit3::Poly3,
    /// Only on j = 0 (the radial balance): the gas pressure at the exact volume.
    pub radial_only: bool,
}

impl QuadTerm {
    pub fn name(&self) -> String {
        let pre = crate::emit::monomial_text(&rat(1), &self.prefactor);
        format!("{pre} * {}_l * {}_m", self.first.text(), self.second.text())
    }
    /// Exact value on target j (selection rules included).
    pub fn value(&self, t: &crate::algebra::triple::Triple, j: usize, l: usize, m: usize) -> Rat {
        let k = t.product_coefficient(l, m, j);
        if k.is_zero() || (self.radial_only && j != 0) {
            return Rat::zero();
        }
        let x = [l as i64, m as i64, j as i64];
        let mut v = k * self.numerator.eval(x);
        if self.denominator {
            v /= rat(((l + 1) * (m + 1) * (j + 1)) as i64);
        }
        if j == 0 { v } else { -v }
    }
}

/// The quadratic free-bubble table.
#[derive(Clone, Debug)]
pub struct QuadraticData {
    pub spec_path: String,
    pub terms: Vec<QuadTerm>,
    /// Modes of the fit and of the exact check beyond it.
    pub fit_modes: usize,
    pub check_modes: usize,
}

/// Even modes used to find the closed forms, and the largest mode of the check beyond them.
pub const FIT_MODES: usize = 8;
pub const CHECK_MODES: usize = 10;
/// Largest total degree tried for a numerator.
const MAX_DEGREE: u32 = 7;

type Key = (Mono, Amp2, Amp2);

/// Bilinear part of F⁽²⁾_j: (type, (first mode, second mode), value) with the symmetric halving.
fn bilinear(f2: &Poly, l: usize, m: usize) -> Result<Vec<(Key, (usize, usize), Rat)>, String> {
    let mut out = Vec::new();
    for (mono, c) in &f2.terms {
        let amps: Vec<(char, Amp2, &str)> = mono.0.iter().filter_map(|(s, p)| Amp2::of(s).map(|(w, a)| { let _ = p; (w, a, s.as_str()) })).collect();
        let (Some(kl), Some(km)) = (amps.iter().find(|a| a.0 == 'l'), amps.iter().find(|a| a.0 == 'm')) else { continue };
        if amps.len() != 2 || mono.power(kl.2) != 1 || mono.power(km.2) != 1 {
            continue;
        }
        let pre = mono.filter(|s| Amp2::of(s).is_none());
        if let Some((bad, _)) = pre.0.iter().find(|(s, _)| !["rho", "gamma", "R", "Rd", "Rdd", "pg", "kappa"].contains(&s.as_str())) {
            return Err(format!("quadratic load has an unexpected symbol `{bad}`"));
        }
        let (a, b) = (kl.1, km.1);
        if a == b {
            out.push(((pre.clone(), a, b), (l, m), c / rat(2)));
            if l != m {
                out.push(((pre, a, b), (m, l), c / rat(2)));
            }
        } else if a > b {
            out.push(((pre, a, b), (l, m), c.clone()));
        } else {
            out.push(((pre, b, a), (m, l), c.clone()));
        }
    }
    Ok(out)
}

/// Derive the quadratic table: exact expansions for every pair of even modes up to
/// `CHECK_MODES`, closed forms fitted on the modes up to `FIT_MODES` and verified exactly on the rest.
pub fn derive_quadratic(spec_path: &str) -> Result<QuadraticData, String> {
    let mut proj = Projector::default();
    let triple = crate::algebra::triple::Triple::new(2 * CHECK_MODES);
    let mut data: BTreeMap<Key, Vec<([i64; 3], Rat)>> = BTreeMap::new();
    let mut seen: Vec<(Key, [i64; 3])> = Vec::new();
    for l in (2..=CHECK_MODES).step_by(2) {
        for m in (l..=CHECK_MODES).step_by(2) {
            let x = expand_pair(l, m, &mut proj);
            for (j, f2) in &x.f2 {
                for (key, (p, q), v) in bilinear(f2, l, m)? {
                    let k = triple.product_coefficient(p, q, *j);
                    data.entry(key.clone()).or_default().push(([p as i64, q as i64, *j as i64], v / k));
                    seen.push((key, [p as i64, q as i64, *j as i64]));
                }
            }
        }
    }
    let mut terms = Vec::new();
    for (key, pts) in data {
        // every allowed triple of the range must be present for a term (missing = zero)
        let mut all = pts.clone();
        for l in (2..=CHECK_MODES).step_by(2) {
            for m in (2..=CHECK_MODES).step_by(2) {
                for j in (l.abs_diff(m)..=l + m).step_by(2) {
                    let x = [l as i64, m as i64, j as i64];
                    if !all.iter().any(|(y, _)| *y == x) {
                        all.push((x, Rat::zero()));
                    }
                }
            }
        }
        let fit_set: Vec<([i64; 3], Rat)> = all.iter().filter(|(x, _)| x[0] <= FIT_MODES as i64 && x[1] <= FIT_MODES as i64).cloned().collect();
        let mut found = None;
        for denominator in [false, true] {
            let scaled = |pts: &[([i64; 3], Rat)]| -> Vec<([i64; 3], Rat)> {
                pts.iter().map(|(x, v)| (*x, if denominator { v * rat((x[0] + 1) * (x[1] + 1) * (x[2] + 1)) } else { v.clone() })).collect()
            };
            if let Some(p) = super::fit3::fit_poly3(&scaled(&fit_set), MAX_DEGREE) {
                let checked = scaled(&all).iter().all(|(x, v)| &p.eval(*x) == v);
                if !checked {
                    return Err(format!("quadratic term {:?}: the closed form fitted on modes ≤ {FIT_MODES} fails on modes ≤ {CHECK_MODES}", key));
                }
                found = Some((denominator, p));
                break;
            }
        }
        // a term of the radial balance alone (the gas at the exact volume): data on j = 0, l = m
        let mut radial_only = false;
        if found.is_none() && all.iter().all(|(x, v)| x[2] == 0 || v.is_zero()) {
            radial_only = true;
            let pts: Vec<([i64; 3], Rat)> = all.iter().filter(|(x, _)| x[2] == 0).cloned().collect();
            let fit: Vec<([i64; 3], Rat)> = pts.iter().filter(|(x, _)| x[0] <= FIT_MODES as i64).cloned().collect();
            if let Some(p) = super::fit3::fit_poly3_in(&fit, MAX_DEGREE, [true, false, false]) {
                if !pts.iter().all(|(x, v)| &p.eval(*x) == v) {
                    return Err(format!("quadratic radial term {}: the closed form fails on modes ≤ {CHECK_MODES}", key.0.text()));
                }
                found = Some((false, p));
            }
        }
        let Some((denominator, numerator)) = found else {
            return Err(format!("quadratic term {} {:?} {:?}: no closed form N(l,m,j)/D of degree ≤ {MAX_DEGREE}", key.0.text(), key.1, key.2));
        };
        terms.push(QuadTerm { first: key.1, second: key.2, prefactor: key.0, denominator, numerator, radial_only });
    }
    let _ = seen;
    Ok(QuadraticData { spec_path: spec_path.to_string(), terms, fit_modes: FIT_MODES, check_modes: CHECK_MODES })
}

/// The pieces `quadratic.rs` may select, and the one value each the engine knows.
pub const PIECES: [(&str, &str); 3] = [("liquid", "inviscid"), ("interface", "surface_tension"), ("gas", "polytropic")];

/// Check the spec: exactly the pieces of [`PIECES`], each with its known value.
pub fn check_spec(spec: &crate::spec::Spec) -> Result<(), crate::CodegenError> {
    use crate::spec::ExprKind;
    for l in &spec.lets {
        let Some((_, want)) = PIECES.iter().find(|(n, _)| *n == l.name) else {
            let names: Vec<&str> = PIECES.iter().map(|(n, _)| *n).collect();
            return Err(crate::spec::parse::err(&spec.path, l.pos, format!("unknown piece `{}` (the quadratic engine knows {})", l.name, names.join(", "))));
        };
        match &l.value.kind {
            ExprKind::Name(v) if v == want => {}
            _ => return Err(crate::spec::parse::err(&spec.path, l.value.pos, format!("`{}`: the quadratic engine knows only `{want}`", l.name))),
        }
    }
    for (n, _) in PIECES {
        if spec.get(n).is_none() {
            return Err(crate::spec::parse::err(&spec.path, Default::default(), format!("missing piece `let {n} = …;`")));
        }
    }
    Ok(())
}

/// [`derive_quadratic`], computed once per process (it depends on no input but the pieces).
pub fn derive_cached(spec_path: &str) -> Result<QuadraticData, String> {
    static CACHE: std::sync::OnceLock<Result<QuadraticData, String>> = std::sync::OnceLock::new();
    let mut d = CACHE.get_or_init(|| derive_quadratic("")).clone()?;
    d.spec_path = spec_path.to_string();
    Ok(d)
}

trait Pipe: Sized {
    fn pipe<T>(self, f: impl FnOnce(Self) -> T) -> T {
        f(self)
    }
}
impl Pipe for Poly {}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::algebra::triple::Triple;

    #[test]
    fn linear_parts_are_the_runtime_equations() {
        let mut proj = Projector::default();
        for l in [2usize, 4] {
            let x = expand_pair(l, l + 2, &mut proj);
            let n = l as i64;
            // −(ρR/(n+1))[ä + 3Ṙȧ/R − (n−1)R̈a/R] − (n−1)(n+2)γ a/R²
            let expect = v("addl").add(&v("Rd").mul(&v("adl")).mul(&rp(-1)).scale(&rat(3))).sub(&v("Rdd").mul(&v("al")).mul(&rp(-1)).scale(&rat(n - 1)));
            let expect = expect.mul(&v("rho")).mul(&rp(1)).scale(&crate::algebra::ratio(-1, n + 1)).sub(&v("gamma").mul(&v("al")).mul(&rp(-2)).scale(&rat((n - 1) * (n + 2))));
            assert_eq!(x.f1_l, expect, "l = {l}");
            let rp0 = v("rho").mul(&rp(1).mul(&v("Rdd")).add(&v("Rd").powi(2).scale(&crate::algebra::ratio(3, 2)))).neg();
            let expect0 = rp0.add(&v("pg")).sub(&v("gamma").mul(&rp(-1)).scale(&rat(2))).sub(&v("pinf"));
            assert_eq!(x.f0, expect0);
        }
    }

    #[test]
    fn table_terms_and_the_gas_row() {
        let q = derive_quadratic("x").unwrap();
        assert_eq!(q.terms.len(), 7, "{:?}", q.terms.iter().map(|t| t.name()).collect::<Vec<_>>());
        let radial: Vec<String> = q.terms.iter().filter(|t| t.radial_only).map(|t| t.name()).collect();
        assert_eq!(radial, vec!["kappa*pg/R^2 * a_l * a_m".to_string()]);
        // the gas at the exact volume: p_g(R)(V_R/V)^κ ≈ p_g(1 − 3κ Σ a_n²/((2n+1)R²)) on P_0
        let t = Triple::new(20);
        let gas = q.terms.iter().find(|t| t.radial_only).unwrap();
        for n in [2usize, 4, 16] {
            assert_eq!(gas.value(&t, 0, n, n), rat(-3) / rat(2 * n as i64 + 1));
        }
    }
}
