//! Emission of the second-order membrane loads (issue 12; derive/quadratic_membrane.rs), as Rust
//! (module `quadratic_membrane`) and as review markdown.

use crate::algebra::triple::Triple;
use crate::algebra::{rat_f64, rat_text};
use crate::derive::fit3::Poly3;
use crate::derive::project::Load;
use crate::derive::quadratic_membrane::{Ab, MembraneTerm2};
use crate::emit::f;
use crate::Derived;
use num_traits::{One, Signed};
use proc_macro2::{Literal, TokenStream};
use quote::quote;

/// N(L_l, L_m, L_j) as text, e.g. `4 - 2*Ll - 2*Lm`.
pub fn numerator_text(p: &Poly3) -> String {
    if p.terms.is_empty() {
        return "0".into();
    }
    let mut s = String::new();
    for (i, (e, c)) in p.terms.iter().enumerate() {
        let a = c.abs();
        let mut factors: Vec<String> = Vec::new();
        for (name, k) in ["Ll", "Lm", "Lj"].iter().zip(e) {
            match k {
                0 => {}
                1 => factors.push(name.to_string()),
                _ => factors.push(format!("{name}^{k}")),
            }
        }
        let body = match (a.is_one(), factors.is_empty()) {
            (true, true) => "1".to_string(),
            (true, false) => factors.join("*"),
            (false, true) => rat_text(&a),
            (false, false) => format!("{}*{}", rat_text(&a), factors.join("*")),
        };
        s += &match (i, c.is_negative()) {
            (0, false) => body,
            (0, true) => format!("-{body}"),
            (_, false) => format!(" + {body}"),
            (_, true) => format!(" - {body}"),
        };
    }
    s
}

fn ab(a: Ab) -> TokenStream {
    match a {
        Ab::A => quote!(Ab::A),
        Ab::B => quote!(Ab::B),
        Ab::Ad => quote!(Ab::Ad),
        Ab::Bd => quote!(Ab::Bd),
    }
}

fn term(t: &MembraneTerm2) -> TokenStream {
    let name = t.name();
    let form = match t.form {
        "paper" => quote!(Form::Paper),
        _ => quote!(Form::Tension),
    };
    let load = match t.load {
        Load::Normal => quote!(super::Load::Normal),
        Load::Tangential => quote!(super::Load::Tangential),
    };
    let (first, second) = (ab(t.first), ab(t.second));
    let pre = t.prefactor.0.iter().map(|(s, p)| {
        let p = Literal::i32_unsuffixed(*p);
        quote!((#s, #p))
    });
    let num = t.numerator.terms.iter().map(|(e, c)| {
        let (a, b, cc) = (Literal::u32_unsuffixed(e[0]), Literal::u32_unsuffixed(e[1]), Literal::u32_unsuffixed(e[2]));
        let v = f(rat_f64(c));
        quote!(([#a, #b, #cc], #v))
    });
    let text = numerator_text(&t.numerator);
    quote!(Term { name: #name, form: #form, load: #load, first: #first, second: #second, prefactor: &[#(#pre),*], numerator: &[#(#num),*], numerator_text: #text })
}

/// The `quadratic_membrane` module of the generated file (empty without laws).
pub fn rust(d: &Derived) -> TokenStream {
    if d.membrane_quadratic.is_empty() {
        return quote!();
    }
    let laws = d.membrane_quadratic.iter().map(|q| {
        let (name, spec) = (&q.law, &q.spec_path);
        let symbols = q.symbols.iter();
        let terms = q.terms.iter().map(term);
        quote!(Law { name: #name, spec: #spec, symbols: &[#(#symbols),*], terms: &[#(#terms),*] })
    });
    let (fit, check) = (
        Literal::usize_unsuffixed(crate::derive::quadratic_membrane::FIT_MODES),
        Literal::usize_unsuffixed(crate::derive::quadratic_membrane::CHECK_MODES),
    );
    quote! {
        /// Second-order membrane loads of the laws with a strain energy (issue 12; docs/model.md,
        /// "Quadratic mode coupling"): the bilinear part of the load F_n (on P_j) or F_t (on P^1_j),
        /// at the material angle, is Σ_T Σ_{l,m} value_T(j, l, m) · prefactor_T · first_T(l) ·
        /// second_T(m), value = C(j, l, m) N_T(L_l, L_m, L_j)/D, C the coefficient of P_j in P_l P_m,
        /// L_n = n(n+1), D = 1 (normal) or L_j (tangential; no j = 0).
        pub mod quadratic_membrane {
            /// The closed forms were fitted on modes ≤ FIT_MODES and verified exactly up to CHECK_MODES.
            pub const FIT_MODES: usize = #fit;
            pub const CHECK_MODES: usize = #check;
            /// The membrane form (`shell.form`).
            #[derive(Clone, Copy, Debug, PartialEq, Eq)]
            pub enum Form { Paper, Tension }
            /// Which amplitude: a_k or b_k, or their rates ȧ_k, ḃ_k (a viscous law).
            #[derive(Clone, Copy, Debug, PartialEq, Eq)]
            pub enum Ab { A, B, Ad, Bd }
            #[derive(Debug)]
            pub struct Term {
                pub name: &'static str,
                pub form: Form,
                pub load: super::Load,
                pub first: Ab,
                pub second: Ab,
                /// Symbols: R, R0, Rd (Ṙ, a viscous law) and the law's symbols (ε-scaled, as the linear tables).
                pub prefactor: &'static [(&'static str, i32)],
                /// N = Σ coeff · L_l^a L_m^b L_j^c, entries ([a, b, c], coeff).
                pub numerator: &'static [([u32; 3], f64)],
                pub numerator_text: &'static str,
            }
            #[derive(Debug)]
            pub struct Law {
                pub name: &'static str,
                pub spec: &'static str,
                pub symbols: &'static [&'static str],
                pub terms: &'static [Term],
            }
            pub static LAWS: &[Law] = &[#(#laws),*];
        }
    }
}

/// The review markdown of the second-order membrane loads.
pub fn markdown(d: &Derived) -> String {
    let mut s = String::new();
    let t = Triple::new(2 * crate::derive::quadratic_membrane::CHECK_MODES + 2);
    for q in &d.membrane_quadratic {
        s += &format!(
            "\n## Second-order membrane loads of `{}` (from `{}`)\n\nOn target j: Σ_(l,m) C(j,l,m) N(L_l, L_m, L_j)/D · prefactor · first_l · second_m, \
             L_n = n(n+1), D = 1 (normal, on P_j) or L_j (tangential, on P¹_j). Fitted on modes ≤ {}, verified exactly on modes ≤ {}.\n\n\
             | form | load | term | N(Ll, Lm, Lj) |\n|---|---|---|---|\n",
            q.law,
            q.spec_path,
            crate::derive::quadratic_membrane::FIT_MODES,
            crate::derive::quadratic_membrane::CHECK_MODES
        );
        for term in &q.terms {
            s += &format!("| {} | {:?} | `{}` | `{}` |\n", term.form, term.load, term.name(), numerator_text(&term.numerator));
        }
        s += "\nExact values (paper form), modes ≤ 4:\n\n| (j, l, m) |";
        let shown: Vec<&MembraneTerm2> = q.terms.iter().filter(|t| t.form == "paper").collect();
        for term in &shown {
            s += &format!(" {:?} `{}` |", term.load, term.name());
        }
        s += "\n|---|";
        s += &"---|".repeat(shown.len());
        s += "\n";
        for l in [2usize, 4] {
            for m in [2usize, 4] {
                for j in (l.abs_diff(m)..=l + m).step_by(2) {
                    s += &format!("| ({j}, {l}, {m}) |");
                    for term in &shown {
                        s += &format!(" {} |", rat_text(&term.value(&t, j, l, m)));
                    }
                    s += "\n";
                }
            }
        }
    }
    s
}
