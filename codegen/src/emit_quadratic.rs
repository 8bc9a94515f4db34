//! Emission of the quadratic tables (issue 12): the triple-product tensors and the free-bubble
//! quadratic loads (their closed forms), as Rust (module `quadratic`) and as review markdown.

use crate::algebra::triple::Triple;
use crate::algebra::{rat_f64, rat_text, Rat};
use crate::derive::quadratic::{Amp2, QuadTerm};
use crate::Derived;
use proc_macro2::{Literal, TokenStream};
use quote::quote;

use crate::emit::f;

/// (l, m, j) of the even-mode set: 2 ≤ l ≤ m ≤ kmax even, j even in the triangle and ≤ kmax.
fn triples(kmax: usize) -> Vec<(usize, usize, usize)> {
    let mut v = Vec::new();
    for l in (2..=kmax).step_by(2) {
        for m in (l..=kmax).step_by(2) {
            for j in (m - l..=(l + m).min(kmax)).step_by(2) {
                v.push((l, m, j));
            }
        }
    }
    v
}

fn tensor(kmax: usize, t: &Triple, value: impl Fn(&Triple, usize, usize, usize) -> Rat) -> TokenStream {
    let rows = triples(kmax).into_iter().map(|(l, m, j)| {
        let x = f(rat_f64(&value(t, l, m, j)));
        let (l, m, j) = (Literal::u16_unsuffixed(l as u16), Literal::u16_unsuffixed(m as u16), Literal::u16_unsuffixed(j as u16));
        quote!((#l, #m, #j, #x))
    });
    quote!(&[#(#rows),*])
}

fn amp(a: Amp2) -> TokenStream {
    match a {
        Amp2::A => quote!(Amp2::A),
        Amp2::Ad => quote!(Amp2::Ad),
        Amp2::Add => quote!(Amp2::Add),
    }
}

fn term(q: &QuadTerm) -> TokenStream {
    let name = q.name();
    let (first, second) = (amp(q.first), amp(q.second));
    let pre = q.prefactor.0.iter().map(|(s, p)| {
        let p = Literal::i32_unsuffixed(*p);
        quote!((#s, #p))
    });
    let num = q.numerator.terms.iter().map(|(e, c)| {
        let (a, b, cc) = (Literal::u32_unsuffixed(e[0]), Literal::u32_unsuffixed(e[1]), Literal::u32_unsuffixed(e[2]));
        let v = f(rat_f64(c));
        quote!(([#a, #b, #cc], #v))
    });
    let text = q.numerator.text();
    let (den, radial) = (q.denominator, q.radial_only);
    quote!(Term {
        name: #name, first: #first, second: #second, prefactor: &[#(#pre),*],
        denominator: #den, radial_only: #radial, numerator: &[#(#num),*], numerator_text: #text,
    })
}

/// The `quadratic` module of the generated file (empty token stream without the spec).
pub fn rust(d: &Derived) -> TokenStream {
    let Some(q) = &d.quadratic else { return quote!() };
    let t = Triple::new(2 * d.kmax + 2);
    let ppp = tensor(d.kmax, &t, |t, l, m, j| t.ppp(l, m, j));
    let p1p1p = tensor(d.kmax, &t, |t, l, m, j| t.p1p1p(l, m, j));
    let pp1p1 = tensor(d.kmax, &t, |t, l, m, j| t.pp1p1(j, l, m));
    let terms = q.terms.iter().map(term);
    let spec = &q.spec_path;
    let (fit, check) = (Literal::usize_unsuffixed(q.fit_modes), Literal::usize_unsuffixed(q.check_modes));
    quote! {
        /// Second-order (quadratic) mode coupling (issue 12; docs/model.md, "Quadratic mode coupling").
        /// x = cos θ, P^1_n = dP_n/dθ. Tensors over the even-mode set: entries (l, m, j, value) for
        /// 2 ≤ l ≤ m ≤ KMAX, j even with m − l ≤ j ≤ min(l + m, KMAX); zero elsewhere.
        pub mod quadratic {
            /// The spec the free-bubble terms were derived from.
            pub const SPEC: &str = #spec;
            /// The closed forms were fitted on modes ≤ FIT_MODES and verified exactly up to CHECK_MODES.
            pub const FIT_MODES: usize = #fit;
            pub const CHECK_MODES: usize = #check;
            /// ∫_{−1}^{1} P_l P_m P_j dx (Adams), symmetric in (l, m, j).
            pub static PPP: &[(u16, u16, u16, f64)] = #ppp;
            /// ∫ P^1_l P^1_m P_j dx = ½(L_l + L_m − L_j) ∫ P_l P_m P_j dx, L_n = n(n+1).
            pub static P1P1P: &[(u16, u16, u16, f64)] = #p1p1p;
            /// ∫ P_j P^1_l P^1_m dx (a product of two tangential fields on P_j), entries (l, m, j).
            pub static PP1P1: &[(u16, u16, u16, f64)] = #pp1p1;
            /// Which derivative of a mode amplitude: a, ȧ, ä.
            #[derive(Clone, Copy, Debug, PartialEq, Eq)]
            pub enum Amp2 { A, Ad, Add }
            /// One quadratic load: on target j, Σ_{l,m} value(j,l,m) · prefactor · first(l) · second(m),
            /// value = s_j C(j,l,m) N(l,m,j)/D, C the coefficient of P_j in P_l P_m, D = (l+1)(m+1)(j+1)
            /// when `denominator`, else 1; s_0 = +1 (added to the radial balance), s_j = −1 (added to G_n,j).
            /// `radial_only`: only j = 0.
            #[derive(Debug)]
            pub struct Term {
                pub name: &'static str,
                pub first: Amp2,
                pub second: Amp2,
                /// Symbols: rho, gamma, R, Rd (Ṙ), Rdd (R̈), pg (gas pressure at R), kappa.
                pub prefactor: &'static [(&'static str, i32)],
                pub denominator: bool,
                pub radial_only: bool,
                /// N(l, m, j) = Σ coeff · l^a m^b j^c, entries ([a, b, c], coeff).
                pub numerator: &'static [([u32; 3], f64)],
                pub numerator_text: &'static str,
            }
            /// The free bubble in an inviscid liquid with surface tension and a polytropic gas.
            pub static FREE_BUBBLE: &[Term] = &[#(#terms),*];
        }
    }
}

/// The review markdown of the quadratic tables.
pub fn markdown(d: &Derived) -> String {
    let Some(q) = &d.quadratic else { return String::new() };
    let t = Triple::new(2 * d.kmax + 2);
    let mut s = format!(
        "## Quadratic coupling (from `{}`)\n\nOn target j: Σ_(l,m) value(j,l,m) · prefactor · first_l · second_m, \
         value = s_j C(j,l,m) N(l,m,j)/D with C the coefficient of P_j in P_l P_m, D = (l+1)(m+1)(j+1) or 1, \
         s_0 = +1 (radial balance), s_j = −1 (G_n,j). Fitted on modes ≤ {}, verified exactly on modes ≤ {}.\n\n\
         | term | D | N(l, m, j) |\n|---|---|---|\n",
        q.spec_path, q.fit_modes, q.check_modes
    );
    for term in &q.terms {
        let den = if term.denominator { "(l+1)(m+1)(j+1)" } else { "1" };
        let only = if term.radial_only { " (j = 0 only)" } else { "" };
        s += &format!("| `{}`{only} | {den} | `{}` |\n", term.name(), term.numerator.text());
    }
    s += "\nExact values, modes ≤ 6:\n\n| (j, l, m) | C(j,l,m) |";
    for term in &q.terms {
        s += &format!(" `{}` |", term.name());
    }
    s += "\n|---|---|";
    s += &"---|".repeat(q.terms.len());
    s += "\n";
    for l in (2..=6usize.min(d.kmax)).step_by(2) {
        for m in (2..=6usize.min(d.kmax)).step_by(2) {
            for j in (l.abs_diff(m)..=(l + m).min(d.kmax)).step_by(2) {
                s += &format!("| ({j}, {l}, {m}) | {} |", rat_text(&t.product_coefficient(l, m, j)));
                for term in &q.terms {
                    s += &format!(" {} |", rat_text(&term.value(&t, j, l, m)));
                }
                s += "\n";
            }
        }
    }
    let shown = triples(d.kmax.min(8));
    s += "\nTriple integrals (l ≤ m ≤ 8): (l, m, j): ∫PPP, ∫P¹P¹P, ∫P_jP¹_lP¹_m\n\n";
    for (l, m, j) in shown {
        s += &format!("- ({l}, {m}, {j}): {}, {}, {}\n", rat_text(&t.ppp(l, m, j)), rat_text(&t.p1p1p(l, m, j)), rat_text(&t.pp1p1(j, l, m)));
    }
    s + "\n"
}
