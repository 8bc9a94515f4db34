//! Cost snapshots: every shipped scene (scenes/*.toml, shortened so the test stays fast) and the
//! full model of `no_field` in both schemes are run, and the work of the integrator (steps,
//! rejected steps, rhs evaluations, Jacobian evaluations, LU factorisations) and the status are
//! compared with tests/golden/cost.txt. A change of work shows as a diff of that file; bless a
//! reviewed one with `UPDATE_GOLDEN=1 cargo test --release --test suite -- cost_snapshots`.

use magbubble::model::{simulate, RunStatus};
use magbubble::scene;
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The runs: (scene file, overrides).
fn workloads() -> Vec<(String, Vec<String>)> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(root().join("scenes"))
        .expect("scenes/")
        .map(|e| e.expect("dir entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    assert!(files.len() >= 7, "shipped scenes: {files:?}");
    let short = |d: &str| vec![format!("run.duration={d}")];
    let mut out: Vec<(String, Vec<String>)> =
        files.iter().map(|p| (p.file_name().unwrap().to_string_lossy().into_owned(), short("20e-6"))).collect();
    for scheme in ["monolithic", "staggered"] {
        let mut o = short("5e-6");
        o.extend(["drive.amplitude=0.2".into(), "modes.viscous=vorticity".into(), format!("vorticity.scheme={scheme}")]);
        if scheme == "staggered" {
            o.push("run.integrator.dt=2e-9".into());
        }
        out.push(("no_field.toml".into(), o));
    }
    out
}

fn line(file: &str, overrides: &[String]) -> String {
    let s = scene::load(root().join("scenes").join(file), overrides).unwrap_or_else(|e| panic!("{file}: {e}"));
    let report = simulate(&s, &mut |_, _| {}).unwrap_or_else(|e| panic!("{file}: {e}"));
    let st = report.stats;
    let status = match &report.status {
        RunStatus::Completed => "completed".to_string(),
        RunStatus::BlowUp { t, mode } => format!("blow_up({mode} at {:.4e} s)", t),
        RunStatus::Failed { reason } => format!("failed({reason})"),
        RunStatus::OutOfCredibleRange { t, mode, .. } => format!("out_of_credible_range({mode} at {:.4e} s)", t),
    };
    format!(
        "{file} [{}]: {status}; steps {} rejected {} rhs {} jacobians {} lu {}",
        overrides.join(" "),
        st.steps,
        st.rejected,
        st.rhs_evals,
        st.jac_evals,
        st.lu_decompositions
    )
}

#[test]
fn work_of_the_shipped_scenes_matches_the_snapshot() {
    let mut text = String::from("# Integrator work per shipped scene (tests/suite/cost_snapshots.rs; bless with UPDATE_GOLDEN=1).\n");
    for (file, overrides) in workloads() {
        text.push_str(&line(&file, &overrides));
        text.push('\n');
    }
    let path = root().join("tests/golden/cost.txt");
    check(&path, &text);
}

fn check(path: &Path, actual: &str) {
    if std::env::var_os("UPDATE_GOLDEN").is_some() {
        std::fs::write(path, actual).expect("write the cost snapshot");
        return;
    }
    let expected = std::fs::read_to_string(path).unwrap_or_default();
    let diff: Vec<String> = expected
        .lines()
        .zip(actual.lines())
        .filter(|(a, b)| a != b)
        .map(|(a, b)| format!("- {a}\n+ {b}"))
        .collect();
    assert!(
        expected == actual,
        "{} differs from the measured work (bless with UPDATE_GOLDEN=1 after review):\n{}{}",
        path.display(),
        diff.join("\n"),
        if expected.lines().count() != actual.lines().count() { "\n(line counts differ)" } else { "" }
    );
}
