//! The SIMD policy (runtime/simd.rs): `MAGBUBBLE_PORTABLE=1` really selects the portable
//! kernels, a run gives the same bytes with either path, and no kernel probes the processor or
//! opens an `unsafe` block outside the policy's rules.

use magbubble::simd::{self, Kernel, Level};
use std::path::Path;
use std::process::Command;

/// The level this process runs at follows `MAGBUBBLE_PORTABLE` (the CI's portable pass sets it:
/// there every kernel must take its portable path).
#[test]
fn the_level_follows_the_environment() {
    let forced = matches!(std::env::var("MAGBUBBLE_PORTABLE").as_deref().map(str::trim), Ok("1") | Ok("all"));
    if forced {
        assert_eq!(simd::level(), Level::Portable);
        assert_eq!(simd::portable_kernels().len(), Kernel::ALL.len());
        for k in Kernel::ALL {
            assert!(!simd::avx(k) && !simd::avx512(k), "{} not portable under MAGBUBBLE_PORTABLE=1", k.name());
        }
        eprintln!("simd policy: MAGBUBBLE_PORTABLE=1, level {}", simd::level().name());
    } else if std::env::var_os("MAGBUBBLE_PORTABLE").is_none() {
        assert_eq!(simd::level(), simd::detected());
        assert!(simd::portable_kernels().is_empty());
        for k in Kernel::ALL {
            assert_eq!(simd::avx(k), simd::detected() >= Level::Avx2Fma, "{}", k.name());
        }
    }
}

/// A child process of this test binary with `MAGBUBBLE_PORTABLE=1` sees the portable level,
/// and one with a kernel list sees only those kernels portable (whatever this process has).
#[test]
fn the_switch_reaches_a_fresh_process() {
    let exe = std::env::current_exe().unwrap();
    for (value, want) in [("1", "portable:all"), ("expm,pair_rows", "level:expm,pair_rows")] {
        let out = Command::new(&exe)
            .args(["simd_policy::child_reports_the_policy", "--exact", "--nocapture", "--test-threads=1"])
            .env("MAGBUBBLE_PORTABLE", value)
            .env("MAGBUBBLE_SIMD_CHILD", "1")
            .output()
            .unwrap();
        let text = String::from_utf8_lossy(&out.stdout).to_string() + &String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{text}");
        let want = want.replace("level", simd::detected().name()).replace("all", &Kernel::ALL.map(|k| k.name()).join(","));
        assert!(text.contains(&format!("POLICY {want}\n")), "MAGBUBBLE_PORTABLE={value}: expected POLICY {want} in\n{text}");
    }
}

/// Prints the policy (only as the child of [`the_switch_reaches_a_fresh_process`]).
#[test]
fn child_reports_the_policy() {
    if std::env::var_os("MAGBUBBLE_SIMD_CHILD").is_none() {
        return;
    }
    let names: Vec<_> = simd::portable_kernels().iter().map(|k| k.name()).collect();
    println!("POLICY {}:{}", simd::level().name(), names.join(","));
}

/// Runs the CLI with `args` into `out`, with or without `MAGBUBBLE_PORTABLE=1`.
fn cli(args: &[&str], out: &Path, portable: bool) {
    let mut c = Command::new(env!("CARGO_BIN_EXE_magbubble"));
    c.current_dir(env!("CARGO_MANIFEST_DIR")).args(args).arg("--out").arg(out);
    if portable {
        c.env("MAGBUBBLE_PORTABLE", "1");
    } else {
        c.env_remove("MAGBUBBLE_PORTABLE");
    }
    let o = c.output().unwrap();
    assert!(o.status.success(), "{args:?}: {}", String::from_utf8_lossy(&o.stderr));
}

/// Every kernel is its portable form bit for bit, end to end: the runs that exercise them (the
/// quadratic fig-12 run: pair rows, frame sweep, the quadratic factors and Jacobians, both LUs,
/// Radau's loops; the monolithic vorticity run: every vorticity kernel; a stability curve: the
/// matrix exponential) write the same bytes with and without `MAGBUBBLE_PORTABLE=1`.
#[test]
fn runs_are_byte_identical_with_the_portable_kernels() {
    if !simd::test_can_run(Level::Avx2Fma, "SIMD runs against portable runs") {
        return;
    }
    let cases: [(&[&str], &str); 3] = [
        (&["run", "scenes/figures/fig12_chi.toml", "--set", "run.duration=20e-6", "--set", "drive.amplitude=0.2", "--set", "modes.coupling=\"quadratic\""], "series.csv"),
        (&["run", "scenes/no_field.toml", "--set", "drive.amplitude=0.2", "--set", "modes.viscous=vorticity", "--set", "run.duration=5e-6"], "series.csv"),
        (&["stability", "scenes/coil_static.toml", "--freq", "1e6:3e6:4", "--set", "modes.max_order=16", "--abs-tol", "1e-3"], "stability.csv"),
    ];
    for (args, file) in cases {
        let dir = tempfile::tempdir().unwrap();
        let (a, b) = (dir.path().join("simd"), dir.path().join("portable"));
        cli(args, &a, false);
        cli(args, &b, true);
        let (x, y) = (std::fs::read(a.join(file)).unwrap(), std::fs::read(b.join(file)).unwrap());
        assert!(!x.is_empty());
        assert!(x == y, "{args:?}: {file} differs between the SIMD and the portable kernels");
    }
}

/// The policy's rules hold in the source: only runtime/simd.rs probes the processor, and every
/// `unsafe` block or function carries its `SAFETY:` comment or `# Safety` section just above.
#[test]
fn the_source_keeps_the_policy() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("runtime");
    let mut files = Vec::new();
    let mut stack = vec![root.clone()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|x| x == "rs") {
                files.push(p);
            }
        }
    }
    assert!(files.len() > 50, "found {} files under {}", files.len(), root.display());
    let mut bad = Vec::new();
    for f in &files {
        let text = std::fs::read_to_string(f).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        let name = f.strip_prefix(&root).unwrap().display().to_string();
        for (i, l) in lines.iter().enumerate() {
            let code = l.split("//").next().unwrap_or("");
            if code.contains("is_x86_feature_detected") && name != "simd.rs" {
                bad.push(format!("{name}:{}: probes the CPU outside simd.rs", i + 1));
            }
            // a block or function; the comment within the 12 lines above (attributes and the
            // doc's # Safety section between)
            let opens = code.contains("unsafe {") || code.contains("unsafe fn ");
            if opens && !lines[i.saturating_sub(12)..=i].iter().any(|p| p.contains("SAFETY:") || p.contains("# Safety")) {
                bad.push(format!("{name}:{}: unsafe without a SAFETY comment", i + 1));
            }
        }
    }
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}
