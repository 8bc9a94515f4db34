//! Magnetic loads M0, M_n,k, M_t,k (FORMULATION §4.1, eq 2.40) from a generated [`FieldTable`],
//! precomputed once per run in a dense-band form for the simulated modes.
//!
//! For one table component c with prefactor ℋ_c (a monomial in the symbols, including R^{p_R})
//! and zero-order force ∝ r^m (docs/architecture.md):
//!
//! ```text
//! M_n,k = Σ_c ℋ_c [ R^m zero_normal_c(k) + R^(m−1) Σ_couplings value_c(k) · amp_(k+offset) ]
//! ```
//! and M_t,k likewise with the tangential tables; M0 is the row k = 0 of the normal loads.
//!
//! The prefactor is split once into a static constant (all symbols but R, the current and the
//! distance), a time factor (I(t)/I)^p (a/a(t))^p (a(t)/a)^q (1 for a static field, never
//! recomputed), and the R-dependence R^(p_R+m) (zero order) or R^(p_R+m−1) (couplings).
//! Everything is stored nondimensionally (lengths / R0, pressures / (2c1/R0), FORMULATION §4.5).
//! Evaluation does not allocate.

use std::sync::atomic::{AtomicU64, Ordering};

use super::{FieldError, FieldSource, TimeLaw};
use crate::coefficients::{Amp, Load, KMAX};
use crate::model::layout::StateLayout;

/// Largest number of table components handled (COIL_H4 has 3: H2², H2H4, H4²).
pub const MAX_COMPONENTS: usize = 4;

#[derive(Debug)]
struct ComponentLoads {
    /// K̄_c: static part of the prefactor, nondimensional, at the reference current/distance.
    k_static: f64,
    /// Power of R̄ on the zero-order loads (p_R + m) and on the couplings (p_R + m − 1).
    zero_power: i32,
    coupling_power: i32,
    /// Powers of the current ratio and of the distance ratio in the time factor.
    current_power: i32,
    distance_power: i32,
    /// Zero-order normal load per row (row 0 = k = 0 → M0; row r = mode k = 2r).
    zero_n: Vec<f64>,
    /// Zero-order tangential load per row (row 0 unused).
    zero_t: Vec<f64>,
    /// Band coefficients: row r, offset d ∈ [−W, W] (in modes), (a, b) pair.
    band_n: Vec<f64>,
    band_t: Vec<f64>,
    /// The same bands interleaved for the right-hand side: per (row, offset) the four numbers
    /// (normal a, normal b, tangential a, tangential b), rows after rows.
    band_nt: Vec<f64>,
}

/// Prefactors at one (t, R): computed once per right-hand-side evaluation.
#[derive(Debug, Clone, Copy)]
pub struct Factors {
    zero: [f64; MAX_COMPONENTS],
    coupling: [f64; MAX_COMPONENTS],
}

/// The magnetic loads of one field for the simulated modes k = 2, 4, …, 2M.
#[derive(Debug)]
pub struct MagneticLoads {
    comps: Vec<ComponentLoads>,
    modes: usize,
    /// Half-bandwidth W in modes (1 for the paper's H2² coil: k couples to k ± 2).
    width: usize,
    law: TimeLaw,
    /// Per row: the start of its existing sources in `band_nt`, their number, and the index in y
    /// of the first one's a ([`source_range`](Self::source_range), computed once).
    plan: Vec<(usize, usize, usize)>,
    /// Nondimensional angular frequencies (ω t*) of the current and of the distance.
    current_omega: Option<f64>,
    distance: Option<(f64, f64)>,
    evaluations: AtomicU64,
}

impl MagneticLoads {
    /// Builds the loads of `source` for `modes` shape modes (k = 2..=2·modes).
    /// `r0` [m] and `p_unit` [Pa] are the length and pressure scales, `t_star` [s] the time scale.
    pub fn new(source: &FieldSource, modes: usize, r0: f64, p_unit: f64, t_star: f64) -> Result<Self, FieldError> {
        Self::with_parity(source, modes, 0, r0, p_unit, t_star)
    }

    /// The loads of the **odd** shape modes k = 3, 5, …, 2·modes + 1 (state layout
    /// [R, Ṙ, (a_k, ȧ_k, b_k)_k odd], row r ↔ k = 2r + 1, row 0 (k = 1, no shape mode) zero).
    /// Every table offset is even, so the odd modes couple among themselves only, and no table has
    /// a zero-order load on an odd P_j: they are unforced (the model simulates the even modes;
    /// `modes` uses these for the odd frequencies with a field, issue 13 part 6).
    pub fn odd(source: &FieldSource, modes: usize, r0: f64, p_unit: f64, t_star: f64) -> Result<Self, FieldError> {
        Self::with_parity(source, modes, 1, r0, p_unit, t_star)
    }

    fn with_parity(source: &FieldSource, modes: usize, parity: usize, r0: f64, p_unit: f64, t_star: f64) -> Result<Self, FieldError> {
        let table = source.table;
        if table.components.len() > MAX_COMPONENTS {
            return Err(FieldError::UnknownSymbol {
                table: table.name,
                symbol: format!("({} components > {MAX_COMPONENTS})", table.components.len()),
                field: source.kind,
            });
        }
        let width = table
            .components
            .iter()
            .flat_map(|c| c.couplings.iter())
            .map(|cp| (cp.offset.unsigned_abs() as usize) / 2)
            .max()
            .unwrap_or(0);
        let rows = modes + 1;
        let stride = 2 * (2 * width + 1);
        let mut comps = Vec::with_capacity(table.components.len());
        for c in table.components {
            let mut k_si = c.prefactor.coeff;
            let (mut p_r, mut p_h, mut p_a) = (0i32, 0i32, 0i32);
            for &(sym, p) in c.prefactor.powers {
                match sym {
                    "R" => p_r += p,
                    _ => {
                        let v = source.symbol(sym).ok_or_else(|| FieldError::UnknownSymbol {
                            table: table.name,
                            symbol: sym.to_string(),
                            field: source.kind,
                        })?;
                        if sym == "H2" || sym == "H4" {
                            p_h += p;
                        } else if sym == "a" {
                            p_a += p;
                        }
                        k_si *= v.powi(p);
                    }
                }
            }
            let zero_power = p_r + c.r_power;
            let k_static = k_si * r0.powi(zero_power) / p_unit;
            let mut zero_n = vec![0.0; rows];
            let mut zero_t = vec![0.0; rows];
            let own_row = |j: usize| j % 2 == parity && j / 2 < rows && (parity == 0 || j >= 3);
            for &(j, v) in c.zero_normal {
                if own_row(j) {
                    zero_n[j / 2] += v;
                }
            }
            for &(j, v) in c.zero_tangential {
                if j >= 2 && own_row(j) {
                    zero_t[j / 2] += v;
                }
            }
            let mut band_n = vec![0.0; rows * stride];
            let mut band_t = vec![0.0; rows * stride];
            for cp in c.couplings {
                for row in 0..rows {
                    let k = 2 * row + parity;
                    if k > KMAX || (parity == 1 && row == 0) {
                        continue;
                    }
                    let Some(value) = cp.values.get(k).copied().flatten() else { continue };
                    let src = k as i64 + cp.offset as i64;
                    // a_0 = b_0 = 0 and a_{N+2} = b_{N+2} = 0 (FORMULATION §4.1).
                    let par = parity as i64;
                    if src < 2 + par || src > 2 * modes as i64 + par || src % 2 != par {
                        continue;
                    }
                    let d = (cp.offset / 2) as i64 + width as i64;
                    let idx = row * stride + 2 * d as usize + matches!(cp.amp, Amp::B) as usize;
                    match cp.load {
                        Load::Normal => band_n[idx] += value,
                        Load::Tangential if row > 0 => band_t[idx] += value,
                        Load::Tangential => {}
                    }
                }
            }
            let band_nt = band_n.chunks_exact(2).zip(band_t.chunks_exact(2)).flat_map(|(n, t)| [n[0], n[1], t[0], t[1]]).collect();
            comps.push(ComponentLoads {
                band_nt,
                k_static,
                zero_power,
                coupling_power: zero_power - 1,
                current_power: p_h,
                distance_power: p_a - p_h, // H ∝ I/a
                zero_n,
                zero_t,
                band_n,
                band_t,
            });
        }
        let (current_omega, distance) = match source.law {
            TimeLaw::Static => (None, None),
            TimeLaw::Varying { current_omega, distance } => {
                (current_omega.map(|w| w * t_star), distance.map(|(b, w)| (b, w * t_star)))
            }
        };
        let mut loads = Self { comps, modes, width, law: source.law, plan: Vec::new(), current_omega, distance, evaluations: AtomicU64::new(0) };
        loads.plan = (0..rows)
            .map(|row| {
                let (lo, hi, at0) = loads.source_range(row);
                (4 * (row * (2 * width + 1) + lo), hi - lo, at0)
            })
            .collect();
        Ok(loads)
    }

    /// Number of [`factors`](Self::factors) calls so far (one per right-hand-side evaluation).
    pub fn evaluations(&self) -> u64 {
        self.evaluations.load(Ordering::Relaxed)
    }

    /// Half-bandwidth W in modes of the couplings (1: k couples to k ± 2).
    pub fn width(&self) -> usize {
        self.width
    }

    pub fn is_static(&self) -> bool {
        matches!(self.law, TimeLaw::Static)
    }

    /// Prefactors at nondimensional time `t` and radius `r` (= R/R0).
    #[inline]
    pub fn factors(&self, t: f64, r: f64) -> Factors {
        self.evaluations.fetch_add(1, Ordering::Relaxed);
        self.factors_uncounted(t, r)
    }

    #[inline]
    fn factors_uncounted(&self, t: f64, r: f64) -> Factors {
        let (cr, dr) = if self.is_static() {
            (1.0, 1.0)
        } else {
            (
                self.current_omega.map_or(1.0, |w| (w * t).cos()),
                self.distance.map_or(1.0, |(b, w)| 1.0 + b * (w * t).cos()),
            )
        };
        let mut f = Factors { zero: [0.0; MAX_COMPONENTS], coupling: [0.0; MAX_COMPONENTS] };
        for (i, c) in self.comps.iter().enumerate() {
            let mut k = c.k_static;
            if !self.is_static() {
                k *= cr.powi(c.current_power) * dr.powi(c.distance_power);
            }
            f.zero[i] = k * r.powi(c.zero_power);
            f.coupling[i] = k * r.powi(c.coupling_power);
        }
        f
    }

    /// The band of row `row`: (index j of the (a, b) coefficient pair in a component's band,
    /// mode index of the source) for every source mode k ± 2d that exists.
    #[inline]
    fn band_sources(&self, row: usize) -> impl Iterator<Item = (usize, usize)> + '_ {
        let w = self.width as i64;
        let base = row * 2 * (2 * self.width + 1);
        (-w..=w).filter_map(move |d| {
            let src = row as i64 + d;
            (src >= 1 && src <= self.modes as i64).then(|| (base + 2 * (d + w) as usize, src as usize - 1))
        })
    }

    /// The layout of the state y (the boundary-layer layout of the simulated modes).
    #[inline]
    fn layout(&self) -> StateLayout {
        StateLayout::reduced(self.modes)
    }

    /// The offsets d ∈ [lo, hi) (index into the row's band, d = offset + W) whose source mode
    /// row + d − W exists, and the index in y of the first one's a: the same sources as
    /// [`band_sources`](Self::band_sources), as a contiguous range (no per-source test).
    #[inline]
    fn source_range(&self, row: usize) -> (usize, usize, usize) {
        let w = self.width;
        let lo = (w + 1).saturating_sub(row);
        let hi = (2 * w + 1).min((self.modes + w + 1).saturating_sub(row));
        let at = if hi > lo { self.layout().a(row + lo - w - 1) } else { 0 };
        (lo, hi.max(lo), at)
    }

    /// One load row: Σ_c K_c [R^m zero_c(row) + R^(m−1) Σ_sources band · (a, b)] (module doc).
    /// The sources are summed in the order of [`band_sources`](Self::band_sources), so the value
    /// is the same to the bit; the loop runs over pre-cut slices (issue 16: this was 14 % of
    /// the boundary-layer run through the filtered iterator).
    #[inline]
    fn row(&self, f: &Factors, row: usize, y: &[f64], normal: bool) -> f64 {
        let (lo, hi, at0) = self.source_range(row);
        let base = row * 2 * (2 * self.width + 1);
        let ys = if hi > lo { &y[at0..at0 + StateLayout::AMPLITUDES * (hi - lo)] } else { &y[..0] };
        let mut total = 0.0;
        for (i, c) in self.comps.iter().enumerate() {
            let (zero, band) = if normal { (&c.zero_n, &c.band_n) } else { (&c.zero_t, &c.band_t) };
            let coeffs = &band[base + 2 * lo..base + 2 * hi];
            let mut s = -0.0;
            for (ab, yk) in coeffs.chunks_exact(2).zip(ys.chunks(StateLayout::AMPLITUDES)) {
                s += ab[0] * yk[StateLayout::A] + ab[1] * yk[StateLayout::B];
            }
            total += f.zero[i] * zero[row] + f.coupling[i] * s;
        }
        total
    }

    /// The magnetic terms of the balances at once: `pressure` += M0, `gn[m]` −= M_n,k and
    /// `gt[m]` −= M_t,k for every mode index m < `gn.len()` (what [`radial`](Self::radial),
    /// [`normal`](Self::normal) and [`tangential`](Self::tangential) give, to the bit: the same
    /// sums in the same order), with the normal and tangential rows of a mode in one pass over
    /// its sources (issue 16: the separate row calls were 14 % of the boundary-layer run).
    pub fn add_to_balances(&self, f: &Factors, y: &[f64], pressure: &mut f64, gn: &mut [f64], gt: &mut [f64]) {
        let rows = (gn.len().min(gt.len()) + 1).min(self.modes + 1);
        for (row, &(b0, count, at0)) in self.plan[..rows].iter().enumerate() {
            // the sources' (a, ȧ, b) and the row's interleaved band as pre-cut slices (no index
            // checks in the loop; the same operations in the same order as the indexed loop)
            let ys = &y[at0..at0 + StateLayout::AMPLITUDES * count];
            let (mut tn, mut tt) = (0.0, 0.0);
            for (i, c) in self.comps.iter().enumerate() {
                let (mut sn, mut st) = (-0.0, -0.0);
                for (yk, q) in ys.chunks_exact(StateLayout::AMPLITUDES).zip(c.band_nt[b0..b0 + 4 * count].chunks_exact(4)) {
                    let (ya, yb) = (yk[StateLayout::A], yk[StateLayout::B]);
                    sn += q[0] * ya + q[1] * yb;
                    st += q[2] * ya + q[3] * yb;
                }
                tn += f.zero[i] * c.zero_n[row] + f.coupling[i] * sn;
                tt += f.zero[i] * c.zero_t[row] + f.coupling[i] * st;
            }
            if row == 0 {
                *pressure += tn;
            } else {
                gn[row - 1] -= tn;
                gt[row - 1] -= tt;
            }
        }
    }

    /// Adds `scale` × the exact gradient of row `row` (0: M0; m + 1: M_n or M_t of mode index m)
    /// with respect to the state y = [R, Ṙ, (a_k, ȧ_k, b_k)_k] to `grad` (length of y). The loads
    /// are affine in (a, b) with coefficients ∝ R^p, so this is exact (model Jacobian, issue 16).
    pub fn add_row_gradient(&self, f: &Factors, row: usize, y: &[f64], normal: bool, scale: f64, grad: &mut [f64]) {
        let (r, l) = (y[0], self.layout());
        for (i, c) in self.comps.iter().enumerate() {
            let (zero, band) = if normal { (&c.zero_n, &c.band_n) } else { (&c.zero_t, &c.band_t) };
            let mut s = 0.0;
            for (j, m) in self.band_sources(row) {
                s += band[j] * y[l.a(m)] + band[j + 1] * y[l.b(m)];
                grad[l.a(m)] += scale * f.coupling[i] * band[j];
                grad[l.b(m)] += scale * f.coupling[i] * band[j + 1];
            }
            grad[0] += scale
                * (c.zero_power as f64 * f.zero[i] * zero[row] + c.coupling_power as f64 * f.coupling[i] * s)
                / r;
        }
    }

    /// ∂M0/∂R: entry 0 of [`add_row_gradient`](Self::add_row_gradient) of row 0 (normal,
    /// scale 1) into a zeroed gradient, the same sums in the same order, without the buffer.
    pub fn radial_gradient(&self, f: &Factors, y: &[f64]) -> f64 {
        let (r, l) = (y[0], self.layout());
        let mut g = 0.0;
        for (i, c) in self.comps.iter().enumerate() {
            let mut s = 0.0;
            for (j, m) in self.band_sources(0) {
                s += c.band_n[j] * y[l.a(m)] + c.band_n[j + 1] * y[l.b(m)];
            }
            g += 1.0 * (c.zero_power as f64 * f.zero[i] * c.zero_n[0] + c.coupling_power as f64 * f.coupling[i] * s) / r;
        }
        g
    }

    /// The time derivative of the prefactors, dK_c/dt times R^p (same layout as [`Factors`]).
    fn factors_dt(&self, t: f64, r: f64) -> Factors {
        let mut f = Factors { zero: [0.0; MAX_COMPONENTS], coupling: [0.0; MAX_COMPONENTS] };
        if self.is_static() {
            return f;
        }
        let (cr, crd) = self.current_omega.map_or((1.0, 0.0), |w| ((w * t).cos(), -w * (w * t).sin()));
        let (dr, drd) = self.distance.map_or((1.0, 0.0), |(b, w)| (1.0 + b * (w * t).cos(), -b * w * (w * t).sin()));
        // d(x^p)/dt = p x^(p−1) ẋ, written so that p = 0 gives 0 (no 0·∞ at x = 0)
        let dpow = |x: f64, xd: f64, p: i32| if p == 0 { 0.0 } else { p as f64 * x.powi(p - 1) * xd };
        for (i, c) in self.comps.iter().enumerate() {
            let kd = c.k_static
                * (dpow(cr, crd, c.current_power) * dr.powi(c.distance_power) + cr.powi(c.current_power) * dpow(dr, drd, c.distance_power));
            f.zero[i] = kd * r.powi(c.zero_power);
            f.coupling[i] = kd * r.powi(c.coupling_power);
        }
        f
    }

    /// Adds `scale` × the rate of M0 along the motion to `rate` (Keller–Miksis, issue 10):
    /// dM0/dt = ∂M0/∂t + ∂M0/∂R Ṙ + Σ ∂M0/∂a ȧ + Σ ∂M0/∂b ḃ, the last sum as `db` (ḃ is the
    /// closure's, [`crate::model::effects::PressureRate`]); exact partials of the rest in `dq`,
    /// `dq_shape`, and ∂(∂M0/∂b)/∂R in `db_dr`. With M0 = Σ_c K_c(t)[R^{p0} z_c + R^{p1} S_c],
    /// S_c = Σ (α a + β b) over the row-0 band: affine in (a, b), powers of R, so all exact.
    pub fn add_radial_rate(&self, t: f64, y: &[f64], scale: f64, rate: &mut crate::model::effects::PressureRate) {
        let (r, rd, l) = (y[0], y[1], self.layout());
        let f = self.factors_uncounted(t, r);
        let fd = self.factors_dt(t, r);
        for (i, c) in self.comps.iter().enumerate() {
            let (p0, p1) = (c.zero_power as f64, c.coupling_power as f64);
            let (z, f0, f1, f0d, f1d) = (c.zero_n[0], f.zero[i], f.coupling[i], fd.zero[i], fd.coupling[i]);
            let (mut s, mut sa) = (0.0, 0.0); // S_c and Σ α ȧ
            for (j, m) in self.band_sources(0) {
                let (al, be) = (c.band_n[j], c.band_n[j + 1]);
                s += al * y[l.a(m)] + be * y[l.b(m)];
                sa += al * y[l.adot(m)];
                if let Some(sh) = rate.shape.as_deref_mut() {
                    sh.dq_shape[StateLayout::x_a(m)] += scale * (f1d * al + rd * p1 * f1 * al / r);
                    sh.dq_shape[StateLayout::x_adot(m)] += scale * f1 * al;
                    sh.dq_shape[StateLayout::x_b(m)] += scale * (f1d * be + rd * p1 * f1 * be / r);
                    sh.db[m] += scale * f1 * be;
                    sh.db_dr[m] += scale * p1 * f1 * be / r;
                }
            }
            rate.q += scale * (f0d * z + f1d * s + rd * (p0 * f0 * z + p1 * f1 * s) / r + f1 * sa);
            rate.dq[0] += scale
                * (p0 * f0d * z / r + p1 * f1d * s / r
                    + rd * (p0 * (p0 - 1.0) * f0 * z + p1 * (p1 - 1.0) * f1 * s) / (r * r)
                    + p1 * f1 * sa / r);
            rate.dq[1] += scale * (p0 * f0 * z + p1 * f1 * s) / r;
        }
    }

    /// M0 (the P_0 projection, radial equation), nondimensional. `y` is the full state
    /// [R, Ṙ, (a_k, ȧ_k, b_k)_k].
    #[inline]
    pub fn radial(&self, f: &Factors, y: &[f64]) -> f64 {
        self.row(f, 0, y, true)
    }

    /// M_n,k for mode index `m` (k = 2(m+1)), nondimensional.
    #[inline]
    pub fn normal(&self, f: &Factors, m: usize, y: &[f64]) -> f64 {
        self.row(f, m + 1, y, true)
    }

    /// M_t,k for mode index `m` (k = 2(m+1)), nondimensional.
    #[inline]
    pub fn tangential(&self, f: &Factors, m: usize, y: &[f64]) -> f64 {
        self.row(f, m + 1, y, false)
    }
}

#[cfg(test)]
mod tests;
