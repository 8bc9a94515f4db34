//! The parametric-instability threshold table of docs/peer-comparison.md ("Parametric
//! instability …"): the reference's critical ε_p of n = 2 for the four combinations of radial
//! equation and (B, A), per R0 (the reference is tests/suite/support/hlb_reference.rs; the
//! asserting check against magbubble is tests/suite/hlb_parametric.rs). About 3 min:
//!
//! ```text
//! cargo run --release --example hlb_threshold_table
//! ```

// the tests' reference model (it also carries what only the tests use); it reaches its
// integrator as `super::dopri_ref`
#[allow(dead_code)]
#[path = "../tests/suite/support/dopri_ref.rs"]
mod dopri_ref;
#[allow(dead_code)]
#[path = "../tests/suite/support/hlb_reference.rs"]
mod hlb_reference;

use hlb_reference::{first_threshold, Case, Radial, Shape};

/// One row per R0, the four combinations as columns, printed as a Markdown table (stderr).
fn main() {
    let combos = [(Radial::Km, Shape::Magbubble), (Radial::Km, Shape::Hlb), (Radial::HlbRp, Shape::Magbubble), (Radial::HlbRp, Shape::Hlb)];
    std::thread::scope(|sc| {
        let rows: Vec<_> = [4e-6, 4.5e-6, 5e-6, 6e-6, 7e-6]
            .into_iter()
            .map(|r0| {
                sc.spawn(move || {
                    let cells: Vec<String> = combos
                        .iter()
                        .map(|&(radial, shape)| {
                            let t = first_threshold(Case { r0, eps: 0.0, radial, shape });
                            t.map_or("> 1.5".into(), |t| format!("{t:.4}"))
                        })
                        .collect();
                    format!("| {:.1} | {} |", r0 * 1e6, cells.join(" | "))
                })
            })
            .collect();
        eprintln!("| R0 [µm] | KM + magbubble BL | KM + HLB (B, A) | HLB RP + hard core + magbubble BL | HLB RP + hard core + HLB (B, A) |");
        for r in rows {
            eprintln!("{}", r.join().unwrap());
        }
    });
}
