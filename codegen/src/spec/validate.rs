//! Static checks of a parsed spec: names defined before use, known functions and arities,
//! required definitions present. Errors point at the offending token.

use super::ast::{Expr, ExprKind, Spec};
use super::parse::err;
use crate::error::CodegenError;
use num_traits::Zero;
use std::collections::BTreeSet;

/// What a spec describes; decides its built-in names and required definitions.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SpecKind {
    /// `kinematics.rs`: eqs (2.14)–(2.21).
    Kinematics,
    /// A magnetic field (`coil.rs`, `dipole.rs`, …).
    Field,
    /// `membrane.rs`: the membrane equilibrium, σ → loads (eqs 2.26–2.28, FORMULATION §1–2).
    Membrane,
    /// `hyperelastic.rs`: the stresses of a strain energy W (eq 2.25).
    Hyperelastic,
    /// `shape.rs`: the loads of an energy per deformed area that depends on the shape only.
    Shape,
    /// A shell law `shell/NAME.rs`: `symbols` and one of `W`, (`sigma1`, `sigma2`) or `w_area`.
    Law,
}

/// Built-in names of the kinematics spec.
pub const KINEMATIC_BUILTINS: [&str; 6] = ["R", "R0", "Theta", "a_k", "b_k", "k"];
/// Definitions the kinematics spec must provide (the engine reads them).
pub const KINEMATIC_REQUIRED: [&str; 9] = ["r", "theta", "lambda1", "lambda2", "n_r", "n_theta", "t_r", "t_theta", "area"];
/// Built-in names of a field spec (the field point).
pub const FIELD_BUILTINS: [&str; 3] = ["r", "cos_t", "sin_t"];
pub const FIELD_REQUIRED: [&str; 6] = ["symbols", "amplitudes", "h_r", "h_theta", "susceptibility", "unit"];
pub const MEMBRANE_REQUIRED: [&str; 4] = ["paper_n", "paper_t", "tension_n", "tension_t"];
pub const HYPERELASTIC_REQUIRED: [&str; 2] = ["sigma1", "sigma2"];
pub const LAW_REQUIRED: [&str; 1] = ["symbols"];
/// What a shell law may define to say what it is (exactly one).
pub const LAW_KINDS: [&str; 3] = ["W", "sigma1", "w_area"];

const FUNCTIONS: [(&str, usize); 9] =
    [("sqrt", 1), ("sin", 1), ("cos", 1), ("d", 2), ("diff", 2), ("P", 1), ("P1", 1), ("vary", 2), ("rate", 1)];
/// Largest |n| of `.powi(n)`: the exact engine multiplies |n| times (the shipped specs use ≤ 4; an
/// unbounded n from a typo would run for hours instead of failing).
pub const MAX_POWER: u32 = 32;
/// Functions of the shell specs only (a field is static and has no variation).
const SHELL_FUNCTIONS: [&str; 2] = ["vary", "rate"];

/// Check `spec`; `outer` are names visible from another spec (the kinematics, for the membrane).
pub fn validate(spec: &Spec, kind: SpecKind, outer: &[String]) -> Result<(), CodegenError> {
    let path = spec.path.as_str();
    let mut known: BTreeSet<String> = BTreeSet::new();
    let builtins: Vec<&str> = match kind {
        SpecKind::Kinematics => KINEMATIC_BUILTINS.to_vec(),
        SpecKind::Field => FIELD_BUILTINS.to_vec(),
        _ => KINEMATIC_BUILTINS.to_vec(),
    };
    known.extend(builtins.iter().map(|s| s.to_string()));
    known.extend(outer.iter().cloned());
    let builtin_list = builtins.join(", ");
    for (i, l) in spec.lets.iter().enumerate() {
        if spec.lets[..i].iter().any(|o| o.name == l.name) || builtins.contains(&l.name.as_str()) {
            return Err(err(path, l.pos, format!("`{}` is already defined", l.name)));
        }
        if l.name == "symbols" || l.name == "amplitudes" {
            let ExprKind::List(items) = &l.value.kind else {
                return Err(err(path, l.value.pos, format!("expected a list of names `[a, b]` for `{}`", l.name)));
            };
            for it in items {
                let ExprKind::Name(n) = &it.kind else {
                    return Err(err(path, it.pos, "expected a symbol name"));
                };
                if l.name == "symbols" {
                    if known.contains(n) {
                        return Err(err(path, it.pos, format!("symbol `{n}` clashes with a built-in or earlier name")));
                    }
                    known.insert(n.clone());
                } else if !known.contains(n) || builtins.contains(&n.as_str()) {
                    return Err(err(path, it.pos, format!("unknown symbol `{n}`: an amplitude must be declared in `symbols`")));
                }
            }
            continue;
        }
        if l.name == "unit" {
            // the tabulation unit: a plain number
            check_number(path, &l.value)?;
        }
        check(path, &l.value, &known, &builtin_list, kind != SpecKind::Field)?;
        known.insert(l.name.clone());
    }
    let required: &[&str] = match kind {
        SpecKind::Kinematics => &KINEMATIC_REQUIRED,
        SpecKind::Field => &FIELD_REQUIRED,
        SpecKind::Membrane | SpecKind::Shape => &MEMBRANE_REQUIRED,
        SpecKind::Hyperelastic => &HYPERELASTIC_REQUIRED,
        SpecKind::Law => &LAW_REQUIRED,
    };
    for r in required {
        if spec.get(r).is_none() {
            let end = super::Pos { line: 1, column: 1 };
            return Err(err(path, end, format!("missing `let {r} = …;` (required in a {} spec)", format!("{kind:?}").to_lowercase())));
        }
    }
    if kind == SpecKind::Law {
        let defined: Vec<&str> = LAW_KINDS.iter().copied().filter(|n| spec.get(n).is_some()).collect();
        if defined.len() != 1 {
            let p = defined.get(1).and_then(|n| spec.get(n)).map_or(super::Pos { line: 1, column: 1 }, |l| l.pos);
            return Err(err(
                path,
                p,
                "a shell law defines exactly one of `W` (strain energy per reference area), `sigma1` and `sigma2` (stresses σ_i = λ1λ2 τ_i), or `w_area` (energy per deformed area of the shape)",
            ));
        }
        if spec.get("sigma1").is_some() != spec.get("sigma2").is_some() {
            return Err(err(path, super::Pos { line: 1, column: 1 }, "a shell law that defines `sigma1` must define `sigma2` too"));
        }
    }
    Ok(())
}

fn check_number(path: &str, e: &Expr) -> Result<(), CodegenError> {
    match &e.kind {
        ExprKind::Num(_) => Ok(()),
        ExprKind::Neg(x) => check_number(path, x),
        ExprKind::Bin(_, a, b) => check_number(path, a).and(check_number(path, b)),
        _ => Err(err(path, e.pos, "expected a number for `unit` (e.g. `1 / 4`)")),
    }
}

fn check(path: &str, e: &Expr, known: &BTreeSet<String>, builtins: &str, shell: bool) -> Result<(), CodegenError> {
    match &e.kind {
        ExprKind::Num(_) => Ok(()),
        ExprKind::Name(n) => {
            if known.contains(n) {
                Ok(())
            } else {
                Err(err(
                    path,
                    e.pos,
                    format!("unknown symbol `{n}`: expected a name declared in `let symbols = [...]`, an earlier `let`, or a built-in ({builtins})"),
                ))
            }
        }
        ExprKind::Neg(x) => check(path, x, known, builtins, shell),
        ExprKind::Bin(op, a, b) => {
            if *op == super::ast::BinOp::Div {
                if let ExprKind::Num(z) = &b.kind {
                    if z.is_zero() {
                        return Err(err(path, b.pos, "division by zero"));
                    }
                }
            }
            check(path, a, known, builtins, shell)?;
            check(path, b, known, builtins, shell)
        }
        ExprKind::List(_) => Err(err(path, e.pos, "unsupported construct: a list is only allowed for `symbols` and `amplitudes`")),
        ExprKind::Call(f, args) => {
            let Some((_, arity)) = FUNCTIONS.iter().find(|(n, _)| n == f) else {
                return Err(err(path, e.pos, format!("unsupported function `{f}`: expected one of sqrt, sin, cos, d, diff, P, P1, vary, rate")));
            };
            if !shell && SHELL_FUNCTIONS.contains(&f.as_str()) {
                return Err(err(path, e.pos, format!("`{f}` is only available in shell specs (derivations/shell/, membrane.rs)")));
            }
            if args.len() != *arity {
                return Err(err(path, e.pos, format!("`{f}` takes {arity} argument(s), found {}", args.len())));
            }
            match f.as_str() {
                "P" | "P1" => match &args[0].kind {
                    ExprKind::Name(k) if k == "k" => Ok(()),
                    _ => Err(err(path, args[0].pos, format!("expected `{f}(k)`: the mode shape of mode k"))),
                },
                "d" => {
                    match &args[1].kind {
                        ExprKind::Name(t) if t == "Theta" => {}
                        _ => return Err(err(path, args[1].pos, "expected `Theta`: only d(…, Theta) is supported")),
                    }
                    check(path, &args[0], known, builtins, shell)
                }
                "diff" | "vary" => {
                    for a in args {
                        match &a.kind {
                            ExprKind::Name(n) if known.contains(n) => {}
                            _ => return Err(err(path, a.pos, "expected a defined name in `diff(name, variable)`")),
                        }
                    }
                    Ok(())
                }
                _ => args.iter().try_for_each(|a| check(path, a, known, builtins, shell)),
            }
        }
        ExprKind::Method(recv, m, args) => {
            check(path, recv, known, builtins, shell)?;
            match (m.as_str(), args.as_slice()) {
                ("powi", [a]) => match int_literal(a) {
                    Some(n) if n.unsigned_abs() > MAX_POWER => Err(err(
                        path,
                        a.pos,
                        format!("`.powi({n})`: the exponent must be at most {MAX_POWER} in magnitude (the engine multiplies |n| times)"),
                    )),
                    Some(_) => Ok(()),
                    None => Err(err(path, a.pos, "expected an integer literal in `.powi(n)`")),
                },
                ("sqrt", []) | ("sin", []) | ("cos", []) => Ok(()),
                _ => Err(err(path, e.pos, format!("unsupported method `.{m}(…)`: expected `.powi(n)`, `.sqrt()`, `.sin()` or `.cos()`"))),
            }
        }
    }
}

/// The value of an integer literal (possibly negated).
pub fn int_literal(e: &Expr) -> Option<i32> {
    match &e.kind {
        ExprKind::Num(r) if r.is_integer() => r.numer().try_into().ok(),
        ExprKind::Neg(x) => int_literal(x).map(|v| -v),
        _ => None,
    }
}
