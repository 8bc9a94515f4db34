//! `cargo run -p codegen -- --out DIR [--kmax N] [--derivations DIR]`: writes DIR/coefficients.rs
//! and DIR/coefficients.md (the readable table of every coefficient).

use std::path::PathBuf;
use std::process::ExitCode;

fn usage() -> ExitCode {
    eprintln!("usage: codegen --out DIR [--kmax N] [--derivations DIR]");
    ExitCode::from(2)
}

fn main() -> ExitCode {
    let mut out: Option<PathBuf> = None;
    let mut kmax = std::env::var("MAGBUBBLE_KMAX").ok().and_then(|v| v.parse().ok()).unwrap_or(codegen::DEFAULT_KMAX);
    let mut dir = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../derivations"));
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        match (a.as_str(), args.next()) {
            ("--out", Some(v)) => out = Some(v.into()),
            ("--derivations", Some(v)) => dir = v.into(),
            ("--kmax", Some(v)) => match v.parse() {
                Ok(n) => kmax = n,
                Err(_) => {
                    eprintln!("error: --kmax expects a non-negative integer, got `{v}`");
                    return usage();
                }
            },
            _ => return usage(),
        }
    }
    let Some(out) = out else { return usage() };
    let cfg = codegen::Config::new(dir, "derivations", kmax);
    let t = std::time::Instant::now();
    let generated = match codegen::generate(&cfg) {
        Ok(g) => g,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::FAILURE;
        }
    };
    let write = |name: &str, text: &str| -> Result<(), String> {
        std::fs::create_dir_all(&out).map_err(|e| format!("cannot create {}: {e}", out.display()))?;
        let p = out.join(name);
        std::fs::write(&p, text).map_err(|e| format!("cannot write {}: {e}", p.display()))
    };
    for (name, text) in [("coefficients.rs", &generated.rust), ("coefficients.md", &generated.markdown)] {
        if let Err(e) = write(name, text) {
            eprintln!("error: {e}");
            return ExitCode::FAILURE;
        }
    }
    eprintln!("wrote {}/coefficients.{{rs,md}} (KMAX = {kmax}) in {:.2?}", out.display(), t.elapsed());
    ExitCode::SUCCESS
}
