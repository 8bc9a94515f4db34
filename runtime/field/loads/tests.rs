//! Unit tests of [`super::MagneticLoads`].

use super::*;
use crate::scene::{Coil, Current, Field, MembraneForm, Oscillation, Shell};

fn source(current: Current, osc: Option<Oscillation>) -> FieldSource {
    let shell = Shell::mooney_rivlin(0.1, 0.12, 20e-9, 1.0, MembraneForm::Paper);
    let coil = Coil {
        turns: 1000.0,
        distance: 0.1,
        angle: (3.0f64 / 7.0).sqrt().acos(),
        current,
        distance_oscillation: osc,
        include_h4: false,
    };
    FieldSource::from_scene(&Field::Coil(coil), &shell, 10e-6).unwrap()
}

/// The odd rows read the tables at odd k: ∂M/∂(a, b)_{k+offset} = ℋ·R^(m−1)·value(k) for
/// every coupling of the coil table, nothing else, and no zero-order load.
#[test]
fn odd_rows_hold_the_table_values_at_odd_k() {
    let src = source(Current::Static { value: 1e5 }, None);
    let modes = 5; // k = 3, 5, 7, 9, 11
    let odd = MagneticLoads::odd(&src, modes, 10e-6, 2e4, 2.236e-6).unwrap();
    let lay = StateLayout::reduced(modes);
    let mut y = vec![0.0; lay.dim()];
    y[0] = 1.0;
    let f = odd.factors(0.0, 1.0);
    let c = &src.table.components[0];
    assert_eq!(src.table.components.len(), 1);
    let mut nonzero = 0;
    for m in 0..modes {
        let k = 2 * m + 3;
        assert_eq!((odd.normal(&f, m, &y), odd.tangential(&f, m, &y)), (0.0, 0.0), "k = {k}: unforced");
        for normal in [true, false] {
            let mut g = vec![0.0; y.len()];
            odd.add_row_gradient(&f, m + 1, &y, normal, 1.0, &mut g);
            let mut expected = vec![0.0; y.len()];
            for cp in c.couplings.iter().filter(|cp| (cp.load == Load::Normal) == normal) {
                let Some(v) = cp.at(k) else { continue };
                let s = k as i64 + cp.offset as i64;
                if (3..=2 * modes as i64 + 1).contains(&s) {
                    let source = (s as usize - 3) / 2;
                    let at = if cp.amp == Amp::B { lay.b(source) } else { lay.a(source) };
                    expected[at] += f.coupling[0] * v;
                }
            }
            for (i, (got, want)) in g.iter().zip(&expected).enumerate().skip(1) {
                assert!((got - want).abs() <= 1e-14 * want.abs().max(1e-300), "k = {k}, normal {normal}, index {i}: {got} vs {want}");
                nonzero += usize::from(*want != 0.0);
            }
        }
    }
    assert!(nonzero >= 3 * modes, "the couplings are there: {nonzero}");
}

/// The sliced row loop sums the same sources in the same order as the per-source iterator
/// (the gradient's), bit for bit, for the H2² coil (W = 1) and with H4 (W = 2), at every row.
#[test]
fn rows_match_the_source_iterator() {
    for include_h4 in [false, true] {
        let shell = Shell::mooney_rivlin(0.1, 0.12, 20e-9, 1.0, MembraneForm::Paper);
        let coil = Coil {
            turns: 1000.0,
            distance: 0.1,
            angle: 0.9,
            current: Current::Static { value: 1e5 },
            distance_oscillation: None,
            include_h4,
        };
        let src = FieldSource::from_scene(&Field::Coil(coil), &shell, 10e-6).unwrap();
        for modes in [1, 2, 3, 8] {
            let l = MagneticLoads::new(&src, modes, 10e-6, 2e4, 2.236e-6).unwrap();
            let y: Vec<f64> = (0..StateLayout::reduced(modes).dim()).map(|i| 1.0 + 0.37 * (i as f64 * 1.7).sin()).collect();
            let f = l.factors(0.0, y[0]);
            for row in 0..=modes {
                for normal in [true, false] {
                    let mut want = 0.0;
                    for (i, c) in l.comps.iter().enumerate() {
                        let (zero, band) = if normal { (&c.zero_n, &c.band_n) } else { (&c.zero_t, &c.band_t) };
                        let s: f64 = l.band_sources(row).map(|(j, m)| band[j] * y[l.layout().a(m)] + band[j + 1] * y[l.layout().b(m)]).sum();
                        want += f.zero[i] * zero[row] + f.coupling[i] * s;
                    }
                    let got = l.row(&f, row, &y, normal);
                    assert_eq!(got.to_bits(), want.to_bits(), "h4 {include_h4}, modes {modes}, row {row}, normal {normal}");
                }
            }
            let (mut p, mut gn, mut gt) = (0.25, vec![0.5; modes], vec![-0.5; modes]);
            l.add_to_balances(&f, &y, &mut p, &mut gn, &mut gt);
            assert_eq!(p.to_bits(), (0.25 + l.radial(&f, &y)).to_bits());
            for m in 0..modes {
                assert_eq!(gn[m].to_bits(), (0.5 - l.normal(&f, m, &y)).to_bits(), "gn {m}");
                assert_eq!(gt[m].to_bits(), (-0.5 - l.tangential(&f, m, &y)).to_bits(), "gt {m}");
            }
        }
    }
}

#[test]
fn time_factors_follow_current_and_distance() {
    let (r0, pu, ts) = (10e-6, 2e4, 2.236e-6);
    let st = MagneticLoads::new(&source(Current::Static { value: 1e5 }, None), 2, r0, pu, ts).unwrap();
    let ac = MagneticLoads::new(
        &source(Current::Cosine { amplitude: 1e5, frequency_hz: 5e5 }, None),
        2,
        r0,
        pu,
        ts,
    )
    .unwrap();
    let osc = MagneticLoads::new(
        &source(Current::Static { value: 1e5 }, Some(Oscillation { amplitude: 0.1, frequency_hz: 2e5 })),
        2,
        r0,
        pu,
        ts,
    )
    .unwrap();
    assert!(st.is_static() && !ac.is_static() && !osc.is_static());
    let mut y = vec![1.01, 0.0, 1e-3, 0.0, 2e-4, -5e-4, 0.0, 1e-4];
    y[0] = 1.01;
    let t = 0.37; // nondimensional
    let fs = st.factors(t, y[0]);
    let (fa, fo) = (ac.factors(t, y[0]), osc.factors(t, y[0]));
    let c = (2.0 * std::f64::consts::PI * 5e5 * ts * t).cos();
    let d = 1.0 + 0.1 * (2.0 * std::f64::consts::PI * 2e5 * ts * t).cos();
    for m in 0..2 {
        let (n, tn) = (st.normal(&fs, m, &y), st.tangential(&fs, m, &y));
        assert!(n != 0.0 && tn != 0.0);
        // ℋ ∝ H2²/a² ∝ I²/a⁴ (eq 2.31 and the coil prefactor)
        assert!((ac.normal(&fa, m, &y) / n - c * c).abs() < 1e-12);
        assert!((ac.tangential(&fa, m, &y) / tn - c * c).abs() < 1e-12);
        assert!((osc.normal(&fo, m, &y) / n - d.powi(-4)).abs() < 1e-12);
    }
    assert!((ac.radial(&fa, &y) / st.radial(&fs, &y) - c * c).abs() < 1e-12);
    assert_eq!(st.evaluations(), 1);
}
