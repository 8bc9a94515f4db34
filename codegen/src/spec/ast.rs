//! The parsed spec.

use crate::algebra::Rat;

/// 1-based line and column in the spec file.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Pos {
    pub line: usize,
    pub column: usize,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BinOp {
    Add,
    Sub,
    Mul,
    Div,
}

#[derive(Clone, Debug)]
pub enum ExprKind {
    Num(Rat),
    Name(String),
    Neg(Box<Expr>),
    Bin(BinOp, Box<Expr>, Box<Expr>),
    /// `f(args)`
    Call(String, Vec<Expr>),
    /// `receiver.method(args)`
    Method(Box<Expr>, String, Vec<Expr>),
    /// `[a, b, c]`
    List(Vec<Expr>),
}

#[derive(Clone, Debug)]
pub struct Expr {
    pub kind: ExprKind,
    pub pos: Pos,
}

/// `let name = value;`
#[derive(Clone, Debug)]
pub struct Let {
    pub name: String,
    pub pos: Pos,
    pub value: Expr,
}

#[derive(Clone, Debug)]
pub struct Spec {
    /// Path as shown in messages and in the `@generated` header (e.g. `derivations/coil.rs`).
    pub path: String,
    pub lets: Vec<Let>,
}

impl Spec {
    pub fn get(&self, name: &str) -> Option<&Let> {
        self.lets.iter().find(|l| l.name == name)
    }
}
