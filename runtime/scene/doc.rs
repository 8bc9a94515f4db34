//! Text rendered from the schema table: the commented default scene (`scene new`), the
//! parameter reference (`scene explain`, `docs/scenes.md`) and a human summary of a scene.

use super::schema::{self, fmt_num, DefaultValue as D, Kind, Param, SCHEMA};
use super::types::*;
use std::fmt::Write;

/// The value a default is written as in a scene file (`None`: no literal default).
fn literal(p: &Param) -> Option<String> {
    match p.default {
        D::Float(x) => Some(fmt_num(x)),
        D::Int(i) => Some(i.to_string()),
        D::Bool(b) => Some(b.to_string()),
        D::Str(s) => Some(format!("\"{s}\"")),
        D::Required { example } => Some(example.to_string()),
        D::Empty => Some("{}".into()),
        D::SameAs(k) => schema::param(k).and_then(literal),
        D::Derived(_) | D::Absent | D::Present => None,
    }
}

/// Symbol, unit, range and default rule in one line, for comments:
/// `c_1 = eps C_1 (sec 5.3) [N/m], > 0`.
fn facts(p: &Param) -> String {
    let mut head = p.symbol.to_string();
    if !p.unit.is_empty() {
        head = format!("{head} [{}]", p.unit).trim().to_string();
    }
    let mut parts = vec![head];
    let range = p.range.describe();
    if !range.is_empty() {
        parts.push(range);
    }
    if let Kind::Choice(options) = p.kind {
        parts.push(
            options
                .iter()
                .map(|o| format!("\"{o}\""))
                .collect::<Vec<_>>()
                .join(" | "),
        );
    }
    match p.default {
        D::SameAs(k) => parts.push(format!("default = {k}")),
        D::Derived(t) => parts.push(format!("default {t}")),
        _ => {}
    }
    parts.retain(|s| !s.is_empty());
    parts.join(", ")
}

/// Whether a section, or one of its ancestors, is off unless written (drive, field.*).
fn optional(section: &str) -> bool {
    let mut key = section;
    loop {
        if schema::param(key).is_some_and(|p| p.default == D::Absent) {
            return true;
        }
        match key.rsplit_once('.') {
            Some((parent, _)) => key = parent,
            None => return false,
        }
    }
}

/// `magbubble scene new`: a complete, commented scene with every default. Optional effects
/// (drive, coil, dipole) are written commented out with example values.
pub fn default_scene_toml() -> String {
    let mut out = String::new();
    out.push_str(
        "# magbubble scene: every key with its default (docs/model.md defaults, the paper's fig-12 shell).\n\
         # Units are SI. Delete what you do not change; `magbubble scene explain KEY` documents each key.\n\
         # Optional effects are commented out: uncomment [drive] and one of [field.coil] / [field.dipole].\n",
    );
    for section in SCHEMA.iter().filter(|p| p.kind == Kind::Section) {
        let keys: Vec<&Param> = schema::children(section.key)
            .filter(|p| p.kind != Kind::Section)
            .collect();
        let inline = section.key == "field.coil.distance_oscillation";
        if keys.is_empty() || inline {
            // `[field]` has only sub-sections; the oscillation is written as an inline key of [field.coil].
            continue;
        }
        let off = optional(section.key);
        let c = if off { "# " } else { "" };
        let _ = writeln!(out, "\n# {}", section.doc);
        let _ = writeln!(out, "{c}[{}]", section.key);
        for p in keys {
            let name = schema::leaf_name(p.key);
            let _ = writeln!(out, "# {}: {}", facts(p), p.doc);
            match literal(p) {
                Some(v) if !matches!(p.default, D::SameAs(_)) => {
                    let _ = writeln!(out, "{c}{name} = {v}");
                }
                Some(v) => {
                    let _ = writeln!(out, "# {name} = {v}");
                }
                // an optional section's key without a default: not a `# key = value` line (uncommenting
                // the block must give a valid scene)
                None if off => {
                    let _ = writeln!(out, "# {name}: optional, no default");
                }
                None => {
                    let _ = writeln!(out, "# {name} = ...");
                }
            }
            if p.key == "field.coil.include_h4" {
                let osc = "field.coil.distance_oscillation";
                let doc = schema::param(osc).map_or("", |p| p.doc);
                let _ = writeln!(out, "# {doc} Optional:");
                let _ = writeln!(
                    out,
                    "# distance_oscillation = {{ amplitude = 0.1, frequency_hz = 5e5 }}"
                );
            }
        }
    }
    out
}

/// `magbubble scene explain [KEY]`: the entries whose key is `key` or lies under it
/// (all when `key` is empty). `None` when nothing matches.
pub fn explain(key: &str) -> Option<String> {
    let matches: Vec<&Param> = SCHEMA
        .iter()
        .filter(|p| key.is_empty() || p.key == key || p.key.starts_with(&format!("{key}.")))
        .collect();
    if matches.is_empty() {
        return None;
    }
    let mut out = String::new();
    for p in matches {
        if p.kind == Kind::Section {
            let _ = writeln!(
                out,
                "[{}]  {}\n    {}\n",
                p.key,
                p.default.describe(),
                p.doc
            );
            continue;
        }
        let unit = if p.unit.is_empty() {
            "dimensionless".to_string()
        } else {
            p.unit.to_string()
        };
        let _ = writeln!(out, "{}  [{unit}]", p.key);
        let _ = writeln!(out, "    default: {}", p.default.describe());
        let range = match p.kind {
            Kind::Choice(o) => o
                .iter()
                .map(|o| format!("\"{o}\""))
                .collect::<Vec<_>>()
                .join(" | "),
            Kind::Bool => "true | false".into(),
            Kind::ModeMap => format!(
                "{{ k = value }}, k even, 2 <= k <= modes.max_order; values {}",
                p.range.describe()
            ),
            _ => p.range.describe(),
        };
        let _ = writeln!(out, "    allowed: {range}");
        if !p.symbol.is_empty() {
            let _ = writeln!(out, "    paper:   {}", p.symbol);
        }
        let _ = writeln!(out, "    {}\n", p.doc);
    }
    Some(out)
}

/// The body of `docs/scenes.md`: one table per section.
pub fn markdown_reference() -> String {
    let mut out = String::new();
    for section in SCHEMA.iter().filter(|p| p.kind == Kind::Section) {
        let _ = writeln!(
            out,
            "### `[{}]`\n\n{} ({})\n",
            section.key,
            section.doc,
            section.default.describe()
        );
        let keys: Vec<&Param> = schema::children(section.key)
            .filter(|p| p.kind != Kind::Section)
            .collect();
        if keys.is_empty() {
            continue;
        }
        out.push_str(
            "| key | unit | default | allowed | paper | description |\n|---|---|---|---|---|---|\n",
        );
        let mut rows: Vec<&Param> = Vec::new();
        for p in keys {
            rows.push(p);
            rows.extend(schema::children(p.key).filter(|c| c.kind != Kind::Section));
        }
        for p in rows {
            let allowed = match p.kind {
                Kind::Choice(o) => o
                    .iter()
                    .map(|o| format!("`\"{o}\"`"))
                    .collect::<Vec<_>>()
                    .join(", "),
                Kind::Bool => "`true`, `false`".into(),
                Kind::ModeMap => "even k in 2..=max_order".into(),
                _ => p.range.describe(),
            };
            let _ = writeln!(
                out,
                "| `{}` | {} | {} | {} | {} | {} |",
                p.key
                    .strip_prefix(&format!("{}.", section.key))
                    .unwrap_or(p.key),
                p.unit,
                p.default.describe().replace('|', "\\|"),
                allowed.replace('|', "\\|"),
                p.symbol,
                p.doc.replace('|', "\\|")
            );
        }
        out.push('\n');
    }
    out
}

/// A short human description of a resolved scene (`scene check`).
/// A choice as the scene file spells it (`"boundary-layer"`, `"radau5"`), not the Rust name.
fn spelled<T: serde::Serialize>(v: &T) -> String {
    match serde_json::to_value(v) {
        Ok(serde_json::Value::String(s)) => s,
        _ => "?".into(),
    }
}

pub fn summary(s: &Scene) -> String {
    let mut o = String::new();
    let i = &s.bubble.initial;
    let _ = writeln!(
        o,
        "bubble:    R0 = {} m, R(0) = {} m, dR/dt(0) = {} m/s",
        fmt_num(s.bubble.radius),
        fmt_num(i.radius),
        fmt_num(i.velocity)
    );
    for (name, map) in [("a", &i.a), ("da/dt", &i.a_velocity), ("b", &i.b)] {
        if !map.is_empty() {
            let list: Vec<String> = map
                .iter()
                .map(|(k, v)| format!("{k}: {}", fmt_num(*v)))
                .collect();
            let _ = writeln!(o, "           initial {name} = {{ {} }}", list.join(", "));
        }
    }
    let sh = &s.shell;
    let _ = writeln!(
        o,
        "shell:     c1 = {} N/m, c2 = {} N/m, eps = {} m, chi = {}, form \"{}\"",
        fmt_num(sh.c1),
        fmt_num(sh.c2),
        fmt_num(sh.thickness),
        fmt_num(sh.susceptibility),
        spelled(&sh.form)
    );
    let _ = writeln!(
        o,
        "gas:       kappa = {}, p_g0 = {} Pa",
        fmt_num(s.gas.polytropic_exponent),
        fmt_num(s.gas.reference_pressure)
    );
    let l = &s.liquid;
    let _ = writeln!(
        o,
        "liquid:    rho = {} kg/m^3, eta = {} Pa s, p0 = {} Pa",
        fmt_num(l.density),
        fmt_num(l.viscosity),
        fmt_num(l.ambient_pressure)
    );
    match &s.drive {
        Some(d) => {
            let _ = writeln!(
                o,
                "drive:     eps_p = {}, f_d = {} Hz",
                fmt_num(d.amplitude),
                fmt_num(d.frequency_hz)
            );
        }
        None => {
            let _ = writeln!(o, "drive:     none (p_inf = p0)");
        }
    }
    match &s.field {
        None => {
            let _ = writeln!(o, "field:     none");
        }
        Some(Field::Coil(c)) => {
            let current = match c.current {
                Current::Static { value } => format!("I = {} A (static)", fmt_num(value)),
                Current::Cosine {
                    amplitude,
                    frequency_hz,
                } => format!(
                    "I = {} A cos(2 pi {} Hz t)",
                    fmt_num(amplitude),
                    fmt_num(frequency_hz)
                ),
            };
            let _ = writeln!(
                o,
                "field:     coil, N1 = {}, a = {} m, theta_c = {} rad, {current}{}{}",
                fmt_num(c.turns),
                fmt_num(c.distance),
                schema::fmt_sig(c.angle),
                c.distance_oscillation
                    .as_ref()
                    .map_or(String::new(), |d| format!(
                        ", a(t) = a (1 + {} cos(2 pi {} Hz t))",
                        fmt_num(d.amplitude),
                        fmt_num(d.frequency_hz)
                    )),
                if c.include_h4 { ", with H_4" } else { "" }
            );
        }
        Some(Field::Dipole(d)) => {
            let _ = writeln!(
                o,
                "field:     dipole, M = {} A m^2, z = {} m",
                fmt_num(d.moment),
                fmt_num(d.distance)
            );
        }
    }
    let m = &s.modes;
    let _ = writeln!(
        o,
        "modes:     k = 2..{} ({} modes), viscous = \"{}\", boundary_layer_frequency = \"{}\"",
        m.max_order,
        m.count(),
        spelled(&m.viscous),
        spelled(&m.boundary_layer_frequency)
    );
    if m.coupling == super::Coupling::Quadratic {
        let _ = writeln!(
            o,
            "coupling:  quadratic (second-order mode coupling, viscous terms linear with this closure), stops out of the credible range at |a_k|/R0 > {}",
            fmt_num(m.credible_amplitude)
        );
    }
    if m.viscous == Viscous::Vorticity {
        let v = &s.vorticity;
        let _ = writeln!(
            o,
            "vorticity: y_max = {}, {} points, stretching {}, scheme \"{}\"",
            fmt_num(v.y_max),
            v.points,
            fmt_num(v.stretching),
            spelled(&v.scheme)
        );
    }
    let r = &s.run;
    let it = &r.integrator;
    let _ = writeln!(
        o,
        "run:       {} s, sampled every {} s ({} rows, about {} of series.csv), blow-up at |a_k|/R0 > {}",
        fmt_num(r.duration),
        fmt_num(r.sample_interval),
        super::output_estimate(s).0,
        super::human_bytes(super::output_estimate(s).1),
        fmt_num(r.blow_up_threshold)
    );
    let _ = writeln!(
        o,
        "           method \"{}\", rtol {}, atol {}, dt {} s, max {} steps",
        spelled(&it.method),
        fmt_num(it.rtol),
        fmt_num(it.atol),
        schema::fmt_sig(it.dt),
        it.max_steps
    );
    o
}
