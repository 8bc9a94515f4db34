//! `shell.law = "tension-curve"` (issue 31; docs/model.md, "Lipid shells: tension curve"): a
//! measured tension τ(J), J = A/A0 = (R/R0)², between its knots the monotone piecewise-cubic
//! Hermite interpolant PCHIP (Fritsch & Carlson 1980, SIAM J. Numer. Anal. 17, 238: monotone
//! data give a monotone curve), with the interior slopes of Fritsch & Butland 1984 (the weighted
//! harmonic mean of the neighbouring secants, 0 at a local extremum or a flat secant) and the
//! end slopes of the shape-preserving three-point formula — the construction of SciPy's
//! `PchipInterpolator`. Beyond the ends τ is constant (the end values: a plateau below the
//! first knot, as a buckled monolayer, and above the last, as a ruptured one).
//!
//! τ is C¹ at a knot but not C²: each knot is a branch switch of the run (the segment index is
//! the run's branch, effects/lipid.rs `BranchState`), located and never stepped over, and inside
//! a step the cubic of one segment is evaluated (continued a little past its knot).

/// The interpolant in model units (tensions like c1: σ/(p* R0)).
#[derive(Debug, Clone, PartialEq)]
pub struct CurveTension {
    /// J_i, strictly increasing.
    pub j: Vec<f64>,
    /// τ_i.
    pub tau: Vec<f64>,
    /// dτ/dJ at each knot (PCHIP).
    pub slope: Vec<f64>,
}

impl CurveTension {
    /// The PCHIP of knots (J_i, τ_i) (at least 3, J strictly increasing; checked by the scene).
    pub fn new(j: Vec<f64>, tau: Vec<f64>) -> Self {
        let slope = pchip_slopes(&j, &tau);
        Self { j, tau, slope }
    }

    /// The segment of J: 0 below the first knot, i for J_{i−1} ≤ J < J_i, n at or above the last.
    pub fn segment_of(&self, j: f64) -> usize {
        self.j.partition_point(|&k| k <= j)
    }

    /// Number of segments (knots + 1).
    pub fn segments(&self) -> usize {
        self.j.len() + 1
    }

    /// τ(J), dτ/dJ, d²τ/dJ² on segment `seg` (its formula, also a little beyond its ends).
    pub fn eval(&self, seg: usize, x: f64) -> [f64; 3] {
        let n = self.j.len();
        if seg == 0 {
            return [self.tau[0], 0.0, 0.0];
        }
        if seg >= n {
            return [self.tau[n - 1], 0.0, 0.0];
        }
        let (i0, i1) = (seg - 1, seg);
        let h = self.j[i1] - self.j[i0];
        let t = (x - self.j[i0]) / h;
        let (y0, y1, d0, d1) = (self.tau[i0], self.tau[i1], self.slope[i0] * h, self.slope[i1] * h);
        // cubic Hermite basis in t
        let (t2, t3) = (t * t, t * t * t);
        let v = (2.0 * t3 - 3.0 * t2 + 1.0) * y0 + (t3 - 2.0 * t2 + t) * d0 + (-2.0 * t3 + 3.0 * t2) * y1 + (t3 - t2) * d1;
        let dv = (6.0 * t2 - 6.0 * t) * y0 + (3.0 * t2 - 4.0 * t + 1.0) * d0 + (-6.0 * t2 + 6.0 * t) * y1 + (3.0 * t2 - 2.0 * t) * d1;
        let ddv = (12.0 * t - 6.0) * y0 + (6.0 * t - 4.0) * d0 + (-12.0 * t + 6.0) * y1 + (6.0 * t - 2.0) * d1;
        [v, dv / h, ddv / (h * h)]
    }

    /// τ and its derivatives on J's own segment.
    pub fn at(&self, x: f64) -> [f64; 3] {
        self.eval(self.segment_of(x), x)
    }
}

/// PCHIP knot slopes (module doc): interior d_i = 0 when the secants δ_{i−1}, δ_i differ in
/// sign or either is 0, else (w1 + w2)/(w1/δ_{i−1} + w2/δ_i), w1 = 2h_i + h_{i−1},
/// w2 = h_i + 2h_{i−1}; ends by the three-point formula, set to 0 if its sign differs from the
/// first secant's, and to 3δ if the secants change sign and |d| > 3|δ|.
pub fn pchip_slopes(x: &[f64], y: &[f64]) -> Vec<f64> {
    let n = x.len();
    let h: Vec<f64> = (0..n - 1).map(|i| x[i + 1] - x[i]).collect();
    let s: Vec<f64> = (0..n - 1).map(|i| (y[i + 1] - y[i]) / h[i]).collect();
    let mut d = vec![0.0; n];
    for i in 1..n - 1 {
        if s[i - 1] * s[i] > 0.0 {
            let (w1, w2) = (2.0 * h[i] + h[i - 1], h[i] + 2.0 * h[i - 1]);
            d[i] = (w1 + w2) / (w1 / s[i - 1] + w2 / s[i]);
        }
    }
    let end = |h0: f64, h1: f64, m0: f64, m1: f64| {
        let e = ((2.0 * h0 + h1) * m0 - h0 * m1) / (h0 + h1);
        if e.signum() != m0.signum() || m0 == 0.0 {
            0.0
        } else if m0.signum() != m1.signum() && e.abs() > 3.0 * m0.abs() {
            3.0 * m0
        } else {
            e
        }
    };
    d[0] = end(h[0], h[1], s[0], s[1]);
    d[n - 1] = end(h[n - 2], h[n - 3], s[n - 2], s[n - 3]);
    d
}
