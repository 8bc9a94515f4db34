//! Issue 15 class 3: SIGINT/SIGTERM during `run` removes the `*.tmp` files, says so, and exits
//! non-zero (130 / 143).

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::Duration;

#[test]
fn interrupted_run_leaves_no_temporary_files() {
    for (sig, code) in [("INT", 130), ("TERM", 143)] {
        let tmp = tempfile::tempdir().unwrap();
        let out = tmp.path().join("o");
        let child = Command::new(env!("CARGO_BIN_EXE_magbubble"))
            .arg("run")
            .arg(Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/no_field.toml"))
            .arg("--out")
            .arg(&out)
            .args(["--set", "modes.viscous=vorticity", "--set", "run.duration=1e-2", "--set", "run.sample_interval=1e-7"])
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        // Wait until the run has started writing.
        let tmp_csv = out.join("series.csv.tmp");
        for _ in 0..200 {
            if tmp_csv.exists() {
                break;
            }
            std::thread::sleep(Duration::from_millis(25));
        }
        assert!(tmp_csv.exists(), "the run did not start");
        let kill = Command::new("kill").arg(format!("-{sig}")).arg(child.id().to_string()).status().unwrap();
        assert!(kill.success());
        let o = child.wait_with_output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(code), "{err}");
        assert!(err.contains("temporary files removed"), "{err}");
        assert!(!tmp_csv.exists() && !out.join("series.csv").exists());
    }
}
