//! Node-major lane vectors ([`super::batch::V`]) of dropped factorisations, kept per thread for
//! the next ones: Radau5 factors σI − J 1,122 times in the monolithic run, and every factor
//! vector (the Thomas factors, D⁻¹c, D⁻¹r_R, D⁻¹r_Ṙ) is written entry by entry by the kernel that
//! fills it, so a spare vector of the right length needs neither zeroing nor pushes.

use super::batch::{L, V};
use std::cell::RefCell;

thread_local! {
    static SPARE: RefCell<Vec<Vec<V>>> = const { RefCell::new(Vec::new()) };
}

/// At most this many spare vectors are kept (a real and a complex factorisation alive at once,
/// ten vectors each).
const KEEP: usize = 24;

/// A vector of `n` lanes: a spare one (its old values are stale: the caller writes every entry)
/// or a zeroed one.
pub fn take(n: usize) -> Vec<V> {
    let spare = SPARE.try_with(|p| {
        let mut p = p.borrow_mut();
        let at = p.iter().rposition(|v| v.len() == n)?;
        Some(p.swap_remove(at))
    });
    spare.ok().flatten().unwrap_or_else(|| vec![[0.0; L]; n])
}

/// Keeps `v` for a later [`take`] (empty vectors are dropped).
pub fn give(v: Vec<V>) {
    if v.is_empty() {
        return;
    }
    let _ = SPARE.try_with(|p| {
        let mut p = p.borrow_mut();
        if p.len() < KEEP {
            p.push(v);
        }
    });
}
