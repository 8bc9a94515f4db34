//! Tests of [`super::PairRows`] (pair_rows.rs).

use super::*;

/// The AVX kernel for `rows`' stride into outputs that start at `start` (the lengths are
/// those `apply` asserts; the caller checks AVX).
#[cfg(target_arch = "x86_64")]
fn apply_avx(rows: &PairRows, left: &[f64], right: &[f64], w: &mut [f64], start: f64) -> Vec<f64> {
    assert!(crate::simd::detected() >= crate::simd::Level::Avx2Fma);
    let mut out = vec![start; rows.out_at.len()];
    // SAFETY: the processor has AVX (asserted just above); the callers' lengths are those apply asserts.
    unsafe {
        match rows.stride() {
            4 => rows.apply_avx::<1>(left, right, w, &mut out),
            8 => rows.apply_avx::<2>(left, right, w, &mut out),
            12 => rows.apply_avx::<3>(left, right, w, &mut out),
            16 => rows.apply_avx::<4>(left, right, w, &mut out),
            20 => rows.apply_avx::<5>(left, right, w, &mut out),
            24 => rows.apply_avx::<6>(left, right, w, &mut out),
            28 => rows.apply_avx::<7>(left, right, w, &mut out),
            32 => rows.apply_avx::<8>(left, right, w, &mut out),
            st => panic!("no AVX kernel for stride {st}"),
        }
    }
    out
}

/// The AVX-512 kernel for a stride that is a multiple of 8 (as [`apply_avx`]; the caller checks
/// AVX-512F).
#[cfg(target_arch = "x86_64")]
fn apply_avx512(rows: &PairRows, left: &[f64], right: &[f64], w: &mut [f64], start: f64) -> Vec<f64> {
    assert!(crate::simd::detected() >= crate::simd::Level::Avx512);
    let mut out = vec![start; rows.out_at.len()];
    // SAFETY: the processor has AVX-512F (asserted just above); the callers' lengths are those
    // apply asserts.
    unsafe {
        match rows.stride() {
            8 => rows.apply_avx512::<1>(left, right, w, &mut out),
            16 => rows.apply_avx512::<2>(left, right, w, &mut out),
            24 => rows.apply_avx512::<3>(left, right, w, &mut out),
            32 => rows.apply_avx512::<4>(left, right, w, &mut out),
            st => panic!("no AVX-512 kernel for stride {st}"),
        }
    }
    out
}

/// The sparse sums equal the plain double loop over every (output, pair, slot).
#[test]
fn eval_is_the_plain_sum() {
    let (modes, outputs, slots) = (5, 4, 6);
    let coef = |o: usize, l: usize, m: usize, s: usize| if (l + m + o) % 3 == 0 { 0.0 } else { (1 + o + 2 * l + 3 * m + 5 * s) as f64 * 0.01 };
    let rows = PairRows::new(modes, outputs, slots, |o, l, m, c| {
        for (s, x) in c.iter_mut().enumerate() {
            *x = coef(o, l, m, s);
        }
        true
    });
    assert_eq!(rows.stride(), 8);
    let mut out = vec![0.0; outputs];
    // prod(l, m, s) = left_s(l) · right_s(m)
    let (lf, rf) = (|l: usize, s: usize| 1.0 + 0.1 * (l * 7 + s) as f64, |m: usize, s: usize| ((m * 3 + s) as f64).sin());
    let prod = |l: usize, m: usize, s: usize| lf(l, s) * rf(m, s);
    rows.eval(&mut out, |left, right| {
        for (i, (lv, rv)) in left.chunks_exact_mut(8).zip(right.chunks_exact_mut(8)).enumerate() {
            for s in 0..8 {
                (lv[s], rv[s]) = if s < slots { (lf(i, s), rf(i, s)) } else { (0.0, 0.0) };
            }
        }
    });
    for (o, &got) in out.iter().enumerate() {
        let mut want = 0.0;
        for &(l, m) in rows.pairs() {
            for s in 0..slots {
                want += coef(o, l, m, s) * prod(l, m, s);
            }
        }
        assert!((got - want).abs() <= 1e-14 * want.abs().max(1.0), "output {o}: {got} against {want}");
    }
}

/// The AVX kernel is the portable one bit for bit (same products, sums and order), for
/// every stride and for odd and even row counts per output.
#[test]
fn avx_kernel_is_the_portable_one_bit_for_bit() {
    for slots in [3, 8, 13, 16, 21, 32] {
        let (modes, outputs) = (6, 7);
        let rows = PairRows::new(modes, outputs, slots, |o, l, m, c| {
            for (s, x) in c.iter_mut().enumerate() {
                *x = (((o * 31 + l * 7 + m * 3 + s) as f64) * 0.731).sin();
            }
            (o + l + m) % 3 != 1
        });
        let st = rows.stride();
        let left: Vec<f64> = (0..modes * st).map(|i| ((i as f64) * 1.37).cos() * 1e3).collect();
        let right: Vec<f64> = (0..modes * st).map(|i| ((i as f64) * 0.29).sin() * 1e-3).collect();
        let mut w = vec![0.0; rows.pairs().len() * st];
        let mut portable = vec![0.5; outputs];
        match st {
            4 => rows.apply_s::<4>(&left, &right, &mut w, &mut portable),
            8 => rows.apply_s::<8>(&left, &right, &mut w, &mut portable),
            16 => rows.apply_s::<16>(&left, &right, &mut w, &mut portable),
            24 => rows.apply_s::<24>(&left, &right, &mut w, &mut portable),
            _ => rows.apply_s::<32>(&left, &right, &mut w, &mut portable),
        }
        let mut dispatched = vec![0.5; outputs];
        rows.apply(&left, &right, &mut w, &mut dispatched);
        for (a, b) in portable.iter().zip(&dispatched) {
            assert_eq!(a.to_bits(), b.to_bits(), "stride {st}: {a} against {b}");
        }
        // the AVX kernel also where the dispatch above took AVX-512
        #[cfg(target_arch = "x86_64")]
        if crate::simd::test_can_run(crate::simd::Level::Avx2Fma, "pair rows: AVX kernel against the portable one") {
            let avx = apply_avx(&rows, &left, &right, &mut w, 0.5);
            for (a, b) in portable.iter().zip(&avx) {
                assert_eq!(a.to_bits(), b.to_bits(), "stride {st} (AVX): {a} against {b}");
            }
        }
        #[cfg(target_arch = "x86_64")]
        if st % 8 == 0 && crate::simd::test_can_run(crate::simd::Level::Avx512, "pair rows: AVX-512 kernel against the portable one") {
            let wide = apply_avx512(&rows, &left, &right, &mut w, 0.5);
            for (a, b) in portable.iter().zip(&wide) {
                assert_eq!(a.to_bits(), b.to_bits(), "stride {st} (AVX-512): {a} against {b}");
            }
        }
    }
}

/// Twins (outputs with the same pairs, module doc) form where the stride allows, and each
/// output's result is bit for bit the one of a table that holds that output alone.
#[test]
fn twins_change_no_bit() {
    // 2 … 8 modes: twin groups of 1 … 24 rows (every remainder of the four-row trips)
    for (slots, modes) in [3, 8, 16, 21].into_iter().flat_map(|s| (2..=8).map(move |m| (s, m))) {
        let outputs = 7;
        // outputs o and o + 3 share their pairs (different coefficients)
        let fill = |o: usize, l: usize, m: usize, c: &mut [f64]| {
            for (s, x) in c.iter_mut().enumerate() {
                *x = (((o * 31 + l * 7 + m * 3 + s) as f64) * 0.731).sin();
            }
            (o % 3 + l + m) % 3 != 1
        };
        let rows = PairRows::new(modes, outputs, slots, fill);
        let st = rows.stride();
        let twins = rows.groups.iter().filter(|g| g.width == 2).count();
        if modes == 6 {
            assert_eq!(twins, if st <= 16 { 3 } else { 0 }, "stride {st}");
        }
        let left: Vec<f64> = (0..modes * st).map(|i| ((i as f64) * 1.37).cos() * 1e3).collect();
        let right: Vec<f64> = (0..modes * st).map(|i| ((i as f64) * 0.29).sin() * 1e-3).collect();
        let mut w = vec![0.0; rows.pairs().len() * st];
        let mut all = vec![0.25; outputs];
        rows.apply(&left, &right, &mut w, &mut all);
        // the AVX kernel's twin loop also where the dispatch above took AVX-512
        #[cfg(target_arch = "x86_64")]
        if crate::simd::test_can_run(crate::simd::Level::Avx2Fma, "pair rows: AVX twin loop against the portable one") {
            let avx = apply_avx(&rows, &left, &right, &mut w, 0.25);
            for (a, b) in all.iter().zip(&avx) {
                assert_eq!(a.to_bits(), b.to_bits(), "stride {st}, {modes} modes (AVX): {a} against {b}");
            }
        }
        #[cfg(target_arch = "x86_64")]
        if st % 8 == 0 && crate::simd::test_can_run(crate::simd::Level::Avx512, "pair rows: AVX-512 twin loop against the portable one") {
            let wide = apply_avx512(&rows, &left, &right, &mut w, 0.25);
            for (a, b) in all.iter().zip(&wide) {
                assert_eq!(a.to_bits(), b.to_bits(), "stride {st}, {modes} modes (AVX-512): {a} against {b}");
            }
        }
        for (o, &got) in all.iter().enumerate() {
            let alone = PairRows::new(modes, 1, slots, |_, l, m, c| fill(o, l, m, c));
            assert_eq!(alone.groups.len(), 1);
            let mut one = [0.25];
            alone.apply(&left, &right, &mut w, &mut one);
            assert_eq!(got.to_bits(), one[0].to_bits(), "stride {st}, {modes} modes, output {o}: {got} against {}", one[0]);
            // the Jacobian's view of the rows is the output's own
            let n = rows.rows(o).count();
            assert_eq!(n, alone.rows(0).count());
            for (a, b) in rows.rows(o).zip(alone.rows(0)) {
                assert_eq!(a, b, "stride {st}, output {o}");
            }
        }
        assert_eq!(rows.len(), (0..outputs).map(|o| rows.rows(o).count()).sum::<usize>());
    }
}
