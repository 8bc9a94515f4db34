//! The structured solve of (σI − J) x = b for the monolithic system agrees with a dense solve.

use magbubble::analysis::dispersion::{LinearMode, C64};
use magbubble::integrate::OdeSystem;
use magbubble::model::vorticity::linear::LinearCoupling;
use magbubble::model::vorticity::monolithic::Monolithic;
use magbubble::model::vorticity::structured::{dense_jacobian, StructuredJacobian};
use magbubble::model::vorticity::Grid;

fn mode(k: usize) -> LinearMode {
    // nondimensional (R0 = 1, ρ = 1, c1 = 1/2, c2 = 0.6), Re ≈ 63
    crate::common::paper_mode_nd(k, 63.0)
}

#[test]
fn structured_solve_matches_dense_solve() {
    let c = LinearCoupling::new(vec![mode(2), mode(4), mode(6)]);
    let sys = Monolithic::new(&c, Grid::new(2.5, 30, 8.0).unwrap());
    let n = sys.dim();
    // a state with Ṙ ≠ 0 (convection and upwinding active) and non-zero vorticity
    let y: Vec<f64> = (0..n).map(|i| if i == 0 { 1.1 } else if i == 1 { -0.3 } else { 1e-2 * ((i as f64) * 0.7).sin() }).collect();
    let jd = dense_jacobian(&sys, 0.0, &y);
    let js = StructuredJacobian::new(&sys, 0.0, &y);
    let b: Vec<f64> = (0..n).map(|i| ((i * 7 % 11) as f64) - 5.0).collect();
    for sigma in [C64::new(40.0, 0.0), C64::new(25.0, 17.0)] {
        let mut dense = nalgebra::DMatrix::<C64>::from_fn(n, n, |i, j| C64::new(-jd[(i, j)], 0.0));
        for i in 0..n {
            dense[(i, i)] += sigma;
        }
        let bd = nalgebra::DVector::<C64>::from_iterator(n, b.iter().map(|&v| C64::new(v, 0.0)));
        let xd = dense.lu().solve(&bd).unwrap();
        let mut xs: Vec<C64> = b.iter().map(|&v| C64::new(v, 0.0)).collect();
        js.factor(sigma).expect("non-singular").solve(&mut xs);
        let err = xs.iter().zip(xd.iter()).map(|(a, b)| (a - b).norm()).fold(0.0, f64::max);
        let scale = xd.iter().map(|v| v.norm()).fold(0.0, f64::max);
        println!("sigma {sigma}: max |x_s − x_d| = {err:.3e} (scale {scale:.3e})");
        assert!(err < 1e-5 * scale, "structured and dense solves differ by {err} (scale {scale})");
    }
    // and the real version
    let mut xr = b.clone();
    js.factor(40.0f64).unwrap().solve(&mut xr);
    let mut dense = -jd.clone();
    for i in 0..n {
        dense[(i, i)] += 40.0;
    }
    let xd = dense.lu().solve(&nalgebra::DVector::from_column_slice(&b)).unwrap();
    let err = xr.iter().zip(xd.iter()).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    assert!(err < 1e-5 * xd.amax(), "{err}");
}
