//! `magbubble coefficients`: print the generated Legendre-coupling coefficients of a field
//! (issue 2, part 5), next to the paper's printed appendix formulas.
//!
//! Couplings are in units of the prefactor ℋ (coil: μ0χ_sH2²R0²/(4a²R²); dipole:
//! −36μ0χ_sM²R0²/(z⁸R²), the appendix's with its dimension corrected, see
//! docs/derivation-notes.md); the zero-order terms ℋ0, ℋ2, ℋ^1_2 in units of ℋR.

use crate::coefficients::{self, Component, FieldTable};
use crate::field::appendix::{self, CouplingId, PaperField, COUPLINGS};
use anyhow::{bail, Context};
use serde_json::{json, Value};

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

/// One coupling's columns: derived values, exact "p/q", the printed formula's values.
struct Column {
    id: CouplingId,
    values: Vec<Option<f64>>,
    exact: Vec<Option<&'static str>>,
    printed: Vec<Option<f64>>,
    closed_form: &'static str,
    differs: bool,
}

/// Everything printed, gathered once from the generated tables and the appendix.
struct Report {
    field: PaperField,
    kmax: usize,
    spec: &'static str,
    prefactor: &'static str,
    zero: [f64; 3],
    columns: Vec<Column>,
}

pub fn run(args: &CoefficientsArgs) -> anyhow::Result<()> {
    if args.json {
        outln!("{}", coefficients_json(args.field, args.kmax)?);
    } else {
        out!("{}", to_table(&gather(args.field, args.kmax)?));
    }
    Ok(())
}

/// What `coefficients --json` prints (pretty JSON text, keys in the order): the one
/// JSON builder of the CLI and the Python package.
pub fn coefficients_json(field: FieldChoice, kmax: usize) -> anyhow::Result<String> {
    Ok(serde_json::to_string_pretty(&to_json(&gather(field, kmax)?))?)
}

fn gather(choice: FieldChoice, kmax: usize) -> anyhow::Result<Report> {
    if kmax > coefficients::KMAX {
        bail!(
            "--kmax {kmax} is out of range: the tables were generated for k = 0..={} \
             (build setting MAGBUBBLE_KMAX); use --kmax between 0 and {}",
            coefficients::KMAX,
            coefficients::KMAX
        );
    }
    let (field, table): (PaperField, &FieldTable) = match choice {
        FieldChoice::Coil => (PaperField::Coil, &coefficients::COIL),
        FieldChoice::Dipole => (PaperField::Dipole, &coefficients::DIPOLE),
    };
    let [component]: &[Component; 1] = table.components.try_into().with_context(|| {
        format!("the generated `{}` table has {} components, expected the single H2² one", table.name, table.components.len())
    })?;
    let zero_at = |list: &[(usize, f64)], j: usize| list.iter().find(|e| e.0 == j).map_or(0.0, |e| e.1);
    let zero = [
        zero_at(component.zero_normal, 0),
        zero_at(component.zero_normal, 2),
        zero_at(component.zero_tangential, 2),
    ];
    let mut columns = Vec::with_capacity(COUPLINGS.len());
    for id in COUPLINGS {
        let c = component
            .couplings
            .iter()
            .find(|c| c.name == id.name)
            .with_context(|| format!("the generated `{}` table has no coupling {}", table.name, id.name))?;
        let values: Vec<Option<f64>> = (0..=kmax).map(|k| c.values.get(k).copied().flatten()).collect();
        let exact = (0..=kmax).map(|k| c.exact.get(k).copied().flatten()).collect();
        let printed = (0..=kmax)
            .map(|k| {
                let shown = appendix::printed_range(&id, kmax).contains(&k) && values[k].is_some();
                appendix::coupling(field, id.name, k as f64).filter(|v| shown && v.is_finite())
            })
            .collect();
        let differs = appendix::differs(field, &id, kmax, |k| values[k]);
        columns.push(Column { id, values, exact, printed, closed_form: c.closed_form, differs });
    }
    Ok(Report { field, kmax, spec: table.spec, prefactor: component.prefactor.text, zero, columns })
}

/// A JSON value whose objects keep their keys in the order given (serde_json's `Map` sorts them).
enum Node {
    Leaf(Value),
    Object(Vec<(&'static str, Node)>),
}

impl serde::Serialize for Node {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        match self {
            Node::Leaf(v) => v.serialize(s),
            Node::Object(entries) => {
                let mut map = s.serialize_map(Some(entries.len()))?;
                for (k, v) in entries {
                    map.serialize_entry(k, v)?;
                }
                map.end()
            }
        }
    }
}

/// The JSON object of issue 2, keys in the order.
fn to_json(r: &Report) -> Node {
    let leaf = Node::Leaf;
    let by_name = |f: &dyn Fn(&Column) -> Value| -> Node {
        Node::Object(r.columns.iter().map(|c| (c.id.name, Node::Leaf(f(c)))).collect())
    };
    let differs: Vec<&str> = r.columns.iter().filter(|c| c.differs).map(|c| c.id.name).collect();
    Node::Object(vec![
        ("field", leaf(json!(r.field.name()))),
        ("kmax", leaf(json!(r.kmax))),
        ("prefactor", leaf(json!(r.prefactor))),
        (
            "zero_order",
            Node::Object(vec![("H0", leaf(json!(r.zero[0]))), ("H2", leaf(json!(r.zero[1]))), ("H1_2", leaf(json!(r.zero[2])))]),
        ),
        ("couplings", by_name(&|c| json!(c.values))),
        ("exact", by_name(&|c| json!(c.exact))),
        ("appendix", by_name(&|c| json!(c.printed))),
        ("differs", leaf(json!(differs))),
    ])
}

fn to_table(r: &Report) -> String {
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
