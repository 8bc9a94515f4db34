//! syn → [`Spec`]. Every error carries `path:line:column`.

use super::ast::{BinOp, Expr, ExprKind, Let, Pos, Spec};
use crate::algebra::{rat, Rat};
use crate::error::CodegenError;
use num_bigint::BigInt;
use syn::spanned::Spanned;

/// 1-based position of a span of the wrapped text `{<spec>\n}` (see [`parse_spec`]): on line 1
/// the added `{` shifts columns by one.
fn pos(span: proc_macro2::Span) -> Pos {
    let s = span.start();
    let column = if s.line == 1 { s.column } else { s.column + 1 };
    Pos { line: s.line, column: column.max(1) }
}

pub(crate) fn err(path: &str, p: Pos, message: impl Into<String>) -> CodegenError {
    CodegenError::Spec { path: path.to_string(), line: p.line, column: p.column, message: message.into() }
}

/// Parse the text of a spec file; `path` is used in messages.
pub fn parse_spec(path: &str, text: &str) -> Result<Spec, CodegenError> {
    if let Err(e) = text.parse::<proc_macro2::TokenStream>() {
        let s = e.span().start();
        let p = Pos { line: s.line.max(1), column: s.column + 1 };
        return Err(err(path, p, "expected balanced `( )`, `[ ]`, `{ }` and valid tokens (unclosed or unexpected delimiter)"));
    }
    // Wrapped in braces so that an error at the end of the input points at the end of the file.
    let wrapped = format!("{{{text}\n}}");
    let block: syn::Block = syn::parse_str(&wrapped).map_err(|e| {
        let mut p = pos(e.span());
        let lines: Vec<&str> = text.lines().collect();
        if p.line > lines.len() {
            let last = lines.iter().rposition(|l| !l.trim().is_empty()).unwrap_or(0);
            p = Pos { line: last + 1, column: lines.get(last).map_or(0, |l| l.chars().count()) + 1 };
        }
        err(path, p, format!("expected `let NAME = expression;`: {e}"))
    })?;
    let stmts = block.stmts;
    let mut lets = Vec::new();
    for st in stmts {
        let syn::Stmt::Local(local) = &st else {
            return Err(err(path, pos(st.span()), "expected `let NAME = expression;` (only `let` statements are allowed)"));
        };
        let syn::Pat::Ident(pi) = &local.pat else {
            return Err(err(path, pos(local.pat.span()), "expected a plain name after `let`"));
        };
        let Some(init) = &local.init else {
            return Err(err(path, pos(local.span()), format!("expected `= expression` after `let {}`", pi.ident)));
        };
        if init.diverge.is_some() {
            return Err(err(path, pos(local.span()), "unsupported construct `let … else`"));
        }
        lets.push(Let { name: pi.ident.to_string(), pos: pos(pi.ident.span()), value: expr(path, &init.expr)? });
    }
    Ok(Spec { path: path.to_string(), lets })
}

const EXPECTED: &str = "expected a number, a name, `+ - * /`, `( … )`, `[ … ]`, a call `f(…)` or `.powi(n)`";

fn expr(path: &str, e: &syn::Expr) -> Result<Expr, CodegenError> {
    let p = pos(e.span());
    let mk = |kind| Ok(Expr { kind, pos: p });
    match e {
        syn::Expr::Lit(l) => match &l.lit {
            syn::Lit::Int(i) => mk(ExprKind::Num(decimal(i.base10_digits()).ok_or_else(|| err(path, p, "bad integer"))?)),
            syn::Lit::Float(f) => {
                mk(ExprKind::Num(decimal(f.base10_digits()).ok_or_else(|| err(path, p, "bad number: expected digits like 0.25 or 1e-3"))?))
            }
            _ => Err(err(path, p, format!("unsupported literal: {EXPECTED}"))),
        },
        syn::Expr::Path(ep) => match ep.path.get_ident() {
            Some(id) if ep.qself.is_none() => mk(ExprKind::Name(id.to_string())),
            _ => Err(err(path, p, "expected a plain name (paths like `a::b` are not supported)")),
        },
        syn::Expr::Paren(x) => expr(path, &x.expr),
        syn::Expr::Group(x) => expr(path, &x.expr),
        syn::Expr::Unary(u) => match u.op {
            syn::UnOp::Neg(_) => mk(ExprKind::Neg(Box::new(expr(path, &u.expr)?))),
            _ => Err(err(path, p, "unsupported unary operator: expected `-`")),
        },
        syn::Expr::Binary(b) => {
            let op = match b.op {
                syn::BinOp::Add(_) => BinOp::Add,
                syn::BinOp::Sub(_) => BinOp::Sub,
                syn::BinOp::Mul(_) => BinOp::Mul,
                syn::BinOp::Div(_) => BinOp::Div,
                _ => return Err(err(path, pos(b.op.span()), "unsupported operator: expected one of `+ - * /`")),
            };
            mk(ExprKind::Bin(op, Box::new(expr(path, &b.left)?), Box::new(expr(path, &b.right)?)))
        }
        syn::Expr::Call(c) => {
            let syn::Expr::Path(fp) = &*c.func else {
                return Err(err(path, pos(c.func.span()), "expected a function name before `(`"));
            };
            let Some(f) = fp.path.get_ident() else {
                return Err(err(path, pos(c.func.span()), "expected a plain function name"));
            };
            let args = c.args.iter().map(|a| expr(path, a)).collect::<Result<_, _>>()?;
            mk(ExprKind::Call(f.to_string(), args))
        }
        syn::Expr::MethodCall(m) => {
            if m.turbofish.is_some() {
                return Err(err(path, p, "unsupported construct: turbofish"));
            }
            let args = m.args.iter().map(|a| expr(path, a)).collect::<Result<_, _>>()?;
            mk(ExprKind::Method(Box::new(expr(path, &m.receiver)?), m.method.to_string(), args))
        }
        syn::Expr::Array(a) => {
            let items = a.elems.iter().map(|x| expr(path, x)).collect::<Result<_, _>>()?;
            mk(ExprKind::List(items))
        }
        other => Err(err(path, p, format!("unsupported construct `{}`: {EXPECTED}", kind_name(other)))),
    }
}

fn kind_name(e: &syn::Expr) -> &'static str {
    match e {
        syn::Expr::If(_) => "if",
        syn::Expr::Match(_) => "match",
        syn::Expr::Closure(_) => "closure",
        syn::Expr::Block(_) => "block",
        syn::Expr::Loop(_) | syn::Expr::While(_) | syn::Expr::ForLoop(_) => "loop",
        syn::Expr::Index(_) => "indexing",
        syn::Expr::Field(_) => "field access",
        syn::Expr::Macro(_) => "macro",
        syn::Expr::Reference(_) => "reference",
        syn::Expr::Cast(_) => "cast",
        syn::Expr::Tuple(_) => "tuple",
        syn::Expr::Assign(_) => "assignment",
        syn::Expr::Range(_) => "range",
        _ => "expression",
    }
}

/// Exact value of a decimal literal such as `12`, `0.25`, `1e-3`, `2.5E2`.
pub fn decimal(s: &str) -> Option<Rat> {
    let s = s.replace('_', "");
    let (mant, exp) = match s.find(['e', 'E']) {
        Some(i) => (&s[..i], s[i + 1..].parse::<i32>().ok()?),
        None => (&s[..], 0),
    };
    let (int, frac) = match mant.find('.') {
        Some(i) => (&mant[..i], &mant[i + 1..]),
        None => (mant, ""),
    };
    let digits: BigInt = format!("{int}{frac}").parse().ok()?;
    let e = exp - frac.len() as i32;
    let ten = rat(10);
    let mut r = Rat::from_integer(digits);
    for _ in 0..e.unsigned_abs() {
        if e > 0 {
            r *= &ten;
        } else {
            r /= &ten;
        }
    }
    Some(r)
}
