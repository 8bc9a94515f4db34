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

impl quadratic::Term {
    /// The coefficient on target j of first(l)·second(m) (docs/architecture.md, the quadratic
    /// module): s_j C(j, l, m) N(l, m, j)/D; 0 outside the selection rules or the tables.
    pub fn value(&self, j: usize, l: usize, m: usize) -> f64 {
        if self.radial_only && j != 0 {
            return 0.0;
        }
        let c = quadratic_lookup::ppp(l, m, j) * (2.0 * j as f64 + 1.0) / 2.0;
        if c == 0.0 {
            return 0.0;
        }
        let x = [l as f64, m as f64, j as f64];
        let n: f64 = self.numerator.iter().map(|(e, v)| v * x[0].powi(e[0] as i32) * x[1].powi(e[1] as i32) * x[2].powi(e[2] as i32)).sum();
        let d = if self.denominator { (x[0] + 1.0) * (x[1] + 1.0) * (x[2] + 1.0) } else { 1.0 };
        let s = if j == 0 { 1.0 } else { -1.0 };
        s * c * n / d
    }

    /// The prefactor at the given symbol values (rho, gamma, R, Rd, Rdd, pg, kappa); None if one is unknown.
    pub fn prefactor_at(&self, value: impl Fn(&str) -> Option<f64>) -> Option<f64> {
        self.prefactor.iter().try_fold(1.0, |acc, (s, p)| value(s).map(|v| acc * v.powi(*p)))
    }
}

impl quadratic::Amp2 {
    /// Index of a, ȧ, ä.
    pub fn order(self) -> usize {
        match self {
            quadratic::Amp2::A => 0,
            quadratic::Amp2::Ad => 1,
            quadratic::Amp2::Add => 2,
        }
    }
}

pub mod quadratic_lookup {
    //! Lookups in the generated triple-product tensors.
    use super::quadratic::PPP;

    /// ∫ P_l P_m P_j dx for even modes 2 ≤ l, m ≤ KMAX and even j ≤ KMAX (0 when not allowed).
    pub fn ppp(l: usize, m: usize, j: usize) -> f64 {
        let (l, m) = (l.min(m) as u16, l.max(m) as u16);
        let j = j as u16;
        PPP.binary_search_by(|e| (e.0, e.1, e.2).cmp(&(l, m, j))).map_or(0.0, |i| PPP[i].3)
    }
}
