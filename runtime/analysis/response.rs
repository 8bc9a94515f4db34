//! The linear radial response (issue 30 part 3; docs/model.md, "Linear response"): the radial
//! equation linearised at rest by the model's own exact gradients — the terms' ∂P/∂(R, Ṙ)
//! ([`crate::model::effects::Term::add_pressure_and_gradient`]) through the radial form's
//! partials, the drive entering as −p∞ in P and −dp∞/dt in Keller–Miksis' rate —
//!
//!   ẍ + c ẋ + k x = −(d_P p_a + d_q ṗ_a),   x = R − R0,
//!
//! k = −∂R̈/∂R, c = −∂R̈/∂Ṙ, d_P = ∂R̈/∂P, d_q = ∂R̈/∂q. For p_a = P_a e^{iωt}:
//! X/P_a = −(d_P + iω d_q)/(k − ω² + iωc). The damping c splits by source: each term's
//! d_P ∂P_term/∂Ṙ (liquid viscosity, shell viscosity, …) and the radial form's own part
//! (radiation, Keller–Miksis). δ = c/ω. The scattered far field of the linear motion is
//! ρR0²ω²|X| / r per unit P_a (eq E2 with V̈ = 4πR0² ẍ), so σ_s = 4π (ρR0²ω²|X/P_a|)²; for the
//! incompressible free bubble this is the textbook 4πR0²/[((ω0/ω)² − 1)² + δ²]. σ_e = σ_s δ/δ_rad,
//! δ_rad = ωR0/c_sound (needs `liquid.sound_speed`).

use crate::model::effects::At;
use crate::model::{Model, ModelError};
use crate::scene::Scene;
use serde::Serialize;
use std::f64::consts::PI;

/// Damping rates c [1/s] (ẍ + c ẋ + …) by source.
#[derive(Debug, Clone, Default, Serialize, PartialEq)]
pub struct DampingSplit {
    pub total: f64,
    pub liquid_viscosity: f64,
    pub radiation: f64,
    pub shell_viscosity: f64,
    /// Every other term with a Ṙ-dependent pressure (0 for the shipped effects).
    pub other: f64,
}

/// The response at one frequency.
#[derive(Debug, Clone, Serialize)]
pub struct ResponsePoint {
    pub frequency_hz: f64,
    /// |X/P_a| [m/Pa]
    pub amplitude_m_per_pa: f64,
    /// arg(X/P_a) [rad] (x = Re X e^{iωt} for p_a = P_a cos ωt)
    pub phase_rad: f64,
    /// δ = c/ω per source (dimensionless damping constants).
    pub delta: DampingSplit,
    /// σ_s [m²]
    pub sigma_s_m2: f64,
    /// σ_e [m²] (null without liquid.sound_speed)
    pub sigma_e_m2: Option<f64>,
}

/// The linear response of a scene.
#[derive(Debug, Clone, Serialize)]
pub struct Response {
    /// √k / 2π [Hz] (Minnaert with surface tension and shell for the radial equation).
    pub natural_frequency_hz: f64,
    /// The frequency of the largest |X/P_a| on the grid [Hz].
    pub resonance_frequency_hz: f64,
    /// c [1/s] by source (at rest; Keller–Miksis' radiation part is frequency independent).
    pub damping_rates_per_s: DampingSplit,
    pub points: Vec<ResponsePoint>,
}

/// The linear response of `scene` (its drive ignored) at `frequencies` [Hz].
pub fn response(scene: &Scene, frequencies: &[f64]) -> Result<Response, ModelError> {
    let mut s = scene.clone();
    s.drive = None;
    s.echo = None;
    s.bubble.initial.radius = s.bubble.radius;
    s.bubble.initial.velocity = 0.0;
    crate::model::refuse_reduced_thermal(&s, "the linear response is computed from the radial balance without the reduced model's p_b: use gas.thermal = \"prosperetti\" (its small-amplitude limit)")?;
    let model = Model::from_scene(&s)?;
    let eq = model.equations();
    let (ts, l, pscale) = (model.time_scale(), model.scales().length, model.scales().pressure);
    let mut z = vec![0.0; model.system().dim()];
    z[0] = 1.0;
    let at = At { t: 0.0, z: &z };
    // P and its gradient, per term and in total (the sum in the terms' order, as the model's)
    let (mut p, mut dp) = (0.0, [0.0; 2]);
    let mut by_term = Vec::new();
    for term in eq.terms() {
        let (mut pt, mut dpt) = (0.0, [0.0; 2]);
        term.add_pressure_and_gradient(&at, &mut pt, &mut dpt);
        p += pt;
        dp[0] += dpt[0];
        dp[1] += dpt[1];
        by_term.push((term.name(), dpt[1]));
    }
    let mut shape = crate::model::effects::ShapeRate::default();
    let (rate, _) = eq.rate(0.0, &z, &mut shape);
    let rho = eq.params.rho;
    let d = if eq.form().needs_rate() { eq.form().partials_rate(rho, 1.0, 0.0, p, &rate) } else { eq.form().partials_rate(rho, 1.0, 0.0, p, &Default::default()) };
    // nondimensional k, c; SI by t*
    let k = -(d[0] + d[2] * dp[0] + d[3] * rate.dq[0] + d[4] * rate.ds[0]) / (ts * ts);
    // (+ 0.0: no −0 for a form without radiation)
    let mut split = DampingSplit { radiation: -(d[1] + d[3] * rate.dq[1] + d[4] * rate.ds[1]) / ts + 0.0, ..Default::default() };
    for (name, dpr) in by_term {
        let c = -d[2] * dpr / ts;
        match name {
            "liquid viscosity" => split.liquid_viscosity += c,
            "shell viscosity" => split.shell_viscosity += c,
            _ => split.other += c,
        }
    }
    split.total = split.liquid_viscosity + split.radiation + split.shell_viscosity + split.other;
    // forcing per Pa: R̈ [m/s²] per p_a [Pa], per ṗ_a [Pa/s]
    let (f_p, f_q) = (-d[2] * l / (ts * ts) / pscale, -d[3] * l / ts / pscale);
    let r0 = scene.bubble.radius;
    let rho_si = scene.liquid.density;
    let points: Vec<ResponsePoint> = frequencies
        .iter()
        .map(|&f| {
            let w = 2.0 * PI * f;
            // X = (f_p + iω f_q) / (k − ω² + iωc)
            let (nr, ni) = (f_p, w * f_q);
            let (dr, di) = (k - w * w, w * split.total);
            let den = dr * dr + di * di;
            let (xr, xi) = ((nr * dr + ni * di) / den, (ni * dr - nr * di) / den);
            let amp = xr.hypot(xi);
            let scale = |c: f64| c / w;
            let delta = DampingSplit {
                total: scale(split.total),
                liquid_viscosity: scale(split.liquid_viscosity),
                radiation: scale(split.radiation),
                shell_viscosity: scale(split.shell_viscosity),
                other: scale(split.other),
            };
            let sigma_s = 4.0 * PI * (rho_si * r0 * r0 * w * w * amp).powi(2);
            let sigma_e = scene.liquid.sound_speed.map(|c| sigma_s * delta.total / (w * r0 / c));
            ResponsePoint { frequency_hz: f, amplitude_m_per_pa: amp, phase_rad: xi.atan2(xr), delta, sigma_s_m2: sigma_s, sigma_e_m2: sigma_e }
        })
        .collect();
    let resonance = points.iter().max_by(|a, b| a.amplitude_m_per_pa.total_cmp(&b.amplitude_m_per_pa)).map_or(f64::NAN, |p| p.frequency_hz);
    Ok(Response { natural_frequency_hz: k.max(0.0).sqrt() / (2.0 * PI), resonance_frequency_hz: resonance, damping_rates_per_s: split, points })
}

/// `A:B:N[:log]` → N frequencies from A to B [Hz] (linear, or logarithmic with `:log`).
pub fn parse_grid(spec: &str) -> Result<Vec<f64>, String> {
    let parts: Vec<&str> = spec.split(':').collect();
    let bad = || format!("--freq {spec}: expected A:B:N or A:B:N:log (A, B in Hz, 0 < A < B, N >= 2)");
    let (a, b, n, log) = match parts[..] {
        [a, b, n] => (a, b, n, false),
        [a, b, n, "log"] => (a, b, n, true),
        _ => return Err(bad()),
    };
    let (a, b): (f64, f64) = (a.parse().map_err(|_| bad())?, b.parse().map_err(|_| bad())?);
    let n: usize = n.parse().map_err(|_| bad())?;
    if !(a > 0.0 && b > a && b.is_finite() && n >= 2) {
        return Err(bad());
    }
    Ok((0..n)
        .map(|i| {
            let u = i as f64 / (n - 1) as f64;
            if log { a * (b / a).powf(u) } else { a + (b - a) * u }
        })
        .collect())
}
