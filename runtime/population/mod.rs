//! Polydisperse suspensions (issue 33; docs/population.md): a size distribution resolved into
//! bins ([`quadrature`]), each bin a scene of its own ([`bin_template`]), and the population
//! quantities over the bins — the weighted fraction unstable ([`fraction`]) and the attenuation
//! and backscatter of the suspension ([`attenuation`]). The commands are `api::population` and
//! `api::attenuation`.

pub mod attenuation;
pub mod tables;
pub mod fraction;
pub mod quadrature;

use crate::scene::schema::fmt_num;
use crate::scene::{Population, PopulationBin};
use crate::scene::SceneTemplate;
use anyhow::Context;

/// The scene of one bin: `base` with bubble.radius = the bin's radius and every key of
/// `population.scale_with_radius` multiplied by R_bin / R0 (R0 = the scene's bubble.radius),
/// validated like a scene file. The radius is written in Rust's shortest round-trip form, so the
/// bin's scene is bit for bit the scene file with that radius.
pub fn bin_template(base: &SceneTemplate, population: &Population, index: usize, bin: PopulationBin) -> anyhow::Result<SceneTemplate> {
    let r0 = base.scene().bubble.radius;
    let mut set = vec![format!("bubble.radius={:?}", bin.radius)];
    for key in &population.scale_with_radius {
        let v = base.given_number(key).with_context(|| {
            format!("population.scale_with_radius: `{key}` is not given in the scene; give its value to scale it with the radius")
        })?;
        set.push(format!("{key}={:?}", v * (bin.radius / r0)));
    }
    base.with_overrides(&set).with_context(|| format!("population bin {index} (radius {} m, weight {})", fmt_num(bin.radius), fmt_num(bin.weight)))
}

/// Every bin's scene (the first invalid bin is the error: nothing is computed for a population
/// with one).
pub fn bin_templates(base: &SceneTemplate, population: &Population) -> anyhow::Result<Vec<SceneTemplate>> {
    population.bins.iter().enumerate().map(|(i, &b)| bin_template(base, population, i, b)).collect()
}
