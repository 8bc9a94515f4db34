//! Galerkin projection of a load (a polynomial in cosΘ, sinΘ, the mode-shape markers and the
//! amplitudes) onto P_j (normal, weight 2/(2j+1)) or P^1_j = dP_j/dΘ (tangential, weight
//! 2j(j+1)/(2j+1)), exactly, for a concrete mode k (FORMULATION §0–1).

use crate::algebra::dual::marker_order;
use crate::algebra::legendre::{self, Basis, Series};
use crate::algebra::{rat, Mono, Poly, Rat};
use num_traits::Zero;
use std::collections::BTreeMap;

/// Which load: projected on P_j or on P^1_j.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Load {
    Normal,
    Tangential,
}

/// Which amplitude a first-order term multiplies: a_k, b_k, or their rates ȧ_k, ḃ_k (viscous laws).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Amp {
    A,
    B,
    Ad,
    Bd,
}

/// The amplitude symbols of the engine, with their [`Amp`].
pub const AMPLITUDES: [(&str, Amp); 4] = [("#a", Amp::A), ("#b", Amp::B), ("#ad", Amp::Ad), ("#bd", Amp::Bd)];

/// Projections keyed by (amplitude or None for zero order, the remaining symbolic monomial);
/// the series holds the coefficient on P_j (normal) or P^1_j (tangential) at index j.
pub type Projected = BTreeMap<(Option<Amp>, Mono), Series>;

struct Piece {
    marker: Option<u32>,
    x: i32,
    s: i32,
    c: Rat,
}

/// Project `p` (for mode k; `k` is ignored when `p` has no mode-shape marker).
pub fn project(p: &Poly, load: Load, k: usize, basis: &mut Basis) -> Result<Projected, String> {
    let mut groups: BTreeMap<(Option<Amp>, Mono), Vec<Piece>> = BTreeMap::new();
    for (m, c) in &p.terms {
        let powers: Vec<(i32, Amp)> = AMPLITUDES.iter().map(|(n, a)| (m.power(n), *a)).filter(|(p, _)| *p != 0).collect();
        let amp = match powers.as_slice() {
            [] => None,
            [(1, a)] => Some(*a),
            _ => return Err(format!("term `{}` is not linear in the amplitudes", m.text())),
        };
        let markers: Vec<(u32, i32)> = m.0.iter().filter_map(|(n, pw)| marker_order(n).map(|i| (i, *pw))).collect();
        let marker = match (markers.as_slice(), amp) {
            ([], None) => None,
            ([(i, 1)], Some(_)) => Some(*i),
            ([], Some(_)) => return Err("an amplitude a_k/b_k appears without a mode shape P(k)/P1(k)".into()),
            (_, None) => return Err("a mode shape P(k)/P1(k) appears without an amplitude a_k/b_k".into()),
            _ => return Err(format!("term `{}` is not linear in the mode shape", m.text())),
        };
        for bad in ["#r", "#ct", "#st", "#free", "#v"] {
            if m.power(bad) != 0 {
                return Err(format!("internal variable {bad} left in a load"));
            }
        }
        if m.0.iter().any(|(n, _)| crate::algebra::dual::jet_order(n).is_some()) {
            return Err("the test function of `vary` left in a load".into());
        }
        let x = m.power("#x");
        if x < 0 {
            return Err("load has a factor 1/cosΘ".into());
        }
        let rest = m.filter(|n| !(n.starts_with('#')));
        groups.entry((amp, rest)).or_default().push(Piece { marker, x, s: m.power("#s"), c: c.clone() });
    }
    let mut out = Projected::new();
    for (key, pieces) in groups {
        let parity = match load {
            Load::Normal => 0,
            Load::Tangential => 1,
        };
        if let Some(bad) = pieces.iter().find(|p| (p.s - parity).rem_euclid(2) != 0) {
            let _ = bad;
            return Err(match load {
                Load::Normal => "normal load is not even in sinΘ (not axisymmetric-regular)".into(),
                Load::Tangential => "tangential load is not odd in sinΘ".into(),
            });
        }
        let min_half = pieces.iter().map(|p| (p.s - parity) / 2).min().unwrap_or(0);
        let shift = (-min_half).max(0);
        let mut by_marker: BTreeMap<Option<u32>, Vec<Rat>> = BTreeMap::new();
        for pc in &pieces {
            let half = (pc.s - parity) / 2 + shift;
            // c x^p (1 − x²)^half as a dense polynomial
            let mut poly = vec![Rat::zero(); pc.x as usize + 1];
            poly[pc.x as usize] = pc.c.clone();
            for _ in 0..half {
                let mut next = vec![Rat::zero(); poly.len() + 2];
                for (i, v) in poly.iter().enumerate() {
                    next[i] += v;
                    next[i + 2] -= v;
                }
                poly = next;
            }
            let acc = by_marker.entry(pc.marker).or_default();
            if acc.len() < poly.len() {
                acc.resize(poly.len(), Rat::zero());
            }
            for (a, v) in acc.iter_mut().zip(poly) {
                *a += v;
            }
        }
        let mut series: Series = Vec::new();
        for (mk, poly) in by_marker {
            let s = match mk {
                None => legendre::poly_times(&poly, &[rat(1)]),
                Some(i) => legendre::poly_times(&poly, basis.get(k, i)),
            };
            legendre::add_scaled(&mut series, &s, &rat(1));
        }
        for _ in 0..shift {
            series = legendre::div_one_minus_x2(&series)?;
        }
        let coeffs = match load {
            Load::Normal => legendre::trim(series),
            Load::Tangential => legendre::tangential_coefficients(&series),
        };
        if !coeffs.is_empty() {
            out.insert(key, coeffs);
        }
    }
    Ok(out)
}
