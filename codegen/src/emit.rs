//! Emission: the Rust tables (quote + prettyplease, deterministic) and the markdown review table.

use crate::algebra::dual::RATE_R;
use crate::algebra::{rat_f64, rat_text, Mono, Rat};
use crate::derive::field::{ComponentData, CouplingData, FieldData};
use crate::derive::fit::poly_text;
use crate::derive::membrane::{Membrane, MembraneCoeff};
use crate::derive::project::{Amp, Load};
use crate::error::CodegenError;
use crate::Derived;
use num_traits::{One, Signed, Zero};
use proc_macro2::{Literal, TokenStream};
use quote::{format_ident, quote};

/// f64 literal tokens (a leading `-` is a separate token).
pub(crate) fn f(v: f64) -> TokenStream {
    let lit = Literal::f64_unsuffixed(v.abs());
    if v.is_sign_negative() && v != 0.0 {
        quote!(-#lit)
    } else {
        quote!(#lit)
    }
}

/// `coeff * Π symbol^power` as text, e.g. `mu0*chi_s*H2^2*R0^2/(4*a^2*R^2)`.
pub fn monomial_text(c: &Rat, m: &Mono) -> String {
    let fmt = |(s, p): &(String, i32)| if p.abs() == 1 { s.clone() } else { format!("{s}^{}", p.abs()) };
    let mut num: Vec<String> = Vec::new();
    let mut den: Vec<String> = Vec::new();
    if !c.numer().abs().is_one() {
        num.push(c.numer().abs().to_string());
    }
    if !c.denom().is_one() {
        den.push(c.denom().to_string());
    }
    num.extend(m.0.iter().filter(|(_, p)| *p > 0).map(fmt));
    den.extend(m.0.iter().filter(|(_, p)| *p < 0).map(fmt));
    let sign = if c.is_negative() { "-" } else { "" };
    let n = if num.is_empty() { "1".to_string() } else { num.join("*") };
    match den.len() {
        0 => format!("{sign}{n}"),
        1 => format!("{sign}{n}/{}", den[0]),
        _ => format!("{sign}{n}/({})", den.join("*")),
    }
}

fn monomial(c: &Rat, m: &Mono) -> TokenStream {
    let coeff = f(rat_f64(c));
    let exact = rat_text(c);
    let powers = m.0.iter().map(|(s, p)| {
        let p = Literal::i32_unsuffixed(*p);
        quote!((#s, #p))
    });
    let text = monomial_text(c, m);
    quote!(Monomial { coeff: #coeff, coeff_exact: #exact, powers: &[#(#powers),*], text: #text })
}

fn coupling(c: &CouplingData) -> TokenStream {
    let name = &c.name;
    let load = match c.load {
        Load::Normal => quote!(Load::Normal),
        Load::Tangential => quote!(Load::Tangential),
    };
    let amp = match c.amp {
        Amp::A => quote!(Amp::A),
        Amp::B => quote!(Amp::B),
        // rate amplitudes exist only in shell laws (validate rejects `rate` in a field spec)
        Amp::Ad | Amp::Bd => quote!(compile_error!("rate amplitude in a field table")),
    };
    let offset = Literal::i32_unsuffixed(c.offset);
    let values = c.values.iter().map(|v| match v {
        Some(v) => {
            let x = f(rat_f64(v));
            quote!(Some(#x))
        }
        None => quote!(None),
    });
    let exact = c.values.iter().map(|v| match v {
        Some(v) => {
            let s = rat_text(v);
            quote!(Some(#s))
        }
        None => quote!(None),
    });
    let closed = c.closed.as_ref().map(|c| c.text()).unwrap_or_default();
    quote!(Coupling {
        name: #name, load: #load, amp: #amp, offset: #offset,
        values: &[#(#values),*],
        exact: &[#(#exact),*],
        closed_form: #closed,
    })
}

fn component(c: &ComponentData) -> TokenStream {
    let pre = monomial(&c.prefactor.0, &c.prefactor.1);
    let m = Literal::i32_unsuffixed(c.r_power);
    let pairs = |v: &[(usize, Rat)]| -> Vec<TokenStream> {
        v.iter()
            .map(|(j, x)| {
                let x = f(rat_f64(x));
                let j = Literal::usize_unsuffixed(*j);
                quote!((#j, #x))
            })
            .collect()
    };
    let (zn, zt) = (pairs(&c.zero_normal), pairs(&c.zero_tangential));
    let cs = c.couplings.iter().map(coupling);
    quote!(Component {
        prefactor: #pre, r_power: #m,
        zero_normal: &[#(#zn),*], zero_tangential: &[#(#zt),*],
        couplings: &[#(#cs),*],
    })
}

fn field(fd: &FieldData) -> TokenStream {
    let ident = format_ident!("{}", fd.name.to_uppercase());
    let (name, spec) = (&fd.name, &fd.spec_path);
    let comps = fd.components.iter().map(component);
    let doc = format!(" Magnetic load table `{name}`, derived from `{spec}`.");
    quote!(#[doc = #doc] pub static #ident: FieldTable = FieldTable { name: #name, spec: #spec, components: &[#(#comps),*] };)
}

fn arg_name(sym: &str) -> String {
    sym.to_lowercase()
}

/// `pub fn s1(r, r0, c1, c2, k)`, or with `d_r` its exact derivative ∂/∂R `pub fn s1_dr(…)` (for
/// the model's analytic Jacobian: each monomial R^p becomes p R^(p−1)).
fn membrane_fn(c: &MembraneCoeff, args: &[String], d_r: bool) -> Result<TokenStream, CodegenError> {
    let mut body: Vec<String> = Vec::new();
    for (mono, p) in &c.terms {
        let r_power = mono.0.iter().find(|(s, _)| s == "R").map_or(0, |(_, pw)| *pw);
        if d_r && r_power == 0 {
            continue;
        }
        let poly: Vec<String> = p
            .iter()
            .enumerate()
            .filter(|(_, v)| !v.is_zero())
            .map(|(i, v)| {
                let lit = format!("{:?}", rat_f64(v));
                match i {
                    0 => format!("({lit})"),
                    1 => format!("({lit}) * n"),
                    _ => format!("({lit}) * n.powi({i})"),
                }
            })
            .collect();
        let mut factors = vec![format!("({})", poly.join(" + "))];
        if d_r {
            factors.push(format!("({:?})", r_power as f64));
        }
        for (s, pw) in &mono.0 {
            let pw = if d_r && s == "R" { pw - 1 } else { *pw };
            factors.push(format!("{}.powi({pw})", arg_name(s)));
        }
        body.push(factors.join(" * "));
    }
    let expr_text = if body.is_empty() { "0.0".to_string() } else { body.join(" + ") };
    let expr: syn::Expr = syn::parse_str(&expr_text).map_err(|e| CodegenError::Emit(format!("{e}: {expr_text}")))?;
    let name = if d_r { format_ident!("{}_dr", c.name) } else { format_ident!("{}", c.name) };
    let params = args.iter().map(|a| {
        let a = format_ident!("{a}");
        quote!(#a: f64)
    });
    let doc = if d_r {
        format!(" ∂{}/∂R, {} = {}", c.name.to_uppercase(), c.name.to_uppercase(), membrane_text(c))
    } else {
        format!(" {} = {}", c.name.to_uppercase(), membrane_text(c))
    };
    if c.uses_k {
        Ok(quote!(#[doc = #doc] #[allow(unused_variables)] #[inline] pub fn #name(#(#params,)* k: f64) -> f64 { let n = k * (k + 1.0); #expr }))
    } else {
        Ok(quote!(#[doc = #doc] #[allow(unused_variables)] #[inline] pub fn #name(#(#params),*) -> f64 { #expr }))
    }
}

/// Exact text of a membrane coefficient, e.g. `(2*n - 4)*C1/R^2 + …`.
pub fn membrane_text(c: &MembraneCoeff) -> String {
    let parts: Vec<String> = c
        .terms
        .iter()
        .map(|(mono, p)| {
            let lcm = p.iter().fold(num_bigint::BigInt::one(), |acc, v| num_integer::Integer::lcm(&acc, v.denom()));
            let ints: Vec<num_bigint::BigInt> = p.iter().map(|v| (v * Rat::from_integer(lcm.clone())).to_integer()).collect();
            let poly = poly_text(&ints, "n");
            let scale = if lcm.is_one() { String::new() } else { format!("/{lcm}") };
            format!("({poly}){scale}*{}", monomial_text(&Rat::one(), mono))
        })
        .collect();
    if parts.is_empty() {
        "0".into()
    } else {
        parts.join(" + ")
    }
}

/// Arguments of every function of one law: r, r0, then rd when a coefficient depends on Ṙ, then
/// the law's symbols (lower case).
fn law_args(m: &Membrane) -> Vec<String> {
    let mut args = vec!["r".to_string(), "r0".to_string()];
    let rate = m.variants.iter().flat_map(|v| v.coeffs.iter()).flat_map(|c| c.terms.iter()).any(|(mono, _)| mono.power(RATE_R) != 0);
    if rate {
        args.push(arg_name(RATE_R));
    }
    args.extend(m.symbols.iter().map(|s| arg_name(s)));
    args
}

fn law(m: &Membrane) -> Result<TokenStream, CodegenError> {
    let args = law_args(m);
    let mut mods = Vec::new();
    for v in &m.variants {
        let fns = v
            .coeffs
            .iter()
            .flat_map(|c| [membrane_fn(c, &args, false), membrane_fn(c, &args, true)])
            .collect::<Result<Vec<_>, _>>()?;
        let name = format_ident!("{}", v.variant);
        let doc = match v.variant {
            "paper" => " The paper's form: F = −div σ/(λ1λ2) (eqs 2.26–2.29, FORMULATION §1).",
            _ => " The tension form: F_t from the divergence of εσ/α (FORMULATION §2).",
        };
        mods.push(quote!(#[doc = #doc] pub mod #name { #(#fns)* }));
    }
    let name = format_ident!("{}", m.law);
    let doc = format!(" Shell law `{}`, derived from `{}` with {}.", m.law, m.spec_path, m.mechanics.join(", "));
    let spec = &m.spec_path;
    let syms = m.symbols.iter();
    let arg_list = args.join(", ");
    Ok(quote!(#[doc = #doc] pub mod #name {
        /// The spec the law was derived from.
        pub const SPEC: &str = #spec;
        /// The law's symbols, in the order of the functions' arguments after r, r0 (and rd).
        pub const SYMBOLS: &[&str] = &[#(#syms),*];
        /// The arguments of every function of this law (k last, where it applies).
        pub const ARGS: &str = #arg_list;
        #(#mods)*
    }))
}

fn membrane(d: &Derived) -> Result<TokenStream, CodegenError> {
    let laws = d.membranes.iter().map(law).collect::<Result<Vec<_>, _>>()?;
    let names = d.membranes.iter().map(|m| &m.law);
    let compat = if d.membranes.iter().any(|m| m.law == "mooney_rivlin") {
        quote!(
            /// The paper's Mooney–Rivlin membrane (eq 2.24) under its historical names.
            pub use self::mooney_rivlin::{paper, tension};
        )
    } else {
        quote!()
    };
    let doc = " Shell loads (ε-scaled: c_i = ε C_i; 2-D laws in N/m), one module per law of derivations/shell/; k enters through n = k(k+1).";
    Ok(quote!(#[doc = #doc] pub mod membrane {
        /// The laws, in module order.
        pub const LAWS: &[&str] = &[#(#names),*];
        #compat
        #(#laws)*
    }))
}

/// The `@generated` header line.
pub fn header(d: &Derived) -> String {
    format!("// @generated by codegen from {}.  Do not edit.\n", d.specs.join(", "))
}

/// The Rust source of the tables (see docs/architecture.md).
pub fn rust(d: &Derived) -> Result<String, CodegenError> {
    let kmax = Literal::usize_unsuffixed(d.kmax);
    let fields = d.fields.iter().map(field);
    let membrane = membrane(d)?;
    let quadratic = crate::emit_quadratic::rust(d);
    let quadratic_membrane = crate::emit_quadratic_membrane::rust(d);
    let tokens = quote! {
        /// Largest mode of the tables (build setting MAGBUBBLE_KMAX).
        pub const KMAX: usize = #kmax;
        /// Load a coupling lands on: normal (projected on P_j) or tangential (on P^1_j).
        #[derive(Clone, Copy, Debug, PartialEq, Eq)]
        pub enum Load { Normal, Tangential }
        /// Amplitude a coupling multiplies: a_k or b_k.
        #[derive(Clone, Copy, Debug, PartialEq, Eq)]
        pub enum Amp { A, B }
        /// coeff · Π symbol^power.
        #[derive(Debug)]
        pub struct Monomial {
            pub coeff: f64,
            pub coeff_exact: &'static str,
            pub powers: &'static [(&'static str, i32)],
            pub text: &'static str,
        }
        /// Load on target mode k from the amplitude of mode k + offset, in units of ℋ·R^(m−1).
        #[derive(Debug)]
        pub struct Coupling {
            pub name: &'static str,
            pub load: Load,
            pub amp: Amp,
            pub offset: i32,
            pub values: &'static [Option<f64>],
            pub exact: &'static [Option<&'static str>],
            pub closed_form: &'static str,
        }
        /// One product of field amplitudes.
        #[derive(Debug)]
        pub struct Component {
            pub prefactor: Monomial,
            pub r_power: i32,
            pub zero_normal: &'static [(usize, f64)],
            pub zero_tangential: &'static [(usize, f64)],
            pub couplings: &'static [Coupling],
        }
        /// The magnetic load table of one field spec.
        #[derive(Debug)]
        pub struct FieldTable {
            pub name: &'static str,
            pub spec: &'static str,
            pub components: &'static [Component],
        }
        #(#fields)*
        #membrane
        #quadratic
        #quadratic_membrane
    };
    let file: syn::File = syn::parse2(tokens).map_err(|e| CodegenError::Emit(e.to_string()))?;
    Ok(format!("{}{}", header(d), prettyplease::unparse(&file)))
}

/// A readable markdown table of every coefficient.
pub fn markdown(d: &Derived) -> String {
    let mut s = format!("<!-- {} -->\n# Coefficient tables (KMAX = {})\n\n", header(d).trim_start_matches("// ").trim(), d.kmax);
    s += "Conventions: FORMULATION §0–1 (x = cos Θ, P^1_k = dP_k/dΘ, Condon–Shortley). A coupling `offset` o means: \
          load on target mode k from the amplitude of mode k + o. Normal loads scale as ℋ·R^m (zero order) and \
          ℋ·R^(m−1) per unit amplitude.\n\n";
    for fd in &d.fields {
        s += &format!("## Field `{}` (from `{}`)\n\n", fd.name, fd.spec_path);
        for (i, c) in fd.components.iter().enumerate() {
            s += &format!(
                "### Component {} ({}): ℋ = {}, m = {}\n\n",
                i + 1,
                monomial_text(&Rat::one(), &c.amplitudes),
                monomial_text(&c.prefactor.0, &c.prefactor.1),
                c.r_power
            );
            let list = |v: &[(usize, Rat)], p: &str| v.iter().map(|(j, x)| format!("{p}_{j}: {}", rat_text(x))).collect::<Vec<_>>().join(", ");
            s += &format!("Zero order (× ℋ·R^m): normal {{{}}}; tangential {{{}}}\n\n", list(&c.zero_normal, "P"), list(&c.zero_tangential, "P^1"));
            s += "| coupling | load | amp | offset | closed form |\n|---|---|---|---|---|\n";
            for cp in &c.couplings {
                let cf = cp.closed.as_ref().map(|c| format!("`{}`", c.text())).unwrap_or_else(|| "(none found)".into());
                s += &format!("| {} | {:?} | {:?} | {:+} | {cf} |\n", cp.name, cp.load, cp.amp, cp.offset);
            }
            s += "\nExact values (target k):\n\n| k |";
            for cp in &c.couplings {
                s += &format!(" {} |", cp.name);
            }
            s += "\n|---|";
            s += &"---|".repeat(c.couplings.len());
            s += "\n";
            for k in 0..=d.kmax {
                s += &format!("| {k} |");
                for cp in &c.couplings {
                    s += &format!(" {} |", cp.values[k].as_ref().map(rat_text).unwrap_or_else(|| "—".into()));
                }
                s += "\n";
            }
            s += "\n";
        }
    }
    for m in &d.membranes {
        s += &format!(
            "## Shell law `{}` (from `{}` with {}), n = k(k+1); arguments ({}, k)\n\n",
            m.law,
            m.spec_path,
            m.mechanics.join(", "),
            law_args(m).join(", ")
        );
        for v in &m.variants {
            s += &format!("### {}\n\n", v.variant);
            for c in &v.coeffs {
                s += &format!("- {} = {}\n", c.name.to_uppercase(), membrane_text(c));
            }
            s += "\n";
        }
    }
    s + &crate::emit_quadratic::markdown(d) + &crate::emit_quadratic_membrane::markdown(d)
}
