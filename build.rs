//! Generates the coefficient tables from `derivations/` with `codegen` (see docs/architecture.md).
//! Writes `$OUT_DIR/coefficients.rs` only when its text changed; a malformed spec stops the build
//! with `path:line:column: message` and no panic backtrace.

use std::path::PathBuf;
use std::process::exit;

fn main() {
    println!("cargo:rerun-if-changed=derivations");
    println!("cargo:rerun-if-changed=codegen/src");
    println!("cargo:rerun-if-changed=codegen/Cargo.toml");
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-env-changed=MAGBUBBLE_KMAX");
    // The CLI as a position-dependent executable on Linux: a PIE binary has ~17,000 relative
    // relocations that the loader applies at every start (0.26 M instructions and ~70 page
    // faults of a one-step run's 1.6 M; issue 34, docs/performance.md "Radial runs against
    // APECSS"). The Python module (a cdylib) and the library stay position-independent.
    if std::env::var("CARGO_CFG_TARGET_OS").as_deref() == Ok("linux") {
        println!("cargo:rustc-link-arg-bins=-no-pie");
    }
    let kmax = match std::env::var("MAGBUBBLE_KMAX") {
        Err(_) => codegen::DEFAULT_KMAX,
        Ok(v) => match v.trim().parse::<usize>() {
            Ok(n) if n >= 2 => n,
            _ => fail(&format!("MAGBUBBLE_KMAX must be an integer >= 2, got `{v}`")),
        },
    };
    let Some(out_dir) = std::env::var_os("OUT_DIR").map(PathBuf::from) else { fail("OUT_DIR is not set") };
    let manifest = std::env::var_os("CARGO_MANIFEST_DIR").map(PathBuf::from).unwrap_or_default();
    let cfg = codegen::Config::new(manifest.join("derivations"), "derivations", kmax);
    let generated = match codegen::generate(&cfg) {
        Ok(g) => g,
        Err(e) => fail(&e.to_string()),
    };
    let target = out_dir.join("coefficients.rs");
    let unchanged = std::fs::read_to_string(&target).is_ok_and(|old| old == generated.rust);
    if !unchanged {
        if let Err(e) = std::fs::write(&target, &generated.rust) {
            fail(&format!("cannot write {}: {e}", target.display()));
        }
    }
}

fn fail(message: &str) -> ! {
    for line in message.lines() {
        println!("cargo:warning={line}");
    }
    eprintln!("error: {message}");
    exit(1)
}
