//! Second-order (bilinear) membrane loads of a shell law (issue 12, scope 1: the membrane),
//! derived from the same specs as the linear tables: `kinematics.rs` (the exact stretches, normal
//! and curvatures of r = R + Σ a_n P_n(cos Θ), θ = Θ + Σ b_n P¹_n/R), and the law: a W through
//! `hyperelastic.rs` (σ_i = λ_i ∂W/∂λ_i) and `membrane.rs` (F_n, F_t in both forms), stresses
//! σ1, σ2 (a viscous law, by `rate`: terms then hold ȧ, ḃ or Ṙ) through `membrane.rs`, or a shape
//! energy w_area (bending, by `vary`) through `shape.rs` — expanded to the bilinear order for
//! pairs of modes (l, m) by [`super::jet2`] and
//! projected exactly on P_j (normal, weight (2j+1)/2) and P¹_j (tangential, weight
//! (2j+1)/(2j(j+1))) at the material angle, as the linear loads S1, S2, S11, S12 are.
//!
//! The bilinear part of a load on target j is Σ_T Σ_{l,m} value_T(j, l, m) · prefactor_T ·
//! first_T(l) · second_T(m), first/second ∈ {a, b}, prefactor_T a monomial in R, R0 and the law's
//! symbols, and
//!
//!   value_T(j, l, m) = C(j, l, m) N_T(L_l, L_m, L_j) / D,
//!
//! C the coefficient of P_j in P_l P_m (Adams), L_n = n(n+1), N_T a polynomial, D = 1 (normal)
//! or L_j (tangential). That form is what the geometry predicts (an isotropic law on a surface
//! displaced by a_n P_n n̂ and moved along the meridian by b_n ∇P_n: every bilinear invariant
//! reduces to L's times ∫P_l P_m P_j); the build finds N_T from the exact values of the modes
//! ≤ FIT_MODES and checks it exactly on modes ≤ CHECK_MODES, and fails otherwise.

use super::fit3::{fit_poly3, Poly3};
use super::jet2::{self, Env2};
use super::project::{project, Load};
use crate::algebra::legendre::Basis;
use crate::algebra::triple::Triple;
use crate::algebra::{rat, Mono, Poly, Rat};
use crate::spec::ast::Spec;
use num_traits::Zero;
use std::collections::BTreeMap;

pub const FIT_MODES: usize = 8;
pub const CHECK_MODES: usize = 10;
/// Largest total degree of N_T in (L_l, L_m, L_j).
const MAX_DEGREE: u32 = 5;

/// Which amplitude: a (normal) or b (tangential), or their rates ȧ, ḃ (a viscous law).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Ab {
    A,
    B,
    Ad,
    Bd,
}

impl Ab {
    pub fn text(self) -> &'static str {
        match self {
            Ab::A => "a",
            Ab::B => "b",
            Ab::Ad => "ad",
            Ab::Bd => "bd",
        }
    }
    /// The kind of an amplitude symbol of [`jet2::L_SYMS`] / [`jet2::M_SYMS`].
    fn of(symbol: &str) -> Ab {
        match symbol {
            "al" | "am" => Ab::A,
            "bl" | "bm" => Ab::B,
            "adl" | "adm" => Ab::Ad,
            _ => Ab::Bd,
        }
    }
}

/// The mechanics specs a law's loads go through: `hyperelastic.rs` and `membrane.rs` for a
/// strain energy W, `membrane.rs` for stresses σ1, σ2 (a viscous law, by `rate`), `shape.rs`
/// for a shape energy w_area (bending, by `vary`).
#[derive(Clone, Copy, Debug)]
pub struct Mechanics<'a> {
    pub hyper: &'a Spec,
    pub membrane: &'a Spec,
    pub shape: &'a Spec,
}

/// One bilinear load term of one form (`paper` / `tension`) and load (normal / tangential).
#[derive(Clone, Debug)]
pub struct MembraneTerm2 {
    pub form: &'static str,
    pub load: Load,
    pub first: Ab,
    pub second: Ab,
    /// Monomial in R, R0 and the law's symbols.
    pub prefactor: Mono,
    /// N_T in (L_l, L_m, L_j) (the Poly3 variables l, m, j stand for L_l, L_m, L_j).
    pub numerator: Poly3,
}

impl MembraneTerm2 {
    pub fn name(&self) -> String {
        format!("{} * {}_l * {}_m", crate::emit::monomial_text(&rat(1), &self.prefactor), self.first.text(), self.second.text())
    }
    /// Exact value on target j (0 outside the selection rules; tangential loads have no j = 0).
    pub fn value(&self, t: &Triple, j: usize, l: usize, m: usize) -> Rat {
        let c = t.product_coefficient(l, m, j);
        if c.is_zero() || (self.load == Load::Tangential && j == 0) {
            return Rat::zero();
        }
        let big = |n: usize| (n * (n + 1)) as i64;
        let v = c * self.numerator.eval([big(l), big(m), big(j)]);
        match self.load {
            Load::Normal => v,
            Load::Tangential => v / rat(big(j)),
        }
    }
}

/// The second-order tables of one law.
#[derive(Clone, Debug)]
pub struct MembraneQuadratic {
    pub law: String,
    pub spec_path: String,
    pub symbols: Vec<String>,
    pub terms: Vec<MembraneTerm2>,
}

type Key = (&'static str, Load, Mono, Ab, Ab);

/// The projected bilinear loads of one pair (l ≤ m): (form, load, projected (rest mono → series)).
pub fn pair_loads(law: &Spec, specs: Mechanics<'_>, kin: &Spec, l: usize, m: usize) -> Result<Vec<(&'static str, Load, Poly)>, String> {
    let mut env = Env2::kinematic(l, m);
    jet2::eval_spec(kin, &mut env)?;
    if law.get("W").is_some() {
        let mut st = Env2::symbolic_stretches();
        jet2::eval_spec(law, &mut st)?;
        jet2::eval_spec(specs.hyper, &mut st)?;
        let (s1, s2) = (st.scalar("sigma1")?, st.scalar("sigma2")?);
        let (l1, l2) = (env.scalar("lambda1")?, env.scalar("lambda2")?);
        env.values.insert("sigma1".into(), jet2::V::S(jet2::substitute_stretches(&s1, &l1, &l2)?));
        env.values.insert("sigma2".into(), jet2::V::S(jet2::substitute_stretches(&s2, &l1, &l2)?));
        jet2::eval_spec(specs.membrane, &mut env)?;
    } else {
        // stresses (by `rate`) or a shape energy (by `vary`): the law on the kinematics
        jet2::eval_spec(law, &mut env)?;
        jet2::eval_spec(if law.get("w_area").is_some() { specs.shape } else { specs.membrane }, &mut env)?;
    }
    let mut out = Vec::new();
    for form in ["paper", "tension"] {
        for (load, suffix) in [(Load::Normal, "n"), (Load::Tangential, "t")] {
            out.push((form, load, jet2::part(&env.scalar(&format!("{form}_{suffix}"))?, 1, 1)));
        }
    }
    Ok(out)
}

/// Bilinear data points of one pair: (key, (first mode, second mode), j, value).
fn bilinear(form: &'static str, load: Load, p: &Poly, l: usize, m: usize, basis: &mut Basis) -> Result<Vec<(Key, usize, usize, usize, Rat)>, String> {
    let mut out = Vec::new();
    for ((_, mono), series) in project(p, load, 0, basis)? {
        let fl = jet2::L_SYMS.iter().find(|s| mono.power(s) == 1).ok_or("bilinear term without a mode-l amplitude")?;
        let fm = jet2::M_SYMS.iter().find(|s| mono.power(s) == 1).ok_or("bilinear term without a mode-m amplitude")?;
        let pre = mono.filter(|s| !jet2::L_SYMS.contains(&s) && !jet2::M_SYMS.contains(&s));
        let (a, b) = (Ab::of(fl), Ab::of(fm));
        for (j, c) in series.iter().enumerate() {
            if c.is_zero() {
                continue;
            }
            if a == b {
                out.push(((form, load, pre.clone(), a, b), l, m, j, c / rat(2)));
                if l != m {
                    out.push(((form, load, pre.clone(), a, b), m, l, j, c / rat(2)));
                }
            } else if a < b {
                out.push(((form, load, pre.clone(), a, b), l, m, j, c.clone()));
            } else {
                out.push(((form, load, pre.clone(), b, a), m, l, j, c.clone()));
            }
        }
    }
    Ok(out)
}

/// Derive the second-order tables of a law (exact expansions for every pair of even modes up to
/// CHECK_MODES; closed forms fitted on modes ≤ FIT_MODES, verified exactly on the rest).
pub fn derive_membrane_quadratic(name: &str, law: &Spec, specs: Mechanics<'_>, kin: &Spec) -> Result<MembraneQuadratic, String> {
    let triple = Triple::new(2 * CHECK_MODES + 2);
    let mut basis = Basis::default();
    let mut data: BTreeMap<Key, BTreeMap<[i64; 3], Rat>> = BTreeMap::new();
    // the exact expansions of the pairs are independent: spread them over the cores
    let pairs: Vec<(usize, usize)> = (2..=CHECK_MODES).step_by(2).flat_map(|l| (l..=CHECK_MODES).step_by(2).map(move |m| (l, m))).collect();
    let workers = std::thread::available_parallelism().map_or(1, |n| n.get()).min(pairs.len()).max(1);
    let list = &pairs;
    let expanded: Vec<Result<Vec<(&'static str, Load, Poly)>, String>> = std::thread::scope(|sc| {
        let handles: Vec<_> = (0..workers)
            .map(|w| sc.spawn(move || list.iter().enumerate().filter(|(i, _)| i % workers == w).map(|(i, &(l, m))| (i, pair_loads(law, specs, kin, l, m))).collect::<Vec<_>>()))
            .collect();
        let mut all: Vec<(usize, Result<Vec<(&'static str, Load, Poly)>, String>)> =
            handles.into_iter().flat_map(|h| h.join().unwrap_or_else(|_| vec![(usize::MAX, Err("a derivation thread panicked".into()))])).collect();
        all.sort_by_key(|(i, _)| *i);
        all.into_iter().map(|(_, r)| r).collect()
    });
    for (&(l, m), loads) in pairs.iter().zip(expanded) {
        {
            for (form, load, p) in loads? {
                for (key, p_, q_, j, v) in bilinear(form, load, &p, l, m, &mut basis)? {
                    if !crate::algebra::triple::allowed(p_, q_, j) {
                        return Err(format!("{name} {form}: the pair ({p_}, {q_}) loads mode {j}, outside the selection rules"));
                    }
                    let k = triple.product_coefficient(p_, q_, j);
                    let x = [p_ as i64, q_ as i64, j as i64];
                    let y = if load == Load::Tangential { v * rat((j * (j + 1)) as i64) } else { v } / k;
                    if let Some(old) = data.entry(key).or_default().insert(x, y.clone()) {
                        if old != y {
                            return Err(format!("{name}: two values for one coefficient at {x:?}"));
                        }
                    }
                }
            }
        }
    }
    let big = |n: i64| n * (n + 1);
    let mut terms = Vec::new();
    for (key, pts) in data {
        let mut all: Vec<([i64; 3], Rat)> = Vec::new();
        for l in (2..=CHECK_MODES).step_by(2) {
            for m in (2..=CHECK_MODES).step_by(2) {
                for j in (l.abs_diff(m)..=l + m).step_by(2) {
                    if key.1 == Load::Tangential && j == 0 {
                        continue;
                    }
                    let x = [l as i64, m as i64, j as i64];
                    all.push(([big(x[0]), big(x[1]), big(x[2])], pts.get(&x).cloned().unwrap_or_else(Rat::zero)));
                }
            }
        }
        let fit_limit = big(FIT_MODES as i64);
        let fit: Vec<([i64; 3], Rat)> = all.iter().filter(|(x, _)| x[0] <= fit_limit && x[1] <= fit_limit).cloned().collect();
        let p = fit_poly3(&fit, MAX_DEGREE)
            .ok_or_else(|| format!("{name} {} {:?} `{}` {:?}{:?}: no closed form C·N(L_l, L_m, L_j)/D of degree ≤ {MAX_DEGREE}", key.0, key.1, key.2.text(), key.3, key.4))?;
        if !all.iter().all(|(x, v)| &p.eval(*x) == v) {
            return Err(format!("{name} {} {:?} `{}`: the closed form fitted on modes ≤ {FIT_MODES} fails on modes ≤ {CHECK_MODES}", key.0, key.1, key.2.text()));
        }
        if !p.terms.is_empty() {
            terms.push(MembraneTerm2 { form: key.0, load: key.1, first: key.3, second: key.4, prefactor: key.2, numerator: p });
        }
    }
    let symbols = match law.get("symbols").map(|l| &l.value.kind) {
        Some(crate::spec::ast::ExprKind::List(items)) => items.iter().filter_map(|i| if let crate::spec::ast::ExprKind::Name(n) = &i.kind { Some(n.clone()) } else { None }).collect(),
        _ => Vec::new(),
    };
    Ok(MembraneQuadratic { law: name.to_string(), spec_path: law.path.clone(), symbols, terms })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(file: &str) -> Spec {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../derivations");
        let text = std::fs::read_to_string(root.join(file)).unwrap();
        crate::spec::parse::parse_spec(&format!("derivations/{file}"), &text).unwrap()
    }

    /// A surface tension as a law (W = γλ1λ2, loads γ(κ1 + κ2)) with b = 0 is the free bubble's
    /// interface: its normal a_l a_m load must be the free-bubble table's γ term (derived
    /// independently, in Eulerian form, by derive/quadratic.rs), on every target.
    #[test]
    fn surface_tension_law_matches_the_free_bubble_laplace_term() {
        let (hyper, membrane, shape) = (spec("hyperelastic.rs"), spec("membrane.rs"), spec("shape.rs"));
        let q = derive_membrane_quadratic("surface_tension", &spec("shell/surface_tension.rs"), Mechanics { hyper: &hyper, membrane: &membrane, shape: &shape }, &spec("kinematics.rs")).unwrap();
        let free = crate::derive::quadratic::derive_cached("x").unwrap();
        let gamma_free = free.terms.iter().find(|t| t.name() == "gamma/R^3 * a_l * a_m").expect("the free bubble's Laplace term");
        let aa: Vec<&MembraneTerm2> = q.terms.iter().filter(|t| t.load == Load::Normal && t.form == "paper" && t.first == Ab::A && t.second == Ab::A).collect();
        assert_eq!(aa.len(), 1, "one prefactor (gamma/R^3): {:?}", aa.iter().map(|t| t.name()).collect::<Vec<_>>());
        assert_eq!(aa[0].name(), "gamma/R^3 * a_l * a_m");
        let t = Triple::new(40);
        for l in (2..=16).step_by(2) {
            for m in (2..=16).step_by(2) {
                for j in (0..=l + m).step_by(2) {
                    // the free table adds Q_0 to P and Q_j to G_n,j; the membrane load enters P with −
                    let s = if j == 0 { rat(-1) } else { rat(1) };
                    assert_eq!(gamma_free.value(&t, j, l, m), s * aa[0].value(&t, j, l, m), "(j, l, m) = ({j}, {l}, {m})");
                }
            }
        }
        // the surface tension has no tangential load in the tension form, at second order too
        assert!(q.terms.iter().all(|t| !(t.form == "tension" && t.load == Load::Tangential)));
    }
}
