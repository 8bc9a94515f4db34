//! The echo a hydrophone measures (issue 30 part 2; docs/model.md, "Echo"): the scattered
//! pressure at the `[echo]` points, sampled with the run, and its spectrum.
//!
//! * [`volume`]: the exact volume of r = R + Σ a_k P_k(cos θ) and its rates (eq E1);
//! * [`field`]: far field ρV̈/(4πr) (E2) and near field from the unsteady Bernoulli equation (E3);
//! * [`spectrum`]: the one-sided amplitude spectrum (Hann window) and the summary levels;
//! * [`Recorder`]: per output sample, R̈ and ä_k from the model's right-hand side (exact, not
//!   differences of samples) and the pressure at every point.

pub mod field;
pub mod spectrum;
pub mod volume;

use crate::model::Model;
use crate::scene::Scene;
use field::{Field, Kinematics};

/// Within this many R0 the near-field form (E3) is used, beyond it the far field (E2).
pub const NEAR_FIELD_RADII: f64 = 10.0;

/// The echo of a run: the pressure at each point per sample, and the shape modes' part of the
/// far-field monopole.
#[derive(Debug, Clone)]
pub struct EchoSeries {
    /// Observation times [s]: the sample times, + (r − R0)/c for a retarded far field.
    pub t: Vec<f64>,
    /// Column names: `p_<distance>m_<angle>deg`.
    pub names: Vec<String>,
    /// p_s [Pa] per point (outer index), per sample.
    pub p: Vec<Vec<f64>>,
    /// The shape modes' part of the far-field echo, ρ(V̈ − 4π(R²R̈ + 2RṘ²))/(4πr) [Pa].
    pub shape_part: Vec<f64>,
    /// "far" (E2) or "near" (E3).
    pub form: &'static str,
    /// (r − R0)/c [s] when the far field is retarded, else 0.
    pub delay: f64,
}

/// Samples the echo during a run (see the module doc).
#[derive(Debug)]
pub struct Recorder {
    field: Field,
    distance: f64,
    angles: Vec<f64>,
    near: bool,
    length: f64,
    time: f64,
    dy: Vec<f64>,
    out: EchoSeries,
}

impl Recorder {
    /// The recorder of a scene's `[echo]` (`None` without one).
    pub fn for_scene(scene: &Scene, model: &Model) -> Option<Recorder> {
        let e = scene.echo.as_ref()?;
        let near = e.distance <= NEAR_FIELD_RADII * scene.bubble.radius;
        let delay = match (near, scene.liquid.sound_speed) {
            (false, Some(c)) => (e.distance - scene.bubble.radius) / c,
            _ => 0.0,
        };
        let names = e.angles_deg.iter().map(|a| format!("p_{}m_{}deg", fmt(e.distance), fmt(*a))).collect();
        Some(Recorder {
            field: Field::new(scene.liquid.density, model.orders()),
            distance: e.distance,
            angles: e.angles_deg.iter().map(|a| a.to_radians()).collect(),
            near,
            length: model.scales().length,
            time: model.time_scale(),
            dy: vec![0.0; model.system().dim()],
            out: EchoSeries {
                t: Vec::new(),
                names,
                p: vec![Vec::new(); e.angles_deg.len()],
                shape_part: Vec::new(),
                form: if near { "near" } else { "far" },
                delay,
            },
        })
    }

    /// The instant of state `z` (model units) at time t [s], in SI, with R̈ and ä_k from the
    /// model's right-hand side.
    pub fn kinematics(&mut self, model: &Model, t: f64, z: &[f64]) -> Kinematics {
        model.system().rhs(t / self.time, z, &mut self.dy);
        let (l, tt) = (self.length, self.time);
        let si = |x: f64, v: f64, a: f64| [x * l, v * l / tt, a * l / (tt * tt)];
        let lay = crate::model::layout::StateLayout::reduced(model.orders().len());
        let r = si(z[lay.r()], z[lay.rdot()], self.dy[lay.rdot()]);
        let a = (0..lay.modes()).map(|m| si(z[lay.a(m)], z[lay.adot(m)], self.dy[lay.adot(m)])).collect();
        Kinematics { r, a }
    }

    /// Records the sample at t [s] with the full state `z` (model units).
    pub fn record(&mut self, model: &Model, t: f64, z: &[f64]) {
        let k = self.kinematics(model, t, z);
        let r = self.distance;
        let far = self.field.far_of(self.field.volume(&k).2, r);
        for (col, &theta) in self.out.p.iter_mut().zip(&self.angles) {
            col.push(if self.near { self.field.near(&k, r, theta) } else { far });
        }
        // without shape modes their part is exactly zero (not the roundoff of two forms of ρV̈/(4πr))
        let shape = if k.a.is_empty() { 0.0 } else { far - self.field.far_spherical(&k, r) };
        self.out.shape_part.push(shape);
        self.out.t.push(t + self.out.delay);
    }

    pub fn finish(self) -> EchoSeries {
        self.out
    }
}

/// A number in a column name: `0.05`, `90`.
fn fmt(x: f64) -> String {
    let s = format!("{x}");
    s
}

/// Runs `scene` (boundary-layer or radial model) and records its echo: the run's rows go to
/// `observer` as [`crate::model::simulate`] gives them, the echo to the returned series.
pub fn simulate(
    scene: &Scene,
    observer: &mut dyn FnMut(f64, &[f64]),
) -> Result<(crate::model::RunReport, Option<EchoSeries>), crate::model::ModelError> {
    if scene.echo.is_none() {
        return crate::model::simulate(scene, observer).map(|r| (r, None));
    }
    if scene.modes.viscous == crate::scene::Viscous::Vorticity && scene.modes.max_order > 0 {
        return Err(crate::model::ModelError::Unsupported {
            key: "echo",
            value: "[echo]".into(),
            reason: "the echo is recorded from the boundary-layer model's state; with modes.viscous = \"vorticity\" remove [echo]",
        });
    }
    let model = Model::from_scene(scene)?;
    let mut rec = Recorder::for_scene(scene, &model).expect("[echo] present");
    // each row carries the full state (R, Ṙ, a, ȧ, b): recorded as it is, no copy
    let report = model.run_rows(&scene.run, &mut |row| {
        rec.record(&model, row.t, row.z);
        observer(row.t, row.si);
    });
    Ok((report, Some(rec.finish())))
}
