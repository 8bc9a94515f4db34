//! Loading scenes: defaults (FORMULATION.md's table), `--set` overrides, the schema table.

use magbubble::scene::schema::{self, DefaultValue, Kind, SCHEMA};
use magbubble::scene::*;

const NO_SET: &[&str] = &[];

#[test]
fn empty_scene_takes_formulation_defaults() {
    let s = load_str("", "empty", NO_SET).unwrap();
    assert_eq!(s.bubble.radius, 10e-6);
    assert_eq!(s.bubble.initial.radius, s.bubble.radius);
    assert!(s.bubble.initial.a.is_empty() && s.bubble.initial.b.is_empty());
    assert_eq!(
        (
            s.shell.c1,
            s.shell.c2,
            s.shell.thickness,
            s.shell.susceptibility
        ),
        (0.1, 0.12, 20e-9, 1.0)
    );
    assert_eq!(s.shell.form, MembraneForm::Paper);
    assert_eq!(
        (s.gas.polytropic_exponent, s.gas.reference_pressure),
        (1.4, 101325.0)
    );
    assert_eq!(
        (
            s.liquid.density,
            s.liquid.viscosity,
            s.liquid.ambient_pressure
        ),
        (1000.0, 1e-3, 101325.0)
    );
    assert_eq!(s.drive, None);
    assert_eq!(s.field, None);
    assert_eq!(s.modes.max_order, 16);
    assert_eq!(s.modes.viscous, Viscous::BoundaryLayer);
    assert_eq!(
        s.modes.boundary_layer_frequency,
        BoundaryLayerFrequency::Auto
    );
    assert_eq!(
        (
            s.run.duration,
            s.run.sample_interval,
            s.run.blow_up_threshold
        ),
        (100e-6, 1e-8, 0.5)
    );
    assert_eq!(s.run.integrator.method, Method::Auto);
    assert!(!s.run.integrator.dt_given);
    assert_eq!((s.run.integrator.rtol, s.run.integrator.atol), (1e-6, 1e-9));
    assert_eq!(s.run.integrator.max_steps, 50_000_000);
    // dt = 1e-3 t*, t* = sqrt(rho R0^3/(2 c1)) = 2.236 µs for the defaults (FORMULATION audit 12: 2.2 ns).
    let t_star = (1000.0_f64 * 1e-15 / 0.2).sqrt();
    assert!((s.run.integrator.dt - 1e-3 * t_star).abs() < 1e-24);
    assert!((s.run.integrator.dt - 2.236e-9).abs() < 1e-12);
}

#[test]
fn same_as_defaults_follow_their_key() {
    let s = load_str(
        "[bubble]\nradius = 20e-6\n[liquid]\nambient_pressure = 2e5\n",
        "x",
        NO_SET,
    )
    .unwrap();
    assert_eq!(s.bubble.initial.radius, 20e-6);
    assert_eq!(s.gas.reference_pressure, 2e5);
}

#[test]
fn default_coil_angle_is_the_root_of_p1_4() {
    let x = (3.0_f64 / 7.0).sqrt();
    assert!((schema::DEFAULT_COIL_ANGLE - x.acos()).abs() < 1e-15);
    // P_4'(x) ∝ 35x^3 - 15x = 5x(7x^2 - 3): zero at x^2 = 3/7, so P^1_4(cos θc) = 0.
    let c = schema::DEFAULT_COIL_ANGLE.cos();
    assert!((35.0 * c.powi(3) - 15.0 * c).abs() < 1e-13);
}

#[test]
fn set_overrides_scalars_tables_and_strings() {
    let base = "[field.coil]\ncurrent = 100e3\n[drive]\namplitude = 0.5\n";
    let s = load_str(
        base,
        "x",
        &[
            "field.coil.current=150e3",
            "drive.amplitude=0.3",
            "modes.viscous=vorticity",
        ],
    )
    .unwrap();
    let Some(Field::Coil(c)) = &s.field else {
        panic!("coil expected")
    };
    assert_eq!(c.current, Current::Static { value: 150e3 });
    assert_eq!(s.drive.as_ref().unwrap().amplitude, 0.3);
    assert_eq!(s.modes.viscous, Viscous::Vorticity);

    let s = load_str(
        base,
        "x",
        &["field.coil.current={amplitude=150e3,frequency_hz=5e5}"],
    )
    .unwrap();
    let Some(Field::Coil(c)) = &s.field else {
        panic!("coil expected")
    };
    assert_eq!(
        c.current,
        Current::Cosine {
            amplitude: 150e3,
            frequency_hz: 5e5
        }
    );
    assert!((c.angle - schema::DEFAULT_COIL_ANGLE).abs() == 0.0);
    assert_eq!((c.turns, c.distance, c.include_h4), (1000.0, 0.1, false));

    // Creating sections that were absent, and mode entries.
    let s = load_str(
        "",
        "x",
        &[
            "field.dipole.moment=2",
            "bubble.initial.a.2=1e-8",
            "drive.amplitude=0.2",
        ],
    )
    .unwrap();
    assert_eq!(
        s.field,
        Some(Field::Dipole(Dipole {
            moment: 2.0,
            distance: 0.01
        }))
    );
    assert_eq!(s.bubble.initial.a.get(&2), Some(&1e-8));
    assert_eq!(
        s.drive,
        Some(Drive::cosine(0.2, 1e6))
    );
}

#[test]
fn zero_drive_amplitude_means_no_drive() {
    let s = load_str("[drive]\namplitude = 0.0\n", "x", NO_SET).unwrap();
    assert_eq!(s.drive, None);
}

#[test]
fn every_choice_value_loads_through_set() {
    for p in SCHEMA {
        if let Kind::Choice(options) = p.kind {
            for o in options {
                // a drive key needs the drive's required keys (a burst: its cycles)
                let mut set = vec![format!("{}={o}", p.key)];
                if p.key.starts_with("drive.") {
                    set.extend(["drive.amplitude=0.1".to_string(), "drive.cycles=3".to_string()]);
                    if *o == "continuous" {
                        set.pop();
                    }
                }
                // a population from a file needs the file (issue 33)
                if p.key == "population.distribution" && *o == "file" {
                    let csv = std::env::temp_dir().join(format!("magbubble-choice-{}.csv", std::process::id()));
                    std::fs::write(&csv, "radius,weight\n2e-6,1\n").unwrap();
                    set.push(format!("population.file=\"{}\"", csv.display()));
                }
                // a tension curve needs its file (issue 31)
                if *o == "tension-curve" {
                    let csv = std::env::temp_dir().join(format!("magbubble-curve-{}.csv", std::process::id()));
                    std::fs::write(&csv, "area_ratio,tension\n0.9,0\n1.0,0.02\n1.1,0.05\n").unwrap();
                    set.push(format!("shell.tension_file=\"{}\"", csv.display()));
                }
                // a Marmottant law needs its elasticity (issue 31: required, no default)
                let text = match *o {
                    o if o.starts_with("marmottant") || o == "sarkar" => "[shell]\nelasticity = 0.5\n",
                    // radial only (issue 31)
                    "church-hoff" => "[shell]\nmodulus = 5e7\n[modes]\nmax_order = 0\n",
                    // radial only (issue 31 part 2)
                    "reduced" => "[modes]\nmax_order = 0\n",
                    _ => "",
                };
                let scene = load_str(text, "x", &set);
                assert!(scene.is_ok(), "{}={o}: {:?}", p.key, scene.err());
            }
        }
    }
}

#[test]
fn schema_defaults_are_in_range_and_keys_are_unique() {
    for (i, p) in SCHEMA.iter().enumerate() {
        assert!(
            SCHEMA[..i].iter().all(|q| q.key != p.key),
            "duplicate key {}",
            p.key
        );
        if let Some((parent, _)) = p.key.rsplit_once('.') {
            assert!(
                schema::param(parent).is_some(),
                "{} has no parent entry",
                p.key
            );
        }
        match p.default {
            DefaultValue::Float(x) => {
                assert!(p.range.admits(x), "{} default {x} out of range", p.key)
            }
            DefaultValue::Int(x) => assert!(
                p.range.admits(x as f64),
                "{} default {x} out of range",
                p.key
            ),
            DefaultValue::Str(s) => assert!(
                matches!(p.kind, Kind::Choice(o) if o.contains(&s)),
                "{}",
                p.key
            ),
            DefaultValue::SameAs(k) => {
                assert!(schema::param(k).is_some(), "{} refers to {k}", p.key)
            }
            _ => {}
        }
    }
}
