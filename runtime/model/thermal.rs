//! The thermal seed and the natural size of the shape amplitudes (docs/model.md, "Thermal seed";
//! issue 29 item 5).
//!
//! **Equipartition.** At R = R0, Ṙ = 0 mode k is an oscillator ä_k = −ω_k² a_k (ω_k of
//! docs/model.md §4.4, [`crate::analysis::frequencies`]) whose kinetic energy is the liquid's,
//! T_k = ½ m_k ȧ_k² with the potential flow φ = −R0 ȧ_k (R0/r)^(k+1) P_k/(k+1):
//!
//! ```text
//! m_k = 4π ρ R0³ / ((k+1)(2k+1)),   K_k = m_k ω_k²,   a_th,k = √(k_B T / K_k)
//! ```
//! (½ K_k ⟨a_k²⟩ = ½ k_B T). Without a field, ω_k² = 12(c1+c2)(k−1)(k+1)(k+2)/[ρR0³(2k²+2k−1)]
//! gives K_k = 48π(c1+c2)(k−1)(k+2)/[(2k+1)(2k²+2k−1)]; a free bubble with surface tension γ,
//! K_k = 4πγ(k−1)(k+2)/(2k+1), the surface energy of a P_k deformation.
//!
//! **Error weights.** The adaptive steppers measure the error of a_k, ȧ_k, b_k against
//! atol·w_k + rtol·|y| ([`crate::integrate::OdeSystem::error_scale`]); R and Ṙ have w = 1 (R
//! against R0). w_k is the natural size of mode k: its seed, max(|a_k(0)|, |ȧ_k(0)| t*,
//! |b_k(0)|)/R0 (the thermal amplitude under the thermal seed): an error far below atol·w_k is
//! far below what the mode starts from. A mode that starts at zero is fed by the field or the
//! coupling at whatever amplitude the equations give (1e-38 m for a_16 in coil_static.toml) and
//! its growth to blow-up starts from there; an absolute floor above that level lets the
//! stepper's own error seed the mode instead (Dopri5 at atol 1e-9 blew up at 10.54 µs instead
//! of 20.57 µs: an explicit step unstable on a_16 is not rejected while |a_16| is below atol).
//! So a mode that starts at zero has the weight of the static amplitude the loads at rest force
//! it to ([`static_response`]: one Newton step from rest, so the field's couplings pass it on
//! from mode to mode): an error far below atol times that is far below what the field gives
//! the mode, and a transient that decays below it (a static field's ringing, ȧ_k → 0) is not
//! followed into roundoff (relative control there took hard/long_static from 1201 to 1.3·10^6
//! steps). A mode neither seeded nor forced (it stays zero unless a coupling feeds it) has
//! w = [`UNSEEDED`] = ε², ε the machine epsilon, also the floor of every weight: relative to itself down to atol·ε² R0 (5e-41 R0
//! at the default atol). (w = 0, pure relative control, fails: a component that starts at
//! exactly zero then has a zero scale, and Radau5's Newton iteration cannot meet it.)

use super::ModelError;
use crate::scene::{Scene, Seed};
use std::collections::BTreeMap;
use std::f64::consts::PI;

/// Boltzmann's constant [J/K] (exact in the SI since 2019).
pub const BOLTZMANN: f64 = 1.380_649e-23;

/// The weight of a mode that starts at zero (module doc): ε².
pub const UNSEEDED: f64 = f64::EPSILON * f64::EPSILON;

/// m_k [kg]: the liquid's kinetic-energy mass of mode k at R0 (module doc).
pub fn mode_mass(rho: f64, r0: f64, k: usize) -> f64 {
    let k = k as f64;
    4.0 * PI * rho * r0.powi(3) / ((k + 1.0) * (2.0 * k + 1.0))
}

/// a_th,k [m] for every simulated k (module doc), from the scene's own ω_k at R0.
pub fn amplitudes(scene: &Scene) -> Result<BTreeMap<usize, f64>, ModelError> {
    let err = |why: String| ModelError::Seed(why);
    let orders: Vec<usize> = scene.modes.orders().collect();
    let Some(&kmax) = orders.last() else { return Ok(BTreeMap::new()) };
    let mut given = scene.clone();
    given.bubble.initial.seed = Seed::Given;
    let f = crate::analysis::frequencies::natural_frequencies(&given, kmax).map_err(|e| err(format!("the modes' stiffness at R0: {e}")))?;
    let kt = BOLTZMANN * scene.liquid.temperature;
    let mut out = BTreeMap::new();
    for k in orders {
        let s = f.shape.iter().find(|s| s.k == k).ok_or_else(|| err(format!("no natural frequency of mode {k}")))?;
        let omega_sq = s.omega_sq_nondim / (f.t_star * f.t_star);
        if !(omega_sq > 0.0 && omega_sq.is_finite()) {
            return Err(err(format!(
                "mode {k} has no positive stiffness at R0 (omega_k^2 t*^2 = {:.3e}): its equipartition amplitude is unbounded",
                s.omega_sq_nondim
            )));
        }
        let stiffness = mode_mass(scene.liquid.density, scene.bubble.radius, k) * omega_sq;
        out.insert(k, (kt / stiffness).sqrt());
    }
    Ok(out)
}

/// The static amplitude the loads at rest force each mode to (nondimensional, module doc): one
/// Newton step from rest (R = R0, everything else 0, t = 0) toward the equilibrium,
/// δy = −J⁻¹ f, with the exact Jacobian, so a mode forced only through the field's coupling to
/// another gets its share; |δa_k| per mode, all 0 when J is singular (a mode without stiffness).
pub fn static_response(bl: &super::boundary_layer::BoundaryLayerSystem) -> Vec<f64> {
    use crate::integrate::OdeSystem;
    let n = bl.dim();
    let m = bl.modes().len();
    let (mut y, mut f, mut jac) = (vec![0.0; n], vec![0.0; n], vec![0.0; n * n]);
    y[0] = 1.0;
    bl.rhs(0.0, &y, &mut f);
    bl.jacobian(0.0, &y, &mut jac);
    let j = nalgebra::DMatrix::from_row_slice(n, n, &jac);
    let rhs = nalgebra::DVector::from_iterator(n, f.iter().map(|v| -v));
    match j.lu().solve(&rhs) {
        Some(d) if d.iter().all(|v| v.is_finite()) => (0..m).map(|k| d[crate::model::layout::StateLayout::reduced(m).a(k)].abs()).collect(),
        _ => vec![0.0; m],
    }
}

/// The absolute-tolerance weight of each simulated mode (module doc), in `scene.modes.orders()`
/// order, given the thermal amplitudes when the scene seeds thermally, t* [s] and the
/// [`static_response`] of each mode.
pub fn weights(scene: &Scene, thermal: Option<&BTreeMap<usize, f64>>, t_star: f64, forced: &[f64]) -> Vec<f64> {
    let init = &scene.bubble.initial;
    let get = |m: &BTreeMap<usize, f64>, k: usize| m.get(&k).map_or(0.0, |v| v.abs());
    scene
        .modes
        .orders()
        .enumerate()
        .map(|(m, k)| {
            let a = init.a.get(&k).map(|v| v.abs()).or_else(|| thermal.and_then(|t| t.get(&k)).copied()).unwrap_or(0.0);
            let seed = a.max(get(&init.a_velocity, k) * t_star).max(get(&init.b, k)) / scene.bubble.radius;
            // never below ε²: a field of 1e-6 A forces a mode to far less, and Radau5's Newton
            // iteration failed at t = 0 on such a scale (tests/suite/scene_derived.rs)
            let size = seed.max(forced.get(m).copied().unwrap_or(0.0));
            if size.is_finite() {
                size.max(UNSEEDED)
            } else {
                UNSEEDED
            }
        })
        .collect()
}
