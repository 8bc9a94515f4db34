//! Scenes built by hand for the analysis tests (the paper's fig 5–12 parameters).
#![allow(dead_code)]

use magbubble::scene::*;
use std::collections::BTreeMap;

pub const R0: f64 = 10e-6;
pub const C1: f64 = 0.1;
pub const C2: f64 = 0.12;

/// Water at 20 °C and air, the liquid and gas of the hand-built scenes: density [kg/m³],
/// viscosity [Pa s], ambient pressure [Pa], polytropic exponent, sound speed [m/s], surface
/// tension [N/m].
pub mod water {
    pub const RHO: f64 = 1000.0;
    pub const ETA: f64 = 1e-3;
    pub const P0: f64 = 101325.0;
    pub const KAPPA: f64 = 1.4;
    pub const C: f64 = 1500.0;
    pub const GAMMA: f64 = 0.072;
}

pub fn scene(max_order: usize, eps_p: f64, f_hz: f64) -> Scene {
    Scene {
        bubble: Bubble {
            radius: R0,
            initial: Initial { radius: R0, velocity: 0.0, a: BTreeMap::new(), a_velocity: BTreeMap::new(), b: BTreeMap::new() },
        },
        shell: Shell::mooney_rivlin(C1, C2, 20e-9, 1.0, MembraneForm::Paper),
        gas: Gas { polytropic_exponent: 1.4, reference_pressure: 101325.0, reference_pressure_given: true, vapour_pressure: 0.0 },
        liquid: Liquid { density: 1000.0, viscosity: 1e-3, ambient_pressure: 101325.0, sound_speed: None },
        drive: Some(Drive { amplitude: eps_p, frequency_hz: f_hz }),
        field: None,
        modes: Modes { max_order, viscous: Viscous::BoundaryLayer, boundary_layer_frequency: BoundaryLayerFrequency::Auto, coupling: Coupling::Linear, credible_amplitude: 0.1 },
        vorticity: VorticityGrid { y_max: 2.0, points: 200, stretching: 1.0, scheme: VorticityScheme::Monolithic },
        run: Run {
            duration: 100e-6,
            sample_interval: 1e-7,
            integrator: IntegratorSettings { method: Method::Dopri5, rtol: 1e-8, atol: 1e-12, dt: 1e-9, max_steps: 100_000_000 },
            blow_up_threshold: 0.5,
            max_output_bytes: 1e9,
        },
    }
}

pub fn coil(current: f64) -> Field {
    Field::Coil(Coil {
        turns: 1000.0,
        distance: 0.1,
        angle: (3.0f64 / 7.0).sqrt().acos(),
        current: Current::Static { value: current },
        distance_oscillation: None,
        include_h4: false,
    })
}

pub fn dipole(moment: f64, distance: f64) -> Field {
    Field::Dipole(Dipole { moment, distance })
}
