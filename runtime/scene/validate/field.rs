//! `[field]` → [`Field`] (a coil or a dipole, docs/model.md §2) and `[vorticity]` →
//! [`VorticityGrid`] (the full model's grid).

use super::super::raw::*;
use super::super::schema::fmt_num;
use super::super::types::*;
use super::Check;

pub(super) fn build_field(c: &mut Check, raw: Option<RawField>, r0: f64) -> Option<Field> {
    let raw = raw?;
    if raw.coil.is_some() && raw.dipole.is_some() {
        c.push(
            "field",
            None,
            "give at most one of [field.coil] and [field.dipole]",
        );
    }
    if let Some(rc) = raw.coil {
        let current = match rc.current {
            None => {
                c.push(
                    "field.coil.current",
                    None,
                    "required when [field.coil] is present",
                );
                Current::Static { value: f64::NAN }
            }
            Some(RawCurrent::Static(value)) => {
                c.range("field.coil.current", value);
                Current::Static { value }
            }
            Some(RawCurrent::Cosine(o)) => Current::Cosine {
                amplitude: c.float("field.coil.current.amplitude", o.amplitude),
                frequency_hz: c.float("field.coil.current.frequency_hz", o.frequency_hz),
            },
        };
        let distance_oscillation = rc.distance_oscillation.map(|o| Oscillation {
            amplitude: c.float("field.coil.distance_oscillation.amplitude", o.amplitude),
            frequency_hz: c.float(
                "field.coil.distance_oscillation.frequency_hz",
                o.frequency_hz,
            ),
        });
        return Some(Field::Coil(Coil {
            turns: c.float("field.coil.turns", rc.turns),
            distance: c.float("field.coil.distance", rc.distance),
            angle: c.float("field.coil.angle", rc.angle),
            current,
            distance_oscillation,
            include_h4: c.bool("field.coil.include_h4", rc.include_h4),
        }));
    }
    if let Some(rd) = raw.dipole {
        let moment = c.float("field.dipole.moment", rd.moment);
        let distance = c.float("field.dipole.distance", rd.distance);
        if distance > 0.0 && r0 > 0.0 && distance <= r0 {
            c.push(
                "field.dipole.distance",
                Some(fmt_num(distance)),
                format!(
                    "must exceed bubble.radius = {} (the dipoles are outside the bubble)",
                    fmt_num(r0)
                ),
            );
        }
        return Some(Field::Dipole(Dipole { moment, distance }));
    }
    None
}

pub(super) fn build_vorticity(c: &mut Check, raw: Option<RawVorticity>) -> VorticityGrid {
    let rv = raw.unwrap_or_default();
    VorticityGrid {
        y_max: c.float("vorticity.y_max", rv.y_max),
        points: usize::try_from(c.int("vorticity.points", rv.points)).unwrap_or(0),
        stretching: c.float("vorticity.stretching", rv.stretching),
        scheme: match c.choice("vorticity.scheme", rv.scheme.as_deref()) {
            "staggered" => VorticityScheme::Staggered,
            "monolithic" => VorticityScheme::Monolithic,
            other => unreachable!("schema choice {other}"),
        },
    }
}
