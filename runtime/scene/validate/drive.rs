//! `[drive]` → [`Drive`] (docs/model.md, "Drives"): the envelope's keys only with a burst, a file
//! instead of the tones, the file read and checked here (so a bad file is refused before
//! anything is written).

use super::super::raw::{RawDrive, RawEcho};
use super::super::schema::fmt_num;
use super::super::types::*;
use super::Check;
use crate::drive::{Samples, Shape};
use std::path::PathBuf;

pub(super) fn build(c: &mut Check, raw: Option<RawDrive>) -> Option<Drive> {
    let d = raw?;
    let envelope = match c.choice("drive.envelope", d.envelope.as_deref()) {
        "continuous" => Envelope::Continuous,
        "rectangular" => Envelope::Rectangular,
        "hann" => Envelope::Hann,
        "gaussian" => Envelope::Gaussian,
        "tukey" => Envelope::Tukey,
        other => unreachable!("schema choice {other}"),
    };
    let name = d.envelope.clone().unwrap_or_else(|| "continuous".into());
    let file = d.file.as_ref().map(|path| {
        let scale = c.float("drive.file_scale", d.file_scale);
        let samples = match Samples::read(std::path::Path::new(path)) {
            Ok(s) => s,
            Err(reason) => {
                c.push("drive.file", Some(format!("\"{path}\"")), reason);
                Samples::new(vec![0.0, 1.0], vec![0.0, 0.0]).expect("two knots")
            }
        };
        DriveFile { path: PathBuf::from(path), scale, samples }
    });
    let amplitude = if file.is_some() {
        // a measured waveform replaces the tones: no key of theirs may be given
        let tone_keys = [
            ("drive.amplitude", d.amplitude.map(fmt_num)),
            ("drive.phase", d.phase.filter(|&p| p != 0.0).map(fmt_num)),
            ("drive.components", d.components.as_ref().filter(|v| !v.is_empty()).map(|v| format!("[{} tone(s)]", v.len()))),
            ("drive.envelope", d.envelope.as_ref().filter(|e| *e != "continuous").map(|e| format!("\"{e}\""))),
        ];
        for (key, v) in tone_keys {
            if let Some(v) = v {
                c.push(key, Some(v), "cannot be combined with drive.file (the file gives the whole acoustic pressure)");
            }
        }
        0.0
    } else {
        if let Some(s) = d.file_scale.filter(|&s| s != 1.0) {
            c.push("drive.file_scale", Some(fmt_num(s)), "does nothing without drive.file");
        }
        c.float("drive.amplitude", d.amplitude)
    };
    let frequency_hz = c.float("drive.frequency_hz", d.frequency_hz);
    let phase = c.float("drive.phase", d.phase);
    let delay = c.float("drive.delay", d.delay);
    let tukey_fraction = c.float("drive.tukey_fraction", d.tukey_fraction);
    let cycles = d.cycles.map(|v| {
        c.range("drive.cycles", v);
        v
    });
    let repeat_hz = d.repeat_hz.map(|v| {
        c.range("drive.repeat_hz", v);
        v
    });
    let components: Vec<Component> = d
        .components
        .unwrap_or_default()
        .into_iter()
        .map(|rc| Component {
            amplitude: c.float("drive.components.amplitude", rc.amplitude),
            frequency_hz: c.float("drive.components.frequency_hz", rc.frequency_hz),
            phase: c.float("drive.components.phase", rc.phase),
        })
        .collect();
    if envelope == Envelope::Continuous {
        for (key, v) in [("drive.cycles", d.cycles), ("drive.delay", d.delay.filter(|&t| t != 0.0)), ("drive.repeat_hz", d.repeat_hz)] {
            if let Some(v) = v {
                c.push(key, Some(fmt_num(v)), "does nothing with drive.envelope = \"continuous\" (choose a burst envelope)");
            }
        }
    } else if cycles.is_none() {
        c.push("drive.cycles", None, format!("required with drive.envelope = \"{name}\" (the burst length in periods of drive.frequency_hz)"));
    }
    // (a key at its default does nothing either way: `scene new` writes them all)
    if let (Some(v), false) = (d.tukey_fraction.filter(|&f| f != 0.5), envelope == Envelope::Tukey) {
        c.push("drive.tukey_fraction", Some(fmt_num(v)), format!("does nothing with drive.envelope = \"{name}\" (only \"tukey\" has a taper)"));
    }
    // a train: each burst must end before the next starts
    if let (Some(prf), Some(n)) = (repeat_hz, cycles) {
        let shape = if envelope == Envelope::Gaussian { Shape::Gaussian } else { Shape::Rectangular };
        let length = shape.length_in_periods(n) / frequency_hz;
        if prf > 0.0 && n > 0.0 && 1.0 / prf < length {
            c.push(
                "drive.repeat_hz",
                Some(fmt_num(prf)),
                format!("the period 1/repeat_hz = {} s is shorter than one burst ({} s): the bursts would overlap", fmt_num(1.0 / prf), fmt_num(length)),
            );
        }
    }
    let silent = amplitude == 0.0 && components.iter().all(|t| t.amplitude == 0.0) && file.is_none();
    (!silent).then_some(Drive { amplitude, frequency_hz, phase, envelope, cycles, delay, tukey_fraction, repeat_hz, components, file })
}

pub(super) fn build_echo(c: &mut Check, raw: Option<RawEcho>, bubble: &Bubble, run: &Run) -> Option<Echo> {
    let e = raw?;
    let distance = c.float("echo.distance", e.distance);
    let inside = bubble.radius.max(bubble.initial.radius);
    if distance.is_finite() && distance <= inside {
        c.push("echo.distance", Some(fmt_num(distance)), format!("the point is inside the bubble (R0 = {}, R(0) = {} m)", fmt_num(bubble.radius), fmt_num(bubble.initial.radius)));
    }
    let angles_deg = e.angles_deg.unwrap_or_else(|| vec![0.0]);
    if angles_deg.is_empty() {
        c.push("echo.angles_deg", Some("[]".into()), "give at least one angle");
    }
    for a in &angles_deg {
        if !(0.0..=180.0).contains(a) {
            c.push("echo.angles_deg", Some(fmt_num(*a)), "must be in [0, 180] degrees");
        }
    }
    let window = e.window.and_then(|w| {
        let shown = format!("[{}]", w.iter().map(|x| fmt_num(*x)).collect::<Vec<_>>().join(", "));
        match w[..] {
            [t0, t1] if t0 >= 0.0 && t0 < t1 && t1 <= run.duration => Some([t0, t1]),
            _ => {
                c.push("echo.window", Some(shown), format!("must be [t0, t1] with 0 <= t0 < t1 <= run.duration = {}", fmt_num(run.duration)));
                None
            }
        }
    });
    Some(Echo { distance, angles_deg, window })
}
