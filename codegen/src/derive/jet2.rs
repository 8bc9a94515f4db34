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
//! and substituting the expanded stretches. Laws that state stresses by `rate` (viscous) or a
//! shape energy by `vary` (bending) are not supported here: an error says so.

use crate::algebra::dual::Dual;
use crate::algebra::legendre::legendre_poly;
use crate::algebra::{rat, Mono, Poly, Rat};
use crate::spec::ast::{BinOp, Expr, ExprKind, Spec};
use crate::spec::validate::int_literal;
use num_traits::Zero;
use std::collections::BTreeMap;

/// Amplitude symbols of the two modes.
pub const L_SYMS: [&str; 2] = ["al", "bl"];
pub const M_SYMS: [&str; 2] = ["am", "bm"];

/// Degrees of a monomial in the mode-l and mode-m amplitudes.
fn degrees(m: &Mono) -> (i32, i32) {
    let d = |syms: [&str; 2]| syms.iter().map(|s| m.power(s)).sum::<i32>();
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

/// (z0, u) with p = z0 (1 + u), z0 the single-monomial zero-order part.
fn split(p: &Poly, what: &str) -> Result<(Mono, Rat, Poly), String> {
    let z0 = part(p, 0, 0);
    let Some((m, c)) = z0.single() else {
        return Err(format!("cannot {what}: the zero-order part `{}` is not a single monomial", z0.terms.keys().map(|m| m.text()).collect::<Vec<_>>().join(" + ")));
    };
    let (m, c) = (m.clone(), c.clone());
    let inv0 = Poly::term(m.pow(-1), num_traits::Inv::inv(c.clone()));
    let u = p.sub(&z0).mul(&inv0);
    Ok((m, c, u))
}

/// 1/p = (1/z0)(1 − u + u²).
pub fn inv(p: &Poly) -> Result<Poly, String> {
    let (m, c, u) = split(p, "divide by it")?;
    let inv0 = Poly::term(m.pow(-1), num_traits::Inv::inv(c));
    Ok(mul(&inv0, &Poly::constant(rat(1)).sub(&u).add(&mul(&u, &u))))
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
    let series = Poly::constant(rat(1)).add(&u.scale(&crate::algebra::ratio(1, 2))).sub(&mul(&u, &u).scale(&crate::algebra::ratio(1, 8)));
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
        Env2 { values, modes: Some((l, m)) }
    }
    /// λ1, λ2 as the plain symbols L1, L2 (the stresses of a strain energy).
    pub fn symbolic_stretches() -> Env2 {
        let mut values = BTreeMap::new();
        values.insert("lambda1".to_string(), V::S(Poly::var("L1")));
        values.insert("lambda2".to_string(), V::S(Poly::var("L2")));
        Env2 { values, modes: None }
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
        let v = match v {
            V::S(p) => V::S(env.expand_modes(p)?),
            V::Angle(p) => V::Angle(env.expand_modes(p)?),
            other => other,
        };
        env.values.insert(l.name.clone(), v);
    }
    Ok(())
}

fn trig(f: &str, v: V) -> Result<V, String> {
    let V::Angle(beta) = v else { return Err(format!("`{f}` applies to an angle")) };
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
            "rate" => Err("`rate` (a viscous law): its second-order terms are not derived".into()),
            "vary" => Err("`vary` (a shape energy): its second-order terms are not derived".into()),
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
