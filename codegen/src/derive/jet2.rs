//! Second-order evaluation of the mechanics specs for a pair of modes (issue 12, the membrane):
//! the kinematics, a shell law's stresses and the membrane loads, expanded to the bilinear order
//! in the amplitudes of two concrete modes l, m (exact rationals, polynomials in cos Θ, sin Θ).
//!
//! The amplitudes are the symbols `al`, `bl` (mode l) and `am`, `bm` (mode m); a value is kept
//! *bi-affine*: degree ≤ 1 in (al, bl) and ≤ 1 in (am, bm). Its part of degree (1, 1) is the
//! second-order part that couples the two modes, which is all the quadratic tables need (the
//! squares of one mode come from the pair (l, l), where `al`, `am` multiply the same P_l).
//! The spec's `a_k * P(k)` and `b_k * P1(k)` are replaced, right after the `let` that forms
//! them, by Σ_{n = l, m} a_n P_n(cos Θ) and Σ b_n dP_n/dΘ; everything else is the exact spec
//! expression, truncated: products drop what is beyond the bilinear order, 1/p and √p expand
//! about a single-monomial zero-order part (as the first-order engine, [`super::eval`]), and
//! sin/cos(Θ + β) = sinΘ cos β + cosΘ sin β with cos β = 1 − β²/2, sin β = β.
//!
//! A shell law's stresses are taken from its strain energy W(λ1, λ2) by evaluating the law and
//! `hyperelastic.rs` with λ1, λ2 as plain symbols (`diff` is then an exact partial derivative)
//! and substituting the expanded stretches.
//!
//! `rate(e)` (a viscous law) is the time derivative at a fixed material point: R → Ṙ (`Rd`),
//! a_n → ȧ_n (`adl`, `adm`), b_n → ḃ_n (`bdl`, `bdm`); a rate symbol counts in its mode's degree,
//! so the bilinear order is kept exactly (d/dt(a_l a_m f(R)) = ȧ_l a_m f + a_l ȧ_m f + a_l a_m Ṙ f′).
//! `vary(L, q)` (a shape energy) varies the earlier definition q → q + #v·η(Θ) and re-evaluates
//! the definitions between q and L, as the first-order engine does ([`super::eval`]); the
//! virtual `#v` is a third direction of degree ≤ 1 (Poly drops #v²), so 1/p and √p expand to the
//! third power of their relative part (the product of the three directions).

use crate::algebra::dual::{Dual, RATE_R};
use crate::algebra::legendre::legendre_poly;
use crate::algebra::poly::VIRTUAL;
use crate::algebra::{rat, Mono, Poly, Rat};
use crate::spec::ast::{BinOp, Expr, ExprKind, Spec};
use crate::spec::validate::int_literal;
use num_traits::Zero;
use std::collections::BTreeMap;

/// Amplitude symbols of the two modes: a, b and their rates ȧ, ḃ (viscous laws).
pub const L_SYMS: [&str; 4] = ["al", "bl", "adl", "bdl"];
pub const M_SYMS: [&str; 4] = ["am", "bm", "adm", "bdm"];

/// Degrees of a monomial in the mode-l and mode-m amplitudes.
fn degrees(m: &Mono) -> (i32, i32) {
    let d = |syms: [&str; 4]| syms.iter().map(|s| m.power(s)).sum::<i32>();
    (d(L_SYMS), d(M_SYMS))
}

/// The part of p of degree (dl, dm).
pub fn part(p: &Poly, dl: i32, dm: i32) -> Poly {
    Poly { terms: p.terms.iter().filter(|(m, _)| degrees(m) == (dl, dm)).map(|(m, c)| (m.clone(), c.clone())).collect() }
}

const PARTS: [(i32, i32); 4] = [(0, 0), (1, 0), (0, 1), (1, 1)];

/// a·b, bi-affine (the products beyond the bilinear order are never formed).
pub fn mul(a: &Poly, b: &Poly) -> Poly {
    let pa: Vec<Poly> = PARTS.iter().map(|&(l, m)| part(a, l, m)).collect();
    let pb: Vec<Poly> = PARTS.iter().map(|&(l, m)| part(b, l, m)).collect();
    let mut out = Poly::zero();
    for (i, x) in PARTS.iter().enumerate() {
        for (k, y) in PARTS.iter().enumerate() {
            if x.0 + y.0 <= 1 && x.1 + y.1 <= 1 && !pa[i].is_zero() && !pb[k].is_zero() {
                out = out.add(&pa[i].mul(&pb[k]));
            }
        }
    }
    out
}

/// (z0, u) with p = z0 (1 + u), z0 the single-monomial zero-order part (no amplitude, no #v).
fn split(p: &Poly, what: &str) -> Result<(Mono, Rat, Poly), String> {
    let z0 = part(p, 0, 0);
    let z0 = Poly { terms: z0.terms.into_iter().filter(|(m, _)| m.power(VIRTUAL) == 0).collect() };
    let Some((m, c)) = z0.single() else {
        return Err(format!("cannot {what}: the zero-order part `{}` is not a single monomial", z0.terms.keys().map(|m| m.text()).collect::<Vec<_>>().join(" + ")));
    };
    let (m, c) = (m.clone(), c.clone());
    let inv0 = Poly::term(m.pow(-1), num_traits::Inv::inv(c.clone()));
    let u = p.sub(&z0).mul(&inv0);
    Ok((m, c, u))
}

/// 1/p = (1/z0)(1 − u + u² − u³) (u³ vanishes unless #v is present).
pub fn inv(p: &Poly) -> Result<Poly, String> {
    let (m, c, u) = split(p, "divide by it")?;
    let inv0 = Poly::term(m.pow(-1), num_traits::Inv::inv(c));
    let u2 = mul(&u, &u);
    let mut series = Poly::constant(rat(1)).sub(&u).add(&u2);
    if u.has(VIRTUAL) {
        series = series.sub(&mul(&u2, &u));
    }
    Ok(mul(&inv0, &series))
}

/// p^n for any integer n.
pub fn powi(p: &Poly, n: i32) -> Result<Poly, String> {
    let base = if n < 0 { inv(p)? } else { p.clone() };
    let mut r = Poly::constant(rat(1));
    for _ in 0..n.unsigned_abs() {
        r = mul(&r, &base);
    }
    Ok(r)
}

/// √p = √z0 (1 + u/2 − u²/8); z0 an exact square monomial.
pub fn sqrt(p: &Poly) -> Result<Poly, String> {
    let (m, c, u) = split(p, "take the square root")?;
    let (n, d) = (c.numer().sqrt(), c.denom().sqrt());
    if m.0.iter().any(|(_, e)| e % 2 != 0) || &(&n * &n) != c.numer() || &(&d * &d) != c.denom() {
        return Err(format!("cannot take the square root of `{}`: not an exact square", m.text()));
    }
    let root0 = Poly::term(Mono(m.0.iter().map(|(s, e)| (s.clone(), e / 2)).collect()), Rat::new(n, d));
    let u2 = mul(&u, &u);
    let mut series = Poly::constant(rat(1)).add(&u.scale(&crate::algebra::ratio(1, 2))).sub(&u2.scale(&crate::algebra::ratio(1, 8)));
    if u.has(VIRTUAL) {
        series = series.add(&mul(&u2, &u).scale(&crate::algebra::ratio(1, 16)));
    }
    Ok(mul(&root0, &series))
}

/// d/dΘ along the material meridian (x = cos Θ, s = sin Θ).
pub fn d_theta(p: &Poly) -> Poly {
    Dual::zero_order(p.clone()).d_theta().z
}

/// d^i P_n / dx^i as a polynomial in `#x`.
fn legendre_derivative(n: usize, i: u32) -> Poly {
    let mut c = legendre_poly(n);
    for _ in 0..i {
        c = c.iter().enumerate().skip(1).map(|(k, v)| v * rat(k as i64)).collect();
    }
    let mut p = Poly::zero();
    for (k, v) in c.iter().enumerate() {
        if !v.is_zero() {
            p = p.add(&Poly::term(Mono::var("#x", k as i32), v.clone()));
        }
    }
    p
}

/// A value of the second-order evaluation.
#[derive(Clone, Debug)]
pub enum V {
    S(Poly),
    /// Θ + shift (the shift has no zero-order part).
    Angle(Poly),
    Mode,
    Names(Vec<String>),
}

/// Bindings for one pair of modes (or none: the symbolic-λ stage of a law).
#[derive(Clone, Debug)]
pub struct Env2 {
    pub values: BTreeMap<String, V>,
    modes: Option<(usize, usize)>,
    /// The `let`s evaluated so far (across specs) and their expressions: what `vary` re-evaluates.
    asts: BTreeMap<String, Expr>,
    order: Vec<String>,
}

impl Env2 {
    /// The kinematic built-ins for modes (l, m).
    pub fn kinematic(l: usize, m: usize) -> Env2 {
        let mut values = BTreeMap::new();
        values.insert("R".to_string(), V::S(Poly::var("R")));
        values.insert("R0".to_string(), V::S(Poly::var("R0")));
        values.insert("Theta".to_string(), V::Angle(Poly::zero()));
        values.insert("a_k".to_string(), V::S(Poly::var("#a")));
        values.insert("b_k".to_string(), V::S(Poly::var("#b")));
        values.insert("k".to_string(), V::Mode);
        Env2 { values, modes: Some((l, m)), asts: BTreeMap::new(), order: Vec::new() }
    }
    /// λ1, λ2 as the plain symbols L1, L2 (the stresses of a strain energy).
    pub fn symbolic_stretches() -> Env2 {
        let mut values = BTreeMap::new();
        values.insert("lambda1".to_string(), V::S(Poly::var("L1")));
        values.insert("lambda2".to_string(), V::S(Poly::var("L2")));
        Env2 { values, modes: None, asts: BTreeMap::new(), order: Vec::new() }
    }
    pub fn scalar(&self, name: &str) -> Result<Poly, String> {
        match self.values.get(name) {
            Some(V::S(p)) => Ok(p.clone()),
            _ => Err(format!("`{name}` is not a defined quantity")),
        }
    }
    /// Replace `#a·#P_i` and `#b·#P_i` by the two modes' amplitudes times d^iP_n/dx^i.
    fn expand_modes(&self, p: Poly) -> Result<Poly, String> {
        let Some((l, m)) = self.modes else { return Ok(p) };
        if !p.has("#a") && !p.has("#b") {
            return Ok(p);
        }
        let mut out = Poly::zero();
        for (mono, c) in &p.terms {
            let (pa, pb) = (mono.power("#a"), mono.power("#b"));
            if pa == 0 && pb == 0 {
                out = out.add(&Poly::term(mono.clone(), c.clone()));
                continue;
            }
            let markers: Vec<(u32, i32)> = mono.0.iter().filter_map(|(n, e)| crate::algebra::dual::marker_order(n).map(|i| (i, *e))).collect();
            let [(i, 1)] = markers.as_slice() else { return Err(format!("term `{}` is not linear in one mode shape", mono.text())) };
            if pa + pb != 1 {
                return Err(format!("term `{}` is not linear in the amplitudes", mono.text()));
            }
            let (sl, sm) = if pa == 1 { ("al", "am") } else { ("bl", "bm") };
            let rest = Poly::term(mono.with("#a", 0).with("#b", 0).with(&crate::algebra::dual::marker(*i), 0), c.clone());
            let shapes = Poly::var(sl).mul(&legendre_derivative(l, *i)).add(&Poly::var(sm).mul(&legendre_derivative(m, *i)));
            out = out.add(&rest.mul(&shapes));
        }
        Ok(out)
    }
}

fn scalar(v: V) -> Result<Poly, String> {
    match v {
        V::S(p) => Ok(p),
        V::Angle(_) => Err("expected a quantity, found an angle".into()),
        V::Mode => Err("`k` may only appear as `P(k)` or `P1(k)`".into()),
        V::Names(_) => Err("expected a quantity, found a list of names".into()),
    }
}

/// Evaluate every `let` of `spec` in order into `env`; errors carry the spec position.
pub fn eval_spec(spec: &Spec, env: &mut Env2) -> Result<(), String> {
    for l in &spec.lets {
        let v = match &l.value.kind {
            ExprKind::List(items) => {
                let names: Vec<String> = items.iter().filter_map(|i| if let ExprKind::Name(n) = &i.kind { Some(n.clone()) } else { None }).collect();
                if l.name == "symbols" {
                    for n in &names {
                        env.values.insert(n.clone(), V::S(Poly::var(n)));
                    }
                }
                V::Names(names)
            }
            _ => eval(env, &l.value).map_err(|m| format!("{}:{}:{}: {m}", spec.path, l.value.pos.line, l.value.pos.column))?,
        };
        let v = env.expanded(v)?;
        env.asts.insert(l.name.clone(), l.value.clone());
        env.order.retain(|n| n != &l.name);
        env.order.push(l.name.clone());
        env.values.insert(l.name.clone(), v);
    }
    Ok(())
}

impl Env2 {
    /// A `let`'s value with the mode shapes expanded ([`Env2::expand_modes`]).
    fn expanded(&self, v: V) -> Result<V, String> {
        Ok(match v {
            V::S(p) => V::S(self.expand_modes(p)?),
            V::Angle(p) => V::Angle(self.expand_modes(p)?),
            other => other,
        })
    }
}

/// `rate(p)`: the time derivative at a fixed material point (module doc).
fn rate(p: &Poly) -> Result<Poly, String> {
    let rates = [("R", RATE_R), ("al", "adl"), ("bl", "bdl"), ("am", "adm"), ("bm", "bdm")];
    if rates.iter().any(|(_, r)| p.has(r)) {
        return Err("`rate` of a rate is not supported".into());
    }
    let mut out = Poly::zero();
    for (s, r) in rates {
        if p.has(s) {
            out = out.add(&mul(&p.diff(s), &Poly::var(r)));
        }
    }
    Ok(out)
}

/// `vary(L, q)`: the Euler–Lagrange expression of the density L under q → q + #v·η(Θ) (as the
/// first-order engine's, [`super::eval`]): the `let`s between q and L that depend on q are
/// re-evaluated, the part linear in #v is Σ_i c_i η^(i), and the result is Σ_i (−d/dΘ)^i c_i.
fn vary(env: &Env2, f: &Expr, q: &Expr) -> Result<V, String> {
    let (ExprKind::Name(fname), ExprKind::Name(qname)) = (&f.kind, &q.kind) else {
        return Err("expected `vary(density, variable)` with two defined names".into());
    };
    let base = env.scalar(qname)?;
    if base.has(VIRTUAL) {
        return Err("nested `vary` is not supported".into());
    }
    let mut local = env.clone();
    local.values.insert(qname.clone(), V::S(base.add(&Poly::var(VIRTUAL).mul(&Poly::var(&crate::algebra::dual::jet(0))))));
    for name in super::eval::chain(&env.order, &env.asts, qname, fname) {
        let v = eval(&local, &env.asts[&name])?;
        let v = local.expanded(v)?;
        local.values.insert(name, v);
    }
    let first = local.scalar(fname)?.diff(VIRTUAL);
    let mut orders: Vec<u32> = first.terms.keys().flat_map(|m| m.0.iter().filter_map(|(n, _)| crate::algebra::dual::jet_order(n)).collect::<Vec<_>>()).collect();
    orders.sort();
    orders.dedup();
    let mut out = Poly::zero();
    for i in orders {
        let mut c = first.diff(&crate::algebra::dual::jet(i));
        if c.terms.keys().any(|m| m.0.iter().any(|(n, _)| crate::algebra::dual::jet_order(n).is_some() || n == VIRTUAL)) {
            return Err(format!("`vary({fname}, {qname})`: the density is not linear in the variation"));
        }
        for _ in 0..i {
            c = d_theta(&c);
        }
        out = if i % 2 == 0 { out.add(&c) } else { out.sub(&c) };
    }
    Ok(V::S(out))
}

fn trig(f: &str, v: V) -> Result<V, String> {
    let V::Angle(beta) = v else { return Err(format!("`{f}` applies to an angle")) };
    if beta.has(VIRTUAL) {
        return Err(format!("`{f}` of an angle that a `vary` varies is not supported"));
    }
    let (x, s) = (Poly::var("#x"), Poly::var("#s"));
    let cos_b = Poly::constant(rat(1)).sub(&mul(&beta, &beta).scale(&crate::algebra::ratio(1, 2)));
    Ok(V::S(match f {
        "sin" => mul(&s, &cos_b).add(&mul(&x, &beta)),
        _ => mul(&x, &cos_b).sub(&mul(&s, &beta)),
    }))
}

/// Evaluate one expression.
pub fn eval(env: &Env2, e: &Expr) -> Result<V, String> {
    match &e.kind {
        ExprKind::Num(r) => Ok(V::S(Poly::constant(r.clone()))),
        ExprKind::Name(n) => env.values.get(n).cloned().ok_or_else(|| format!("unknown symbol `{n}` (not available to the second-order engine)")),
        ExprKind::List(_) => Err("unsupported construct: a list".into()),
        ExprKind::Neg(x) => Ok(V::S(scalar(eval(env, x)?)?.neg())),
        ExprKind::Bin(op, a, b) => {
            let (va, vb) = (eval(env, a)?, eval(env, b)?);
            match (op, va, vb) {
                (BinOp::Add, V::Angle(s), V::S(d)) | (BinOp::Add, V::S(d), V::Angle(s)) => Ok(V::Angle(s.add(&d))),
                (BinOp::Sub, V::Angle(s), V::S(d)) => Ok(V::Angle(s.sub(&d))),
                (op, va, vb) => {
                    let (x, y) = (scalar(va)?, scalar(vb)?);
                    Ok(V::S(match op {
                        BinOp::Add => x.add(&y),
                        BinOp::Sub => x.sub(&y),
                        BinOp::Mul => mul(&x, &y),
                        BinOp::Div => mul(&x, &inv(&y)?),
                    }))
                }
            }
        }
        ExprKind::Method(recv, m, args) => {
            let v = eval(env, recv)?;
            match m.as_str() {
                "sin" | "cos" => trig(m, v),
                "sqrt" => Ok(V::S(sqrt(&scalar(v)?)?)),
                "powi" => {
                    let n = args.first().and_then(int_literal).ok_or("expected `.powi(n)` with an integer n")?;
                    Ok(V::S(powi(&scalar(v)?, n)?))
                }
                _ => Err(format!("unsupported method `.{m}(…)`")),
            }
        }
        ExprKind::Call(f, args) => match f.as_str() {
            "P" => Ok(V::S(Poly::var(&crate::algebra::dual::marker(0)))),
            "P1" => Ok(V::S(Poly::var("#s").mul(&Poly::var(&crate::algebra::dual::marker(1))).neg())),
            "sin" | "cos" => trig(f, eval(env, &args[0])?),
            "sqrt" => Ok(V::S(sqrt(&scalar(eval(env, &args[0])?)?)?)),
            "d" => match eval(env, &args[0])? {
                V::Angle(shift) => Ok(V::S(Poly::constant(rat(1)).add(&d_theta(&shift)))),
                v => Ok(V::S(d_theta(&scalar(v)?))),
            },
            "diff" => {
                let f = scalar(eval(env, &args[0])?)?;
                let x = scalar(eval(env, &args[1])?)?;
                let Some((m, c)) = x.single() else { return Err("`diff` by a compound quantity".into()) };
                let [(s, 1)] = m.0.as_slice() else { return Err("`diff` by a compound quantity".into()) };
                if !c.is_zero() && *c == rat(1) {
                    Ok(V::S(f.diff(s)))
                } else {
                    Err("`diff` by a compound quantity".into())
                }
            }
            "rate" => Ok(V::S(rate(&scalar(eval(env, &args[0])?)?)?)),
            "vary" => vary(env, &args[0], &args[1]),
            _ => Err(format!("unsupported function `{f}`")),
        },
    }
}

/// Substitute L1 → λ1, L2 → λ2 (expanded) in a polynomial of the symbolic-λ stage.
pub fn substitute_stretches(p: &Poly, l1: &Poly, l2: &Poly) -> Result<Poly, String> {
    let mut cache: BTreeMap<(usize, i32), Poly> = BTreeMap::new();
    let mut out = Poly::zero();
    for (m, c) in &p.terms {
        let mut t = Poly::term(m.with("L1", 0).with("L2", 0), c.clone());
        for (i, (name, base)) in [("L1", l1), ("L2", l2)].iter().enumerate() {
            let e = m.power(name);
            if e != 0 {
                if !cache.contains_key(&(i, e)) {
                    cache.insert((i, e), powi(base, e)?);
                }
                t = mul(&t, &cache[&(i, e)]);
            }
        }
        out = out.add(&t);
    }
    Ok(out)
}
