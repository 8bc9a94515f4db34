//! The Legendre-coupling coefficient tables, generated at build time by `codegen` from the specs
//! in `derivations/` (build.rs → `$OUT_DIR/coefficients.rs`). Contract: docs/architecture.md.
//! Conventions: FORMULATION §0–1 (P^1_k = dP_k/dΘ, Condon–Shortley; normal loads on P_j,
//! tangential on P^1_j). Nothing here is typed in: regenerate with `cargo run -p codegen -- --out DIR`.

include!(concat!(env!("OUT_DIR"), "/coefficients.rs"));

/// All field tables, in a fixed order.
pub static FIELDS: [&FieldTable; 3] = [&COIL, &DIPOLE, &COIL_H4];

/// The field table called `name` ("coil", "dipole", "coil_h4").
pub fn field(name: &str) -> Option<&'static FieldTable> {
    FIELDS.iter().copied().find(|t| t.name == name)
}

impl FieldTable {
    /// The coupling `name` of the first component that has it (for the paper's one-component
    /// fields: "F1".."F6", "F1t".."F6t").
    pub fn coupling(&self, name: &str) -> Option<&'static Coupling> {
        self.components.iter().flat_map(|c| c.couplings.iter()).find(|c| c.name == name)
    }
}

impl Component {
    /// Zero-order normal value on P_j (in units of ℋ·R^m), 0 when absent.
    pub fn zero_normal_at(&self, j: usize) -> f64 {
        self.zero_normal.iter().find(|(i, _)| *i == j).map_or(0.0, |(_, v)| *v)
    }
    /// Zero-order tangential value on P^1_j (in units of ℋ·R^m), 0 when absent.
    pub fn zero_tangential_at(&self, j: usize) -> f64 {
        self.zero_tangential.iter().find(|(i, _)| *i == j).map_or(0.0, |(_, v)| *v)
    }
    /// The coupling with this load, amplitude and offset, if the field has it.
    pub fn coupling(&self, load: Load, amp: Amp, offset: i32) -> Option<&'static Coupling> {
        self.couplings.iter().find(|c| c.load == load && c.amp == amp && c.offset == offset)
    }
}

impl Coupling {
    /// Value for target mode k (None where the coupling does not exist or k > KMAX).
    pub fn at(&self, k: usize) -> Option<f64> {
        self.values.get(k).copied().flatten()
    }
    /// Exact value "p/q" for target mode k.
    pub fn exact_at(&self, k: usize) -> Option<&'static str> {
        self.exact.get(k).copied().flatten()
    }
    /// Source mode of the amplitude for target k (k + offset), if it is a mode ≥ 0.
    pub fn source(&self, k: usize) -> Option<usize> {
        usize::try_from(k as i64 + self.offset as i64).ok()
    }
}

impl Monomial {
    /// Evaluate with symbol values given by `value(name)`; None if a symbol is unknown.
    pub fn eval(&self, value: impl Fn(&str) -> Option<f64>) -> Option<f64> {
        self.powers.iter().try_fold(self.coeff, |acc, (s, p)| value(s).map(|v| acc * v.powi(*p)))
    }
}
