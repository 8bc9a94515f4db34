//! The shortest round-trip decimal digits of a normal f64 written straight in Rust's `{:e}` shape
//! (`d.ddde-x`), for the CSV series: the digit search of the `zmij` crate (Schubfach with
//! Xiang JunBo's scaling, zmij 1.0.23 `to_decimal`, MIT/Apache-2.0, a port of Victor Zverovich's
//! C++ zmij), so the digits are zmij's — a unit test checks this text against zmij's output,
//! rewritten by [`super::csv`]'s general path, on random doubles of every exponent.
//!
//! zmij prints to its own buffer in its own shape (fixed notation for 1e-5 ≤ |v| < 1e16, a `+`
//! in the exponent), which the CSV then had to search and rewrite: two thirds of the CSV's cost
//! in the boundary-layer run (issue 16). Here the digits go to the row directly. Only normal
//! values with a non-zero stored significand take this path (`None` otherwise: zero,
//! subnormals, powers of two, non-finite — the CSV's zmij path).

/// Writes `v` at `o[0..]` (at least 24 bytes) and returns the length, or `None` (module doc).
#[inline]
pub(crate) fn write_exp(v: f64, o: &mut [u8]) -> Option<usize> {
    let bits = v.to_bits();
    let raw_exp = ((bits >> 52) & 0x7ff) as i32;
    let frac = bits & ((1u64 << 52) - 1);
    if raw_exp == 0 || raw_exp == 0x7ff || frac == 0 {
        return None;
    }
    let (digits, exp) = to_decimal(frac | (1u64 << 52), raw_exp - EXP_OFFSET);
    let mut n = 0;
    if bits >> 63 != 0 {
        o[0] = b'-';
        n = 1;
    }
    // the 17 digits of D zero-padded (D < 10^17), the leading one at 17 − (its digit count);
    // the trailing zeros counted on the text (8 digits per word)
    let mut t = [b'0'; 34];
    let (hi, lo) = ((digits / 100_000_000) as u32, (digits % 100_000_000) as u32);
    t[0] = b'0' + (hi / 100_000_000) as u8;
    let (h8, l8) = (digits8(hi % 100_000_000), digits8(lo));
    t[1..9].copy_from_slice(&h8);
    t[9..17].copy_from_slice(&l8);
    let all = count_digits(digits);
    let zeros = |w: [u8; 8]| (u64::from_le_bytes(w) ^ 0x3030_3030_3030_3030).leading_zeros() as usize / 8;
    let tz = match zeros(l8) {
        8 => 8 + zeros(h8),
        z => z,
    };
    let nd = all - tz.min(all - 1);
    // [-]D0.D1…: fixed-size copies (what lies past the text is overwritten by the exponent or
    // left past the end)
    let first = 17 - all;
    o[n] = t[first];
    let mut k = n + 1;
    if nd > 1 {
        o[n + 1] = b'.';
        o[n + 2..n + 18].copy_from_slice(&t[first + 1..first + 17]);
        k = n + 1 + nd;
    }
    let e10 = exp + all as i32 - 1;
    o[k] = b'e';
    k += 1;
    if e10 < 0 {
        o[k] = b'-';
        k += 1;
    }
    let u = e10.unsigned_abs() as usize;
    if u >= 100 {
        o[k] = b'0' + (u / 100) as u8;
        k += 1;
    }
    let u2 = u % 100;
    if u >= 10 {
        o[k..k + 2].copy_from_slice(&DIGITS2[u2 & 127]);
        k += 2;
    } else {
        o[k] = b'0' + u2 as u8;
        k += 1;
    }
    Some(k)
}

/// The 8 decimal digits of `x` < 10^8, zero-padded.
#[inline(always)]
fn digits8(x: u32) -> [u8; 8] {
    let (a, b) = (x / 10_000, x % 10_000);
    let [p, q, r, s] = [a / 100, a % 100, b / 100, b % 100].map(|v| DIGITS2[(v & 127) as usize]);
    [p[0], p[1], q[0], q[1], r[0], r[1], s[0], s[1]]
}

/// The number of decimal digits of `x` (1 ≤ x < 10^19).
#[inline(always)]
fn count_digits(x: u64) -> usize {
    const P10: [u64; 20] = {
        let mut t = [1u64; 20];
        let mut i = 1;
        while i < 20 {
            t[i] = t[i - 1] * 10;
            i += 1;
        }
        t
    };
    // ⌊log10 x⌋ from the bit length (1233/4096 ≈ log10 2), then one correction
    let guess = (((64 - x.leading_zeros()) * 1233) >> 12) as usize;
    guess + usize::from(x >= P10[guess])
}

const EXP_OFFSET: i32 = 1023 + 52;
const EXTRA_SHIFT: u32 = 6;

/// The shortest digits D and the exponent of D's last digit (v = D·10^e to the shortest
/// round-trip precision) of the regular value `bin_sig`·2^`bin_exp` (significand with its
/// implicit bit, not a power of two): zmij's `to_decimal` for f64, regular branch, and the
/// last-digit choice of its `write`.
#[inline(always)]
fn to_decimal(bin_sig: u64, bin_exp: i32) -> (u64, i32) {
    // floor(log10(2^bin_exp))
    let dec_exp = (bin_exp * 315_653) >> 20;
    // the shift that puts the decimal point at a fixed bit (zmij's exp-shift table entry)
    let pow10_bin_exp = (-(dec_exp + 1) * 217_707) >> 16;
    let shift = ((bin_exp + pow10_bin_exp + 1) as u8).wrapping_add(EXTRA_SHIFT as u8) as u32;
    let even = 1 - (bin_sig & 1);
    let (hi, lo) = POW10[(-dec_exp - 1 + 293) as usize];
    let y = bin_sig << shift;
    let p = u128::from(hi) * u128::from(y);
    let plo = (p as u64).wrapping_add(((u128::from(lo) * u128::from(y)) >> 64) as u64);
    let phi = (p >> 64) as u64 + u64::from(plo < p as u64);
    let mut integral = phi >> EXTRA_SHIFT;
    let fractional = (phi << (64 - EXTRA_SHIFT)) | (plo >> EXTRA_SHIFT);
    let half_ulp = (hi >> (EXTRA_SHIFT + 1 - shift)) + even;
    let round_up = fractional.wrapping_add(half_ulp) < fractional;
    let round_down = half_ulp > fractional;
    integral += u64::from(round_up);
    let mut digit = ((u128::from(fractional) * 10 + u128::from((1u64 << 63) + 6)) >> 64) as u64;
    if fractional == 1u64 << 62 {
        digit = 2; // round 2.5 to 2
    }
    if round_up || round_down {
        (integral, dec_exp + 1)
    } else {
        (integral * 10 + digit, dec_exp)
    }
}

/// "00", "01", …, "99" (and 28 unused entries, so that an index masked by 127 needs no check).
static DIGITS2: [[u8; 2]; 128] = {
    let mut t = [[b'0'; 2]; 128];
    let mut i = 0;
    while i < 100 {
        t[i] = [b'0' + (i / 10) as u8, b'0' + (i % 10) as u8];
        i += 1;
    }
    t
};

/// 128-bit significands of 10^(i − 293), rounded down (zmij's table, built the same way).
static POW10: [(u64, u64); 618] = pow10_table();

const fn pow10_table() -> [(u64, u64); 618] {
    #[rustfmt::skip]
    const MINOR: [u64; 28] = [
        0x8000000000000000, 0xa000000000000000, 0xc800000000000000,
        0xfa00000000000000, 0x9c40000000000000, 0xc350000000000000,
        0xf424000000000000, 0x9896800000000000, 0xbebc200000000000,
        0xee6b280000000000, 0x9502f90000000000, 0xba43b74000000000,
        0xe8d4a51000000000, 0x9184e72a00000000, 0xb5e620f480000000,
        0xe35fa931a0000000, 0x8e1bc9bf04000000, 0xb1a2bc2ec5000000,
        0xde0b6b3a76400000, 0x8ac7230489e80000, 0xad78ebc5ac620000,
        0xd8d726b7177a8000, 0x878678326eac9000, 0xa968163f0a57b400,
        0xd3c21bcecceda100, 0x84595161401484a0, 0xa56fa5b99019a5c8,
        0xcecb8f27f4200f3a,
    ];
    #[rustfmt::skip]
    const MAJOR: [(u64, u64); 23] = [
        (0xaf8e5410288e1b6f, 0x07ecf0ae5ee44dda), (0xb1442798f49ffb4a, 0x99cd11cfdf41779d),
        (0xb2fe3f0b8599ef07, 0x861fa7e6dcb4aa15), (0xb4bca50b065abe63, 0x0fed077a756b53aa),
        (0xb67f6455292cbf08, 0x1a3bc84c17b1d543), (0xb84687c269ef3bfb, 0x3d5d514f40eea742),
        (0xba121a4650e4ddeb, 0x92f34d62616ce413), (0xbbe226efb628afea, 0x890489f70a55368c),
        (0xbdb6b8e905cb600f, 0x5400e987bbc1c921), (0xbf8fdb78849a5f96, 0xde98520472bdd034),
        (0xc16d9a0095928a27, 0x75b7053c0f178294), (0xc350000000000000, 0x0000000000000000),
        (0xc5371912364ce305, 0x6c28000000000000), (0xc722f0ef9d80aad6, 0x424d3ad2b7b97ef6),
        (0xc913936dd571c84c, 0x03bc3a19cd1e38ea), (0xcb090c8001ab551c, 0x5cadf5bfd3072cc6),
        (0xcd036837130890a1, 0x36dba887c37a8c10), (0xcf02b2c21207ef2e, 0x94f967e45e03f4bc),
        (0xd106f86e69d785c7, 0xe13336d701beba52), (0xd31045a8341ca07c, 0x1ede48111209a051),
        (0xd51ea6fa85785631, 0x552a74227f3ea566), (0xd732290fbacaf133, 0xa97c177947ad4096),
        (0xd94ad8b1c7380874, 0x18375281ae7822bc),
    ];
    #[rustfmt::skip]
    const FIXUPS: [u32; 20] = [
        0x0a4e363f, 0x00001840, 0x00006400, 0x24200040, 0x00000000,
        0x0c000000, 0x82c81380, 0x5e4ce01f, 0xd730f60f, 0x0000001b,
        0x00000000, 0xcdf7fffc, 0x6e8201d8, 0x40cd3fd1, 0xdb642501,
        0x00000d0d, 0x14042400, 0x53713840, 0x11781db4, 0x00000000,
    ];
    let mut t = [(0u64, 0u64); 618];
    let mut i = 0;
    while i < 618 {
        // Dougall Johnson's method (zmij `Pow10SignificandTable::compute`)
        let m = MINOR[(i + 10) % 28];
        let (hhi, hlo) = MAJOR[(i + 10) / 28];
        let h1 = ((hlo as u128 * m as u128) >> 64) as u64;
        let c0 = hlo.wrapping_mul(m);
        let c1 = h1.wrapping_add(hhi.wrapping_mul(m));
        let c2 = (c1 < h1) as u64 + ((hhi as u128 * m as u128) >> 64) as u64;
        let (rhi, mut rlo) = if (c2 >> 63) != 0 { (c2, c1) } else { ((c2 << 1) | (c1 >> 63), (c1 << 1) | (c0 >> 63)) };
        rlo -= ((FIXUPS[i >> 5] >> (i & 31)) & 1) as u64;
        t[i] = (rhi, rlo);
        i += 1;
    }
    t
}
