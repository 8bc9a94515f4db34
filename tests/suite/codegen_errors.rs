//! Each kind of malformed spec stops generation with `path:line:column: message`.

use std::path::Path;

/// Run codegen on the fixture kinematics + mechanics + one shell law and one field spec with text `field`.
fn error_for(field: &str) -> String {
    let dir = tempfile::tempdir().expect("tempdir");
    let spec = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden/spec");
    std::fs::create_dir(dir.path().join("shell")).expect("mkdir");
    for f in ["kinematics.rs", "membrane.rs", "hyperelastic.rs", "shell/neo_hookean.rs"] {
        std::fs::copy(spec.join(f), dir.path().join(f)).expect("copy spec");
    }
    std::fs::write(dir.path().join("bad.rs"), field).expect("write spec");
    let cfg = codegen::Config::new(dir.path(), "derivations", 4);
    match codegen::generate(&cfg) {
        Ok(_) => panic!("a malformed spec generated code"),
        Err(e) => e.to_string(),
    }
}

const HEAD: &str = "let symbols = [mu0, chi_s, G];\nlet amplitudes = [G];\n";
const TAIL: &str = "let susceptibility = mu0 * chi_s;\nlet unit = 1;\n";

fn field(body: &str) -> String {
    format!("{HEAD}{body}{TAIL}")
}

#[test]
fn syntax_error_points_at_the_token() {
    let e = error_for(&field("let h_r = G * r *;\nlet h_theta = G;\n"));
    assert!(e.starts_with("derivations/bad.rs:3:"), "{e}");
    assert!(e.contains("expected"), "{e}");
}

#[test]
fn missing_semicolon_is_a_syntax_error() {
    let e = error_for(&field("let h_r = G * r\nlet h_theta = G;\n"));
    assert!(e.starts_with("derivations/bad.rs:4:1: "), "{e}");
    assert!(e.contains("expected `;`"), "{e}");
}

#[test]
fn unknown_symbol_is_named() {
    let e = error_for(&field("let h_r = G * r * Q;\nlet h_theta = G;\n"));
    assert!(e.starts_with("derivations/bad.rs:3:19: unknown symbol `Q`"), "{e}");
}

#[test]
fn unsupported_construct_is_named() {
    let e = error_for(&field("let h_r = if r { G } else { G };\nlet h_theta = G;\n"));
    assert!(e.starts_with("derivations/bad.rs:3:11: unsupported construct `if`"), "{e}");
}

#[test]
fn unsupported_operator_is_named() {
    let e = error_for(&field("let h_r = G % r;\nlet h_theta = G;\n"));
    assert!(e.starts_with("derivations/bad.rs:3:13: unsupported operator: expected one of `+ - * /`"), "{e}");
}

#[test]
fn unsupported_function_is_named() {
    let e = error_for(&field("let h_r = exp(r);\nlet h_theta = G;\n"));
    assert!(e.starts_with("derivations/bad.rs:3:11: unsupported function `exp`"), "{e}");
}

#[test]
fn non_integer_power_is_rejected() {
    let e = error_for(&field("let h_r = r.powi(G);\nlet h_theta = G;\n"));
    assert!(e.starts_with("derivations/bad.rs:3:18: expected an integer literal in `.powi(n)`"), "{e}");
}

#[test]
fn non_let_statement_is_rejected() {
    let e = error_for(&field("fn f() {}\nlet h_r = G;\nlet h_theta = G;\n"));
    assert!(e.starts_with("derivations/bad.rs:3:1: expected `let NAME = expression;`"), "{e}");
}

#[test]
fn missing_definition_is_named() {
    let e = error_for(&field("let h_r = G * r;\n"));
    assert!(e.contains("derivations/bad.rs:1:1: missing `let h_theta = …;` (required in a field spec)"), "{e}");
}

#[test]
fn redefinition_is_rejected() {
    let e = error_for(&field("let h_r = G * r;\nlet h_r = G;\nlet h_theta = G;\n"));
    assert!(e.starts_with("derivations/bad.rs:4:5: `h_r` is already defined"), "{e}");
}

#[test]
fn a_non_invertible_division_is_located() {
    let e = error_for(&field("let h_r = G / (r + G);\nlet h_theta = G;\n"));
    assert!(e.starts_with("derivations/bad.rs:3:11: cannot divide by it"), "{e}");
}

#[test]
fn missing_final_semicolon_points_at_the_end_of_the_file() {
    let e = error_for(&format!("{HEAD}let h_r = G;\nlet h_theta = G;\nlet susceptibility = mu0 * chi_s;\nlet unit = 1"));
    assert!(e.starts_with("derivations/bad.rs:6:13: expected"), "{e}");
}

#[test]
fn unclosed_parenthesis_is_a_syntax_error() {
    let e = error_for(&field("let h_r = (G * r;\nlet h_theta = G;\n"));
    assert!(e.starts_with("derivations/bad.rs:3:"), "{e}");
}

#[test]
fn first_line_columns_are_exact() {
    let e = error_for("let symbols = [mu0, chi_s, Q2 + 1];\n");
    assert!(e.starts_with("derivations/bad.rs:1:28: expected a symbol name"), "{e}");
}
