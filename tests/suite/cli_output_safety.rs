//! Issue 29 items 3, 8, 9: an output directory is one process's at a time (the second gets an
//! error naming the owner, the first's files survive); nothing temporary survives a write error
//! (a full disk, simulated by a file-size limit); a run without --plot leaves no old plot.
use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

fn magbubble() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_magbubble"));
    c.current_dir(env!("CARGO_MANIFEST_DIR"));
    c
}

fn files(dir: &Path) -> Vec<PathBuf> {
    let mut v = Vec::new();
    for e in std::fs::read_dir(dir).into_iter().flatten().flatten() {
        let p = e.path();
        if p.is_dir() {
            v.extend(files(&p));
        }
        v.push(p);
    }
    v
}

/// Waits until `dir` holds the lock's note (the owner started writing).
fn wait_for_lock(dir: &Path, child: &mut std::process::Child) {
    let start = Instant::now();
    while !dir.join(magbubble::output::LOCK_FILE).exists() {
        assert!(child.try_wait().unwrap().is_none(), "the first process ended before it took the lock");
        assert!(start.elapsed() < Duration::from_secs(60), "no lock after 60 s");
        std::thread::sleep(Duration::from_millis(5));
    }
}

#[test]
fn a_second_process_cannot_write_into_an_owned_directory() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("D");
    // a run long enough to still hold D while the second starts
    let mut first = magbubble()
        .args(["run", "scenes/no_field.toml", "--set", "run.duration=300e-6", "--out"])
        .arg(&out)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    wait_for_lock(&out, &mut first);
    for second in [
        vec!["run", "scenes/coil_static.toml", "--set", "drive.amplitude=0.3", "--out"],
        vec!["sweep", "scenes/radial_only.toml", "--grid", "drive.amplitude=0.1,0.2", "--set", "run.duration=1e-6", "--out"],
        vec!["stability", "scenes/no_field.toml", "--freq", "1e6", "--set", "modes.max_order=2", "--out"],
    ] {
        let o = magbubble().args(&second).arg(&out).output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{second:?} wrote into an owned directory: {err}");
        assert!(err.contains("in use by another process") && err.contains(&format!("pid {}", first.id())), "{second:?}: {err}");
    }
    let o = first.wait_with_output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // every file the first reported is there, and nothing of the others
    for f in ["series.csv", "summary.json"] {
        assert!(out.join(f).exists(), "{f} missing");
    }
    let left: Vec<PathBuf> = files(&out);
    assert_eq!(left.len(), 2, "{left:?}");
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(summary.contains("no_field.toml"), "the summary is another run's");
    // released: a later process may write
    let o = magbubble().args(["run", "scenes/radial_only.toml", "--set", "run.duration=1e-6", "--out"]).arg(&out).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

/// Runs `cmd` with writes limited to `bytes` per file (EFBIG, as a full disk gives ENOSPC).
fn with_file_limit(mut cmd: Command, bytes: u64) -> std::process::Output {
    // SAFETY: only async-signal-safe calls (setrlimit, signal) between fork and exec.
    unsafe {
        cmd.pre_exec(move || {
            let lim = libc::rlimit { rlim_cur: bytes, rlim_max: bytes };
            libc::setrlimit(libc::RLIMIT_FSIZE, &lim);
            libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
            Ok(())
        });
    }
    cmd.output().unwrap()
}

#[test]
fn a_write_error_leaves_nothing_temporary() {
    let tmp = tempfile::tempdir().unwrap();
    // run: series.csv of ~2.5 MB against a 64 kB limit
    let out = tmp.path().join("run");
    let mut cmd = magbubble();
    cmd.args(["run", "scenes/no_field.toml", "--set", "modes.max_order=4", "--set", "run.duration=20e-6", "--out"]).arg(&out);
    let o = with_file_limit(cmd, 64 << 10);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "a run whose series cannot be written succeeded");
    assert!(err.contains("series.csv"), "{err}");
    let left = files(&out);
    assert!(left.iter().all(|p| !p.file_name().unwrap().to_string_lossy().contains(".tmp")), "temporary files left: {left:?}");
    // sweep --keep-series: every series.csv beyond the limit fails, none stays as .tmp
    let out = tmp.path().join("sweep");
    let mut cmd = magbubble();
    cmd.args(["sweep", "scenes/no_field.toml", "--grid", "drive.amplitude=0.1:0.3:4", "--set", "modes.max_order=2"])
        .args(["--set", "run.duration=20e-6", "--keep-series", "--out"])
        .arg(&out);
    let _ = with_file_limit(cmd, 64 << 10);
    let left = files(&out);
    assert!(left.iter().all(|p| !p.file_name().unwrap().to_string_lossy().contains(".tmp")), "temporary files left: {left:?}");
}

#[test]
fn a_run_without_plot_removes_the_old_plot() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("D");
    let run = |plot: bool| {
        let mut c = magbubble();
        c.args(["run", "scenes/radial_only.toml", "--set", "run.duration=2e-6", "--out"]).arg(&out);
        if plot {
            c.arg("--plot");
        }
        let o = c.output().unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8_lossy(&o.stderr).into_owned()
    };
    run(true);
    assert!(out.join("series.svg").exists() && out.join("series.png").exists());
    let err = run(false);
    assert!(!out.join("series.svg").exists() && !out.join("series.png").exists(), "a stale plot survived");
    assert!(err.contains("series.svg"), "the removal is not said: {err}");
}
