//! Exact algebra: rationals (BigRational, cannot overflow), sparse Laurent polynomials over
//! named symbols, first-order (dual) numbers, and Legendre series.

pub mod dual;
pub mod legendre;
pub mod poly;
pub mod triple;

pub use dual::Dual;
pub use poly::{Mono, Poly};

use num_bigint::BigInt;
use num_rational::BigRational;

/// Exact rational number.
pub type Rat = BigRational;

/// The integer `n` as a rational.
pub fn rat(n: i64) -> Rat {
    BigRational::from_integer(BigInt::from(n))
}

/// `n / d` as a reduced rational (`d != 0`).
pub fn ratio(n: i64, d: i64) -> Rat {
    BigRational::new(BigInt::from(n), BigInt::from(d))
}

/// "p/q" (or "p" when q = 1), the exact text used in the generated tables.
pub fn rat_text(r: &Rat) -> String {
    if r.denom() == &BigInt::from(1) {
        r.numer().to_string()
    } else {
        format!("{}/{}", r.numer(), r.denom())
    }
}

/// Nearest f64 (num-rational rounds correctly).
pub fn rat_f64(r: &Rat) -> f64 {
    use num_traits::ToPrimitive;
    r.to_f64().unwrap_or(f64::NAN)
}
