//! Butcher tableaus of the explicit methods, as data with named, cited constructors
//! (in the manner of diffsol's `ode_solver/tableau.rs`).
//!
//! Conventions: stage i (0-based) is evaluated at t + c_i h, y + h Σ_{j<i} a_ij k_j; the
//! solution is y + h Σ b_i k_i. The error estimate is described by [`ErrorEstimator`].

/// How the local error of one step is estimated from the stages.
#[derive(Debug, Clone, PartialEq)]
pub enum ErrorEstimator {
    /// err = h Σ e_i k_i with e = b − b̂ (an embedded lower-order solution).
    Embedded { e: Vec<f64> },
    /// Hairer's DOP853 estimator: a 5th-order difference e5 = Σ er_i k_i and a 3rd-order one
    /// e3 = Σ b_i k_i − Σ bhh_j k_{i_j}; err = h ‖e5‖² / sqrt(‖e5‖² + 0.01 ‖e3‖²)
    /// (Hairer, Nørsett & Wanner, *Solving ODEs I*, 2nd ed., sec. II.10; code `dop853.f`).
    Dop853 { e5: Vec<f64>, bhh: [(usize, f64); 3] },
}

/// Dense output between the two ends of an accepted step.
#[derive(Debug, Clone, PartialEq)]
pub enum DenseOutput {
    /// Cubic Hermite from y and f at both ends (3rd order; needs f(t+h, y_new)).
    Hermite,
    /// Dormand–Prince's continuous extension of order 4 (Hairer's `contd5`):
    /// y(θ) = y0 + θ(Δ + (1−θ)(hk1 − Δ + θ(Δ − hk7 − (hk1 − Δ) + (1−θ) h Σ d_i k_i))), Δ = y1 − y0.
    Dopri5 { d: Vec<f64> },
    /// DOP853's continuous extension of order 7 (three more stages per step, computed only for
    /// a step the dense output is asked in; constants in `integrate/dop853_dense.rs`).
    Dop853,
}

/// An explicit Runge–Kutta method with an error estimator.
#[derive(Debug, Clone, PartialEq)]
pub struct ButcherTableau {
    pub name: &'static str,
    /// Order of the propagated solution.
    pub order: u32,
    pub c: Vec<f64>,
    /// Strictly lower-triangular rows: `a[i].len() == i`.
    pub a: Vec<Vec<f64>>,
    pub b: Vec<f64>,
    pub error: Option<ErrorEstimator>,
    /// First same as last: the last stage is f(t + h, y_new) and is reused as the next k_1.
    pub fsal: bool,
    pub dense: DenseOutput,
    /// Exponent denominator q of the step-size controller: h_new ∝ err^(−1/q) (Hairer: 5, 8).
    pub controller_order: f64,
    /// Bounds of h_new / h: (smallest, largest).
    pub step_ratio: (f64, f64),
}

impl ButcherTableau {
    pub fn stages(&self) -> usize {
        self.c.len()
    }

    /// Checks the shape (a is strictly lower triangular, b and c have one entry per stage) and
    /// the row-sum condition Σ_j a_ij = c_i to `tol`. Returns the first violation.
    pub fn check(&self, tol: f64) -> Result<(), String> {
        let s = self.stages();
        if self.a.len() != s || self.b.len() != s {
            return Err(format!("{}: a has {} rows, b {} entries, c {} entries", self.name, self.a.len(), self.b.len(), s));
        }
        for (i, row) in self.a.iter().enumerate() {
            if row.len() != i {
                return Err(format!("{}: row {i} of a has {} entries, expected {i}", self.name, row.len()));
            }
            let sum: f64 = row.iter().sum();
            if (sum - self.c[i]).abs() > tol {
                return Err(format!("{}: row {i}: Σ a = {sum}, c = {}", self.name, self.c[i]));
            }
        }
        let sb: f64 = self.b.iter().sum();
        if (sb - 1.0).abs() > tol {
            return Err(format!("{}: Σ b = {sb}", self.name));
        }
        if let Some(ErrorEstimator::Embedded { e }) = &self.error {
            if e.len() != s || e.iter().sum::<f64>().abs() > tol {
                return Err(format!("{}: error weights must have {s} entries summing to 0", self.name));
            }
        }
        Ok(())
    }

    /// Classical fourth-order Runge–Kutta (Kutta 1901; Hairer–Nørsett–Wanner I, Table II.1.2),
    /// the paper's fixed-step scheme. No error estimate.
    pub fn rk4() -> Self {
        ButcherTableau {
            name: "rk4",
            order: 4,
            c: vec![0.0, 0.5, 0.5, 1.0],
            a: vec![vec![], vec![0.5], vec![0.0, 0.5], vec![0.0, 0.0, 1.0]],
            b: vec![1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0],
            error: None,
            fsal: false,
            dense: DenseOutput::Hermite,
            controller_order: 4.0,
            step_ratio: (0.2, 5.0),
        }
    }

    /// Dormand & Prince (1980), "A family of embedded Runge–Kutta formulae", J. Comput. Appl.
    /// Math. 6, 19–26: RK5(4)7M; dense output of Dormand & Prince (1986) as in Hairer's `dopri5.f`
    /// (Hairer–Nørsett–Wanner I, Table II.5.2 and sec. II.6). Step ratio bounds of `dopri5.f`.
    pub fn dopri5() -> Self {
        let b = vec![35.0 / 384.0, 0.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0, 11.0 / 84.0, 0.0];
        let b_hat = [5179.0 / 57600.0, 0.0, 7571.0 / 16695.0, 393.0 / 640.0, -92097.0 / 339200.0, 187.0 / 2100.0, 1.0 / 40.0];
        let e = b.iter().zip(b_hat).map(|(b, bh)| b - bh).collect();
        ButcherTableau {
            name: "dopri5",
            order: 5,
            c: vec![0.0, 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0, 1.0, 1.0],
            a: vec![
                vec![],
                vec![1.0 / 5.0],
                vec![3.0 / 40.0, 9.0 / 40.0],
                vec![44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0],
                vec![19372.0 / 6561.0, -25360.0 / 2187.0, 64448.0 / 6561.0, -212.0 / 729.0],
                vec![9017.0 / 3168.0, -355.0 / 33.0, 46732.0 / 5247.0, 49.0 / 176.0, -5103.0 / 18656.0],
                b[..6].to_vec(),
            ],
            b,
            error: Some(ErrorEstimator::Embedded { e }),
            fsal: true,
            dense: DenseOutput::Dopri5 {
                d: vec![
                    -12715105075.0 / 11282082432.0,
                    0.0,
                    87487479700.0 / 32700410799.0,
                    -10690763975.0 / 1880347072.0,
                    701980252875.0 / 199316789632.0,
                    -1453857185.0 / 822651844.0,
                    69997945.0 / 29380423.0,
                ],
            },
            controller_order: 5.0,
            step_ratio: (0.2, 10.0),
        }
    }

    /// Dormand & Prince 8(5,3): Prince & Dormand (1981), "High order embedded Runge–Kutta
    /// formulae", J. Comput. Appl. Math. 7, 67–75, with Hairer's 5th/3rd-order error estimator
    /// and coefficients as in `dop853.f` (Hairer–Nørsett–Wanner I, sec. II.10). 12 stages; the
    /// 13th evaluation f(t+h, y_new) is the next step's k_1. Step ratio bounds of `dop853.f`.
    pub fn dop853() -> Self {
        let c = vec![
            0.0,
            0.526001519587677318785587544488e-01,
            0.789002279381515978178381316732e-01,
            0.118350341907227396726757197510e+00,
            0.281649658092772603273242802490e+00,
            0.333333333333333333333333333333e+00,
            0.25e+00,
            0.307692307692307692307692307692e+00,
            0.651282051282051282051282051282e+00,
            0.6e+00,
            0.857142857142857142857142857142e+00,
            1.0,
        ];
        let a = vec![
            vec![],
            vec![5.26001519587677318785587544488e-2],
            vec![1.97250569845378994544595329183e-2, 5.91751709536136983633785987549e-2],
            vec![2.95875854768068491816892993775e-2, 0.0, 8.87627564304205475450678981324e-2],
            vec![2.41365134159266685502369798665e-1, 0.0, -8.84549479328286085344864962717e-1, 9.24834003261792003115737966543e-1],
            vec![3.7037037037037037037037037037e-2, 0.0, 0.0, 1.70828608729473871279604482173e-1, 1.25467687566822425016691814123e-1],
            vec![3.7109375e-2, 0.0, 0.0, 1.70252211019544039314978060272e-1, 6.02165389804559606850219397283e-2, -1.7578125e-2],
            vec![
                3.70920001185047927108779319836e-2,
                0.0,
                0.0,
                1.70383925712239993810214054705e-1,
                1.07262030446373284651809199168e-1,
                -1.53194377486244017527936158236e-2,
                8.27378916381402288758473766002e-3,
            ],
            vec![
                6.24110958716075717114429577812e-1,
                0.0,
                0.0,
                -3.36089262944694129406857109825e0,
                -8.68219346841726006818189891453e-1,
                2.75920996994467083049415600797e1,
                2.01540675504778934086186788979e1,
                -4.34898841810699588477366255144e1,
            ],
            vec![
                4.77662536438264365890433908527e-1,
                0.0,
                0.0,
                -2.48811461997166764192642586468e0,
                -5.90290826836842996371446475743e-1,
                2.12300514481811942347288949897e1,
                1.52792336328824235832596922938e1,
                -3.32882109689848629194453265587e1,
                -2.03312017085086261358222928593e-2,
            ],
            vec![
                -9.3714243008598732571704021658e-1,
                0.0,
                0.0,
                5.18637242884406370830023853209e0,
                1.09143734899672957818500254654e0,
                -8.14978701074692612513997267357e0,
                -1.85200656599969598641566180701e1,
                2.27394870993505042818970056734e1,
                2.49360555267965238987089396762e0,
                -3.0467644718982195003823669022e0,
            ],
            vec![
                2.27331014751653820792359768449e0,
                0.0,
                0.0,
                -1.05344954667372501984066689879e1,
                -2.00087205822486249909675718444e0,
                -1.79589318631187989172765950534e1,
                2.79488845294199600508499808837e1,
                -2.85899827713502369474065508674e0,
                -8.87285693353062954433549289258e0,
                1.23605671757943030647266201528e1,
                6.43392746015763530355970484046e-1,
            ],
        ];
        let b = vec![
            5.42937341165687622380535766363e-2,
            0.0,
            0.0,
            0.0,
            0.0,
            4.45031289275240888144113950566e0,
            1.89151789931450038304281599044e0,
            -5.8012039600105847814672114227e0,
            3.1116436695781989440891606237e-1,
            -1.52160949662516078556178806805e-1,
            2.01365400804030348374776537501e-1,
            4.47106157277725905176885569043e-2,
        ];
        let e5 = vec![
            0.1312004499419488073250102996e-01,
            0.0,
            0.0,
            0.0,
            0.0,
            -0.1225156446376204440720569753e+01,
            -0.4957589496572501915214079952e+00,
            0.1664377182454986536961530415e+01,
            -0.3503288487499736816886487290e+00,
            0.3341791187130174790297318841e+00,
            0.8192320648511571246570742613e-01,
            -0.2235530786388629525884427845e-01,
        ];
        let bhh = [
            (0, 0.244094488188976377952755905512e+00),
            (8, 0.733846688281611857341361741547e+00),
            (11, 0.220588235294117647058823529412e-01),
        ];
        ButcherTableau {
            name: "dop853",
            order: 8,
            c,
            a,
            b,
            error: Some(ErrorEstimator::Dop853 { e5, bhh }),
            fsal: false,
            dense: DenseOutput::Dop853,
            controller_order: 8.0,
            step_ratio: (1.0 / 3.0, 6.0),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tableaus_are_consistent() {
        for t in [ButcherTableau::rk4(), ButcherTableau::dopri5(), ButcherTableau::dop853()] {
            t.check(1e-14).unwrap();
        }
    }

    /// Order conditions up to order 4 (Σb c³ = 1/4, Σ b a c² … ) hold for all three; a typo in a
    /// coefficient breaks one of them.
    #[test]
    fn order_conditions_to_four() {
        for t in [ButcherTableau::rk4(), ButcherTableau::dopri5(), ButcherTableau::dop853()] {
            let s = t.stages();
            let a = |i: usize, j: usize| if j < i { t.a[i][j] } else { 0.0 };
            let ac: Vec<f64> = (0..s).map(|i| (0..s).map(|j| a(i, j) * t.c[j]).sum()).collect();
            let ac2: Vec<f64> = (0..s).map(|i| (0..s).map(|j| a(i, j) * t.c[j] * t.c[j]).sum()).collect();
            let aac: Vec<f64> = (0..s).map(|i| (0..s).map(|j| a(i, j) * ac[j]).sum()).collect();
            let dot = |v: &dyn Fn(usize) -> f64| (0..s).map(|i| t.b[i] * v(i)).sum::<f64>();
            let conds = [
                (dot(&|i| t.c[i]), 0.5),
                (dot(&|i| t.c[i].powi(2)), 1.0 / 3.0),
                (dot(&|i| ac[i]), 1.0 / 6.0),
                (dot(&|i| t.c[i].powi(3)), 0.25),
                (dot(&|i| t.c[i] * ac[i]), 1.0 / 8.0),
                (dot(&|i| ac2[i]), 1.0 / 12.0),
                (dot(&|i| aac[i]), 1.0 / 24.0),
            ];
            for (k, (got, want)) in conds.iter().enumerate() {
                assert!((got - want).abs() < 1e-13, "{}: condition {k}: {got} vs {want}", t.name);
            }
        }
    }

    #[test]
    fn dopri5_dense_weights_sum_to_zero() {
        // y(θ) must reproduce a linear solution exactly: Σ d_i = 0.
        if let DenseOutput::Dopri5 { d } = ButcherTableau::dopri5().dense {
            assert!(d.iter().sum::<f64>().abs() < 1e-14);
        } else {
            panic!("dopri5 has its own dense output");
        }
    }
}
