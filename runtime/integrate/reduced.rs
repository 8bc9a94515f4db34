//! σI − J for a Jacobian with "position" rows y'_p = y_v (a second-order system written in first
//! order: R' = Ṙ, a_k' = ȧ_k): the positions are eliminated and a dense LU of the remaining
//! n − m unknowns is factored — the reduction Hairer's `radau5.f` makes for systems with
//! y'_i = y_{i+M2}, i ≤ M1 (its options IWORK(9) = M1, IWORK(10) = M2).
//!
//! A position row p of J is the unit row e_v (J_pv = 1, the rest 0, v not a position itself).
//! Its equation of (σI − J) x = b reads σ x_p − x_v = b_p, so x_p = (b_p + x_v)/σ; in every
//! other row r (the kept rows, with the kept unknowns in the same order)
//!
//! ```text
//! σ x_r − Σ_{c kept} J_rc x_c − Σ_p (J_rp / σ) x_{v(p)} = b_r + Σ_p J_rp b_p / σ
//! ```
//!
//! A [`StructuredJacobian`] for [`super::linear`]: the boundary-layer model (n = 2 + 3M, m = 1 + M)
//! factors a dense (1 + 2M)-square matrix instead of the (2 + 3M)-square one.

use super::linalg::Scalar;
use super::linear::{AnalyticStructure, Factorization};
use std::rc::Rc;

#[derive(Debug)]
struct Parts {
    /// The kept rows / unknowns (not positions), ascending.
    kept: Vec<usize>,
    /// Per position p (ascending): p, and the index of v(p) among the kept unknowns.
    pos: Vec<(usize, usize)>,
    /// J on kept rows × kept columns, row-major (nr × nr).
    jkk: Vec<f64>,
    /// The non-zero J_rp on kept rows × position columns, row after row: (p, the index of v(p)
    /// among the kept unknowns, J_rp); row a's entries are `jkp[start[a]..start[a + 1]]`.
    jkp: Vec<(usize, usize, f64)>,
    start: Vec<usize>,
}

/// J of a system with position rows at one (t, y), factored for any shift σ ≠ 0.
#[derive(Debug)]
pub struct PositionRows(Rc<Parts>);

impl PositionRows {
    /// Splits the row-major n × n `jac`. `None` when an entry is non-finite or J has no position
    /// row (nothing to eliminate).
    pub fn new(jac: &[f64], n: usize) -> Option<Self> {
        if jac.len() < n * n || jac[..n * n].iter().any(|v| !v.is_finite()) {
            return None;
        }
        // v(p) for each unit row p
        let unit = |r: usize| -> Option<usize> {
            let row = &jac[r * n..(r + 1) * n];
            let v = row.iter().position(|&x| x != 0.0)?;
            (row[v] == 1.0 && v != r && row[v + 1..].iter().all(|&x| x == 0.0)).then_some(v)
        };
        let target: Vec<Option<usize>> = (0..n).map(unit).collect();
        // a position whose velocity is itself a position is kept (no chains)
        let is_pos: Vec<bool> = (0..n).map(|r| target[r].is_some_and(|v| target[v].is_none())).collect();
        let kept: Vec<usize> = (0..n).filter(|&r| !is_pos[r]).collect();
        if kept.len() == n {
            return None;
        }
        let mut index = vec![usize::MAX; n];
        for (a, &r) in kept.iter().enumerate() {
            index[r] = a;
        }
        let pos: Vec<(usize, usize)> = (0..n).filter(|&r| is_pos[r]).map(|p| (p, index[target[p].expect("a position")])).collect();
        let nr = kept.len();
        let mut jkk = Vec::with_capacity(nr * nr);
        let (mut jkp, mut start) = (Vec::new(), Vec::with_capacity(nr + 1));
        for &r in &kept {
            let row = &jac[r * n..(r + 1) * n];
            jkk.extend(kept.iter().map(|&c| row[c]));
            start.push(jkp.len());
            jkp.extend(pos.iter().filter(|&&(p, _)| row[p] != 0.0).map(|&(p, v)| (p, v, row[p])));
        }
        start.push(jkp.len());
        Some(PositionRows(Rc::new(Parts { kept, pos, jkk, jkp, start })))
    }

}

/// Built from the system's analytic Jacobian: no rhs calls.
impl AnalyticStructure for PositionRows {
    type Lu<T: Scalar + 'static> = ReducedLu<T>;

    fn factor_as<T: Scalar + 'static>(&self, sigma: T) -> Option<ReducedLu<T>> {
        let p = &self.0;
        let nr = p.kept.len();
        let inv_sigma = T::from_real(1.0) / sigma;
        if !(inv_sigma.mag().is_finite()) {
            return None;
        }
        let mut a: Vec<T> = p.jkk.iter().map(|&j| -T::from_real(j)).collect();
        for r in 0..nr {
            let row = &mut a[r * nr..(r + 1) * nr];
            row[r] = row[r] + sigma;
            for &(_, v, jp) in &p.jkp[p.start[r]..p.start[r + 1]] {
                row[v] = row[v] - inv_sigma.scale(jp);
            }
        }
        let lu = T::dense_factor(nr, a).ok()?;
        let scratch = std::cell::RefCell::new(vec![T::ZERO; nr]);
        Some(ReducedLu { parts: Rc::clone(&self.0), inv_sigma, lu, scratch })
    }
}

/// The factorisation of σI − J (module doc).
pub(crate) struct ReducedLu<T: Scalar> {
    parts: Rc<Parts>,
    inv_sigma: T,
    lu: T::DenseLu,
    /// The kept part of the right-hand side and solution (no allocation per solve).
    scratch: std::cell::RefCell<Vec<T>>,
}

impl<T: Scalar> Factorization<T> for ReducedLu<T> {
    fn solve(&self, b: &mut [T]) {
        let p = &*self.parts;
        let mut guard = self.scratch.borrow_mut();
        let xk = &mut guard[..];
        // one pass over the rows' position entries, in the order they were stored
        for ((x, &r), w) in xk.iter_mut().zip(&p.kept).zip(p.start.windows(2)) {
            let mut s = T::ZERO;
            for &(pp, _, jp) in &p.jkp[w[0]..w[1]] {
                s = s + b[pp].scale(jp);
            }
            *x = b[r] + s * self.inv_sigma;
        }
        T::dense_solve(&self.lu, xk);
        for (&x, &r) in xk.iter().zip(&p.kept) {
            b[r] = x;
        }
        for &(pp, v) in &p.pos {
            b[pp] = (b[pp] + xk[v]) * self.inv_sigma;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrate::linear::{assert_solves_like_dense, StructuredJacobian};
    use nalgebra::Complex;

    /// A 2 + 3·4 system laid out like the boundary-layer model (R, Ṙ, (a, ȧ, b)_k): the reduced
    /// solve agrees with the dense LU of σI − J, real and complex σ.
    #[test]
    fn agrees_with_the_dense_lu() {
        let n = 14;
        let mut jac = vec![0.0; n * n];
        let mut x: u64 = 0x2545_f491_4f6c_dd1d;
        let mut rnd = || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x % 2001) as f64 / 1000.0 - 1.0
        };
        for r in 0..n {
            for c in 0..n {
                jac[r * n + c] = rnd();
            }
        }
        let mut unit = |p: usize, v: usize| {
            jac[p * n..(p + 1) * n].fill(0.0);
            jac[p * n + v] = 1.0;
        };
        unit(0, 1);
        let l = crate::model::layout::StateLayout::reduced(4);
        for k in 0..4 {
            unit(l.a(k), l.adot(k));
        }
        let so = PositionRows::new(&jac, n).expect("position rows");
        assert_eq!(so.0.kept.len(), n - 5);
        let b: Vec<f64> = (0..n).map(|i| (i as f64).sin() + 1.0).collect();
        let hook: &dyn StructuredJacobian = &so;
        for sigma in [0.3, -4.0] {
            assert_solves_like_dense(&*hook.factor(sigma).unwrap(), sigma, &jac, n, &b);
        }
        let sc = Complex::new(0.3, -2.0);
        let bc: Vec<Complex<f64>> = b.iter().map(|&v| Complex::new(v, -v)).collect();
        assert_solves_like_dense(&*hook.factor_complex(sc).unwrap(), sc, &jac, n, &bc);
        // no unit row: nothing to eliminate
        let full: Vec<f64> = (0..n * n).map(|i| 1.0 + i as f64).collect();
        assert!(PositionRows::new(&full, n).is_none());
    }
}
