//! Keller–Miksis with a magnetic field (issue 10 left part): `MagneticTerm::add_rate` gives dM0/dt
//! exactly (∂t of the current/distance laws, ∂R of the R powers, Σ ∂M0/∂a ȧ), and the part
//! Σ ∂M0/∂b ḃ through the closure's ḃ_k, which the boundary-layer system evaluates before R̈
//! (runtime/model/boundary_layer.rs). Checked against
//!
//! * a (Richardson-extrapolated) central difference of P(t, z + hż) along the motion of the coupled rhs (the independent
//!   reference for the whole rate, ḃ part included), for a static coil, an AC coil, an
//!   oscillating coil distance, a dipole and the H4 coil (wider band);
//! * finite differences of the rhs (the exact Jacobian) and the Jacobian pattern;
//! * the incompressible limit: c = 1e9 m/s gives the incompressible series.

use crate::support::jacobian::assert_jacobian_matches_fd_step;
use magbubble::model::layout::StateLayout;
use magbubble::model::effects::{At, PressureRate, ShapeRate};
use magbubble::model::Model;
use magbubble::scene;

const FIELDS: [&str; 5] = [
    "[field.coil]\ncurrent = 1e6\n",
    "[field.coil]\ncurrent = { amplitude = 1.5e6, frequency_hz = 0.5e6 }\n",
    "[field.coil]\ncurrent = 1e6\ndistance_oscillation = { amplitude = 0.1, frequency_hz = 0.5e6 }\n",
    "[field.dipole]\nmoment = 100.0\ndistance = 0.01\n",
    "[field.coil]\ncurrent = 1e6\nangle = 0.7853981633974483\ninclude_h4 = true\n",
];

fn model(field: &str, extra: &str, over: &[&str]) -> Model {
    let text = format!(
        "[bubble]\nradius = 10e-6\n[liquid]\nsound_speed = 1500.0\n[drive]\namplitude = 0.3\nfrequency_hz = 1e6\n\
         {field}[modes]\nmax_order = 6\n{extra}"
    );
    let s = scene::load_str(&text, "km + field (test)", over).unwrap();
    Model::from_scene(&s).unwrap_or_else(|e| panic!("KM + field must be assembled: {e}"))
}

#[test]
fn pressure_rate_with_a_field_matches_a_finite_difference_along_the_motion() {
    for field in FIELDS {
        let m = model(field, "", &[]);
        let (eq, sys) = (m.equations(), m.system());
        let n = sys.dim();
        for (t, seed) in [(0.37, 1.0), (1.9, -0.6)] {
            let mut z: Vec<f64> = (0..n).map(|i| seed * 0.01 * (i as f64 + 1.0).sin()).collect();
            z[0] = 1.0 + 0.2 * seed;
            z[1] = -0.3 * seed;
            let mut dz = vec![0.0; n];
            sys.rhs(t, &z, &mut dz);
            let mut shape = ShapeRate::default();
            let (rate, all) = eq.rate(t, &z, &mut shape);
            assert!(all, "{field}: every term provides the rate");
            let l = StateLayout::reduced_of_dim(n);
            let bdot: f64 = (0..l.modes()).map(|j| rate.db(j) * dz[l.b(j)]).sum();
            let exact = rate.q + bdot + rate.s * dz[1];
            let p = |h: f64| {
                let zh: Vec<f64> = z.iter().zip(&dz).map(|(x, d)| x + h * d).collect();
                eq.loads(t + h, &zh, &mut [], &mut [])
            };
            // central differences at h and h/2, Richardson-extrapolated (error O(h⁴))
            let d = |h: f64| (p(h) - p(-h)) / (2.0 * h);
            let h = 2e-4;
            let fd = (4.0 * d(h / 2.0) - d(h)) / 3.0;
            // the magnetic share must be visible in the check
            let mag = eq.terms().find(|t| t.name() == "magnetic").unwrap();
            let mut mr_shape = ShapeRate::default();
            let mut mr = PressureRate::with_shape(&mut mr_shape);
            assert!(mag.add_rate(&At { t, z: &z }, &mut mr));
            let mag_share = mr.q + (0..l.modes()).map(|j| mr.db(j) * dz[l.b(j)]).sum::<f64>();
            eprintln!("{}: dP/dt FD {fd:.6e}, exact {exact:.6e}, magnetic part {mag_share:.3e} (ḃ part {bdot:.3e})", field.lines().nth(1).unwrap());
            assert!(mag_share.abs() > 1e-4 * fd.abs(), "{field}: magnetic part {mag_share} too small to be tested");
            assert!(bdot != 0.0, "{field}: the ḃ part is exercised");
            assert!((fd - exact).abs() < 1e-9 * (1.0 + fd.abs()), "{field} t = {t}: FD {fd} vs exact {exact}");
        }
    }
}

#[test]
fn keller_miksis_with_a_field_jacobian_matches_finite_differences_and_its_pattern() {
    for field in FIELDS {
        let m = model(field, "", &[]);
        let sys = m.system();
        // a step of 1e-5 (absolute floor): the default 1e-6·max(|y|, 1e-3) is below the rounding
        // noise of the ä rows here (|ä_6| ≈ 43 against entries of 4e-6)
        assert_jacobian_matches_fd_step(sys, field, 1e-5);
        let bl = m.boundary_layer().expect("a boundary-layer system");
        let pat = bl.jacobian_pattern();
        let n = sys.dim();
        let mut y: Vec<f64> = (0..n).map(|i| 0.01 * (i as f64 + 1.0).cos()).collect();
        y[0] = 1.1;
        let mut jac = vec![0.0; n * n];
        assert!(sys.jacobian(0.2, &y, &mut jac));
        for i in 0..n {
            for j in 0..n {
                assert!(pat.may_be_nonzero(i, j) || jac[i * n + j] == 0.0, "{field}: ({i},{j}) outside the pattern");
            }
        }
        assert!(pat.radial == 2 * pat.band && pat.band > 0);
    }
}

#[test]
fn keller_miksis_with_a_field_tends_to_the_incompressible_series() {
    let over = ["run.duration=5e-6", "run.sample_interval=1e-7", "run.integrator.method=dop853", "run.integrator.rtol=1e-11", "run.integrator.atol=1e-13"];
    for field in [FIELDS[1], FIELDS[3]] {
        let text = |c: &str| {
            format!(
                "[bubble]\nradius = 10e-6\ninitial = {{ a = {{ 2 = 1e-8 }} }}\n{c}[drive]\namplitude = 0.3\nfrequency_hz = 1e6\n{field}[modes]\nmax_order = 6\n"
            )
        };
        let run = |t: String| {
            let s = scene::load_str(&t, "km + field (test)", &over).unwrap();
            let mut rows = Vec::new();
            let rep = magbubble::model::simulate(&s, &mut |_, row| rows.push(row.to_vec())).unwrap();
            assert_eq!(rep.status, magbubble::model::RunStatus::Completed, "{t}");
            rows
        };
        let (inc, km, km_slow) = (run(text("")), run(text("[liquid]\nsound_speed = 1e9\n")), run(text("[liquid]\nsound_speed = 1500.0\n")));
        let diff = |a: &[Vec<f64>], b: &[Vec<f64>]| {
            a.iter().zip(b).flat_map(|(x, y)| x.iter().zip(y).map(|(u, v)| (u - v).abs())).fold(0.0f64, f64::max) / 10e-6
        };
        let (d_fast, d_slow) = (diff(&inc, &km), diff(&inc, &km_slow));
        eprintln!("{}: max |Δ|/R0 incompressible vs KM c = 1e9: {d_fast:.2e}, vs c = 1500: {d_slow:.2e}", field.lines().nth(1).unwrap());
        // the O(Ṙ/c) ≈ 1e-9 difference sits below the integrators' own 1e-8 at rtol 1e-11
        assert!(d_fast < 1e-7, "{d_fast}");
        assert!(d_slow > 1e-4, "c = 1500 m/s must differ visibly: {d_slow}");
    }
}

