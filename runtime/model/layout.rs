//! The state layout of the models (issue 28 part 2): where R, Ṙ, each mode's (a_k, ȧ_k, b_k) and
//! the vorticity nodes sit in a state vector. Every offset into a model state is computed here.
//!
//! Two layouts, one type ([`StateLayout`]):
//!
//! * the **boundary-layer** (reduced) layout, docs/model.md §4.3:
//!   z = [R, Ṙ, (a_k, ȧ_k, b_k) for k = 2, 4, …, N], dimension 2 + 3M. The terms
//!   ([`super::effects::At`]), the Jacobians and the full model's ODE part use it;
//! * the **monolithic** full-model layout, docs/model.md §4.2 (mode-major, a mode's unknowns
//!   contiguous): y = [R, Ṙ, (a_k, ȧ_k, b_k, T_k,1 … T_k,n−2)_k], dimension 2 + M(3 + n − 2).
//!
//! The boundary-layer layout is the monolithic one with no nodes: mode m's block starts at
//! 2 + m·(3 + nodes) and holds (a, ȧ, b) first, then its nodes. The reduced layout's offsets do
//! not depend on the mode count, and [`StateLayout::reduced`] is a `const fn` with `nodes = 0`, so
//! `StateLayout::reduced(m).a(i)` compiles to the `2 + 3i` it replaces.
//!
//! The linear mode system of Floquet and the spectra, x = (a_k, ȧ_k, b_k)_k (dimension 3M, no R,
//! Ṙ), is the reduced layout's shape part: [`StateLayout::x_a`] and friends. The staggered
//! scheme's step-1 ODE holds the same unknowns component-major, u = [R, Ṙ, a(M), ȧ(M), b(M)]
//! ([`StateLayout::component_major`]).
//!
//! **The gas slot** (issue 31 part 2, `gas.thermal = "reduced"`, docs/model.md "Reduced thermal
//! model"): the reduced heat-transfer model makes the bubble pressure p_b a state variable. Its
//! slot comes after every mode block, y = [R, Ṙ, (mode blocks), p_b], so every offset above is
//! unchanged ([`StateLayout::with_gas`], [`StateLayout::p_b`]); a layout without it (every scene
//! but a reduced-thermal one) is the one described above, dimension unchanged.

use std::ops::Range;

/// The offsets of one model state (module doc). Copy and three words: pass it by value.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StateLayout {
    modes: usize,
    nodes: usize,
    /// Gas slots after the mode blocks: 1 with the reduced thermal model's p_b, else 0.
    gas: usize,
}

impl StateLayout {
    /// The radial slots R, Ṙ come first; the first mode block starts here.
    pub const RADIAL: usize = 2;
    /// The length of a mode's amplitudes (a, ȧ, b): the block of the reduced layout.
    pub const AMPLITUDES: usize = 3;
    /// Offsets of a_k, ȧ_k, b_k within their mode block.
    pub const A: usize = 0;
    pub const ADOT: usize = 1;
    pub const B: usize = 2;

    /// The boundary-layer layout of M shape modes (dimension 2 + 3M).
    #[inline]
    pub const fn reduced(modes: usize) -> Self {
        Self { modes, nodes: 0, gas: 0 }
    }

    /// The boundary-layer layout of a state of dimension `dim` (2 + 3M; panics otherwise).
    #[inline]
    pub fn reduced_of_dim(dim: usize) -> Self {
        assert!(dim >= Self::RADIAL && (dim - Self::RADIAL) % Self::AMPLITUDES == 0, "a boundary-layer state has dimension 2 + 3M, not {dim}");
        Self::reduced((dim - Self::RADIAL) / Self::AMPLITUDES)
    }

    /// The monolithic full-model layout: M modes, each with `nodes` interior vorticity nodes
    /// (n − 2 of a grid of n points).
    #[inline]
    pub const fn monolithic(modes: usize, nodes: usize) -> Self {
        Self { modes, nodes, gas: 0 }
    }

    /// This layout with the gas slot p_b after the mode blocks (module doc).
    #[inline]
    pub const fn with_gas(self) -> Self {
        Self { gas: 1, ..self }
    }

    /// Index of the bubble pressure p_b (the reduced thermal model's state), if the layout has
    /// the gas slot: right after the last mode block.
    #[inline]
    pub const fn p_b(self) -> Option<usize> {
        if self.gas == 1 {
            Some(Self::RADIAL + self.modes * self.block())
        } else {
            None
        }
    }

    /// Number of shape modes M.
    #[inline]
    pub const fn modes(self) -> usize {
        self.modes
    }

    /// Interior vorticity nodes per mode (0 in the boundary-layer layout).
    #[inline]
    pub const fn nodes(self) -> usize {
        self.nodes
    }

    /// Length of one mode block, 3 + nodes.
    #[inline]
    pub const fn block(self) -> usize {
        Self::AMPLITUDES + self.nodes
    }

    /// Dimension of the state, 2 + M·block (+ 1 with the gas slot).
    #[inline]
    pub const fn dim(self) -> usize {
        Self::RADIAL + self.modes * self.block() + self.gas
    }

    /// Index of R.
    #[inline]
    pub const fn r(self) -> usize {
        0
    }

    /// Index of Ṙ.
    #[inline]
    pub const fn rdot(self) -> usize {
        1
    }

    /// Index of a_k of mode index m (k = 2(m + 1)).
    #[inline]
    pub const fn a(self, m: usize) -> usize {
        Self::RADIAL + m * self.block() + Self::A
    }

    /// Index of ȧ_k of mode index m.
    #[inline]
    pub const fn adot(self, m: usize) -> usize {
        self.a(m) - Self::A + Self::ADOT
    }

    /// Index of b_k of mode index m.
    #[inline]
    pub const fn b(self, m: usize) -> usize {
        self.a(m) - Self::A + Self::B
    }

    /// Mode index m's whole block: (a, ȧ, b) and its nodes.
    #[inline]
    pub const fn mode_block(self, m: usize) -> Range<usize> {
        let start = Self::RADIAL + m * self.block();
        start..start + self.block()
    }

    /// Mode index m's amplitudes (a, ȧ, b).
    #[inline]
    pub const fn amplitudes(self, m: usize) -> Range<usize> {
        let start = Self::RADIAL + m * self.block();
        start..start + Self::AMPLITUDES
    }

    /// Mode index m's interior vorticity nodes T_k,1 … T_k,n−2 (empty in the reduced layout).
    #[inline]
    pub const fn node_range(self, m: usize) -> Range<usize> {
        let start = Self::RADIAL + m * self.block() + Self::AMPLITUDES;
        start..start + self.nodes
    }

    /// Every mode block, 2..2 + M·block (the shape part of the state; the gas slot excluded).
    #[inline]
    pub const fn shape(self) -> Range<usize> {
        Self::RADIAL..Self::RADIAL + self.modes * self.block()
    }

    /// The mode blocks of modes `modes` (a range of mode indices), contiguous.
    #[inline]
    pub const fn blocks(self, modes: Range<usize>) -> Range<usize> {
        Self::RADIAL + modes.start * self.block()..Self::RADIAL + modes.end * self.block()
    }

    /// The mode index of a shape index i ≥ 2.
    #[inline]
    pub const fn mode_of(self, i: usize) -> usize {
        (i - Self::RADIAL) / self.block()
    }

    /// Whether index i is an a_k.
    #[inline]
    pub const fn is_a(self, i: usize) -> bool {
        i >= Self::RADIAL && (i - Self::RADIAL) % self.block() == Self::A
    }

    /// The boundary-layer layout of the same modes: the full model's ODE part z.
    #[inline]
    pub const fn boundary_layer(self) -> Self {
        Self::reduced(self.modes)
    }

    /// The index in the boundary-layer layout of index i of this one (`None` for a node).
    #[inline]
    pub const fn to_boundary_layer(self, i: usize) -> Option<usize> {
        if i < Self::RADIAL {
            return Some(i);
        }
        let (m, o) = ((i - Self::RADIAL) / self.block(), (i - Self::RADIAL) % self.block());
        if o < Self::AMPLITUDES {
            Some(Self::reduced(self.modes).a(m) + o)
        } else {
            None
        }
    }

    /// The ODE part z (boundary-layer layout) of a state y in this layout: R, Ṙ and every mode's
    /// (a, ȧ, b).
    #[inline]
    pub fn gather_amplitudes(self, y: &[f64], z: &mut [f64]) {
        let bl = self.boundary_layer();
        z[..Self::RADIAL].copy_from_slice(&y[..Self::RADIAL]);
        for m in 0..self.modes {
            z[bl.amplitudes(m)].copy_from_slice(&y[self.amplitudes(m)]);
        }
    }

    /// The reverse of [`gather_amplitudes`](Self::gather_amplitudes): z's R, Ṙ and (a, ȧ, b)
    /// into y (the nodes untouched).
    #[inline]
    pub fn scatter_amplitudes(self, z: &[f64], y: &mut [f64]) {
        let bl = self.boundary_layer();
        y[..Self::RADIAL].copy_from_slice(&z[..Self::RADIAL]);
        for m in 0..self.modes {
            y[self.amplitudes(m)].copy_from_slice(&z[bl.amplitudes(m)]);
        }
    }

    /// Index of a_k of mode index m in the linear mode system x = (a_k, ȧ_k, b_k)_k (the reduced
    /// layout's shape part, dimension 3M: Floquet's and the spectra's A(t)).
    #[inline]
    pub const fn x_a(m: usize) -> usize {
        Self::AMPLITUDES * m + Self::A
    }

    /// Index of ȧ_k in x.
    #[inline]
    pub const fn x_adot(m: usize) -> usize {
        Self::AMPLITUDES * m + Self::ADOT
    }

    /// Index of b_k in x.
    #[inline]
    pub const fn x_b(m: usize) -> usize {
        Self::AMPLITUDES * m + Self::B
    }

    /// The mode index of entry i of x.
    #[inline]
    pub const fn x_mode(i: usize) -> usize {
        i / Self::AMPLITUDES
    }

    /// Which of (a, ȧ, b) entry i of x is ([`Self::A`], [`Self::ADOT`] or [`Self::B`]).
    #[inline]
    pub const fn x_entry(i: usize) -> usize {
        i % Self::AMPLITUDES
    }

    /// The index in x of index i ≥ 2 of the reduced state.
    #[inline]
    pub const fn x_of(i: usize) -> usize {
        i - Self::RADIAL
    }

    /// Dimension of x for M modes, 3M.
    #[inline]
    pub const fn x_dim(modes: usize) -> usize {
        Self::AMPLITUDES * modes
    }

    /// The component-major ordering of the boundary-layer unknowns, u = [R, Ṙ, a(M), ȧ(M),
    /// b(M)] (the staggered scheme's step 1; dimension 2 + 3M): the ranges of the a, ȧ and b.
    #[inline]
    pub const fn component_major(self) -> [Range<usize>; 3] {
        let (m, s) = (self.modes, Self::RADIAL);
        [s..s + m, s + m..s + 2 * m, s + 2 * m..s + 3 * m]
    }
}

#[cfg(test)]
mod tests {
    use super::StateLayout;

    #[test]
    fn reduced_offsets_are_the_documented_ones() {
        let l = StateLayout::reduced(4);
        assert_eq!(l.dim(), 14);
        assert_eq!(StateLayout::reduced_of_dim(14), l);
        for m in 0..4 {
            assert_eq!((l.a(m), l.adot(m), l.b(m)), (2 + 3 * m, 3 + 3 * m, 4 + 3 * m));
            assert_eq!(l.mode_block(m), 2 + 3 * m..5 + 3 * m);
            assert!(l.node_range(m).is_empty());
            assert_eq!(l.to_boundary_layer(l.b(m)), Some(l.b(m)));
            assert_eq!(l.mode_of(l.b(m)), m);
            assert_eq!((StateLayout::x_a(m), StateLayout::x_b(m)), (l.a(m) - 2, l.b(m) - 2));
        }
        assert_eq!(l.shape(), 2..14);
        assert_eq!(l.blocks(1..3), 5..11);
        assert_eq!(l.component_major(), [2..6, 6..10, 10..14]);
        assert_eq!(l.p_b(), None);
    }

    #[test]
    fn the_gas_slot_follows_the_mode_blocks_and_moves_nothing_else() {
        for (l, p) in [(StateLayout::reduced(0), 2), (StateLayout::reduced(3), 11), (StateLayout::monolithic(2, 4), 16)] {
            let g = l.with_gas();
            assert_eq!(g.p_b(), Some(p));
            assert_eq!(g.dim(), l.dim() + 1);
            assert_eq!(g.shape(), l.shape());
            for m in 0..l.modes() {
                assert_eq!((g.a(m), g.adot(m), g.b(m), g.mode_block(m)), (l.a(m), l.adot(m), l.b(m), l.mode_block(m)));
            }
        }
    }

    #[test]
    fn monolithic_blocks_hold_amplitudes_then_nodes_and_map_to_the_reduced_layout() {
        let (l, nodes) = (StateLayout::monolithic(3, 5), 5);
        assert_eq!(l.dim(), 2 + 3 * (3 + nodes));
        let z = l.boundary_layer();
        let y: Vec<f64> = (0..l.dim()).map(|i| i as f64).collect();
        let mut zz = vec![0.0; z.dim()];
        l.gather_amplitudes(&y, &mut zz);
        for m in 0..3 {
            let o = 2 + m * (3 + nodes);
            assert_eq!((l.a(m), l.adot(m), l.b(m)), (o, o + 1, o + 2));
            assert_eq!(l.node_range(m), o + 3..o + 3 + nodes);
            assert_eq!([zz[z.a(m)], zz[z.adot(m)], zz[z.b(m)]], [o as f64, (o + 1) as f64, (o + 2) as f64]);
            assert_eq!(l.to_boundary_layer(l.adot(m)), Some(z.adot(m)));
            assert_eq!(l.to_boundary_layer(l.node_range(m).start), None);
        }
        let mut back = vec![-1.0; l.dim()];
        l.scatter_amplitudes(&zz, &mut back);
        assert!((0..l.dim()).all(|i| l.to_boundary_layer(i).is_none() == (back[i] == -1.0)));
    }
}
