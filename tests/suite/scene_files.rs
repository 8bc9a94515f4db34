//! Shipped scenes, `scene new` and `docs/scenes.md` against the schema table.

use magbubble::scene::{doc, load, load_str, Current, Field};
use std::path::Path;

const NO_SET: &[&str] = &[];

#[test]
fn every_shipped_scene_validates() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let mut names = Vec::new();
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") {
            if let Err(e) = load(&path, NO_SET) {
                panic!("{e}");
            }
            names.push(path.file_stem().unwrap().to_string_lossy().into_owned());
        }
    }
    names.sort();
    for required in [
        "coil_ac_current",
        "coil_oscillating_distance",
        "coil_static",
        "dipole",
        "no_field",
        "radial_only",
    ] {
        assert!(
            names.iter().any(|n| n == required),
            "scenes/{required}.toml missing"
        );
    }
}

#[test]
fn shipped_figure_scenes_carry_the_paper_parameters() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let s = load(root.join("coil_static.toml"), NO_SET).unwrap();
    assert_eq!(
        (
            s.bubble.radius,
            s.shell.c1,
            s.shell.c2,
            s.shell.thickness,
            s.shell.susceptibility
        ),
        (10e-6, 0.1, 0.12, 20e-9, 1.0)
    );
    let d = s.drive.unwrap();
    assert_eq!((d.amplitude, d.frequency_hz), (0.5, 1e6));
    let Some(Field::Coil(c)) = s.field else {
        panic!("coil")
    };
    assert_eq!(
        (c.turns, c.current.clone()),
        (1000.0, Current::Static { value: 100e3 })
    );
    assert_eq!(s.run.duration, 100e-6);

    let s = load(root.join("coil_ac_current.toml"), NO_SET).unwrap();
    let Some(Field::Coil(c)) = s.field else {
        panic!("coil")
    };
    assert_eq!(
        c.current,
        Current::Cosine {
            amplitude: 150e3,
            frequency_hz: 0.5e6
        }
    );

    let s = load(root.join("dipole.toml"), NO_SET).unwrap();
    assert_eq!(s.shell.susceptibility, 5.0);
    assert!(matches!(s.field, Some(Field::Dipole(ref d)) if d.moment == 1.0 && d.distance == 0.01));

    let s = load(root.join("radial_only.toml"), NO_SET).unwrap();
    assert_eq!(s.modes.max_order, 0);
}

#[test]
fn scene_new_is_valid_and_equals_the_defaults() {
    let text = doc::default_scene_toml();
    let from_new = load_str(&text, "scene new", NO_SET).unwrap_or_else(|e| panic!("{e}\n{text}"));
    assert_eq!(from_new, load_str("", "empty", NO_SET).unwrap());
}

/// Uncommenting an optional block of `scene new` gives a valid scene with that effect.
#[test]
fn scene_new_optional_blocks_are_valid_when_uncommented() {
    let text = doc::default_scene_toml();
    for (header, check) in [
        (
            "# [drive]",
            (|s: &magbubble::scene::Scene| s.drive.is_some()) as fn(&_) -> bool,
        ),
        (
            "# [field.coil]",
            |s| matches!(s.field, Some(Field::Coil(ref c)) if c.distance_oscillation.is_some()),
        ),
        ("# [field.dipole]", |s| {
            matches!(s.field, Some(Field::Dipole(_)))
        }),
    ] {
        let mut out = String::new();
        let mut inside = false;
        for line in text.lines() {
            if line.starts_with("# [") || line.starts_with('[') {
                inside = line == header;
            }
            // Inside the block, uncomment `# key = value` and `# [section]` lines, not the docs.
            let is_code = line.strip_prefix("# ").is_some_and(|l| {
                l.starts_with('[') || l.split_once(" = ").is_some_and(|(k, _)| !k.contains(' '))
            });
            if inside && is_code {
                out.push_str(&line[2..]);
            } else {
                out.push_str(line);
            }
            out.push('\n');
        }
        let scene = load_str(&out, header, NO_SET).unwrap_or_else(|e| panic!("{e}\n{out}"));
        assert!(check(&scene), "{header}");
    }
}

#[test]
fn explain_covers_keys_and_sections() {
    let one = doc::explain("shell.c1").unwrap();
    assert!(
        one.contains("shell.c1  [N/m]")
            && one.contains("default: 0.1")
            && one.contains("allowed: >= 0"),
        "{one}"
    );
    assert!(one.contains("c_1 = eps C_1"), "{one}");
    let section = doc::explain("run.integrator").unwrap();
    for k in ["method", "rtol", "atol", "dt", "max_steps"] {
        assert!(
            section.contains(&format!("run.integrator.{k}")),
            "{k}: {section}"
        );
    }
    assert!(doc::explain("shell.c").is_none());
}

/// `docs/scenes.md` holds the reference generated from the schema; regenerate it with
/// `MAGBUBBLE_BLESS=1 cargo test --test scene_files`.
#[test]
fn docs_scene_reference_is_generated_from_the_schema() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/scenes.md");
    let text = std::fs::read_to_string(&path).unwrap();
    let (begin, end) = (
        "<!-- BEGIN GENERATED: scene::doc::markdown_reference -->\n",
        "<!-- END GENERATED -->",
    );
    let start = text.find(begin).expect("begin marker") + begin.len();
    let stop = text.find(end).expect("end marker");
    let fresh = doc::markdown_reference();
    if std::env::var_os("MAGBUBBLE_BLESS").is_some() {
        std::fs::write(&path, format!("{}{fresh}{}", &text[..start], &text[stop..])).unwrap();
        return;
    }
    assert!(
        text[start..stop] == fresh,
        "docs/scenes.md is stale: run MAGBUBBLE_BLESS=1 cargo test --test scene_files"
    );
}
