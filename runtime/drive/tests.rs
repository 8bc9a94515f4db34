use super::*;

fn tones(burst: Option<Burst>, extra: &[Tone]) -> Waveform {
    let mut t = vec![Tone { amplitude: 0.5, omega: 2.0 * std::f64::consts::PI * 1e6, phase: 0.3 }];
    t.extend_from_slice(extra);
    Waveform::Tones { p_ref: 101325.0, tones: t, burst }
}

fn burst(shape: Shape, period: Option<f64>) -> Option<Burst> {
    Some(Burst { shape, start: 1e-6, length: 3e-6, period })
}

/// dp/dt against a central difference of p, for every kind of drive, away from the edges.
#[test]
fn rate_is_the_derivative() {
    let second = [Tone { amplitude: 0.2, omega: 2.0 * std::f64::consts::PI * 2e6, phase: std::f64::consts::PI }];
    let file = Waveform::File(Samples::new(vec![0.0, 1e-6, 2.5e-6, 7e-6], vec![0.0, 3e4, -1e4, 0.0]).unwrap());
    let mut drives = vec![tones(None, &[]), tones(None, &second), file];
    for s in [Shape::Rectangular, Shape::Hann, Shape::Gaussian, Shape::Tukey(0.5)] {
        drives.push(tones(burst(s, None), &second));
        drives.push(tones(burst(s, Some(5e-6)), &[]));
    }
    for d in &drives {
        let stops = d.stop_times(0.0, 2e-5);
        for i in 0..400 {
            let t = i as f64 * 5e-8 + 1.3e-9;
            let h = 1e-12;
            if stops.iter().any(|s| (s - t).abs() < 2.0 * h) {
                continue;
            }
            let fd = (d.pressure(t + h) - d.pressure(t - h)) / (2.0 * h);
            let r = d.rate(t);
            assert!((fd - r).abs() < 1e-5 * 101325.0 * 2e7, "{d:?} t={t}: {r} vs {fd}");
            assert_eq!(d.pressure(t), d.pressure_and_rate(t).0);
        }
    }
}

/// The fast single-tone path is the general formula.
#[test]
fn single_tone_fast_path() {
    let d = tones(None, &[]);
    let Waveform::Tones { p_ref, tones, .. } = &d else { unreachable!() };
    for i in 0..100 {
        let t = i as f64 * 3.7e-8;
        let x = tones[0].omega * t + tones[0].phase;
        assert_eq!(d.pressure(t), tones[0].amplitude * p_ref * x.cos());
        let general = d.pressure_and_rate(t);
        assert!((d.pressure(t) - general.0).abs() < 1e-9 && (d.rate(t) - general.1).abs() < 1e-2);
    }
}

/// `sin_cos` returns sin and cos to the bit (glibc's sincos on Linux), over arguments from 1e-8
/// to 1e6 rad of both signs (a drive's phase ω t reaches 2π·1e4 at 1 MHz after 10 ms); and the
/// single-tone pressure and rate are the general `pressure_and_rate` to the bit, which the far
/// field's one-call `add_with_rate` relies on.
#[test]
fn sin_cos_is_sin_and_cos() {
    let mut x = 1e-8_f64;
    let mut n = 0;
    while x < 1e6 {
        for v in [x, -x, x * 1.000_000_1] {
            let (s, c) = sin_cos(v);
            assert_eq!((s.to_bits(), c.to_bits()), (v.sin().to_bits(), v.cos().to_bits()), "x = {v:e}");
            n += 1;
        }
        x *= 1.000_5;
    }
    assert!(n > 100_000, "{n} arguments");
    let d = tones(None, &[]);
    for i in 0..2000 {
        let t = i as f64 * 3.7e-8 + 1e-10;
        let (p, r) = d.pressure_and_rate(t);
        assert_eq!((d.pressure(t).to_bits(), d.rate(t).to_bits()), (p.to_bits(), r.to_bits()), "t = {t:e}");
    }
}

/// Zero outside the bursts, the edges as stop times, a train repeats.
#[test]
fn bursts_edges_and_trains() {
    let single = tones(burst(Shape::Rectangular, None), &[]);
    assert_eq!(single.pressure(0.99e-6), 0.0);
    assert_eq!(single.pressure(4.01e-6), 0.0);
    assert!(single.pressure(1.0e-6).abs() > 0.0);
    assert_eq!(single.stop_times(0.0, 1e-3), vec![1e-6, 4e-6]);
    assert_eq!(single.stop_times(1e-6, 4e-6), Vec::<f64>::new());
    let train = tones(burst(Shape::Hann, Some(5e-6)), &[]);
    // start + nP in floating point (1e-6 + 2·5e-6 = 1.1000000000000001e-5)
    let stops = train.stop_times(0.0, 1.2e-5);
    let want = [1e-6, 4e-6, 6e-6, 9e-6, 1.1e-5];
    assert_eq!(stops.len(), want.len(), "{stops:?}");
    assert!(stops.iter().zip(want).all(|(a, b)| (a - b).abs() < 1e-18), "{stops:?}");
    for t in [1.7e-6, 2.9e-6, 3.5e-6] {
        assert!((train.pressure(t) - train.pressure(t + 5e-6)).abs() < 1e-6);
    }
    assert_eq!(train.pressure(5e-6), 0.0);
}

/// Rescaling commutes with evaluation: p'(t/T) = p(t)/P.
#[test]
fn scaling() {
    let (tt, pp) = (2.5e-7, 3.0e4);
    let file = Waveform::File(Samples::new(vec![0.0, 1e-6, 4e-6], vec![1.0, 3e4, -1e4]).unwrap());
    for d in [tones(burst(Shape::Gaussian, Some(7e-6)), &[]), file] {
        let s = d.scaled(tt, pp);
        for i in 0..50 {
            let t = i as f64 * 1.9e-7;
            assert!((s.pressure(t / tt) - d.pressure(t) / pp).abs() < 1e-9, "{d:?} {t}");
            assert!((s.rate(t / tt) - d.rate(t) * tt / pp).abs() < 1e-6 * (1.0 + d.rate(t) * tt / pp).abs());
        }
        let st: Vec<f64> = d.stop_times(0.0, 1e-5).iter().map(|x| x / tt).collect();
        let ss = s.stop_times(0.0, 1e-5 / tt);
        assert_eq!(st.len(), ss.len());
        assert!(st.iter().zip(&ss).all(|(a, b)| (a - b).abs() < 1e-9 * a.abs()));
    }
}

#[test]
fn periodicity() {
    assert!(tones(None, &[]).periodic_omegas().is_ok());
    let e = tones(burst(Shape::Hann, None), &[]).periodic_omegas().unwrap_err().to_string();
    assert!(e.contains("hann") && e.contains("stability --method series"), "{e}");
}

/// On its piece, p_a at an edge is the piece's own limit: the burst's value at its end from
/// inside, zero at its start from before; a file's segment slope at its end knot. Decided from
/// t, the edge belongs to the next piece.
#[test]
fn a_piece_keeps_its_side_at_the_edges() {
    for (shape, period) in [(Shape::Rectangular, None), (Shape::Tukey(0.3), Some(5e-6)), (Shape::Gaussian, None)] {
        let d = tones(burst(shape, period), &[]);
        let (start, end) = (1e-6, 4e-6);
        let inside = 0.5 * (start + end);
        let left_limit = d.pressure_and_rate(end - 1e-15);
        let on = d.pressure_and_rate_on(end, inside);
        assert!((on.0 - left_limit.0).abs() < 1e-3 && (on.1 - left_limit.1).abs() < 1e-6 * 1e7 * 101325.0, "{shape:?}: {on:?} vs {left_limit:?}");
        assert_eq!(d.pressure_and_rate(end), if period.is_some() { d.pressure_and_rate(end) } else { (0.0, 0.0) });
        assert_eq!(d.pressure_and_rate_on(start, 0.5 * start), (0.0, 0.0));
        assert_eq!(d.pressure_and_rate_on(start, inside), d.pressure_and_rate(start));
        if shape == Shape::Rectangular {
            assert!(on.0.abs() > 1e3, "the rectangular burst is on at its end from inside");
        }
    }
    let s = Samples::new(vec![0.0, 1.0, 3.0], vec![0.0, 2.0, -2.0]).unwrap();
    assert_eq!(s.at_on(1.0, 0.5), (2.0, 2.0));
    assert_eq!(s.at_on(1.0, 2.0), (2.0, -2.0));
    assert_eq!(s.at_on(3.0, 2.0), (-2.0, -2.0));
    assert_eq!(s.at_on(3.0, 3.5), (0.0, 0.0));
}
