//! The sparse bilinear sums shared by the quadratic terms (issue 12, "Performance";
//! docs/performance.md): out_o = Σ_{pairs l ≤ m} Σ_s c_o(l, m, s) · w_s(l, m), where the *slots*
//! s of a pair are the products the term needs (a_l a_m, a_l b_m, …, each times a prefactor) and
//! only the (output, pair) rows the selection rules allow (|l − m| ≤ j ≤ l + m, l + m + j even)
//! are stored, grouped by output.
//!
//! Every slot is a product of a factor of mode l and a factor of mode m, so the caller gives, per
//! mode, its left factors (prefactors included) and its right factors (`stride` each); the
//! products w(l, m) = left(l) ⊙ right(m) are formed once per evaluation (they are shared by every
//! output of a pair, no gathers) and [`PairRows::eval`] runs one contiguous dot product per output — the
//! coefficients are read once, in order, into independent partial sums (AVX where the processor
//! has it: the same sums in the same order, so bit for bit the SSE2 result). The Jacobian walks
//! the same rows ([`PairRows::rows`]), so rhs and Jacobian share one table and one sparsity.
//!
//! Two outputs with the same pair list (the membrane's normal and tangential loads on P_j and
//! P¹_j: the same C(j, l, m) ≠ 0) are *twins*: one row per pair holds both outputs' coefficients,
//! so the kernel reads the row's offset and products once for both (at stride ≤ 16, where both
//! outputs' partial sums stay in registers). Each output's sums and their order are the ones it
//! has alone, so twinning changes no bit.

use std::cell::RefCell;

/// The rows of one term: `stride` slots per pair (a multiple of 4).
#[derive(Debug)]
pub struct PairRows {
    stride: usize,
    modes: usize,
    /// the unordered pairs l ≤ m (mode indices), in the layout of w
    pairs: Vec<(usize, usize)>,
    /// the outputs, one or two (twins, module doc) per group, in evaluation order
    groups: Vec<Group>,
    /// (group, half) of each output
    out_at: Vec<(usize, usize)>,
    /// pair index of each group row
    row_pair: Vec<usize>,
    /// offset of each group row's products in w: pair index · stride
    row_off: Vec<u32>,
    /// per group, its rows' coefficients: row · width · stride + half · stride + slot, from
    /// `coef_at` on (64-byte aligned: the wide loads of a row do not straddle cache lines)
    coef_buf: Vec<f64>,
    coef_at: usize,
    /// their number (all groups' rows × width × stride)
    coef_len: usize,
    /// number of (output, pair) rows
    len: usize,
}

/// Outputs that share one pair list (module doc).
#[derive(Debug, Clone, Copy)]
struct Group {
    /// the outputs (`outs[1]` only when `width` is 2)
    outs: [usize; 2],
    width: usize,
    /// its rows: `rows.0..rows.1` of `row_pair`
    rows: (usize, usize),
    /// where its coefficients start in `coef`
    coef: usize,
}

thread_local! {
    /// Scratch for w (no allocation per evaluation once grown).
    static SCRATCH: RefCell<Vec<f64>> = const { RefCell::new(Vec::new()) };
}

/// `v` copied into a buffer at a 64-byte aligned start (the buffer is never reallocated, so the
/// start stays aligned): (buffer, start).
fn aligned(v: &[f64]) -> (Vec<f64>, usize) {
    let mut buf = vec![0.0; v.len() + 8];
    let at = buf.as_ptr().align_offset(64).min(8);
    buf[at..at + v.len()].copy_from_slice(v);
    (buf, at)
}

impl PairRows {
    /// `modes` mode indices, `outputs` outputs, `slots` products per pair; `fill(o, l, m, c)`
    /// writes the coefficients of output o on pair (l ≤ m) into `c` (length `slots`, zeroed) and
    /// returns false when the selection rules exclude the row (the closure need not look at it).
    /// A row is kept when a coefficient is non-zero.
    pub fn new(modes: usize, outputs: usize, slots: usize, mut fill: impl FnMut(usize, usize, usize, &mut [f64]) -> bool) -> Self {
        let stride = slots.div_ceil(4).max(1) * 4;
        assert!(stride <= 32, "PairRows: at most 32 slots per pair");
        let pairs: Vec<(usize, usize)> = (0..modes).flat_map(|l| (l..modes).map(move |m| (l, m))).collect();
        // per output: its pairs and their coefficients
        let mut each: Vec<(Vec<usize>, Vec<f64>)> = Vec::with_capacity(outputs);
        let mut c = vec![0.0; stride];
        for o in 0..outputs {
            let (mut ps, mut cs) = (Vec::new(), Vec::new());
            for (p, &(l, m)) in pairs.iter().enumerate() {
                c.fill(0.0);
                if fill(o, l, m, &mut c[..slots]) && c.iter().any(|&x| x != 0.0) {
                    ps.push(p);
                    cs.extend_from_slice(&c);
                }
            }
            each.push((ps, cs));
        }
        // twins (module doc): an output and the first later one with the same pairs, while both
        // outputs' accumulators fit in the AVX registers
        let mut grouped = vec![false; outputs];
        let (mut groups, mut out_at, mut row_pair, mut coef) = (Vec::new(), vec![(0, 0); outputs], Vec::new(), Vec::new());
        for o in 0..outputs {
            if grouped[o] {
                continue;
            }
            let twin = (stride <= 16 && !each[o].0.is_empty()).then(|| (o + 1..outputs).find(|&t| !grouped[t] && each[t].0 == each[o].0)).flatten();
            let (r0, c0) = (row_pair.len(), coef.len());
            for (i, &p) in each[o].0.iter().enumerate() {
                row_pair.push(p);
                coef.extend_from_slice(&each[o].1[i * stride..(i + 1) * stride]);
                if let Some(t) = twin {
                    coef.extend_from_slice(&each[t].1[i * stride..(i + 1) * stride]);
                }
            }
            out_at[o] = (groups.len(), 0);
            grouped[o] = true;
            if let Some(t) = twin {
                out_at[t] = (groups.len(), 1);
                grouped[t] = true;
            }
            groups.push(Group { outs: [o, twin.unwrap_or(o)], width: 1 + usize::from(twin.is_some()), rows: (r0, row_pair.len()), coef: c0 });
        }
        let len = each.iter().map(|(ps, _)| ps.len()).sum();
        let row_off = row_pair.iter().map(|&p| u32::try_from(p * stride).expect("PairRows: pair table too large")).collect();
        let (coef_buf, coef_at) = aligned(&coef);
        let coef_len = coef.len();
        Self { stride, modes, pairs, groups, out_at, row_pair, row_off, coef_buf, coef_at, coef_len, len }
    }

    /// Slots per pair as laid out (a multiple of 4, padding included).
    pub fn stride(&self) -> usize {
        self.stride
    }
    #[cfg(test)]
    pub fn pairs(&self) -> &[(usize, usize)] {
        &self.pairs
    }
    /// The coefficients of every group, in order (`Group::coef` into it).
    fn coef(&self) -> &[f64] {
        &self.coef_buf[self.coef_at..self.coef_at + self.coef_len]
    }

    /// Number of stored (output, pair) rows.
    pub fn len(&self) -> usize {
        self.len
    }

    /// The rows of output o: (pair (l, m), the `stride` coefficients).
    pub fn rows(&self, o: usize) -> impl Iterator<Item = ((usize, usize), &[f64])> + '_ {
        let (gi, half) = self.out_at[o];
        let g = self.groups[gi];
        let (s, n) = (self.stride, g.rows.1 - g.rows.0);
        let coef = &self.coef()[g.coef..g.coef + n * g.width * s];
        self.row_pair[g.rows.0..g.rows.1].iter().zip(coef.chunks_exact(g.width * s)).map(move |(&p, c)| (self.pairs[p], &c[half * s..(half + 1) * s]))
    }

    /// out_o += Σ rows of o · w, w(l, m) = left(l) ⊙ right(m), with `factors(left, right)`
    /// writing every entry of left and right (modes × `stride` each, padding included: a
    /// padding slot's factors are 0). `out.len()` outputs.
    pub fn eval(&self, out: &mut [f64], factors: impl FnOnce(&mut [f64], &mut [f64])) {
        let s = self.stride;
        let (nm, np) = (self.modes * s, self.pairs.len() * s);
        SCRATCH.with(|cell| {
            let mut buf = cell.borrow_mut();
            if buf.len() < 2 * nm + np + 8 {
                buf.resize(2 * nm + np + 8, 0.0);
            }
            // a 64-byte aligned start (the wide loads of w do not straddle cache lines)
            let at = buf.as_ptr().align_offset(64).min(8);
            let (lr, w) = buf[at..].split_at_mut(2 * nm);
            let (left, right) = lr.split_at_mut(nm);
            factors(left, right);
            self.apply(left, right, &mut w[..np], out);
        });
    }
}

#[path = "pair_rows_kernels.rs"]
mod kernels;

#[cfg(test)]
#[path = "pair_rows_tests.rs"]
mod tests;
