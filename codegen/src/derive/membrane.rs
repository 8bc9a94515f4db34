//! Shell loads S0, S1, S2, S^1_1, S^1_2 (eq 2.29; FORMULATION §2) of every shell law
//! (`derivations/shell/NAME.rs`): derived exactly for concrete k with R, R0 and the law's symbols
//! symbolic, fitted as polynomials in n = k(k+1) on the first modes and verified on the others.
//! A viscous law adds the rate coefficients S1d, S2d, S^1_1d, S^1_2d (of ȧ_k, ḃ_k) and Ṙ (`Rd`)
//! in its monomials.

use super::eval::Env;
use super::fit::fit_poly;
use super::project::{project, Amp, Load};
use crate::algebra::legendre::Basis;
use crate::algebra::{rat, Mono, Rat};
use crate::error::CodegenError;
use crate::spec::Spec;
use num_traits::Zero;
use std::collections::BTreeMap;

/// Modes used for the fit and the verification of the membrane coefficients.
pub const MEMBRANE_MODES: std::ops::RangeInclusive<usize> = 2..=10;

/// One coefficient: Σ_mono (polynomial in n) · mono.
#[derive(Clone, Debug, PartialEq)]
pub struct MembraneCoeff {
    pub name: &'static str,
    /// Does it depend on k (through n)?
    pub uses_k: bool,
    /// (monomial in R, R0, C1, C2, …; ascending coefficients of the polynomial in n).
    pub terms: Vec<(Mono, Vec<Rat>)>,
}

#[derive(Clone, Debug)]
pub struct MembraneData {
    /// "paper" (divergence of the Cauchy stress) or "tension" (divergence of εσ/α).
    pub variant: &'static str,
    pub coeffs: Vec<MembraneCoeff>,
}

#[derive(Clone, Debug)]
pub struct Membrane {
    /// The law's name (its file stem, e.g. `skalak`).
    pub law: String,
    /// The law's spec, then the mechanics specs it was evaluated with.
    pub spec_path: String,
    pub mechanics: Vec<String>,
    /// Declared constitutive symbols (C1, C2, …), in order.
    pub symbols: Vec<String>,
    pub variants: Vec<MembraneData>,
}

fn structure(spec: &Spec, m: String) -> CodegenError {
    CodegenError::Structure { spec: spec.path.clone(), message: m }
}

/// Exact S-coefficients of one variant for one concrete k: name → mono → value.
pub fn membrane_at_k(spec: &Spec, env: &Env, variant: &str, k: usize) -> Result<BTreeMap<&'static str, BTreeMap<Mono, Rat>>, CodegenError> {
    let n = env.scalar(spec, &format!("{variant}_n"))?;
    let t = env.scalar(spec, &format!("{variant}_t"))?;
    let mut basis = Basis::default();
    let mut out: BTreeMap<&'static str, BTreeMap<Mono, Rat>> = BTreeMap::new();
    let e = |m: String| structure(spec, format!("{variant}, mode {k}: {m}"));
    let zn = project(&n.z, Load::Normal, 0, &mut basis).map_err(e)?;
    for ((_, mono), s) in zn {
        if s.iter().skip(1).any(|v| !v.is_zero()) {
            return Err(structure(spec, format!("{variant}: zero-order normal load is not uniform")));
        }
        out.entry("s0").or_default().insert(mono, s[0].clone());
    }
    for (load, d, names) in [(Load::Normal, &n, ["s1", "s2", "s1d", "s2d"]), (Load::Tangential, &t, ["s11", "s12", "s11d", "s12d"])] {
        for ((amp, mono), s) in project(&d.e, load, k, &mut basis).map_err(e)? {
            if s.iter().enumerate().any(|(j, v)| j != k && !v.is_zero()) {
                return Err(structure(spec, format!("{variant}: mode {k} couples to another mode")));
            }
            let name = match amp {
                Some(Amp::A) => names[0],
                Some(Amp::B) => names[1],
                Some(Amp::Ad) => names[2],
                Some(Amp::Bd) => names[3],
                None => return Err(structure(spec, format!("{variant}: a first-order load without an amplitude"))),
            };
            let v = s.get(k).cloned().unwrap_or_else(Rat::zero);
            out.entry(name).or_default().insert(mono, v);
        }
    }
    Ok(out)
}

/// Names of the coefficients: always the five of eq 2.29, then the rate ones a viscous law has.
pub const NAMES: [&str; 9] = ["s0", "s1", "s2", "s11", "s12", "s1d", "s2d", "s11d", "s12d"];

/// Derive both variants of one law. `env` is the law evaluated on the kinematics and then on its
/// mechanics specs; `mech` is the spec that defines the loads (`membrane.rs` or `shape.rs`).
pub fn derive_membrane(law: &str, law_spec: &Spec, mechanics: &[&Spec], env: &Env) -> Result<Membrane, CodegenError> {
    let spec = mechanics.last().copied().unwrap_or(law_spec);
    let symbols = env.names("symbols");
    let mut variants = Vec::new();
    for variant in ["paper", "tension"] {
        let per_k: Vec<(usize, BTreeMap<&'static str, BTreeMap<Mono, Rat>>)> =
            MEMBRANE_MODES.map(|k| membrane_at_k(spec, &env, variant, k).map(|v| (k, v))).collect::<Result<_, _>>()?;
        let mut coeffs = Vec::new();
        for name in NAMES {
            let mut monos: Vec<Mono> = per_k.iter().flat_map(|(_, m)| m.get(name).into_iter().flat_map(|x| x.keys().cloned())).collect();
            monos.sort();
            monos.dedup();
            let mut terms = Vec::new();
            for mono in monos {
                let xs: Vec<Rat> = per_k.iter().map(|(k, _)| rat((k * (k + 1)) as i64)).collect();
                let ys: Vec<Rat> = per_k.iter().map(|(_, m)| m.get(name).and_then(|x| x.get(&mono)).cloned().unwrap_or_else(Rat::zero)).collect();
                let p = fit_poly(&xs, &ys, 4).ok_or_else(|| {
                    structure(spec, format!("{variant} {name}: the coefficient of {} is not a polynomial in n = k(k+1)", mono.text()))
                })?;
                if p.iter().any(|c| !c.is_zero()) {
                    if let Some((bad, _)) = mono.0.iter().find(|(s, _)| !["R", "R0", crate::algebra::dual::RATE_R].contains(&s.as_str()) && !symbols.contains(s)) {
                        return Err(structure(law_spec, format!("{variant} {name}: `{bad}` is neither R, R0, Rd nor one of the law's `symbols`")));
                    }
                    terms.push((mono, p));
                }
            }
            coeffs.push(MembraneCoeff { name, uses_k: name != "s0", terms });
        }
        variants.push(MembraneData { variant, coeffs });
    }
    // the rate coefficients only when the law has them
    let has = |name: &str| variants.iter().any(|v| v.coeffs.iter().any(|c| c.name == name && !c.terms.is_empty()));
    let keep: Vec<&str> = NAMES.iter().copied().enumerate().filter(|(i, n)| *i < 5 || has(n)).map(|(_, n)| n).collect();
    for v in &mut variants {
        v.coeffs.retain(|c| keep.contains(&c.name));
    }
    Ok(Membrane {
        law: law.to_string(),
        spec_path: law_spec.path.clone(),
        mechanics: mechanics.iter().map(|s| s.path.clone()).collect(),
        symbols,
        variants,
    })
}
