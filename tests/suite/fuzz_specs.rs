//! Issue 15 "fuzzing": the derivation-spec parser and deriver (codegen) on random edits of the
//! shipped specs (derivations/*.rs, derivations/shell/*.rs) give a result or a
//! `path:line:column` error, never a panic. proptest, like fuzz_inputs.rs; failures persist in
//! tests/suite/proptest-regressions/fuzz_specs.txt (committed).
//!
//! * parser: every shipped spec, edited (bytes deleted, tokens inserted or replaced, lines
//!   dropped, duplicated or swapped), through `parse_spec` and, for the kinds that need no outer
//!   spec, `validate`;
//! * deriver: a copy of derivations/ with one file edited, through `codegen::derive` (kmax 4).

use codegen::spec::parse::parse_spec;
use codegen::spec::validate::{validate, SpecKind};
use proptest::prelude::*;
use proptest::sample::Index;
use proptest::test_runner::FileFailurePersistence;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};

const REGRESSIONS: &str = "tests/suite/proptest-regressions/fuzz_specs.txt";

fn config(cases: u32) -> ProptestConfig {
    ProptestConfig {
        // PROPTEST_CASES=N runs a longer hunt (docs/robustness.md gives the last one).
        cases: std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(cases),
        failure_persistence: Some(Box::new(FileFailurePersistence::Direct(REGRESSIONS))),
        ..ProptestConfig::default()
    }
}

fn derivations() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("derivations")
}

/// (path relative to derivations/, text) of every shipped spec, sorted.
fn specs() -> Vec<(String, String)> {
    let mut v = Vec::new();
    for sub in ["", "shell"] {
        for e in std::fs::read_dir(derivations().join(sub)).unwrap().flatten() {
            if e.path().extension().is_some_and(|x| x == "rs") {
                let rel = if sub.is_empty() { e.file_name().to_string_lossy().into_owned() } else { format!("{sub}/{}", e.file_name().to_string_lossy()) };
                v.push((rel, std::fs::read_to_string(e.path()).unwrap()));
            }
        }
    }
    v.sort();
    v
}

/// Tokens a spec writer might mistype or a fuzzer might find: operators, delimiters, keywords,
/// the built-in names, unknown names, odd numbers and calls.
const TOKENS: [&str; 40] = [
    "+", "-", "*", "/", "(", ")", "[", "]", "{", "}", ";", ",", ".", "=", "let ", "let x = 1;", "'", "\"", "#", "//",
    ".powi(", ".powi(3)", ".powi(-7)", ".powi(40)", ".powi(2147483647)", ".sqrt()", ".sin()", "sqrt(", "d(", "diff(R, Theta)",
    "P(k)", "P1(", "vary(", "rate(", "0", "1/0", "0.0", "1e400", "R", "k",
];

#[derive(Clone, Debug)]
enum Edit {
    Delete(Index, usize),
    Insert(Index, usize),
    Replace(Index, usize, usize),
    DropLine(Index),
    DupLine(Index),
    SwapLines(Index, Index),
}

fn edit() -> impl Strategy<Value = Edit> {
    prop_oneof![
        3 => (any::<Index>(), 1usize..8).prop_map(|(i, n)| Edit::Delete(i, n)),
        4 => (any::<Index>(), 0..TOKENS.len()).prop_map(|(i, t)| Edit::Insert(i, t)),
        3 => (any::<Index>(), 1usize..6, 0..TOKENS.len()).prop_map(|(i, n, t)| Edit::Replace(i, n, t)),
        1 => any::<Index>().prop_map(Edit::DropLine),
        1 => any::<Index>().prop_map(Edit::DupLine),
        1 => (any::<Index>(), any::<Index>()).prop_map(|(i, j)| Edit::SwapLines(i, j)),
    ]
}

/// The char boundary at or before byte `i`.
fn floor(s: &str, mut i: usize) -> usize {
    i = i.min(s.len());
    while !s.is_char_boundary(i) {
        i -= 1;
    }
    i
}

fn apply(text: &str, edits: &[Edit]) -> String {
    let mut s = text.to_string();
    for e in edits {
        match e {
            Edit::Delete(i, n) | Edit::Replace(i, n, _) => {
                let a = floor(&s, i.index(s.len() + 1));
                let b = floor(&s, a + n);
                let with = if let Edit::Replace(_, _, t) = e { TOKENS[*t] } else { "" };
                s.replace_range(a..b, with);
            }
            Edit::Insert(i, t) => {
                let a = floor(&s, i.index(s.len() + 1));
                s.insert_str(a, TOKENS[*t]);
            }
            Edit::DropLine(i) | Edit::DupLine(i) => {
                let mut lines: Vec<&str> = s.lines().collect();
                if !lines.is_empty() {
                    let k = i.index(lines.len());
                    if matches!(e, Edit::DropLine(_)) {
                        lines.remove(k);
                    } else {
                        lines.insert(k, lines[k]);
                    }
                }
                s = lines.join("\n");
            }
            Edit::SwapLines(i, j) => {
                let mut lines: Vec<&str> = s.lines().collect();
                if !lines.is_empty() {
                    let (a, b) = (i.index(lines.len()), j.index(lines.len()));
                    lines.swap(a, b);
                }
                s = lines.join("\n");
            }
        }
    }
    s
}

/// The kind `validate` needs for a spec that has no outer spec (None: it needs one, or is the
/// quadratic spec, which the deriver checks).
fn standalone_kind(rel: &str) -> Option<SpecKind> {
    match rel {
        "kinematics.rs" => Some(SpecKind::Kinematics),
        "membrane.rs" | "hyperelastic.rs" | "shape.rs" | "quadratic.rs" => None,
        r if r.starts_with("shell/") => None,
        _ => Some(SpecKind::Field),
    }
}

proptest! {
    #![proptest_config(config(200))]

    #[test]
    fn edited_specs_parse_to_a_spec_or_an_error(file in any::<Index>(), edits in prop::collection::vec(edit(), 1..5)) {
        let all = specs();
        let (rel, text) = &all[file.index(all.len())];
        let edited = apply(text, &edits);
        let path = format!("derivations/{rel}");
        let r = catch_unwind(AssertUnwindSafe(|| {
            if let Ok(spec) = parse_spec(&path, &edited) {
                if let Some(kind) = standalone_kind(rel) {
                    let _ = validate(&spec, kind, &[]);
                }
            }
        }));
        prop_assert!(r.is_ok(), "parse/validate panicked on {rel} edited to:\n{edited}");
    }
}

proptest! {
    #![proptest_config(config(24))]

    #[test]
    fn edited_derivations_derive_or_fail_with_an_error(file in any::<Index>(), edits in prop::collection::vec(edit(), 1..4)) {
        let all = specs();
        let k = file.index(all.len());
        let dir = tempfile::tempdir().unwrap();
        std::fs::create_dir(dir.path().join("shell")).unwrap();
        for (i, (rel, text)) in all.iter().enumerate() {
            let t = if i == k { apply(text, &edits) } else { text.clone() };
            std::fs::write(dir.path().join(rel), t).unwrap();
        }
        let cfg = codegen::Config::new(dir.path(), "derivations", 4);
        let r = catch_unwind(AssertUnwindSafe(|| codegen::derive(&cfg).map(|_| ()).map_err(|e| e.to_string())));
        match r {
            Err(_) => prop_assert!(false, "derive panicked with {} edited to:\n{}", all[k].0, std::fs::read_to_string(dir.path().join(&all[k].0)).unwrap()),
            Ok(Err(msg)) => prop_assert!(!msg.is_empty()),
            Ok(Ok(())) => {}
        }
    }
}

/// A huge `.powi(n)` is refused by validation (it would multiply a polynomial n times).
#[test]
fn a_huge_power_is_an_error_not_a_hang() {
    let text = "let symbols = [mu0, chi_s, G];\nlet amplitudes = [G];\nlet h_r = (G * r + 1).powi(2147483647);\n\
                let h_theta = G;\nlet susceptibility = mu0 * chi_s;\nlet unit = 1;\n";
    let spec = parse_spec("derivations/big.rs", text).unwrap();
    let e = validate(&spec, SpecKind::Field, &[]).unwrap_err().to_string();
    assert!(e.starts_with("derivations/big.rs:3:"), "{e}");
    assert!(e.contains("powi"), "{e}");
}
