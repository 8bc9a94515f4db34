//! A load term's exact Jacobian ([`LoadJacobian`]: rows P, G_n,k, G_t,k) against central
//! differences of its loads, every row, at a finite-amplitude state (so that the bilinear
//! derivatives of the quadratic terms are large).

use magbubble::model::effects::{LoadJacobian, Loads};

/// The state z of dimension 2 + 3·`modes`: R = 1.2, every other entry 0.05 sin(1.7 i).
pub fn finite_state(modes: usize) -> Vec<f64> {
    (0..magbubble::model::layout::StateLayout::reduced(modes).dim()).map(|i| if i == 0 { 1.2 } else { 0.05 * (1.7 * i as f64).sin() }).collect()
}

/// The loads `add` writes from zero, flattened as [P, G_n,k…, G_t,k…].
pub fn flat_loads(modes: usize, add: impl FnOnce(&mut Loads)) -> Vec<f64> {
    let (mut gn, mut gt) = (vec![0.0; modes], vec![0.0; modes]);
    let mut l = Loads { pressure: 0.0, gn: &mut gn, gt: &mut gt };
    add(&mut l);
    let mut v = vec![l.pressure];
    v.extend(gn);
    v.extend(gt);
    v
}

/// Asserts |∂load_i/∂y_j − FD| ≤ 1e-7 (1 + |FD|) for every row of `jac` (evaluated at `y`)
/// and every column j, with `loads(z)` the flattened loads ([`flat_loads`]) and step 1e-6;
/// `label` names the case.
pub fn assert_load_jacobian_matches_fd(jac: &LoadJacobian, y: &[f64], loads: impl Fn(&[f64]) -> Vec<f64>, label: &str) {
    let modes = (y.len() - 2) / 3;
    let an: Vec<&[f64]> = std::iter::once(&jac.pressure[..]).chain((0..modes).map(|m| jac.gn_row(m))).chain((0..modes).map(|m| jac.gt_row(m))).collect();
    for j in 0..y.len() {
        let h = 1e-6;
        let (mut yp, mut ym) = (y.to_vec(), y.to_vec());
        yp[j] += h;
        ym[j] -= h;
        let (fp, fm) = (loads(&yp), loads(&ym));
        for (i, row) in an.iter().enumerate() {
            let fd = (fp[i] - fm[i]) / (2.0 * h);
            assert!((row[j] - fd).abs() <= 1e-7 * (1.0 + fd.abs()), "{label}: row {i}, ∂/∂y{j}: {} vs {fd}", row[j]);
        }
    }
}
