//! Magnetic loads from a field spec (eqs 2.30–2.40, FORMULATION §0).
//!
//! The engine, not the spec, computes the ponderomotive force F = μ0χ_s (∇h)·h in spherical
//! components (eq 2.33), evaluates it at the deformed point (r, θ) of eq 2.14, rotates it onto
//! the deformed normal and tangent (eq 2.39, from the kinematics spec's exact n̂, t̂), multiplies
//! by the area factor 1/(λ1λ2) once (with its b terms), linearizes in a_k, b_k and projects.

use super::eval::{self, Env, Value};
use super::fit::{fit_rational, ClosedForm};
use super::project::{project, Amp, Load};
use crate::algebra::legendre::Basis;
use crate::algebra::{Dual, Mono, Poly, Rat};
use crate::error::CodegenError;
use crate::spec::Spec;
use num_traits::Zero;
use std::collections::{BTreeMap, BTreeSet};

/// Largest |source − target| the engine looks for (a wider coupling is an error).
pub const MAX_BAND: usize = 12;

/// One coupling of a component: load on target mode j from amplitude of mode j + offset.
#[derive(Clone, Debug)]
pub struct CouplingData {
    pub name: String,
    pub load: Load,
    pub amp: Amp,
    pub offset: i32,
    /// index = target k = 0..=KMAX; None where the coupling does not exist.
    pub values: Vec<Option<Rat>>,
    pub closed: Option<ClosedForm>,
}

/// One product of field amplitudes.
#[derive(Clone, Debug)]
pub struct ComponentData {
    /// Product of field amplitudes, e.g. H2^2.
    pub amplitudes: Mono,
    /// ℋ = coeff · mono (includes R0²/R² of the area factor).
    pub prefactor: (Rat, Mono),
    pub r_power: i32,
    pub zero_normal: Vec<(usize, Rat)>,
    pub zero_tangential: Vec<(usize, Rat)>,
    pub couplings: Vec<CouplingData>,
}

#[derive(Clone, Debug)]
pub struct FieldData {
    pub name: String,
    pub spec_path: String,
    pub components: Vec<ComponentData>,
}

/// F = χ (∇h)·h in spherical components, eq (2.33):
/// F_r = h_r ∂_r h_r + (h_θ/r) ∂_θ h_r − h_θ²/r, F_θ = h_r ∂_r h_θ + (h_θ/r) ∂_θ h_θ + h_r h_θ/r.
pub fn force(h_r: &Poly, h_t: &Poly, chi: &Poly) -> (Poly, Poly) {
    let inv_r = Poly::term(Mono::var("#r", -1), crate::algebra::rat(1));
    let d_theta = |p: &Poly| p.diff("#ct").mul(&Poly::var("#st").neg()).add(&p.diff("#st").mul(&Poly::var("#ct")));
    let f_r = h_r.mul(&h_r.diff("#r")).add(&h_t.mul(&inv_r).mul(&d_theta(h_r))).sub(&h_t.mul(h_t).mul(&inv_r));
    let f_t = h_r.mul(&h_t.diff("#r")).add(&h_t.mul(&inv_r).mul(&d_theta(h_t))).add(&h_r.mul(h_t).mul(&inv_r));
    (f_r.mul(chi), f_t.mul(chi))
}

fn structure(spec: &Spec, message: String) -> CodegenError {
    CodegenError::Structure { spec: spec.path.clone(), message }
}

/// Derive the table of one field spec for targets k = 0..=kmax.
pub fn derive_field(name: &str, kin_spec: &Spec, kin: &Env, spec: &Spec, kmax: usize) -> Result<FieldData, CodegenError> {
    let env = eval::eval_spec(spec, eval::field_env())?;
    let h_r = env.scalar(spec, "h_r")?.z;
    let h_t = env.scalar(spec, "h_theta")?.z;
    let chi = env.scalar(spec, "susceptibility")?.z;
    let unit_pos = spec.get("unit").map(|l| l.pos).unwrap_or_default();
    let unit = match env.scalar(spec, "unit")?.z.single() {
        Some((m, c)) if m.is_one() => c.clone(),
        _ => return Err(crate::spec::parse::err(&spec.path, unit_pos, "expected a non-zero number for `unit`")),
    };
    let amplitudes = env.names("amplitudes");
    let (f_r, f_t) = force(&h_r, &h_t, &chi);

    // components: one per product of field amplitudes
    let key = |m: &Mono| m.filter(|s| amplitudes.iter().any(|a| a == s));
    let mut comps: BTreeMap<Mono, (Poly, Poly)> = BTreeMap::new();
    for (which, f) in [(0, &f_r), (1, &f_t)] {
        for (m, c) in &f.terms {
            let e = comps.entry(key(m)).or_default();
            let t = Poly::term(m.clone(), c.clone());
            if which == 0 {
                e.0 = e.0.add(&t);
            } else {
                e.1 = e.1.add(&t);
            }
        }
    }

    // the deformed point (eq 2.14) and the frame (eq 2.21) from the kinematics spec
    let theta = kin.values.get("theta").cloned().ok_or_else(|| structure(kin_spec, "no `theta`".into()))?;
    let at = |f: &str| eval_trig(kin_spec, f, &theta);
    let point = BTreeMap::from([
        ("#r".to_string(), kin.scalar(kin_spec, "r")?),
        ("#ct".to_string(), at("cos")?),
        ("#st".to_string(), at("sin")?),
    ]);
    let [n_r, n_t, t_r, t_t, area] = ["n_r", "n_theta", "t_r", "t_theta", "area"].map(|n| kin.scalar(kin_spec, n));
    let (n_r, n_t, t_r, t_t, area) = (n_r?, n_t?, t_r?, t_t?, area?);

    let mut components = Vec::new();
    for (amp_mono, (fr, ft)) in comps {
        let powers: BTreeSet<i32> = fr.terms.keys().chain(ft.terms.keys()).map(|m| m.power("#r")).collect();
        if powers.len() != 1 {
            return Err(structure(spec, format!("force component {} is not homogeneous in r (powers {powers:?})", amp_mono.text())));
        }
        let m_pow = *powers.iter().next().unwrap_or(&0);
        let sub = |p: &Poly| Dual::zero_order(p.clone()).subst(&point).map_err(|m| structure(spec, m));
        let (fr, ft) = (sub(&fr)?, sub(&ft)?);
        // eq (2.39): loads on the deformed normal and tangent, area factor applied once
        let normal = area.mul(&fr.mul(&n_r).add(&ft.mul(&n_t)));
        let tangential = area.mul(&fr.mul(&t_r).add(&ft.mul(&t_t)));
        components.push(component(spec, amp_mono, m_pow, &unit, &normal, &tangential, kmax)?);
    }
    Ok(FieldData { name: name.to_string(), spec_path: spec.path.clone(), components })
}

fn eval_trig(kin_spec: &Spec, f: &str, theta: &Value) -> Result<Dual, CodegenError> {
    let e = crate::spec::Expr {
        kind: crate::spec::ExprKind::Call(
            f.to_string(),
            vec![crate::spec::Expr { kind: crate::spec::ExprKind::Name("theta".into()), pos: Default::default() }],
        ),
        pos: Default::default(),
    };
    let mut env = Env::default();
    env.bind("theta", theta.clone());
    match eval::eval(kin_spec, &env, &e)? {
        Value::Scalar(d) => Ok(d),
        _ => Err(structure(kin_spec, "`theta` must be an angle".into())),
    }
}

fn component(
    spec: &Spec,
    amp_mono: Mono,
    m_pow: i32,
    unit: &Rat,
    normal: &Dual,
    tangential: &Dual,
    kmax: usize,
) -> Result<ComponentData, CodegenError> {
    let err = |m: String| structure(spec, format!("component {}: {m}", amp_mono.text()));
    let mut basis = Basis::default();
    let zn = project(&normal.z, Load::Normal, 0, &mut basis).map_err(err)?;
    let zt = project(&tangential.z, Load::Tangential, 0, &mut basis).map_err(err)?;
    // the prefactor's symbols: those of the zero-order loads divided by R^m
    let mut mono: Option<Mono> = None;
    for ((_, m), _) in zn.iter().chain(zt.iter()) {
        let h = m.mul(&Mono::var("R", -m_pow));
        if mono.as_ref().is_some_and(|x| x != &h) {
            return Err(err(format!("zero-order loads are not proportional to one monomial ({} vs {})", h.text(), mono.unwrap().text())));
        }
        mono = Some(h);
    }
    // first order, per source mode
    let mut raw: BTreeMap<(Load, Amp, i32), BTreeMap<usize, Rat>> = BTreeMap::new();
    for k in 2..=kmax + MAX_BAND {
        for (load, d) in [(Load::Normal, normal), (Load::Tangential, tangential)] {
            let proj = project(&d.e, load, k, &mut basis).map_err(|m| err(format!("mode {k}: {m}")))?;
            for ((amp, m), series) in proj {
                let Some(amp) = amp else { return Err(err("first-order load without amplitude".into())) };
                let h = m.mul(&Mono::var("R", -(m_pow - 1)));
                if mono.as_ref().is_some_and(|x| x != &h) {
                    return Err(err(format!("first-order load {} is not proportional to the prefactor", m.text())));
                }
                mono = Some(h);
                for (j, v) in series.iter().enumerate() {
                    if v.is_zero() {
                        continue;
                    }
                    let offset = k as i64 - j as i64;
                    if offset.unsigned_abs() as usize > MAX_BAND {
                        return Err(err(format!("mode {k} couples to mode {j}: wider than the supported band {MAX_BAND}")));
                    }
                    if j <= kmax {
                        raw.entry((load, amp, offset as i32)).or_default().insert(j, v / unit);
                    }
                }
            }
        }
        basis.forget(k);
    }
    let Some(mono) = mono else { return Err(err("all loads vanish".into())) };
    let zero = |p: &super::project::Projected| -> Vec<(usize, Rat)> {
        p.values().flat_map(|s| s.iter().enumerate().filter(|(_, v)| !v.is_zero()).map(|(j, v)| (j, v / unit))).collect()
    };
    let keys: Vec<(Load, Amp, i32)> = raw.keys().cloned().collect();
    let paper_names = keys.iter().all(|(_, _, o)| [-2, 0, 2].contains(o));
    let mut couplings = Vec::new();
    for (load, amp, offset) in keys {
        let known = &raw[&(load, amp, offset)];
        let values: Vec<Option<Rat>> = (0..=kmax)
            .map(|j| {
                let source = j as i64 + offset as i64;
                let exists = source >= 2 && (load == Load::Normal || j >= 1);
                exists.then(|| known.get(&j).cloned().unwrap_or_else(Rat::zero))
            })
            .collect();
        let points: Vec<(i64, Rat)> = values.iter().enumerate().filter_map(|(j, v)| v.clone().map(|v| (j as i64, v))).collect();
        let name = coupling_name(load, amp, offset, paper_names);
        couplings.push(CouplingData { name, load, amp, offset, closed: fit_rational(&points), values });
    }
    if paper_names {
        couplings.sort_by_key(|c| (c.load, paper_index(c.amp, c.offset)));
    } else {
        couplings.sort_by_key(|c| (c.load, c.offset, c.amp));
    }
    Ok(ComponentData {
        amplitudes: amp_mono,
        prefactor: (unit.clone(), mono),
        r_power: m_pow,
        zero_normal: zero(&zn),
        zero_tangential: zero(&zt),
        couplings,
    })
}

fn paper_index(amp: Amp, offset: i32) -> i32 {
    let base = match offset {
        0 => 1,
        2 => 3,
        -2 => 5,
        _ => 7,
    };
    base + if amp == Amp::B { 1 } else { 0 }
}

/// F1…F6 (normal), F1t…F6t (tangential) for the paper's band; `N_a[+4]` style otherwise.
fn coupling_name(load: Load, amp: Amp, offset: i32, paper: bool) -> String {
    let t = if load == Load::Tangential { "t" } else { "" };
    if paper {
        format!("F{}{t}", paper_index(amp, offset))
    } else {
        let l = if load == Load::Normal { "N" } else { "T" };
        let a = if amp == Amp::A { "a" } else { "b" };
        format!("{l}_{a}[{offset:+}]")
    }
}
