//! codegen — derives magbubble's coefficient tables from the physics specs in `derivations/`.
//!
//! Pipeline (one module per step): `spec::parse` (syn → AST, errors with file:line:column) →
//! `spec::validate` → `derive` (an exact interpreter over first-order dual numbers of
//! BigRational Laurent polynomials; the engine computes the force, the rotation, the area
//! factor, the linearization and the Galerkin projection) → `emit` (quote + prettyplease).
//! Contract of the output: `docs/architecture.md`.

pub mod algebra;
pub mod derive;
pub mod emit;
pub mod emit_quadratic;
pub mod emit_quadratic_membrane;
pub mod error;
pub mod spec;

pub use error::CodegenError;

use derive::field::FieldData;
use derive::membrane::Membrane;
use spec::validate::{validate, SpecKind};
use spec::Spec;
use std::path::{Path, PathBuf};

/// Default largest mode of the tables.
pub const DEFAULT_KMAX: usize = 64;

/// What to generate.
#[derive(Clone, Debug)]
pub struct Config {
    /// Directory of the specs: `kinematics.rs`, `membrane.rs`, and one `<field>.rs` per field table.
    pub derivations: PathBuf,
    /// Directory name shown in messages and in the header (e.g. `derivations`).
    pub display: String,
    /// Largest target mode k of the tables.
    pub kmax: usize,
}

impl Config {
    pub fn new(derivations: impl Into<PathBuf>, display: impl Into<String>, kmax: usize) -> Config {
        Config { derivations: derivations.into(), display: display.into(), kmax }
    }
}

/// The generated sources.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Generated {
    /// `coefficients.rs` (the runtime `include!`s it).
    pub rust: String,
    /// A readable table of every coefficient.
    pub markdown: String,
}

/// Everything derived, exact (before emission).
#[derive(Clone, Debug)]
pub struct Derived {
    pub kmax: usize,
    /// The spec paths, in the order read.
    pub specs: Vec<String>,
    pub fields: Vec<FieldData>,
    /// One per shell law of `derivations/shell/`, sorted by name.
    pub membranes: Vec<Membrane>,
    /// The quadratic coupling of a free bubble, when `quadratic.rs` exists.
    pub quadratic: Option<derive::quadratic::QuadraticData>,
    /// The second-order membrane loads of every law with a strain energy W, when `quadratic.rs`
    /// exists (derive/quadratic_membrane.rs).
    pub membrane_quadratic: Vec<derive::quadratic_membrane::MembraneQuadratic>,
}

/// Mechanics specs (not fields): the equilibrium of stresses, the stresses of a strain energy,
/// the loads of a shape energy.
pub const MECHANICS: [&str; 4] = ["kinematics.rs", "membrane.rs", "hyperelastic.rs", "shape.rs"];

/// The spec of the quadratic mode coupling (optional: no file, no quadratic table).
pub const QUADRATIC: &str = "quadratic.rs";

/// The directory of the shell laws, inside the derivations directory.
pub const LAWS_DIR: &str = "shell";

/// Read and parse one spec file.
pub fn read_spec(cfg: &Config, file: &str) -> Result<Spec, CodegenError> {
    let path = cfg.derivations.join(file);
    let text = std::fs::read_to_string(&path).map_err(|e| CodegenError::Io { path: path.display().to_string(), source: e })?;
    spec::parse::parse_spec(&format!("{}/{file}", cfg.display), &text)
}

/// The field spec files of a derivations directory (every `*.rs` but kinematics and membrane), sorted.
pub fn field_files(dir: &Path) -> Result<Vec<String>, CodegenError> {
    let rd = std::fs::read_dir(dir).map_err(|e| CodegenError::Io { path: dir.display().to_string(), source: e })?;
    let mut v: Vec<String> = rd
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".rs") && !MECHANICS.contains(&n.as_str()) && n != QUADRATIC)
        .collect();
    v.sort();
    Ok(v)
}

/// The shell-law files `shell/*.rs` (file names relative to the derivations directory), sorted;
/// none when the directory does not exist.
pub fn law_files(dir: &Path) -> Result<Vec<String>, CodegenError> {
    let d = dir.join(LAWS_DIR);
    if !d.is_dir() {
        return Ok(Vec::new());
    }
    let rd = std::fs::read_dir(&d).map_err(|e| CodegenError::Io { path: d.display().to_string(), source: e })?;
    let mut v: Vec<String> = rd
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".rs"))
        .map(|n| format!("{LAWS_DIR}/{n}"))
        .collect();
    v.sort();
    Ok(v)
}

/// Evaluate one shell law on the kinematics, then on its mechanics: a strain energy `W` goes
/// through `hyperelastic.rs` (σ_i = λ_i ∂W/∂λ_i) and `membrane.rs`; stresses `sigma1`, `sigma2`
/// through `membrane.rs`; a shape energy `w_area` through `shape.rs` (its first variation).
fn derive_law(cfg: &Config, file: &str, kin: &derive::eval::Env, cache: &mut Vec<(String, Spec)>) -> Result<Membrane, CodegenError> {
    let law = read_spec(cfg, file)?;
    validate(&law, SpecKind::Law, kin.defined())?;
    let mechanics: &[(&str, SpecKind)] = if law.get("W").is_some() {
        &[("hyperelastic.rs", SpecKind::Hyperelastic), ("membrane.rs", SpecKind::Membrane)]
    } else if law.get("w_area").is_some() {
        &[("shape.rs", SpecKind::Shape)]
    } else {
        &[("membrane.rs", SpecKind::Membrane)]
    };
    let mut env = derive::eval::eval_spec(&law, kin.clone())?;
    let mut specs = Vec::new();
    for (f, kind) in mechanics {
        if !cache.iter().any(|(n, _)| n == f) {
            cache.push((f.to_string(), read_spec(cfg, f)?));
        }
        let spec = cache.iter().find(|(n, _)| n == f).map(|(_, s)| s.clone()).expect("cached above");
        validate(&spec, *kind, env.defined())?;
        env = derive::eval::eval_spec(&spec, env)?;
        specs.push(spec);
    }
    let name = file.trim_start_matches(&format!("{LAWS_DIR}/")).trim_end_matches(".rs");
    let refs: Vec<&Spec> = specs.iter().collect();
    derive::membrane::derive_membrane(name, &law, &refs, &env)
}

/// Parse, validate and derive everything (exact).
pub fn derive(cfg: &Config) -> Result<Derived, CodegenError> {
    let kin_spec = read_spec(cfg, "kinematics.rs")?;
    validate(&kin_spec, SpecKind::Kinematics, &[])?;
    let mut field_specs = Vec::new();
    for file in field_files(&cfg.derivations)? {
        let s = read_spec(cfg, &file)?;
        validate(&s, SpecKind::Field, &[])?;
        field_specs.push((file.trim_end_matches(".rs").to_string(), s));
    }
    let kin = derive::eval::eval_spec(&kin_spec, derive::eval::kinematic_env())?;
    let mut specs = vec![kin_spec.path.clone()];
    let mut fields = Vec::new();
    for (name, s) in &field_specs {
        specs.push(s.path.clone());
        fields.push(derive::field::derive_field(name, &kin_spec, &kin, s, cfg.kmax)?);
    }
    let mut cache = Vec::new();
    let mut membranes = Vec::new();
    for file in law_files(&cfg.derivations)? {
        membranes.push(derive_law(cfg, &file, &kin, &mut cache)?);
    }
    for f in MECHANICS[1..].iter() {
        if let Some((_, s)) = cache.iter().find(|(n, _)| n == f) {
            specs.push(s.path.clone());
        }
    }
    specs.extend(membranes.iter().map(|m| m.spec_path.clone()));
    let quadratic = if cfg.derivations.join(QUADRATIC).is_file() {
        let s = read_spec(cfg, QUADRATIC)?;
        derive::quadratic::check_spec(&s)?;
        specs.push(s.path.clone());
        Some(derive::quadratic::derive_cached(&s.path).map_err(|m| CodegenError::Structure { spec: s.path.clone(), message: m })?)
    } else {
        None
    };
    let mut membrane_quadratic = Vec::new();
    if quadratic.is_some() {
        let (hyper, membrane, shape) = (read_spec(cfg, "hyperelastic.rs")?, read_spec(cfg, "membrane.rs")?, read_spec(cfg, "shape.rs")?);
        let specs = derive::quadratic_membrane::Mechanics { hyper: &hyper, membrane: &membrane, shape: &shape };
        // every law: a strain energy W, a shape energy w_area (bending) or stresses (viscous);
        // the W laws first, in file order, then the others (the tables of the W laws unchanged)
        let files = law_files(&cfg.derivations)?;
        let mut laws = Vec::new();
        for file in &files {
            laws.push((file, read_spec(cfg, file)?));
        }
        laws.sort_by_key(|(_, law)| law.get("W").is_none());
        for (file, law) in laws {
            let name = file.trim_start_matches(&format!("{LAWS_DIR}/")).trim_end_matches(".rs");
            let q = derive::quadratic_membrane::derive_membrane_quadratic(name, &law, specs, &kin_spec)
                .map_err(|m| CodegenError::Structure { spec: law.path.clone(), message: format!("second-order membrane loads: {m}") })?;
            membrane_quadratic.push(q);
        }
    }
    Ok(Derived { kmax: cfg.kmax, specs, fields, membranes, quadratic, membrane_quadratic })
}

/// Generate the Rust tables and the markdown review table.
pub fn generate(cfg: &Config) -> Result<Generated, CodegenError> {
    let d = derive(cfg)?;
    Ok(Generated { rust: emit::rust(&d)?, markdown: emit::markdown(&d) })
}
