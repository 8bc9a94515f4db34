//! `modes`: the natural frequencies of a scene (corrected eq 3.10, docs/model.md §4.4) or its
//! damped linear spectrum s = −γ ± iω at R0 with the scene's viscous closure.

use super::scene::Scene;
use crate::analysis::frequencies::{natural_frequencies, Frequencies};
use crate::model::vorticity::scene::{damped_spectrum, DampedSpectrum};
use anyhow::Context;
use serde::{Serialize, Serializer};

/// What `modes` computes.
#[derive(Debug, Clone)]
pub enum Modes {
    /// Undamped natural frequencies k = 2 … kmax and the radial one.
    Frequencies(Frequencies),
    /// The damped spectrum of the even modes 2 … N.
    Damped(DampedSpectrum),
}

/// Natural frequencies up to `kmax` (default: the scene's `modes.max_order`, at least 2), or
/// with `damped` the damped spectrum of the even modes up to `kmax` (default: the scene's
/// `modes.max_order`).
pub fn modes(scene: &Scene, kmax: Option<usize>, damped: bool) -> anyhow::Result<Modes> {
    let label = scene.origin();
    Ok(if damped {
        Modes::Damped(damped_of(scene.scene(), kmax, label)?)
    } else {
        Modes::Frequencies(frequencies(scene.scene(), kmax, label)?)
    })
}

/// Natural frequencies up to `kmax` (default: the scene's modes.max_order, at least 2).
pub fn frequencies(scene: &crate::scene::Scene, kmax: Option<usize>, label: &str) -> anyhow::Result<Frequencies> {
    let kmax = kmax.unwrap_or(scene.modes.max_order.max(2));
    natural_frequencies(scene, kmax).with_context(|| format!("natural frequencies of {label}"))
}

/// The damped spectrum of the scene's closure, modes k = 2, 4, …, N with N = `kmax` (even
/// part) or the scene's max_order. NaN (JSON null) where a root was not found.
pub fn damped_of(scene: &crate::scene::Scene, kmax: Option<usize>, label: &str) -> anyhow::Result<DampedSpectrum> {
    let mut scene = scene.clone();
    if let Some(kmax) = kmax {
        crate::analysis::frequencies::check_kmax(kmax)?;
        scene.modes.max_order = kmax - kmax % 2;
    }
    anyhow::ensure!(
        scene.modes.max_order >= 2,
        "--damped: the scene has no shape modes (modes.max_order = {}); set modes.max_order ≥ 2",
        scene.modes.max_order
    );
    damped_spectrum(&scene).with_context(|| format!("damped spectrum of {label}"))
}

/// `modes --json` (keys sorted, as it has always printed them).
fn frequencies_value(f: &Frequencies) -> serde_json::Value {
    serde_json::json!({
        "radial": { "omega_rad_s": f.radial.omega_rad_s, "f_hz": f.radial.f_hz },
        "shape": f.shape.iter().map(|m| serde_json::json!({
            "k": m.k, "omega_rad_s": m.omega_rad_s, "f_hz": m.f_hz, "omega_nondim": m.omega_nondim,
            "field_couplings": m.field_couplings,
            // run, floquet and stability evolve the even-mode set (docs/user-guide.md)
            "evolved": m.k % 2 == 0,
        })).collect::<Vec<_>>(),
        "t_star_s": f.t_star,
    })
}

/// `modes --damped --json`.
fn damped_value(d: &DampedSpectrum) -> serde_json::Value {
    serde_json::json!({
        "closure": d.closure,
        "shape": d.shape.iter().map(|m| serde_json::json!({
            "k": m.k, "decay_per_s": m.decay_per_s, "omega_rad_s": m.omega_rad_s,
        })).collect::<Vec<_>>(),
    })
}

/// What `modes --json` prints, and the dict Python's `mb.modes` returns.
impl Serialize for Modes {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            Modes::Frequencies(f) => frequencies_value(f).serialize(s),
            Modes::Damped(d) => damped_value(d).serialize(s),
        }
    }
}
