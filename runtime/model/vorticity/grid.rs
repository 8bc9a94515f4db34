//! The radial grid of the vorticity PDE, y = r/R ∈ [1, Y_max] (paper eq 5.1, FORMULATION §4.2),
//! geometrically stretched so that the points cluster at the wall where the vorticity layer
//! (δ/R0 ≈ 0.04–0.08) lives.

use thiserror::Error;

/// Why a grid cannot be built. Each variant names the scene field at fault.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum GridError {
    #[error("vorticity.y_max = {0}: must be finite and > 1 (y = r/R starts at the wall y = 1)")]
    YMax(f64),
    #[error("vorticity.points = {0}: need at least 4 points (wall, two interior nodes, far end)")]
    Points(usize),
    #[error("vorticity.stretching = {0}: must be finite and > 0 (ratio of last to first spacing)")]
    Stretching(f64),
}

/// Nodes y_0 = 1 < y_1 < … < y_{n−1} = Y_max with spacings h_i = y_{i+1} − y_i growing
/// geometrically from h_0 to h_{n−2} = stretching · h_0.
#[derive(Debug, Clone, PartialEq)]
pub struct Grid {
    /// Node positions (n of them, both ends included).
    pub y: Vec<f64>,
    /// Trapezoid weights w_i for ∫_1^{Y_max} f dy ≈ Σ w_i f(y_i); w_0 = h_0/2 (FORMULATION §4.2).
    pub w: Vec<f64>,
}

impl Grid {
    /// Builds the stretched grid. `points` includes both ends; `stretching` = h_last / h_first.
    pub fn new(y_max: f64, points: usize, stretching: f64) -> Result<Self, GridError> {
        if !(y_max.is_finite() && y_max > 1.0) {
            return Err(GridError::YMax(y_max));
        }
        if points < 4 {
            return Err(GridError::Points(points));
        }
        if !(stretching.is_finite() && stretching > 0.0) {
            return Err(GridError::Stretching(stretching));
        }
        let cells = points - 1;
        let ratio = stretching.powf(1.0 / (cells - 1) as f64);
        // Σ_{i<cells} h0 ratio^i = y_max − 1
        let sum: f64 = (0..cells).map(|i| ratio.powi(i as i32)).sum();
        let h0 = (y_max - 1.0) / sum;
        let mut y = Vec::with_capacity(points);
        y.push(1.0);
        let mut h = h0;
        for _ in 0..cells {
            let next = y.last().copied().unwrap_or(1.0) + h;
            y.push(next);
            h *= ratio;
        }
        y[cells] = y_max; // remove the rounding of the running sum
        let mut w = vec![0.0; points];
        for i in 0..cells {
            let hi = y[i + 1] - y[i];
            w[i] += 0.5 * hi;
            w[i + 1] += 0.5 * hi;
        }
        Ok(Self { y, w })
    }

    /// Number of nodes n (both ends included).
    pub fn len(&self) -> usize {
        self.y.len()
    }

    /// Always false (a grid has at least 4 nodes); present for clippy's `len_without_is_empty`.
    pub fn is_empty(&self) -> bool {
        self.y.is_empty()
    }

    /// Number of unknown interior nodes, n − 2 (T_0 is the wall value, T_{n−1} = 0).
    pub fn interior(&self) -> usize {
        self.y.len() - 2
    }

    /// The first (smallest) spacing h_0 = y_1 − 1.
    pub fn h0(&self) -> f64 {
        self.y[1] - self.y[0]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_spans_the_interval_with_the_requested_stretching() {
        let g = Grid::new(3.0, 101, 20.0).unwrap();
        assert_eq!(g.len(), 101);
        assert_eq!(g.y[0], 1.0);
        assert_eq!(g.y[100], 3.0);
        let first = g.y[1] - g.y[0];
        let last = g.y[100] - g.y[99];
        assert!((last / first - 20.0).abs() < 1e-9, "{}", last / first);
        let total: f64 = g.w.iter().sum();
        assert!((total - 2.0).abs() < 1e-12);
        // trapezoid integrates y exactly
        let iy: f64 = g.w.iter().zip(&g.y).map(|(w, y)| w * y).sum();
        assert!((iy - 4.0).abs() < 1e-12);
    }

    #[test]
    fn bad_parameters_are_rejected_with_the_field() {
        assert!(matches!(Grid::new(1.0, 10, 1.0), Err(GridError::YMax(_))));
        assert!(matches!(Grid::new(2.0, 3, 1.0), Err(GridError::Points(3))));
        assert!(matches!(Grid::new(2.0, 10, -1.0), Err(GridError::Stretching(_))));
        assert!(Grid::new(2.0, 10, f64::NAN).is_err());
    }
}
