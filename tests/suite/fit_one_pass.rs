//! The sensitivity rhs in one pass (runtime/model/sensitivity.rs, fit/sensitivities.rs, issue 32):
//! f is the system's rhs bit for bit, and J·S_j + ∂f/∂θ_j — ∂f/∂θ_j from the loads of the terms
//! that hold the parameter — equals the dense Jacobian times S_j plus central differences of
//! the whole rhs of the models at p ± h (keys that leave the units unchanged, so the models'
//! rhs compare directly), to 1e-9 of the largest entry; incompressible and Keller–Miksis, a
//! field with the shell's ḃ loads.

use magbubble::fit::params::scene_value;
use magbubble::fit::sensitivities::{scale_of, ModelRates};
use magbubble::integrate::sensitivity::ParameterRates;
use magbubble::model::Model;
use magbubble::scene::SceneTemplate;

fn scene(extra: &str) -> String {
    format!(
        "[bubble]\nradius = 10e-6\n[bubble.initial]\na = {{ 2 = 2e-8 }}\n\
         [shell]\nc1 = 0.1\nc2 = 0.12\nthickness = 20e-9\nsusceptibility = 1.0\n\
         [drive]\namplitude = 0.4\nfrequency_hz = 1e6\n\
         [modes]\nmax_order = 6\n\
         [run]\nduration = 3e-6\nsample_interval = 2e-8\n{extra}"
    )
}

fn check(text: &str, keys: &[&str]) {
    let t = SceneTemplate::from_str(text, "test", &[] as &[&str]).unwrap();
    let values: Vec<f64> = keys.iter().map(|k| scene_value(&t, k).unwrap()).collect();
    let set: Vec<(&str, f64)> = keys.iter().copied().zip(values.iter().copied()).collect();
    let m = Model::from_scene(&t.with(&set).unwrap()).unwrap();
    let rates = ModelRates::new(&t, keys, &values, &m).unwrap();
    for (j, k) in keys.iter().enumerate() {
        assert!(rates.from_terms(j), "{k}: not formed from the terms");
    }
    let sys = m.system();
    let (n, p) = (sys.dim(), keys.len());
    // the models at p ± h, for the central differences of the whole rhs
    let at = |j: usize, v: f64| {
        let mut s = set.clone();
        s[j].1 = v;
        Model::from_scene(&t.with(&s).unwrap()).unwrap()
    };
    let y0 = m.initial_state().to_vec();
    for k in 0..5 {
        let tk = 0.3 * k as f64;
        let y: Vec<f64> = y0.iter().enumerate().map(|(i, &v)| v * (1.0 + 0.05 * k as f64) + if i > 0 { 1e-3 * ((i * (k + 1)) % 7) as f64 } else { 0.0 }).collect();
        let s: Vec<f64> = (0..n * p).map(|i| ((i * 37 + k * 11) % 19) as f64 / 9.0 - 1.0).collect();
        let (mut dy, mut ds) = (vec![0.0; n], vec![0.0; n * p]);
        assert!(rates.augmented_rhs(tk, &y, &s, &mut dy, &mut ds));
        let mut f = vec![0.0; n];
        sys.rhs(tk, &y, &mut f);
        for i in 0..n {
            assert_eq!(dy[i].to_bits(), f[i].to_bits(), "f component {i}: {} vs {}", dy[i], f[i]);
        }
        let mut jac = vec![0.0; n * n];
        assert!(sys.jacobian(tk, &y, &mut jac));
        for j in 0..p {
            let h = 1e-3 * scale_of(values[j]);
            let (mp, mm) = (at(j, values[j] + h), at(j, values[j] - h));
            let (mut fp, mut fm) = (vec![0.0; n], vec![0.0; n]);
            mp.system().rhs(tk, &y, &mut fp);
            mm.system().rhs(tk, &y, &mut fm);
            let sj = &s[j * n..(j + 1) * n];
            let expected: Vec<f64> = (0..n)
                .map(|i| {
                    let js: f64 = jac[i * n..(i + 1) * n].iter().zip(sj).map(|(a, b)| a * b).sum();
                    js + (fp[i] - fm[i]) / (2.0 * h) * scale_of(values[j])
                })
                .collect();
            let big = expected.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            for i in 0..n {
                let got = ds[j * n + i];
                assert!((got - expected[i]).abs() <= 1e-9 * big, "{} state {k} component {i}: {got} vs {}", keys[j], expected[i]);
            }
        }
    }
}

#[test]
fn incompressible() {
    check(&scene(""), &["shell.c2", "drive.amplitude"]);
}

#[test]
fn keller_miksis() {
    check(&scene("[liquid]\nsound_speed = 1500.0\n"), &["shell.c2", "drive.amplitude"]);
}

#[test]
fn field_and_shell_viscosity() {
    let extra = "[field.coil]\ncurrent = 3e5\n";
    let text = scene(extra).replace("susceptibility = 1.0\n", "susceptibility = 1.0\ndilatational_viscosity = 1e-9\n");
    check(&text, &["shell.c2", "drive.amplitude", "shell.susceptibility"]);
}
