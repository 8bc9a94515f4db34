//! The boundary-layer model's structured Newton matrix: for every shipped scene with shape modes,
//! at the initial state and at a state with every amplitude set, the model hands the implicit
//! steppers a structured form (no silent dense fallback) — the position rows eliminated
//! (integrate/reduced.rs) at k ≤ 16, the bordered band (integrate/bordered.rs) at k ≤ 32 where
//! its split pays — and its solves of σI − J, real and complex σ, agree with a dense LU.

use magbubble::model::layout::StateLayout;
use magbubble::integrate::OdeSystem;
use magbubble::model::Model;
use magbubble::scene;
use nalgebra::{Complex, DMatrix, DVector};
use std::path::PathBuf;

fn scenes() -> Vec<PathBuf> {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let mut v: Vec<PathBuf> = std::fs::read_dir(&root)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    v.sort();
    v
}

#[test]
fn bordered_band_solve_of_every_shipped_scene_agrees_with_dense() {
    let (mut checked, mut small) = (0, 0);
    for (path, overrides) in scenes().into_iter().flat_map(|p| [(p.clone(), vec![]), (p, vec!["modes.max_order=32".to_string()])]) {
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let s = scene::load(&path, &overrides).unwrap_or_else(|e| panic!("{name}: {e}"));
        let model = Model::from_scene(&s).unwrap();
        let Some(bl) = model.boundary_layer() else { continue };
        let n = bl.dim();
        let mut states = vec![model.initial_state().to_vec()];
        let mut y = model.initial_state().to_vec();
        y[1] = 0.03;
        for (i, v) in y.iter_mut().enumerate().skip(2) {
            *v = 1e-3 * ((i * 7 % 5) as f64 - 2.0);
        }
        states.push(y);
        for (si, y) in states.iter().enumerate() {
            let t = 0.37;
            // The split pays only when the interior is wider than its band (border R, Ṙ and
            // `band` modes; interior half-width 3·band + 2): else a dense LU, by design.
            let band = bl.jacobian_pattern().band;
            let l = StateLayout::reduced_of_dim(n);
            let (border, w) = (l.blocks(0..band).end, l.b(band) - l.a(0));
            let Some(structured) = bl.structured_jacobian(t, y) else {
                assert!(n <= border + 2 * w + 1, "{name} {overrides:?} state {si}: dense fallback (band {band}, n = {n})");
                small += 1;
                continue;
            };
            let mut jac = vec![0.0; n * n];
            assert!(bl.jacobian(t, y, &mut jac));
            let j = DMatrix::from_row_slice(n, n, &jac);
            let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.7).sin() + 0.5).collect();
            for sigma in [0.8, 25.0, 3e3] {
                let mut x = b.clone();
                structured.factor(sigma).expect("factor").solve(&mut x);
                let m = DMatrix::identity(n, n) * sigma - &j;
                let xd = m.lu().solve(&DVector::from_vec(b.clone())).unwrap();
                let scale = xd.amax().max(1e-300);
                let err = x.iter().zip(xd.iter()).map(|(a, d)| (a - d).abs()).fold(0.0, f64::max) / scale;
                assert!(err < 1e-10, "{name} {overrides:?} state {si} σ = {sigma}: relative difference {err:e}");
                let sc = Complex::new(sigma, 0.6 * sigma);
                let bc: Vec<Complex<f64>> = b.iter().map(|&v| Complex::new(v, -0.5 * v)).collect();
                let mut x = bc.clone();
                structured.factor_complex(sc).expect("factor").solve(&mut x);
                let mc = j.map(|v| Complex::new(-v, 0.0)) + DMatrix::<Complex<f64>>::identity(n, n) * sc;
                let xd = mc.lu().solve(&DVector::from_vec(bc)).unwrap();
                let scale = xd.iter().map(|z| z.norm()).fold(1e-300, f64::max);
                let err = x.iter().zip(xd.iter()).map(|(a, d)| (a - d).norm()).fold(0.0, f64::max) / scale;
                assert!(err < 1e-10, "{name} {overrides:?} state {si} σ = {sc}: relative difference {err:e}");
            }
        }
        checked += 1;
    }
    assert!(checked >= 16, "only {checked} scenes with shape modes");
    // coil_h4 at k ≤ 16 (band 3: border 11, interior 15) is the one shipped scene left dense
    assert!(small <= 2, "{small} states without the structured form");
}
