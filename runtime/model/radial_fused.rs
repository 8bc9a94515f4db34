//! The radial Keller–Miksis rhs with the terms dispatched statically (issue 34): R̈ = N/D of
//! [`super::keller_miksis`] from P and its rate, summed by the same [`Term::add_with_rate`] of the
//! same terms, in the same order, as [`Equations::radial_acceleration`] — only the dispatch
//! differs. The terms of a radial scene are copied into [`Kernel`], an enum over their concrete
//! types, so each call is a direct, inlined one: the virtual calls and their memory round trips
//! go, and the rate's (R, Ṙ) gradients, which R̈ does not read, become dead code the compiler
//! drops — or, where they cost calls the compiler cannot drop (the Marmottant law's central
//! difference), the term leaves them out ([`Term::add_with_rate_value`]). No formula is written
//! here: a term's physics stays in its file.
//!
//! Assembled only when every term is one of [`Kernel`]'s types and the form is Keller–Miksis
//! (otherwise the run uses [`Equations::radial_acceleration`]). Same bits:
//! `tests::fused_is_the_generic_sum`, and every shipped scene's series (scripts/compare_series.sh).

use super::effects::{drive, gas, lipid, membrane, reduced_gas, shell, vapour, viscosity, At, Loads, PressureRate, Term};
use super::equations::Equations;
use super::keller_miksis::KellerMiksis;
use std::any::Any;

/// The enum [`Kernel`] of the term types below, its conversion from a `dyn Term` and its
/// statically dispatched `add_with_rate`, from one list (a type added here is fused).
macro_rules! kernels {
    ($($variant:ident($ty:ty)),* $(,)?) => {
        /// A term of a radial scene, by its concrete type (a clone of the assembled term: the
        /// drive's piece and the lipid law's branch are shared with it, `Arc`s).
        #[derive(Debug, Clone)]
        enum Kernel {
            $($variant($ty)),*
        }

        impl Kernel {
            /// `term` as a kernel, when its type is one of the enum's.
            fn of(term: &dyn Term) -> Option<Self> {
                let any: &dyn Any = term.as_any();
                $(if let Some(t) = any.downcast_ref::<$ty>() {
                    return Some(Kernel::$variant(t.clone()));
                })*
                None
            }

            #[inline(always)]
            fn add_with_rate(&self, at: &At<'_>, loads: &mut Loads<'_>, rate: &mut PressureRate) {
                match self {
                    $(Kernel::$variant(t) => t.add_with_rate_value(at, loads, rate)),*
                };
            }
        }
    };
}

kernels!(
    Gas(gas::PolytropicGas),
    ReducedGas(reduced_gas::ReducedGas),
    Vapour(vapour::VapourPressure),
    FarField(drive::FarField),
    Viscosity(viscosity::LiquidViscosity),
    Membrane(membrane::MembraneTerm),
    Lipid(lipid::LipidTerm),
    Tension(shell::OneConstant),
    ShellViscosity(shell::ShellViscosity),
);

/// R̈ of a radial Keller–Miksis scene with the terms dispatched statically (module doc).
#[derive(Debug, Clone)]
pub struct FusedRadial {
    terms: Vec<Kernel>,
    form: KellerMiksis,
    rho: f64,
}

impl FusedRadial {
    /// The fused form of `eq`, when its form is Keller–Miksis and every term has a kernel.
    pub fn of(eq: &Equations) -> Option<Self> {
        let c = eq.params.sound_speed?;
        if !eq.form.needs_rate() || !eq.second.is_empty() {
            return None;
        }
        let terms = eq.terms.iter().map(|t| Kernel::of(t.as_ref())).collect::<Option<Vec<_>>>()?;
        Some(Self { terms, form: KellerMiksis { c }, rho: eq.params.rho })
    }

    /// R̈ at (t, z = [R, Ṙ], or [R, Ṙ, p_b] with the reduced thermal model):
    /// [`Equations::radial_acceleration`]'s sums, term by term in the
    /// same order, and the same form.
    #[inline]
    pub fn acceleration(&self, t: f64, z: &[f64]) -> f64 {
        let at = At { t, z };
        let mut l = Loads { pressure: 0.0, gn: &mut [], gt: &mut [] };
        let mut rate = PressureRate::default();
        for term in &self.terms {
            term.add_with_rate(&at, &mut l, &mut rate);
        }
        use super::radial::RadialForm;
        self.form.acceleration_rate(self.rho, z[0], z[1], l.pressure, &rate)
    }
}

#[cfg(test)]
mod tests {
    use crate::model::{Model, System};

    fn model(shell: &str, extra: &str) -> Model {
        let text = format!(
            "[bubble]\nradius = 5e-6\n[liquid]\nsound_speed = 1500\n[shell]\n{shell}\n[gas]\npolytropic_exponent = 1.4\n{extra}\
             [drive]\namplitude = 0.5\nfrequency_hz = 1e6\n[modes]\nmax_order = 0\n"
        );
        let s = crate::scene::load_str(&text, "fused (test)", &[] as &[&str]).unwrap();
        Model::from_scene(&s).unwrap()
    }

    /// The fused R̈ is the generic one to the bit, for the scenes of benches/apecss.sh (free
    /// bubble, Mooney–Rivlin with γ and κ_s, Marmottant) and a vapour pressure, over a spread of
    /// states and times; and the radial system uses it.
    #[test]
    fn fused_is_the_generic_sum() {
        let cases = [
            ("c1 = 0.0\nc2 = 0.0\nsurface_tension = 0.072", ""),
            ("c1 = 0.1\nc2 = 0.12\nsurface_tension = 0.072\ndilatational_viscosity = 1e-9", ""),
            ("law = \"marmottant\"\nelasticity = 0.5\ninitial_tension = 0.02\nrupture_tension = 0.072\ndilatational_viscosity = 1e-9", ""),
            ("c1 = 0.1\nc2 = 0.12", "vapour_pressure = 2330\n"),
            // the reduced thermal model: p_b the state's third slot
            ("c1 = 0.0\nc2 = 0.0\nsurface_tension = 0.072", "thermal = \"reduced\"\n"),
        ];
        for (shell, extra) in cases {
            let m = model(shell, extra);
            let System::Radial(sys) = m.assembled() else { panic!("radial scene") };
            let fused = sys.fused.as_ref().unwrap_or_else(|| panic!("not fused: {shell}"));
            let mut n = 0;
            for i in 0..400 {
                let x = i as f64;
                let (t, r, rd) = (0.37 * x, 0.3 + 2.5 * (0.61 * x).sin().abs(), 3.0 * (1.3 * x).cos());
                let z = [r, rd, 0.7 + 0.5 * (0.43 * x).sin().abs()];
                let z = &z[..m.initial_state().len()];
                let generic = sys.eq.radial_acceleration(t, z);
                assert_eq!(fused.acceleration(t, z).to_bits(), generic.to_bits(), "{shell}: t {t} R {r} Ṙ {rd}");
                n += usize::from(generic.is_finite());
            }
            assert!(n > 300, "{shell}: {n} finite");
        }
    }

    /// Incompressible scenes keep the generic path.
    #[test]
    fn only_keller_miksis_with_known_terms_is_fused() {
        let s = crate::scene::load_str(
            "[bubble]\nradius = 5e-6\n[shell]\nc1 = 0.1\nc2 = 0.12\n[modes]\nmax_order = 0\n",
            "incompressible (test)",
            &[] as &[&str],
        )
        .unwrap();
        let m = Model::from_scene(&s).unwrap();
        let System::Radial(sys) = m.assembled() else { panic!("radial scene") };
        assert!(sys.fused.is_none());
    }
}
