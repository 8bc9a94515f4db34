//! `magbubble coefficients`: print the generated Legendre-coupling coefficients of a field
//! (issue 2, part 5), next to the paper's printed appendix formulas.
//!
//! Couplings are in units of the prefactor ℋ (coil: μ0χ_sH2²R0²/(4a²R²); dipole:
//! −36μ0χ_sM²R0²/(z⁸R²), the appendix's with its dimension corrected, see
//! docs/derivation-notes.md); the zero-order terms ℋ0, ℋ2, ℋ^1_2 in units of ℋR.

use crate::api::coefficients::{coefficients, Coefficients, Column, Field};
use crate::field::appendix;

/// Which field's tables to print.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum FieldChoice {
    /// Two coils, H2 term (Appendix A).
    Coil,
    /// Two dipoles (Appendix B).
    Dipole,
}

/// Arguments of `magbubble coefficients`.
#[derive(Debug, clap::Args)]
#[command(after_help = "Couplings are in units of the prefactor H (printed as text), the zero-order \
terms H0, H2, H1_2 in units of H*R. Index k of each array is the target mode of eq. (2.40); null \
where a coupling does not exist. `differs` lists the couplings whose printed appendix formula \
disagrees with the derivation for some k <= kmax where the paper prints it (eq. 2.40: F3, F4 from \
k = 0, F1, F2 from k = 2, F5, F6 from k = 4; likewise the tangential F1t..F6t); see \
docs/derivation-notes.md.")]
pub struct CoefficientsArgs {
    /// Field: coil or dipole.
    #[arg(long, value_enum)]
    pub field: FieldChoice,
    /// Highest target mode k to print (0 ..= the build's KMAX).
    #[arg(long)]
    pub kmax: usize,
    /// Print one JSON object instead of a table.
    #[arg(long)]
    pub json: bool,
}

impl From<FieldChoice> for Field {
    fn from(f: FieldChoice) -> Field {
        match f {
            FieldChoice::Coil => Field::Coil,
            FieldChoice::Dipole => Field::Dipole,
        }
    }
}

pub fn run(args: &CoefficientsArgs) -> anyhow::Result<()> {
    let tables = coefficients(args.field.into(), args.kmax)?;
    if args.json {
        outln!("{}", serde_json::to_string_pretty(&tables)?);
    } else {
        out!("{}", to_table(&tables));
    }
    Ok(())
}

fn to_table(r: &Coefficients) -> String {
    use std::fmt::Write;
    let mut out = String::new();
    let _ = writeln!(out, "field: {}   (derived from {})", r.field.name(), r.spec);
    let _ = writeln!(out, "prefactor H = {}", r.prefactor);
    let _ = writeln!(out, "appendix prefactor as printed: {}", appendix::printed_prefactor(r.field));
    let _ = writeln!(out, "zero order (units of H*R): H0 = {}  H2 = {}  H1_2 = {}", r.zero[0], r.zero[1], r.zero[2]);
    let _ = writeln!(out, "\ncouplings (units of H), closed forms in k:");
    for c in &r.columns {
        let mark = if c.differs { "   <- differs from the appendix" } else { "" };
        let _ = writeln!(out, "  {:<4} = {}{}", c.id.name, c.closed_form, mark);
    }
    let _ = write!(out, "\n{:>4}", "k");
    for c in &r.columns {
        let _ = write!(out, " {:>12}", c.id.name);
    }
    out.push('\n');
    for k in 0..=r.kmax {
        let _ = write!(out, "{k:>4}");
        for c in &r.columns {
            let _ = write!(out, " {:>12}", cell(c.values[k]));
        }
        out.push('\n');
    }
    let differing: Vec<&Column> = r.columns.iter().filter(|c| c.differs).collect();
    if !differing.is_empty() {
        let _ = writeln!(out, "\nappendix values where they differ (printed; derived above):");
        let _ = write!(out, "{:>4}", "k");
        for c in &differing {
            let _ = write!(out, " {:>12}", c.id.name);
        }
        out.push('\n');
        for k in 0..=r.kmax {
            if differing.iter().all(|c| c.printed[k].is_none()) {
                continue;
            }
            let _ = write!(out, "{k:>4}");
            for c in &differing {
                let _ = write!(out, " {:>12}", cell(c.printed[k]));
            }
            out.push('\n');
        }
    }
    out
}

fn cell(v: Option<f64>) -> String {
    match v {
        Some(x) => format!("{x:.6}"),
        None => "-".into(),
    }
}
