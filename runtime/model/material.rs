//! The material-frame group of the loads (issue 12; docs/model.md, "One frame for the state"):
//! the terms whose loads are derived for material (Lagrangian) amplitudes — the membrane law,
//! bending, the shell viscosity — are marked by the assembly ([`Equations::material`]). The
//! frame mapping ([`super::effects::quadratic_frame`]) needs their first-order sum L(z) and its
//! Jacobian; the equations core evaluates every term once per rhs anyway, so with second-pass
//! terms it sums the group apart ([`Equations::loads_split`]) and hands it over
//! ([`super::effects::second_order::FirstOrder::material`]) instead of the mapping evaluating
//! the group a second time.

use super::effects::{At, LoadJacobian, Loads};
use super::equations::Equations;

impl Equations {
    /// Whether term `i` of the summation list is in the material-frame group.
    #[inline]
    fn is_material(&self, i: usize) -> bool {
        self.material.get(i).copied().unwrap_or(false)
    }

    /// The material-frame terms' share of P and, for m < gn.len(), of G_n,k, G_t,k at (t, z)
    /// (`gn`, `gt` overwritten).
    pub fn material_loads(&self, t: f64, z: &[f64], gn: &mut [f64], gt: &mut [f64]) -> f64 {
        gn.fill(0.0);
        gt.fill(0.0);
        let (at, mut l) = (At { t, z }, Loads { pressure: 0.0, gn, gt });
        for (_, term) in self.terms.iter().enumerate().filter(|(i, _)| self.is_material(*i)) {
            term.add(&at, &mut l);
        }
        l.pressure
    }

    /// [`loads`](Self::loads) with the material-frame terms' share returned apart as well:
    /// (P of all terms, P of the group), `gn`, `gt` all terms', `mgn`, `mgt` the group's (all
    /// overwritten). Each group is summed on its own and then added, so P and G differ from
    /// [`loads`](Self::loads) by rounding: used only with second-pass terms (a linear scene's
    /// sums are unchanged).
    pub fn loads_split(&self, t: f64, z: &[f64], gn: &mut [f64], gt: &mut [f64], mgn: &mut [f64], mgt: &mut [f64]) -> (f64, f64) {
        for x in [&mut *gn, &mut *gt, &mut *mgn, &mut *mgt] {
            x.fill(0.0);
        }
        let at = At { t, z };
        let mut rest = Loads { pressure: 0.0, gn: &mut *gn, gt: &mut *gt };
        let mut group = Loads { pressure: 0.0, gn: &mut *mgn, gt: &mut *mgt };
        for (i, term) in self.terms.iter().enumerate() {
            term.add(&at, if self.is_material(i) { &mut group } else { &mut rest });
        }
        let pm = group.pressure;
        let p = rest.pressure + pm;
        for (x, y) in gn.iter_mut().zip(mgn.iter()) {
            *x += y;
        }
        for (x, y) in gt.iter_mut().zip(mgt.iter()) {
            *x += y;
        }
        (p, pm)
    }

    /// ∂/∂z of [`material_loads`](Self::material_loads) (`jac` overwritten).
    pub fn material_jacobian(&self, t: f64, z: &[f64], jac: &mut LoadJacobian) {
        jac.clear();
        let at = At { t, z };
        for (_, term) in self.terms.iter().enumerate().filter(|(i, _)| self.is_material(*i)) {
            term.add_jacobian(&at, jac);
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::model::Model;

    /// The assembly marks exactly the membrane law, bending and the shell viscosity — the
    /// frame mapping's material-frame terms — and not γ; a linear scene marks nothing.
    #[test]
    fn the_material_group_is_the_frame_maps() {
        let sets = ["shell.surface_tension=0.05", "shell.bending_modulus=1e-19", "shell.shear_viscosity=1e-9", "shell.dilatational_viscosity=1e-9"];
        for coupling in ["\"quadratic\"", "\"linear\""] {
            let c = format!("modes.coupling={coupling}");
            let mut keys: Vec<&str> = sets.to_vec();
            keys.push(&c);
            let s = crate::scene::load("scenes/figures/fig12_chi.toml", &keys).expect("scene");
            let m = Model::from_scene(&s).expect("model");
            let eq = m.equations();
            let marked: Vec<&str> = eq.terms.iter().enumerate().filter(|(i, _)| eq.is_material(*i)).map(|(_, t)| t.name()).collect();
            let want: &[&str] = if coupling == "\"linear\"" { &[] } else { &["membrane", "bending", "shell viscosity"] };
            assert_eq!(marked, want, "{coupling}");
        }
    }
}
