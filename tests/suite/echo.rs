//! Issue 30 part 2, the echo (docs/model.md, "Echo"): far field against ρ(R²R̈ + 2RṘ²)/r on the
//! series, the exact volume against an independent quadrature, the near field against finite
//! differences of the potential, the spectrum of a period-1 orbit, and end to end through `run`.

use magbubble::echo::field::{Field, Kinematics};
use magbubble::echo::volume::VolumeRule;
use magbubble::scene::load_str;
use std::f64::consts::PI;
use std::process::Command;

const NONE: &[&str] = &[];

/// P_k by the explicit formulas (k = 2, 4), written here from the textbook.
fn p2(x: f64) -> f64 {
    0.5 * (3.0 * x * x - 1.0)
}
fn p4(x: f64) -> f64 {
    (35.0 * x.powi(4) - 30.0 * x * x + 3.0) / 8.0
}

/// (2π/3) ∫_0^π r(θ)³ sin θ dθ by composite Simpson on 20,000 intervals.
fn simpson_volume(r: f64, a2: f64, a4: f64) -> f64 {
    let n = 20_000;
    let h = PI / n as f64;
    let f = |th: f64| {
        let x = th.cos();
        (r + a2 * p2(x) + a4 * p4(x)).powi(3) * th.sin()
    };
    let mut s = f(0.0) + f(PI);
    for i in 1..n {
        s += f(i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 };
    }
    2.0 * PI / 3.0 * s * h / 3.0
}

#[test]
fn volume_of_a_deformed_bubble() {
    let rule = VolumeRule::new(&[2, 4]);
    for (a2, a4) in [(0.1, 0.0), (0.2, -0.15), (-0.3, 0.25)] {
        let (v, _, _) = rule.rates([1.0, 0.0, 0.0], &[[a2, 0.0, 0.0], [a4, 0.0, 0.0]]);
        let q = simpson_volume(1.0, a2, a4);
        assert!((v - q).abs() < 1e-12 * q, "a2 = {a2}, a4 = {a4}: {v} vs {q}");
        // and the a_k² terms matter: the sphere's volume differs at O(a²)
        assert!((v - 4.0 * PI / 3.0).abs() > 1e-3);
    }
}

/// A smooth made-up motion: R(t), a_2(t), a_4(t) and their first two derivatives.
fn motion(t: f64) -> Kinematics {
    let w = 2.0;
    let r = [1.0 + 0.2 * (w * t).sin(), 0.2 * w * (w * t).cos(), -0.2 * w * w * (w * t).sin()];
    let a2 = [0.05 * (1.3 * t).cos(), -0.065 * (1.3 * t).sin(), -0.0845 * (1.3 * t).cos()];
    let a4 = [0.03 * t * t, 0.06 * t, 0.06];
    Kinematics { r, a: vec![a2, a4] }
}

/// The potential of eq E3, typed here: φ = −Q/r − Σ C_k r^−(k+1) P_k, Q = V̇/4π with V̇ from a
/// time difference of the Simpson volume, C_k = R^{k+2}(ȧ_k + 2Ṙa_k/R)/(k+1).
fn potential(t: f64, r: f64, th: f64) -> f64 {
    let h = 1e-5;
    let vol = |t: f64| {
        let m = motion(t);
        simpson_volume(m.r[0], m.a[0][0], m.a[1][0])
    };
    let q = (vol(t + h) - vol(t - h)) / (2.0 * h) / (4.0 * PI);
    let m = motion(t);
    let (big_r, rd) = (m.r[0], m.r[1]);
    let c = |k: f64, a: [f64; 3]| big_r.powf(k + 2.0) * (a[1] + 2.0 * rd * a[0] / big_r) / (k + 1.0);
    let x = th.cos();
    -q / r - c(2.0, m.a[0]) * r.powi(-3) * p2(x) - c(4.0, m.a[1]) * r.powi(-5) * p4(x)
}

/// p = −ρ(∂φ/∂t + ½|∇φ|²) by central differences of the potential, against the library.
#[test]
fn near_field_is_bernoulli() {
    let field = Field::new(1.0, &[2, 4]);
    for &(t, r, th) in &[(0.3, 1.5, 0.4), (1.1, 2.0, 1.2), (2.0, 3.0, 2.5), (0.7, 1.3, 0.0)] {
        let (ht, hr) = (1e-3, 1e-4);
        let phi_t = (potential(t + ht, r, th) - potential(t - ht, r, th)) / (2.0 * ht);
        let phi_r = (potential(t, r + hr, th) - potential(t, r - hr, th)) / (2.0 * hr);
        let phi_th = (potential(t, r, th + hr) - potential(t, r, th - hr)) / (2.0 * hr) / r;
        let p_fd = -(phi_t + 0.5 * (phi_r * phi_r + phi_th * phi_th));
        let p = field.near(&motion(t), r, th);
        assert!((p - p_fd).abs() < 1e-5 * p.abs().max(1e-2), "t={t} r={r} θ={th}: {p} vs {p_fd}");
    }
}

/// Far from the bubble the near field meets ρV̈/(4πr) (its r⁻² and faster terms fall away).
#[test]
fn near_field_meets_far_field() {
    let field = Field::new(1.0, &[2, 4]);
    let m = motion(0.9);
    for r in [1e2, 1e3, 1e4] {
        let (near, far) = (field.near(&m, r, 0.6), field.far(&m, r));
        assert!((near - far).abs() < 2.0 / r * far.abs(), "r = {r}: {near} vs {far}");
    }
}

fn run_scene(dir: &std::path::Path, text: &str) -> (std::process::Output, std::path::PathBuf) {
    let scene = dir.join("s.toml");
    std::fs::write(&scene, text).unwrap();
    let out = dir.join("out");
    let o = Command::new(env!("CARGO_BIN_EXE_magbubble")).arg("run").arg(&scene).arg("--out").arg(&out).output().unwrap();
    (o, out)
}

fn radial(extra: &str) -> String {
    format!(
        "[bubble]\nradius = 10e-6\n[shell]\nc1 = 0.1\nc2 = 0.12\n[drive]\namplitude = 0.1\nfrequency_hz = 1e6\n[modes]\nmax_order = 0\n\
         [run.integrator]\nmethod = \"dop853\"\nrtol = 1e-11\natol = 1e-14\n{extra}"
    )
}

/// A spherical bubble's far-field echo equals ρ(R²R̈ + 2RṘ²)/r with Ṙ, R̈ from central
/// differences of the series over Δt = 10 ns (truncation (ωΔt)²/12 ≈ 3.3e-4 relative). The floor
/// of this check is the second derivative of the samples' dense-output interpolant, not the echo:
/// measured max |Δp|/max|p| = 3.6e-3 at rtol 1e-11 and 1.1e-3 at rtol 1e-13 (the same for Δt = 5,
/// 10, 20 ns), so the run uses rtol 1e-13.
#[test]
fn spherical_far_field_on_the_series() {
    let text = radial("[run]\nduration = 3e-6\nsample_interval = 1e-9\n[echo]\ndistance = 0.05\n").replace("rtol = 1e-11\natol = 1e-14", "rtol = 1e-13\natol = 1e-17");
    let s = load_str(&text, "echo", NONE).unwrap();
    let mut rows = Vec::new();
    let (_, echo) = magbubble::echo::simulate(&s, &mut |t, row| rows.push((t, row[0]))).unwrap();
    let echo = echo.unwrap();
    assert_eq!(echo.form, "far");
    let dt = 1e-9;
    let mut worst: f64 = 0.0;
    let scale = echo.p[0].iter().fold(0.0f64, |m, p| m.max(p.abs()));
    let (dt, j) = (10.0 * dt, 10);
    for i in j..rows.len() - j {
        let (r, rm, rp) = (rows[i].1, rows[i - j].1, rows[i + j].1);
        let (v, a) = ((rp - rm) / (2.0 * dt), (rp - 2.0 * r + rm) / (dt * dt));
        let p = 1000.0 * (r * r * a + 2.0 * r * v * v) / 0.05;
        worst = worst.max((p - echo.p[0][i]).abs());
    }
    assert!(scale > 1.0, "echo amplitude {scale} Pa");
    assert!(worst < 2e-3 * scale, "max |Δp| = {worst:e} Pa of {scale:e} Pa");
    assert!(echo.shape_part.iter().all(|&x| x == 0.0));
}

/// A period-1 orbit (ε_p = 0.1, η = 0.01 Pa s, long after the transient): the f/2 line is ≥ 40 dB below the
/// fundamental; `run` writes echo.csv, spectrum.csv and the summary's echo object.
#[test]
fn period_one_spectrum_end_to_end() {
    let dir = tempfile::tempdir().unwrap();
    // η = 0.01 Pa s: the transient (rate 2η/(ρR0²) = 2e5/s) is gone by 40 µs
    let text = radial("[liquid]\nviscosity = 0.01\n[run]\nduration = 80e-6\nsample_interval = 1e-8\n[echo]\ndistance = 0.05\nangles_deg = [0, 90]\nwindow = [40e-6, 80e-6]\n");
    let (o, out) = run_scene(dir.path(), &text);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let head = std::fs::read_to_string(out.join("echo.csv")).unwrap();
    assert!(head.starts_with("t,p_0.05m_0deg,p_0.05m_90deg\n"), "{}", &head[..60]);
    let spec = std::fs::read_to_string(out.join("spectrum.csv")).unwrap();
    assert!(spec.starts_with("frequency_hz,p_0.05m_0deg_db,p_0.05m_90deg_db\n"));
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let e = &v["echo"];
    let (f, sub) = (e["fundamental_db"].as_f64().unwrap(), e["subharmonic_db"].as_f64().unwrap());
    assert!(f - sub >= 40.0, "fundamental {f} dB, f/2 {sub} dB");
    assert!(e["peak_to_peak_pa"].as_f64().unwrap() > 0.0);
    assert!(e["second_harmonic_db"].as_f64().unwrap() < f);
}

/// An echo point inside the bubble: a clear error, nothing written.
#[test]
fn echo_point_inside_the_bubble() {
    let dir = tempfile::tempdir().unwrap();
    let (o, out) = run_scene(dir.path(), &radial("[echo]\ndistance = 5e-6\n"));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && !out.exists());
    assert!(err.contains("`echo.distance` = 5e-6") && err.contains("inside the bubble"), "{err}");
    let (o, _) = run_scene(dir.path(), &radial("[echo]\nwindow = [2e-6, 1e-6]\n"));
    assert!(String::from_utf8_lossy(&o.stderr).contains("`echo.window`"));
}

/// `run --plot` with [echo] draws echo.svg/png (the pressure at the receiver above the
/// spectrum); a later run without --plot removes them; a scene without [echo] draws none.
#[test]
fn run_plot_draws_the_echo_panels() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    let bin = env!("CARGO_BIN_EXE_magbubble");
    let run = |scene: &str, plot: bool| {
        let mut c = std::process::Command::new(bin);
        c.args(["run", scene, "--set", "run.duration=1e-6", "--out"]).arg(&out);
        if plot {
            c.arg("--plot");
        }
        let o = c.output().unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8_lossy(&o.stdout).into_owned()
    };
    let text = run("scenes/hann_burst.toml", true);
    assert!(text.contains("echo.svg"), "{text}");
    for f in ["echo.svg", "echo.png", "series.svg"] {
        assert!(std::fs::metadata(out.join(f)).unwrap().len() > 1000, "{f}");
    }
    let svg = std::fs::read_to_string(out.join("echo.svg")).unwrap();
    assert!(svg.contains("p_s [Pa]") && svg.contains("dB re 1 Pa") && svg.contains("p_0.05m_0deg"), "the two panels");
    run("scenes/hann_burst.toml", false);
    assert!(!out.join("echo.svg").exists() && !out.join("echo.png").exists());
    run("scenes/radial_only.toml", true);
    assert!(!out.join("echo.svg").exists());
}
