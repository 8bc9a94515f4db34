//! Issue 29 items 4, 10, 12, 13: a law's moduli stand on their own, keys that do nothing warn,
//! meaningless values are errors naming the key, and the unclear messages say what is wrong.
use magbubble::scene;
use std::process::{Command, Stdio};

fn magbubble() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_magbubble"));
    c.current_dir(env!("CARGO_MANIFEST_DIR"));
    c
}

fn load_err(path: &str, set: &[&str]) -> String {
    scene::load(path, set).unwrap_err().to_string()
}

#[test]
fn a_law_is_not_dropped_by_zero_moduli() {
    // c1 = c2 = 0 made skalak.toml a free bubble, without its 0.44 N/m Skalak law
    let e = load_err("scenes/skalak.toml", &["shell.c1=0", "shell.c2=0"]);
    assert!(e.contains("shell.c1") && e.contains("skalak") && e.contains("0.44"), "{e}");
    // a Mooney-Rivlin shell with c1 = c2 = 0 is the documented free bubble
    let s = scene::load("scenes/no_field.toml", &["shell.c1=0", "shell.c2=0"]).unwrap();
    assert!(s.shell.is_free());
}

#[test]
fn keys_that_do_nothing_warn_and_meaningless_values_are_errors() {
    let s = scene::load("scenes/no_field.toml", &["shell.shear_modulus=0.5"]).unwrap();
    assert_eq!(s.warnings.len(), 1, "{:?}", s.warnings);
    assert!(s.warnings[0].contains("shell.shear_modulus") && s.warnings[0].contains("mooney-rivlin"), "{:?}", s.warnings);
    assert!(scene::load("scenes/skalak.toml", &[] as &[&str]).unwrap().warnings.is_empty());
    assert!(scene::load("scenes/keller_miksis.toml", &[] as &[&str]).unwrap().warnings.is_empty());
    // R0/t* = 4.47 m/s: c = 1e-3 m/s is Mach 4472
    let e = load_err("scenes/keller_miksis.toml", &["liquid.sound_speed=1e-3"]);
    assert!(e.contains("liquid.sound_speed") && e.contains("Mach 4472"), "{e}");
    let s = scene::load("scenes/keller_miksis.toml", &["liquid.sound_speed=30"]).unwrap();
    assert!(s.warnings.iter().any(|w| w.contains("liquid.sound_speed") && w.contains("Mach 0.149")), "{:?}", s.warnings);
    // the CLI prints the warning
    let tmp = tempfile::tempdir().unwrap();
    let o = magbubble()
        .args(["run", "scenes/radial_only.toml", "--set", "shell.area_dilatation=2", "--set", "run.duration=1e-6", "--out"])
        .arg(tmp.path().join("o"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success() && err.contains("warning: `shell.area_dilatation` = 2.0 does nothing"), "{err}");
}

#[test]
fn unclear_messages_say_what_is_wrong() {
    let tmp = tempfile::tempdir().unwrap();
    // --vary of an integer key: refused before any work, no directory
    let out = tmp.path().join("s");
    let o = magbubble()
        .args(["stability", "scenes/no_field.toml", "--freq", "1e6", "--vary", "modes.max_order", "--range", "2:16", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && err.contains("--vary modes.max_order") && err.contains("takes integers"), "{err}");
    assert!(!out.exists());
    // --kmax beyond the tables names --kmax and says the limit holds always
    for damped in [false, true] {
        let mut c = magbubble();
        c.args(["modes", "scenes/no_field.toml", "--kmax", "1000"]);
        if damped {
            c.arg("--damped");
        }
        let o = c.output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success() && err.contains("--kmax 1000") && err.contains("with or without a field") && !err.contains("modes.max_order"), "{err}");
    }
    // an undamped, unstiff free bubble: no NaN, no −0
    let o = magbubble().args(["modes", "scenes/free_bubble.toml", "--damped"]).output().unwrap();
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success() && !out.contains("NaN") && !out.contains("-0.0"), "{out}");
    // a tiny credible bound is printed in exponent form
    let o = magbubble()
        .args(["run", "scenes/no_field.toml", "--set", "modes.coupling=\"quadratic\"", "--set", "modes.credible_amplitude=1e-300"])
        .args(["--set", "run.duration=1e-6", "--out"])
        .arg(tmp.path().join("c"))
        .output()
        .unwrap();
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("exceeded 1e-300 (modes.credible_amplitude)"), "{out}");
}

#[test]
fn stability_says_it_was_interrupted_and_exits_130() {
    let tmp = tempfile::tempdir().unwrap();
    let child = magbubble()
        .args(["stability", "scenes/no_field.toml", "--freq", "0.8e6:1.2e6:40", "--method", "series", "--set", "modes.max_order=4", "--out"])
        .arg(tmp.path().join("s"))
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_millis(1500));
    // SAFETY: plain kill(2) on our own child.
    unsafe { libc::kill(child.id() as libc::pid_t, libc::SIGINT) };
    let o = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(130), "{err}");
    assert!(err.contains("interrupted"), "{err}");
}
