//! The linear attenuation and backscatter of a dilute suspension (docs/population.md,
//! "Attenuation"): with n_i = n·w_i bubbles per m³ in bin i and each bin's linear response
//! ([`crate::analysis::response`]: σ_e, σ_s per frequency),
//!
//!   α = 10 log10(e) Σ_i n_i σ_e,i   [dB/m]   (intensity decays as exp(−Σ n σ_e x)),
//!   η_bs = Σ_i n_i σ_s,i / (4π)     [1/(m·sr)]  (a monopole scatters isotropically),
//!
//! the dilute (independent-scattering) limit of Commander & Prosperetti 1989's dispersion
//! relation, in which 2 Im k_m = Σ n σ_e.

use crate::analysis::response::response;
use crate::scene::Scene;
use anyhow::Context;
use rayon::prelude::*;
use std::f64::consts::PI;

/// The population's attenuation at one frequency.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct AttenuationPoint {
    pub frequency_hz: f64,
    pub attenuation_db_per_cm: f64,
    pub backscatter_per_m_sr: f64,
}

/// Per bin (its scene, its number density [1/m³]), σ_e and σ_s at `frequency_hz`, then the sums
/// of the module doc in bin order (parallel over the bins; the sum does not depend on the
/// thread count).
pub fn attenuation_at(bins: &[(Scene, f64)], frequency_hz: f64) -> anyhow::Result<AttenuationPoint> {
    Ok(attenuation_spectrum(bins, &[frequency_hz])?[0])
}

/// [`attenuation_at`] at every frequency of `freqs`, one linear response per bin over all of
/// them (the fit of a measured spectrum, `fit --attenuation`).
pub fn attenuation_spectrum(bins: &[(Scene, f64)], freqs: &[f64]) -> anyhow::Result<Vec<AttenuationPoint>> {
    let per_bin: Vec<Vec<(f64, f64)>> = bins
        .par_iter()
        .enumerate()
        .map(|(i, (scene, _))| {
            let r = response(scene, freqs).with_context(|| format!("linear response of population bin {i}"))?;
            r.points
                .iter()
                .map(|p| {
                    let sigma_e = p.sigma_e_m2.context("the extinction cross-section needs liquid.sound_speed")?;
                    Ok((sigma_e, p.sigma_s_m2))
                })
                .collect::<anyhow::Result<Vec<_>>>()
        })
        .collect::<anyhow::Result<_>>()?;
    Ok(freqs
        .iter()
        .enumerate()
        .map(|(k, &frequency_hz)| {
            let (mut ext, mut sca) = (0.0, 0.0);
            for ((_, n), b) in bins.iter().zip(&per_bin) {
                let (se, ss) = b[k];
                ext += n * se;
                sca += n * ss;
            }
            AttenuationPoint {
                frequency_hz,
                attenuation_db_per_cm: 10.0 * std::f64::consts::LOG10_E * ext / 100.0,
                backscatter_per_m_sr: sca / (4.0 * PI),
            }
        })
        .collect())
}
