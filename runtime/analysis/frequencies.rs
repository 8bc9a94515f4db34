//! Natural frequencies of the shape modes (corrected eq 3.10, FORMULATION §4.4 and audit 2, 6)
//! and of the radial mode (linearised §4.1).
//!
//! At R = R0, Ṙ = R̈ = 0, without damping and with the tangential balance quasi-static
//! (A_a a + B_b b = 0, so b = −B_b⁻¹A_a a):
//!
//! ```text
//! ω² = spec( 𝒟 (A − B B_b⁻¹ A_a) ),   𝒟 = diag((k+1)/(ρR0))
//! ```
//! with A = diag(Ŝ1) − ∂M_n/∂a, B = diag(Ŝ2) − ∂M_n/∂b, A_a = diag(Ŝ11) − ∂M_t/∂a,
//! B_b = diag(Ŝ12) − ∂M_t/∂b (the paper prints B_a⁻¹ and omits 𝒟). The magnetic couplings of the
//! even modes are read from the model's loads (the generated tables); eigenvalues are matched to
//! k by the largest component of their eigenvector. Odd k decouple from the even ones; they are
//! computed from the membrane terms alone (their field couplings are not assembled by the model,
//! which simulates even modes only: `field_couplings = false` in the output says so).
//! Without a field: ω_k² = 12(c1+c2)(k−1)(k+1)(k+2)/[ρR0³(2k²+2k−1)].

use crate::model::effects::{a_index, LoadJacobian};
use crate::model::{Model, ModelError};
use crate::scene::Scene;
use nalgebra::DMatrix;
use serde::Serialize;

/// Errors of the frequency computation.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FrequencyError {
    #[error(transparent)]
    Model(#[from] ModelError),
    #[error("--kmax {kmax}: must be ≥ 2")]
    KmaxTooSmall { kmax: usize },
    #[error("B_b (tangential stiffness on b) is singular at R0: no quasi-static b")]
    SingularTangential,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RadialFrequency {
    pub omega_rad_s: f64,
    pub f_hz: f64,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ShapeFrequency {
    pub k: usize,
    /// ω² < 0 (statically unstable) gives NaN here and `omega_sq_nondim` < 0.
    pub omega_rad_s: f64,
    pub f_hz: f64,
    /// ω t*
    pub omega_nondim: f64,
    /// (ω t*)²
    pub omega_sq_nondim: f64,
    /// Whether this mode's magnetic couplings are included (false: odd k with a field).
    pub field_couplings: bool,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Frequencies {
    pub radial: RadialFrequency,
    pub shape: Vec<ShapeFrequency>,
    /// t* [s]
    pub t_star: f64,
}

/// Natural frequencies of `scene` for k = 2 … kmax (the drive is ignored: p∞ = p0).
pub fn natural_frequencies(scene: &Scene, kmax: usize) -> Result<Frequencies, FrequencyError> {
    if kmax < 2 {
        return Err(FrequencyError::KmaxTooSmall { kmax });
    }
    let mut s = scene.clone();
    s.drive = None;
    s.modes.max_order = kmax - kmax % 2;
    let model = Model::from_scene(&s)?;
    let ts = model.time_scale();
    let bl = model.boundary_layer().expect("max_order ≥ 2 assembles the boundary-layer system");
    let p = *bl.params();
    let mem = p.membrane;
    let r = 1.0;
    let wrap = |w2: f64, k: usize, coupled: bool| {
        let w = if w2 >= 0.0 { w2.sqrt() } else { f64::NAN };
        ShapeFrequency {
            k,
            omega_rad_s: w / ts,
            f_hz: w / ts / (2.0 * std::f64::consts::PI),
            omega_nondim: w,
            omega_sq_nondim: w2,
            field_couplings: coupled,
        }
    };

    // The exact linear structure of the loads at (R0, Ṙ = 0, a = b = 0), t = 0.
    let eq = bl.equations();
    let n = bl.modes().len();
    let mut z = vec![0.0; 2 + 3 * n];
    z[0] = r;
    let mut lj = LoadJacobian::new(n);
    eq.load_jacobian(0.0, &z, &mut lj);

    // Radial: ω0² = −∂R̈/∂R at (R0, Ṙ = 0), undamped (the 4ηṘ/R term vanishes at Ṙ = 0).
    let pressure = eq.loads(0.0, &z, &mut [], &mut []);
    let mut grad = vec![0.0; z.len()];
    eq.acceleration_gradient_at(0.0, &z, pressure, &lj.pressure, &mut grad);
    let w0 = (-grad[0]).max(0.0).sqrt();
    let radial = RadialFrequency { omega_rad_s: w0 / ts, f_hz: w0 / ts / (2.0 * std::f64::consts::PI) };

    // Even modes, coupled by the field: A = ∂G_n/∂a, B = ∂G_n/∂b, A_a = ∂G_t/∂a, B_b = ∂G_t/∂b.
    let pick = |normal: bool, offset: usize| {
        DMatrix::from_fn(n, n, |m, j| {
            let row = if normal { lj.gn_row(m) } else { lj.gt_row(m) };
            row[a_index(j) + offset]
        })
    };
    let (a, b, aa, bb) = (pick(true, 0), pick(true, 2), pick(false, 0), pick(false, 2));
    // No tangential load at all (a free bubble, issue 10: G_t ≡ 0): b does not feed back on the
    // normal balance, ω² = 𝒟A (Lamb's ω_k² with surface tension).
    let no_tangential = b.iter().chain(aa.iter()).chain(bb.iter()).all(|&x| x == 0.0);
    let mut w = if no_tangential {
        a
    } else {
        let bb_inv = bb.try_inverse().ok_or(FrequencyError::SingularTangential)?;
        a - b * bb_inv * aa
    };
    for m in 0..n {
        let scale = (bl.modes()[m].k + 1.0) / (p.rho * p.r0);
        w.row_mut(m).scale_mut(scale);
    }
    let mut shape = Vec::new();
    // Uncoupled (no field): the spectrum is the diagonal, mode by mode (also avoids the
    // eigen-solver on a zero matrix: a free bubble without surface tension has ω_k = 0).
    let diagonal = (0..n).all(|i| (0..n).all(|j| i == j || w[(i, j)] == 0.0));
    if diagonal {
        for m in 0..n {
            shape.push(wrap(w[(m, m)], 2 * (m + 1), true));
        }
    }
    for mu in if diagonal { Vec::new() } else { crate::analysis::floquet::eigenvalues(&w) } {
        let weights = crate::analysis::floquet::eigenvector_weights(&w, mu);
        let m = weights.iter().enumerate().fold(0, |best, (i, &v)| if v > weights[best] { i } else { best });
        shape.push(wrap(mu.re, 2 * (m + 1), true));
    }
    // Odd modes: membrane only (see the module doc).
    let coupled_field = !eq.has("magnetic");
    let (c1, c2) = p.membrane_args;
    let sc = crate::model::Scales::from_scene(&s);
    for k in (3..=kmax).step_by(2) {
        let kf = k as f64;
        // the elastic law, plus surface tension and bending when the scene has them
        let x = crate::model::effects::shell::extra_stiffness(&s.shell, &sc, p.r0, r, kf);
        let (s1, s2, s11, s12) = (
            (mem.s1)(r, p.r0, c1, c2, kf) + x[0],
            (mem.s2)(r, p.r0, c1, c2, kf) + x[1],
            (mem.s11)(r, p.r0, c1, c2, kf) + x[2],
            (mem.s12)(r, p.r0, c1, c2, kf) + x[3],
        );
        let s_eff = if !eq.has("membrane") { 0.0 } else { s1 - s2 * s11 / s12 };
        shape.push(wrap((kf + 1.0) / (p.rho * p.r0) * s_eff, k, coupled_field));
    }
    shape.sort_by(|x, y| x.k.cmp(&y.k).then(x.omega_sq_nondim.total_cmp(&y.omega_sq_nondim)));
    Ok(Frequencies { radial, shape, t_star: ts })
}
