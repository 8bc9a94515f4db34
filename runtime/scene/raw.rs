//! The scene exactly as written in TOML: every key optional where a default exists (the defaults
//! live in [`super::schema::SCHEMA`] and are applied by `TryFrom<RawScene> for Scene`), unknown
//! keys rejected. Enumerations are kept as strings here so that validation can report a bad
//! choice together with every other error.

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// A mode map as written: `{ 2 = 1e-8, 4 = 0.0 }` (TOML keys are strings).
pub type RawModeMap = BTreeMap<String, f64>;

#[derive(Debug, Clone, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawScene {
    pub bubble: Option<RawBubble>,
    pub shell: Option<RawShell>,
    pub gas: Option<RawGas>,
    pub liquid: Option<RawLiquid>,
    pub drive: Option<RawDrive>,
    pub field: Option<RawField>,
    pub modes: Option<RawModes>,
    pub vorticity: Option<RawVorticity>,
    pub run: Option<RawRun>,
    pub echo: Option<RawEcho>,
    pub population: Option<RawPopulation>,
}

#[derive(Debug, Clone, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawPopulation {
    pub distribution: Option<String>,
    pub median_radius: Option<f64>,
    pub geometric_std: Option<f64>,
    pub bins: Option<i64>,
    pub file: Option<String>,
    pub concentration: Option<f64>,
    pub scale_with_radius: Option<String>,
}

#[derive(Debug, Clone, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawEcho {
    pub distance: Option<f64>,
    pub angles_deg: Option<Vec<f64>>,
    pub window: Option<Vec<f64>>,
}

#[derive(Debug, Clone, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawBubble {
    pub radius: Option<f64>,
    pub initial: Option<RawInitial>,
}

#[derive(Debug, Clone, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawInitial {
    pub radius: Option<f64>,
    pub velocity: Option<f64>,
    pub a: Option<RawModeMap>,
    pub a_velocity: Option<RawModeMap>,
    pub b: Option<RawModeMap>,
    pub seed: Option<String>,
}

#[derive(Debug, Clone, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawShell {
    pub c1: Option<f64>,
    pub c2: Option<f64>,
    pub thickness: Option<f64>,
    pub susceptibility: Option<f64>,
    pub form: Option<String>,
    pub law: Option<String>,
    pub shear_modulus: Option<f64>,
    pub area_dilatation: Option<f64>,
    pub bending_modulus: Option<f64>,
    pub shear_viscosity: Option<f64>,
    pub dilatational_viscosity: Option<f64>,
    pub surface_tension: Option<f64>,
    pub elasticity: Option<f64>,
    pub buckling_radius: Option<f64>,
    pub initial_tension: Option<f64>,
    pub rupture_tension: Option<f64>,
    pub smoothing: Option<f64>,
    pub elasticity_decay: Option<f64>,
    pub reference_tension: Option<f64>,
    pub modulus: Option<f64>,
    pub viscosity: Option<f64>,
    pub tension_file: Option<String>,
}

#[derive(Debug, Clone, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawGas {
    pub polytropic_exponent: Option<f64>,
    pub reference_pressure: Option<f64>,
    pub vapour_pressure: Option<f64>,
    pub thermal: Option<String>,
    pub thermal_diffusivity: Option<f64>,
    pub heat_capacity_ratio: Option<f64>,
}

#[derive(Debug, Clone, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawLiquid {
    pub density: Option<f64>,
    pub viscosity: Option<f64>,
    pub ambient_pressure: Option<f64>,
    pub sound_speed: Option<f64>,
    pub temperature: Option<f64>,
}

#[derive(Debug, Clone, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawDrive {
    pub amplitude: Option<f64>,
    pub frequency_hz: Option<f64>,
    pub phase: Option<f64>,
    pub envelope: Option<String>,
    pub cycles: Option<f64>,
    pub delay: Option<f64>,
    pub tukey_fraction: Option<f64>,
    pub repeat_hz: Option<f64>,
    pub components: Option<Vec<RawComponent>>,
    pub file: Option<String>,
    pub file_scale: Option<f64>,
}

/// One of `drive.components = [{ amplitude, frequency_hz, phase }, …]`.
#[derive(Debug, Clone, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawComponent {
    pub amplitude: Option<f64>,
    pub frequency_hz: Option<f64>,
    pub phase: Option<f64>,
}

#[derive(Debug, Clone, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawField {
    pub coil: Option<RawCoil>,
    pub dipole: Option<RawDipole>,
}

#[derive(Debug, Clone, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawCoil {
    pub turns: Option<f64>,
    pub distance: Option<f64>,
    pub angle: Option<f64>,
    pub current: Option<RawCurrent>,
    pub distance_oscillation: Option<RawOscillation>,
    pub include_h4: Option<bool>,
}

/// `current = 100e3` (static) or `current = { amplitude = 150e3, frequency_hz = 5e5 }`.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(untagged)]
pub enum RawCurrent {
    Static(f64),
    Cosine(RawOscillation),
}

/// `{ amplitude, frequency_hz }` (alternating current, oscillating distance).
#[derive(Debug, Clone, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawOscillation {
    pub amplitude: Option<f64>,
    pub frequency_hz: Option<f64>,
}

#[derive(Debug, Clone, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawDipole {
    pub moment: Option<f64>,
    pub distance: Option<f64>,
}

#[derive(Debug, Clone, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawModes {
    pub max_order: Option<i64>,
    pub viscous: Option<String>,
    pub boundary_layer_frequency: Option<String>,
    pub coupling: Option<String>,
    pub credible_amplitude: Option<f64>,
}

#[derive(Debug, Clone, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawVorticity {
    pub y_max: Option<f64>,
    pub points: Option<i64>,
    pub stretching: Option<f64>,
    pub scheme: Option<String>,
}

#[derive(Debug, Clone, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawRun {
    pub duration: Option<f64>,
    pub sample_interval: Option<f64>,
    pub blow_up_threshold: Option<f64>,
    pub max_output_bytes: Option<f64>,
    pub integrator: Option<RawIntegrator>,
}

#[derive(Debug, Clone, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawIntegrator {
    pub method: Option<String>,
    pub rtol: Option<f64>,
    pub atol: Option<f64>,
    pub dt: Option<f64>,
    pub max_steps: Option<i64>,
}
