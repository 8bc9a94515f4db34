//! `coefficients`: the generated Legendre-coupling coefficients of a field (issue 2, part 5),
//! next to the paper's printed appendix formulas.
//!
//! Couplings are in units of the prefactor ℋ (coil: μ0χ_sH2²R0²/(4a²R²); dipole:
//! −36μ0χ_sM²R0²/(z⁸R²), the appendix's with its dimension corrected, see
//! docs/derivation-notes.md); the zero-order terms ℋ0, ℋ2, ℋ^1_2 in units of ℋR.

use crate::coefficients::{self, Component, FieldTable};
use crate::field::appendix::{self, CouplingId, PaperField, COUPLINGS};
use anyhow::{bail, Context};
use serde_json::{json, Value};

/// Which field's tables.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Field {
    /// Two coils, H2 term (Appendix A).
    Coil,
    /// Two dipoles (Appendix B).
    Dipole,
}

/// One coupling's columns: derived values, exact "p/q", the printed formula's values.
pub struct Column {
    pub id: CouplingId,
    pub values: Vec<Option<f64>>,
    pub exact: Vec<Option<&'static str>>,
    pub printed: Vec<Option<f64>>,
    pub closed_form: &'static str,
    pub differs: bool,
}

/// The tables of one field, gathered once from the generated tables and the appendix.
pub struct Coefficients {
    pub field: PaperField,
    pub kmax: usize,
    pub spec: &'static str,
    pub prefactor: &'static str,
    pub zero: [f64; 3],
    pub columns: Vec<Column>,
}

/// The coupling tables of `field` for target modes k = 0 ..= `kmax` (at most the build's KMAX).
pub fn coefficients(choice: Field, kmax: usize) -> anyhow::Result<Coefficients> {
    if kmax > coefficients::KMAX {
        bail!(
            "--kmax {kmax} is out of range: the tables were generated for k = 0..={} \
             (build setting MAGBUBBLE_KMAX); use --kmax between 0 and {}",
            coefficients::KMAX,
            coefficients::KMAX
        );
    }
    let (field, table): (PaperField, &FieldTable) = match choice {
        Field::Coil => (PaperField::Coil, &coefficients::COIL),
        Field::Dipole => (PaperField::Dipole, &coefficients::DIPOLE),
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
    Ok(Coefficients { field, kmax, spec: table.spec, prefactor: component.prefactor.text, zero, columns })
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
fn to_json(r: &Coefficients) -> Node {
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


/// What `coefficients --json` prints (keys in the order) and Python's dict.
impl serde::Serialize for Coefficients {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        to_json(self).serialize(s)
    }
}
