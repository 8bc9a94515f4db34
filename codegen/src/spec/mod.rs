//! Derivation specs: Rust-syntax `let` statements parsed with syn (never compiled or run).
//!
//! A spec is a sequence of `let NAME = EXPR;` (doc comments allowed). Expressions use numbers
//! (exact rationals: `0.25` is 1/4), names, `+ - * /`, parentheses, `.powi(n)`, `.sqrt()`,
//! calls (`sqrt`, `sin`, `cos`, `d(e, Theta)`, `diff(name, var)`, `P(k)`, `P1(k)`) and, for
//! `symbols`/`amplitudes`, a list of names `[a, b]`. See derivations/README.md.

pub mod ast;
pub mod parse;
pub mod validate;

pub use ast::{Expr, ExprKind, Let, Pos, Spec};
