//! Interpreter of a validated spec over exact dual numbers.

use crate::algebra::dual::{jet, jet_order, marker};
use crate::algebra::poly::VIRTUAL;
use crate::algebra::{rat, Dual, Poly};
use crate::error::CodegenError;
use crate::spec::ast::{BinOp, Expr, ExprKind, Pos, Spec};
use crate::spec::parse::err;
use crate::spec::validate::int_literal;
use std::collections::{BTreeMap, BTreeSet};

/// A spec value.
#[derive(Clone, Debug)]
pub enum Value {
    /// A quantity, exact to first order in the amplitudes.
    Scalar(Dual),
    /// An angle Θ + shift (the shift is first order): `Theta`, `theta`.
    Angle(Dual),
    /// The mode index `k` (only inside `P(k)`, `P1(k)`).
    Mode,
    /// A list of declared names (`symbols`, `amplitudes`).
    Names(Vec<String>),
}

/// Bindings built while a spec is evaluated.
#[derive(Clone, Debug, Default)]
pub struct Env {
    pub values: BTreeMap<String, Value>,
    asts: BTreeMap<String, Expr>,
    /// Names defined by `let`, in evaluation order (across specs): `vary` re-evaluates them.
    order: Vec<String>,
}

impl Env {
    pub fn bind(&mut self, name: &str, v: Value) {
        self.values.insert(name.to_string(), v);
    }
    /// The scalar bound to `name` (the spec was validated, so a missing name is a codegen bug
    /// reported as an error, not a panic).
    pub fn scalar(&self, spec: &Spec, name: &str) -> Result<Dual, CodegenError> {
        let pos = spec.get(name).map(|l| l.pos).unwrap_or_default();
        match self.values.get(name) {
            Some(Value::Scalar(d)) => Ok(d.clone()),
            _ => Err(err(&spec.path, pos, format!("expected `{name}` to be a scalar quantity"))),
        }
    }
    /// Every name defined by a `let` so far, in evaluation order.
    pub fn defined(&self) -> &[String] {
        &self.order
    }
    pub fn names(&self, name: &str) -> Vec<String> {
        match self.values.get(name) {
            Some(Value::Names(v)) => v.clone(),
            _ => Vec::new(),
        }
    }
}

/// The kinematic built-ins: R, R0, the material angle Θ, the amplitudes a_k, b_k, and k.
pub fn kinematic_env() -> Env {
    let mut env = Env::default();
    env.bind("R", Value::Scalar(Dual::zero_order(Poly::var("R"))));
    env.bind("R0", Value::Scalar(Dual::zero_order(Poly::var("R0"))));
    env.bind("Theta", Value::Angle(Dual::default()));
    env.bind("a_k", Value::Scalar(Dual::new(Poly::zero(), Poly::var("#a"))));
    env.bind("b_k", Value::Scalar(Dual::new(Poly::zero(), Poly::var("#b"))));
    env.bind("k", Value::Mode);
    env
}

/// The field-point built-ins r, cos θ, sin θ.
pub fn field_env() -> Env {
    let mut env = Env::default();
    env.bind("r", Value::Scalar(Dual::zero_order(Poly::var("#r"))));
    env.bind("cos_t", Value::Scalar(Dual::zero_order(Poly::var("#ct"))));
    env.bind("sin_t", Value::Scalar(Dual::zero_order(Poly::var("#st"))));
    env
}

/// Evaluate every `let` of `spec` in order, starting from `env`.
pub fn eval_spec(spec: &Spec, mut env: Env) -> Result<Env, CodegenError> {
    for l in &spec.lets {
        let v = match &l.value.kind {
            ExprKind::List(items) => {
                let names: Vec<String> = items
                    .iter()
                    .filter_map(|i| if let ExprKind::Name(n) = &i.kind { Some(n.clone()) } else { None })
                    .collect();
                if l.name == "symbols" {
                    for n in &names {
                        env.bind(n, Value::Scalar(Dual::zero_order(Poly::var(n))));
                    }
                }
                Value::Names(names)
            }
            _ => eval(spec, &env, &l.value)?,
        };
        env.asts.insert(l.name.clone(), l.value.clone());
        env.order.retain(|n| n != &l.name);
        env.order.push(l.name.clone());
        env.bind(&l.name, v);
    }
    Ok(env)
}

fn scalar(spec: &Spec, v: Value, pos: Pos) -> Result<Dual, CodegenError> {
    match v {
        Value::Scalar(d) => Ok(d),
        Value::Angle(_) => Err(err(&spec.path, pos, "expected a quantity, found an angle (use sin/cos of it)")),
        Value::Mode => Err(err(&spec.path, pos, "`k` may only appear as `P(k)` or `P1(k)`")),
        Value::Names(_) => Err(err(&spec.path, pos, "expected a quantity, found a list of names")),
    }
}

/// Evaluate one expression.
pub fn eval(spec: &Spec, env: &Env, e: &Expr) -> Result<Value, CodegenError> {
    let path = spec.path.as_str();
    let alg = |r: Result<Dual, String>| r.map(Value::Scalar).map_err(|m| err(path, e.pos, m));
    match &e.kind {
        ExprKind::Num(r) => Ok(Value::Scalar(Dual::constant(r.clone()))),
        ExprKind::Name(n) => env.values.get(n).cloned().ok_or_else(|| err(path, e.pos, format!("unknown symbol `{n}`"))),
        ExprKind::List(_) => Err(err(path, e.pos, "unsupported construct: a list is only allowed for `symbols` and `amplitudes`")),
        ExprKind::Neg(x) => match eval(spec, env, x)? {
            Value::Scalar(d) => Ok(Value::Scalar(d.neg())),
            _ => Err(err(path, e.pos, "only a quantity can be negated")),
        },
        ExprKind::Bin(op, a, b) => {
            let va = eval(spec, env, a)?;
            let vb = eval(spec, env, b)?;
            match (op, va, vb) {
                (BinOp::Add, Value::Angle(s), Value::Scalar(d)) | (BinOp::Add, Value::Scalar(d), Value::Angle(s)) => {
                    Ok(Value::Angle(s.add(&d)))
                }
                (BinOp::Sub, Value::Angle(s), Value::Scalar(d)) => Ok(Value::Angle(s.sub(&d))),
                (op, va, vb) => {
                    let x = scalar(spec, va, a.pos)?;
                    let y = scalar(spec, vb, b.pos)?;
                    match op {
                        BinOp::Add => Ok(Value::Scalar(x.add(&y))),
                        BinOp::Sub => Ok(Value::Scalar(x.sub(&y))),
                        BinOp::Mul => Ok(Value::Scalar(x.mul(&y))),
                        BinOp::Div => alg(x.div(&y)),
                    }
                }
            }
        }
        ExprKind::Method(recv, m, args) => {
            let v = eval(spec, env, recv)?;
            match m.as_str() {
                "sin" | "cos" => trig(spec, m, v, e.pos),
                "sqrt" => alg(scalar(spec, v, recv.pos)?.sqrt()),
                "powi" => {
                    let n = args.first().and_then(int_literal).ok_or_else(|| err(path, e.pos, "expected `.powi(n)` with an integer n"))?;
                    alg(scalar(spec, v, recv.pos)?.powi(n))
                }
                _ => Err(err(path, e.pos, format!("unsupported method `.{m}(…)`"))),
            }
        }
        ExprKind::Call(f, args) => match f.as_str() {
            "P" => Ok(Value::Scalar(Dual::zero_order(Poly::var(&marker(0))))),
            "P1" => {
                // P^1_k(cos Θ) = dP_k/dΘ = −sinΘ P_k'(cos Θ) (Condon–Shortley, FORMULATION §1)
                Ok(Value::Scalar(Dual::zero_order(Poly::var("#s").mul(&Poly::var(&marker(1))).neg())))
            }
            "sin" | "cos" => trig(spec, f, eval(spec, env, &args[0])?, e.pos),
            "sqrt" => alg(scalar(spec, eval(spec, env, &args[0])?, args[0].pos)?.sqrt()),
            "d" => match eval(spec, env, &args[0])? {
                Value::Angle(shift) => Ok(Value::Scalar(Dual::constant(rat(1)).add(&shift.d_theta()))),
                v => Ok(Value::Scalar(scalar(spec, v, args[0].pos)?.d_theta())),
            },
            "diff" => diff(spec, env, &args[0], &args[1]),
            "vary" => vary(spec, env, &args[0], &args[1]),
            "rate" => Ok(Value::Scalar(scalar(spec, eval(spec, env, &args[0])?, args[0].pos)?.rate())),
            _ => Err(err(path, e.pos, format!("unsupported function `{f}`"))),
        },
    }
}

/// sin/cos of Θ + β at first order: sin → sinΘ + cosΘ β, cos → cosΘ − sinΘ β.
fn trig(spec: &Spec, f: &str, v: Value, pos: Pos) -> Result<Value, CodegenError> {
    let Value::Angle(shift) = v else {
        return Err(err(&spec.path, pos, format!("`{f}` applies to an angle (Theta or a deformed angle), not to a quantity")));
    };
    if !shift.z.is_zero() {
        return Err(err(&spec.path, pos, format!("`{f}` of Θ + a finite shift is not supported: the shift must be first order")));
    }
    let (x, s) = (Poly::var("#x"), Poly::var("#s"));
    Ok(Value::Scalar(match f {
        "sin" => Dual::new(s, x.mul(&shift.e)),
        _ => Dual::new(x, s.mul(&shift.e).neg()),
    }))
}

/// `diff(f, v)`: ∂f/∂v, with v a variable in the expression of f, then v set back to its value.
fn diff(spec: &Spec, env: &Env, f: &Expr, v: &Expr) -> Result<Value, CodegenError> {
    let path = spec.path.as_str();
    let (ExprKind::Name(fname), ExprKind::Name(vname)) = (&f.kind, &v.kind) else {
        return Err(err(path, f.pos, "expected `diff(name, variable)`"));
    };
    if !env.asts.contains_key(fname) {
        return Err(err(path, f.pos, format!("`{fname}` is not defined by a `let` in this spec")));
    }
    let value = scalar(spec, env.values.get(vname).cloned().unwrap_or(Value::Mode), v.pos)?;
    let mut local = env.clone();
    let free = "#free";
    local.bind(vname, Value::Scalar(Dual::zero_order(Poly::var(free))));
    for name in env.chain(vname, fname) {
        let val = eval(spec, &local, &env.asts[&name])?;
        local.bind(&name, val);
    }
    let expr = scalar(spec, local.values[fname.as_str()].clone(), f.pos)?;
    let derivative = expr.diff(free);
    let map = BTreeMap::from([(free.to_string(), value)]);
    derivative.subst(&map).map(Value::Scalar).map_err(|m| err(path, f.pos, m))
}

/// Names a spec expression refers to.
fn refs(e: &Expr, out: &mut BTreeSet<String>) {
    match &e.kind {
        ExprKind::Num(_) => {}
        ExprKind::Name(n) => {
            out.insert(n.clone());
        }
        ExprKind::Neg(x) => refs(x, out),
        ExprKind::Bin(_, a, b) => {
            refs(a, out);
            refs(b, out);
        }
        ExprKind::Call(_, args) | ExprKind::List(args) => args.iter().for_each(|a| refs(a, out)),
        ExprKind::Method(r, _, args) => {
            refs(r, out);
            args.iter().for_each(|a| refs(a, out));
        }
    }
}

impl Env {
    /// The `let`s after `var` up to and including `target` that depend on `var` and that
    /// `target` depends on, in evaluation order: what `diff` and `vary` re-evaluate, so that a
    /// derivative goes through intermediate definitions (W of I1(λ1, λ2), …).
    fn chain(&self, var: &str, target: &str) -> Vec<String> {
        chain(&self.order, &self.asts, var, target)
    }
}

/// [`Env::chain`] over explicit bindings (also used by the second-order engine,
/// [`super::jet2`]): the `let`s of `order` after `var` up to `target` that depend on `var` and
/// that `target` depends on.
pub fn chain(order: &[String], asts: &BTreeMap<String, Expr>, var: &str, target: &str) -> Vec<String> {
    let (Some(iv), Some(it)) = (order.iter().position(|n| n == var), order.iter().position(|n| n == target)) else {
        return Vec::new();
    };
    if it <= iv {
        return Vec::new();
    }
    let span = &order[iv + 1..=it];
    let uses = |n: &String| {
        let mut r = BTreeSet::new();
        refs(&asts[n], &mut r);
        r
    };
    let mut affected: BTreeSet<String> = BTreeSet::from([var.to_string()]);
    for n in span {
        if uses(n).iter().any(|r| affected.contains(r)) {
            affected.insert(n.clone());
        }
    }
    let mut needed: BTreeSet<String> = BTreeSet::from([target.to_string()]);
    for n in span.iter().rev() {
        if needed.contains(n) {
            needed.extend(uses(n));
        }
    }
    span.iter().filter(|n| affected.contains(*n) && needed.contains(*n) && !matches!(asts[*n].kind, ExprKind::List(_))).cloned().collect()
}

/// `vary(L, q)`: the Euler–Lagrange expression ∂L/∂q − d/dΘ ∂L/∂q' + d²/dΘ² ∂L/∂q'' − … of the
/// density L (per dΘ) under a variation q → q + δ·η(Θ) of the earlier definition q. Every `let`
/// between q and L on which L depends through q is re-evaluated with q varied (d(·, Theta) of η gives η', η'', …); the part of L
/// linear in δ is Σ_i c_i η^(i), and the result is Σ_i (−d/dΘ)^i c_i (integration by parts; no
/// boundary terms on the closed meridian 0 ≤ Θ ≤ π, where sin Θ vanishes).
fn vary(spec: &Spec, env: &Env, f: &Expr, q: &Expr) -> Result<Value, CodegenError> {
    let path = spec.path.as_str();
    let (ExprKind::Name(fname), ExprKind::Name(qname)) = (&f.kind, &q.kind) else {
        return Err(err(path, f.pos, "expected `vary(density, variable)` with two defined names"));
    };
    let at = |n: &str| env.order.iter().position(|o| o == n);
    let (Some(iq), Some(il)) = (at(qname), at(fname)) else {
        return Err(err(path, f.pos, format!("`vary({fname}, {qname})`: both must be defined by a `let`")));
    };
    if il <= iq {
        return Err(err(path, f.pos, format!("`vary({fname}, {qname})`: `{fname}` must be defined after `{qname}`")));
    }
    let base = scalar(spec, env.values.get(qname).cloned().unwrap_or(Value::Mode), q.pos)?;
    if base.z.has(VIRTUAL) || base.e.has(VIRTUAL) {
        return Err(err(path, f.pos, "nested `vary` is not supported"));
    }
    let mut local = env.clone();
    let delta = Poly::var(VIRTUAL).mul(&Poly::var(&jet(0)));
    local.bind(qname, Value::Scalar(base.add(&Dual::zero_order(delta))));
    for name in env.chain(qname, fname) {
        let v = eval(spec, &local, &env.asts[&name])?;
        local.bind(&name, v);
    }
    let first = scalar(spec, local.values[fname].clone(), f.pos)?.diff(VIRTUAL);
    let mut orders: Vec<u32> = [&first.z, &first.e]
        .iter()
        .flat_map(|p| p.terms.keys().flat_map(|m| m.0.iter().filter_map(|(n, _)| jet_order(n))).collect::<Vec<_>>())
        .collect();
    orders.sort();
    orders.dedup();
    let mut out = Dual::default();
    for i in orders {
        let mut c = first.diff(&jet(i));
        if c.z.terms.keys().chain(c.e.terms.keys()).any(|m| m.0.iter().any(|(n, _)| jet_order(n).is_some())) {
            return Err(err(path, f.pos, format!("`vary({fname}, {qname})`: the density is not linear in the variation")));
        }
        for _ in 0..i {
            c = c.d_theta();
        }
        out = if i % 2 == 0 { out.add(&c) } else { out.sub(&c) };
    }
    Ok(Value::Scalar(out))
}
