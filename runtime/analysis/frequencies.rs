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
//! k by the largest component of their eigenvector. Odd k decouple from the even ones (every
//! table offset is even) and are unforced (no table has a zero-order load on an odd P_j), so the
//! model simulates the even modes only; their frequencies here come from the membrane law plus
//! the shell effects (surface tension, bending) and, with a field, the odd couplings of the same
//! generated tables ([`crate::field::loads::MagneticLoads::odd`]), so `field_couplings` is true
//! for every k (issue 13 part 6).
//! Without a field: ω_k² = 12(c1+c2)(k−1)(k+1)(k+2)/[ρR0³(2k²+2k−1)].

use crate::model::effects::LoadJacobian;
use crate::model::layout::StateLayout;
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
    #[error("--kmax {kmax}: the model's modes stop at k = {limit}, with or without a field (the generated coupling tables; rebuild with MAGBUBBLE_KMAX for more)")]
    KmaxTooLarge { kmax: usize, limit: usize },
    #[error("B_b (tangential stiffness on b) is singular at R0: no quasi-static b")]
    SingularTangential,
    #[error(transparent)]
    Field(#[from] crate::field::FieldError),
    #[error("--kmax: mode k = {k} with a field needs couplings beyond the generated tables (k ≤ {kmax}); use --kmax ≤ {kmax}")]
    BeyondTables { k: usize, kmax: usize },
    #[error("the quasi-static stiffness matrix at R0 is not finite or its eigenvalues do not converge: the scene's loads overflow at rest")]
    NonFiniteStiffness,
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

/// A `--kmax` the modes analyses can take: 2 ≤ kmax ≤ the tables' k (issue 29 item 13: a
/// larger one was reported as `modes.max_order`, a key the user did not set).
pub fn check_kmax(kmax: usize) -> Result<(), FrequencyError> {
    if kmax < 2 {
        return Err(FrequencyError::KmaxTooSmall { kmax });
    }
    // the even modes run the model (its tables stop at KMAX with or without a field); an odd
    // k = KMAX + 1 needs no table without a field (BeyondTables says when it does)
    if kmax - kmax % 2 > crate::coefficients::KMAX {
        return Err(FrequencyError::KmaxTooLarge { kmax, limit: crate::coefficients::KMAX });
    }
    Ok(())
}

/// Natural frequencies of `scene` for k = 2 … kmax (the drive is ignored: p∞ = p0).
pub fn natural_frequencies(scene: &Scene, kmax: usize) -> Result<Frequencies, FrequencyError> {
    check_kmax(kmax)?;
    let mut s = scene.clone();
    s.drive = None;
    s.modes.max_order = kmax - kmax % 2;
    crate::model::refuse_reduced_thermal(scene, "the natural frequencies are those of the linearised shape-mode system, which does not carry the reduced model's p_b: use gas.thermal = \"prosperetti\" (its small-amplitude limit)")?;
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
    let lay = StateLayout::reduced(n);
    let mut z = vec![0.0; lay.dim()];
    z[lay.r()] = r;
    let mut lj = LoadJacobian::new(n);
    eq.load_jacobian(0.0, &z, &mut lj);

    // Radial: ω0² = −∂R̈/∂R at (R0, Ṙ = 0), undamped (the 4ηṘ/R term vanishes at Ṙ = 0).
    let pressure = eq.loads(0.0, &z, &mut [], &mut []);
    let mut grad = vec![0.0; z.len()];
    eq.acceleration_gradient_at(0.0, &z, pressure, &lj.pressure, &mut grad);
    let w0 = (-grad[lay.r()]).max(0.0).sqrt();
    let radial = RadialFrequency { omega_rad_s: w0 / ts, f_hz: w0 / ts / (2.0 * std::f64::consts::PI) };

    // Even modes, coupled by the field: A = ∂G_n/∂a, B = ∂G_n/∂b, A_a = ∂G_t/∂a, B_b = ∂G_t/∂b.
    let pick = |normal: bool, at: fn(StateLayout, usize) -> usize| {
        DMatrix::from_fn(n, n, |m, j| {
            let row = if normal { lj.gn_row(m) } else { lj.gt_row(m) };
            row[at(lay, j)]
        })
    };
    let (a, b, aa, bb) = (pick(true, StateLayout::a), pick(true, StateLayout::b), pick(false, StateLayout::a), pick(false, StateLayout::b));
    let scale: Vec<f64> = bl.modes().iter().map(|md| (md.k + 1.0) / (p.rho * p.r0)).collect();
    let mut shape: Vec<ShapeFrequency> =
        quasi_static_spectrum(a, b, aa, bb, &scale)?.into_iter().map(|(m, w2)| wrap(w2, 2 * (m + 1), true)).collect();
    // Odd modes: the membrane law plus surface tension and bending, and with a field its odd
    // couplings (k → k ± 2 among odd k, from the same generated tables; see the module doc).
    let (c1, c2) = p.membrane_args;
    let sc = crate::model::Scales::from_scene(&s);
    let odd: Vec<usize> = (3..=kmax).step_by(2).collect();
    if odd.is_empty() {
        shape.sort_by(|x, y| x.k.cmp(&y.k).then(x.omega_sq_nondim.total_cmp(&y.omega_sq_nondim)));
        return Ok(Frequencies { radial, shape, t_star: ts });
    }
    let no = odd.len();
    let (mut a, mut b, mut aa, mut bb) =
        (DMatrix::zeros(no, no), DMatrix::zeros(no, no), DMatrix::zeros(no, no), DMatrix::zeros(no, no));
    for (m, &k) in odd.iter().enumerate() {
        let kf = k as f64;
        // the elastic law, plus surface tension and bending when the scene has them
        let x = crate::model::effects::shell::extra_stiffness(&s.shell, &sc, p.r0, r, kf);
        a[(m, m)] = (mem.s1)(r, p.r0, c1, c2, kf) + x[0];
        b[(m, m)] = (mem.s2)(r, p.r0, c1, c2, kf) + x[1];
        aa[(m, m)] = (mem.s11)(r, p.r0, c1, c2, kf) + x[2];
        bb[(m, m)] = (mem.s12)(r, p.r0, c1, c2, kf) + x[3];
    }
    if let Some(field) = &s.field {
        if let Some(&k) = odd.last().filter(|&&k| k > crate::coefficients::KMAX) {
            return Err(FrequencyError::BeyondTables { k, kmax: crate::coefficients::KMAX });
        }
        let source = crate::field::FieldSource::from_scene(field, &s.shell, s.bubble.radius)?;
        let loads = crate::field::loads::MagneticLoads::odd(&source, no, sc.length, sc.pressure, sc.time)?;
        let lay = StateLayout::reduced(no);
        let mut y = vec![0.0; lay.dim()];
        y[lay.r()] = r;
        let f = loads.factors(0.0, r);
        for m in 0..no {
            let (mut gn, mut gt) = (vec![0.0; y.len()], vec![0.0; y.len()]);
            // G = Ŝ·(a, b) − M (effects/magnetic.rs): the magnetic gradient enters with −1.
            loads.add_row_gradient(&f, m + 1, &y, true, -1.0, &mut gn);
            loads.add_row_gradient(&f, m + 1, &y, false, -1.0, &mut gt);
            for j in 0..no {
                a[(m, j)] += gn[lay.a(j)];
                b[(m, j)] += gn[lay.b(j)];
                aa[(m, j)] += gt[lay.a(j)];
                bb[(m, j)] += gt[lay.b(j)];
            }
        }
    }
    let scale: Vec<f64> = odd.iter().map(|&k| (k as f64 + 1.0) / (p.rho * p.r0)).collect();
    shape.extend(quasi_static_spectrum(a, b, aa, bb, &scale)?.into_iter().map(|(m, w2)| wrap(w2, odd[m], true)));
    shape.sort_by(|x, y| x.k.cmp(&y.k).then(x.omega_sq_nondim.total_cmp(&y.omega_sq_nondim)));
    Ok(Frequencies { radial, shape, t_star: ts })
}

/// (mode index, ω²) of 𝒟(A − B B_b⁻¹ A_a) (the module doc's formula; 𝒟 = diag(`scale`)), each
/// eigenvalue matched to the mode holding the largest part of its eigenvector. Without a
/// tangential load (G_t ≡ 0, a free bubble) b does not feed back: ω² = spec 𝒟A. A diagonal
/// matrix (no field) is read mode by mode.
fn quasi_static_spectrum(
    a: DMatrix<f64>,
    b: DMatrix<f64>,
    aa: DMatrix<f64>,
    bb: DMatrix<f64>,
    scale: &[f64],
) -> Result<Vec<(usize, f64)>, FrequencyError> {
    let n = scale.len();
    let no_tangential = b.iter().chain(aa.iter()).chain(bb.iter()).all(|&x| x == 0.0);
    let mut w = if no_tangential {
        a
    } else {
        let bb_inv = bb.try_inverse().ok_or(FrequencyError::SingularTangential)?;
        a - b * bb_inv * aa
    };
    for (m, sc) in scale.iter().enumerate() {
        w.row_mut(m).scale_mut(*sc);
    }
    if (0..n).all(|i| (0..n).all(|j| i == j || w[(i, j)] == 0.0)) {
        return Ok((0..n).map(|m| (m, w[(m, m)])).collect());
    }
    let mus = crate::analysis::floquet::eigenvalues(&w);
    if mus.iter().any(|mu| !mu.re.is_finite()) {
        return Err(FrequencyError::NonFiniteStiffness);
    }
    Ok(mus
        .into_iter()
        .map(|mu| {
            let weights = crate::analysis::floquet::eigenvector_weights(&w, mu);
            let m = weights.iter().enumerate().fold(0, |best, (i, &v)| if v > weights[best] { i } else { best });
            (m, mu.re)
        })
        .collect())
}

/// Q = ω/(2γ) of a damped mode s = −γ ± iω: ∞ for γ = 0 < ω, `None` when both are 0 (nothing
/// oscillates or decays) or either is not a number.
pub fn quality_factor(omega: f64, decay: f64) -> Option<f64> {
    if !(omega.is_finite() && decay.is_finite()) || (omega == 0.0 && decay == 0.0) {
        return None;
    }
    if decay == 0.0 {
        return Some(f64::INFINITY);
    }
    Some(omega / (2.0 * decay))
}
