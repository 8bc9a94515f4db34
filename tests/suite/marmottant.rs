//! The Marmottant laws (issue 31; docs/model.md, "Lipid shells: Marmottant"): the radial R(t)
//! against an implementation of Marmottant et al. 2005's equation written here, the
//! small-amplitude radial and shape frequencies against their closed forms, bad input.

use crate::common;
use crate::common::water::*;
use magbubble::analysis::frequencies::natural_frequencies;
use magbubble::model::simulate;
use magbubble::scene::{load_str, Lipid, Scene, ShellLaw};

/// A BR14-type monolayer (Marmottant 2005 fit an SF6 bubble with χ = 0.54 N/m, κ_s = 7.2e-9 kg/s;
/// here on the paper's 10 µm bubble): χ, σ(R0), σ_r, κ_s.
const CHI: f64 = 0.5;
const SIGMA0: f64 = 0.02;
const SIGMA_R: f64 = 0.072;
const KAPPA_S: f64 = 5e-9;

fn lipid(chi: f64, sigma0: f64, sigma_r: f64) -> Lipid {
    Lipid { elasticity: chi, buckling_radius: common::R0 / (1.0 + sigma0 / chi).sqrt(), initial_tension: sigma0, rupture_tension: sigma_r, smoothing: None }
}

/// The paper's bubble with a Marmottant shell in equilibrium at R0 (p_g0 = p0 + 2σ(R0)/R0).
fn scene(max_order: usize, eps_p: f64, f_hz: f64, l: Lipid) -> Scene {
    let mut s = common::scene(max_order, eps_p, f_hz);
    s.shell.law = ShellLaw::Marmottant(l);
    s.shell.dilatational_viscosity = KAPPA_S;
    s.gas.reference_pressure = P0 + 2.0 * l.initial_tension / common::R0;
    s
}

/// σ(R) of Marmottant et al. 2005, eq 1 (with σ_break = σ_r, reversible rupture).
fn sigma(r: f64, l: &Lipid) -> f64 {
    let rb = l.buckling_radius;
    let rr = rb * (1.0 + l.rupture_tension / l.elasticity).sqrt();
    if r < rb {
        0.0
    } else if r > rr {
        l.rupture_tension
    } else {
        l.elasticity * (r * r / (rb * rb) - 1.0)
    }
}

/// Marmottant 2005 eq 2, the Rayleigh–Plesset equation of a coated bubble, in SI:
/// ρ(RR̈ + 3/2Ṙ²) = p_g0(R0/R)^{3κ} − p0(1 + ε_p cos ωt) − 4ηṘ/R − 2σ(R)/R − 4κ_sṘ/R².
fn rp(t: f64, y: [f64; 2], eps: f64, w: f64, l: &Lipid) -> [f64; 2] {
    let (r, v) = (y[0], y[1]);
    let pg0 = P0 + 2.0 * l.initial_tension / common::R0;
    let p = pg0 * (common::R0 / r).powf(3.0 * KAPPA) - P0 * (1.0 + eps * (w * t).cos()) - 4.0 * ETA * v / r - 2.0 * sigma(r, l) / r - 4.0 * KAPPA_S * v / (r * r);
    [v, (p / RHO - 1.5 * v * v) / r]
}

/// R at the times `ts` by classical RK4 with step h, every step that crosses a branch radius
/// (R_b, R_r) cut at the crossing ([`common::rk4_cut_at`]).
fn reference(eps: f64, f_hz: f64, l: &Lipid, ts: &[f64], h: f64) -> (Vec<f64>, usize) {
    let w = 2.0 * std::f64::consts::PI * f_hz;
    let f = |t: f64, y: [f64; 2]| rp(t, y, eps, w, l);
    let rb = l.buckling_radius;
    let radii = [rb, rb * (1.0 + l.rupture_tension / l.elasticity).sqrt()];
    common::rk4_cut_at(&f, &radii, [common::R0, 0.0], ts, h)
}

/// max |R_magbubble − R_reference| / R0 over 3 drive periods, and the switches.
fn radial_error(eps: f64, f_hz: f64, l: Lipid, rtol: f64) -> (f64, usize) {
    let mut s = scene(0, eps, f_hz, l);
    s.run.duration = 3.0 / f_hz;
    s.run.sample_interval = 0.02 / f_hz;
    let (ts, rs) = common::radial_series(&s, rtol);
    let (rref, switches) = reference(eps, f_hz, &l, &ts, 2e-11);
    let err = rs.iter().zip(&rref).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max) / common::R0;
    (err, switches)
}

#[test]
fn radial_motion_on_the_elastic_branch_matches_the_published_equation_to_1e_8() {
    // σ(R0) = 0.04 N/m: at ε_p = 0.1 R stays between R_b and R_r (no switch)
    let l = lipid(CHI, 0.036, SIGMA_R);
    let (err, switches) = radial_error(0.1, 1e6, l, 1e-12);
    assert_eq!(switches, 0, "the run should stay on the elastic branch");
    assert!(err <= 1e-8, "max |ΔR|/R0 = {err:e}");
}

#[test]
fn radial_motion_through_buckling_and_rupture_matches_the_published_equation() {
    // near the radial resonance (400 kHz), 3 periods, Dopri5 at rtol 1e-12: every switch is
    // located by the run loop's events and the stepper restarts there (model/events.rs).
    // Measured max |ΔR|/R0: 7.3e-12, 2.4e-11, 5.8e-11, 1.2e-10 at ε_p = 0.1, 0.3, 0.6, 1 (7–11
    // switches; before the events, stepping over the kinks: 1.3e-11, 3.7e-10, 2.3e-10, 6.4e-11)
    let l = lipid(CHI, SIGMA0, SIGMA_R);
    for &eps in &[0.1, 0.3, 0.6, 1.0] {
        let (err, switches) = radial_error(eps, 4e5, l, 1e-12);
        println!("eps_p = {eps}: {switches} branch switches, max |dR|/R0 = {err:e}");
        assert!(switches >= 4, "eps_p = {eps}: the run should visit the buckled and ruptured branches ({switches} switches)");
        assert!(err <= 1e-8, "eps_p = {eps}: max |ΔR|/R0 = {err:e}");
    }
}

#[test]
fn elastic_branch_radial_frequency_is_the_closed_form() {
    // ρR0²ω0² = 3κ p_g0 + 4χ/R0 + 2σ(R0)/R0 with p_g0 = p0 + 2σ(R0)/R0 (docs/model.md): the
    // derivative of 2σ(R)/R at R0 is [4(χ + σ0) − 2σ0]/R0²; Marmottant 2005's eq 6 writes
    // 3κp0 + (3κ − 1)2σ0/R0 + 4χ/R0, i.e. this with χR0²/R_b² = χ + σ0 taken ≈ χ
    let r0 = common::R0;
    for &(chi, s0) in &[(0.5, 0.0), (0.5, 0.02), (1.0, 0.05), (0.2, 0.06)] {
        let s = scene(4, 0.0, 1e6, lipid(chi, s0, SIGMA_R));
        let f = natural_frequencies(&s, 4).unwrap();
        let w2 = (3.0 * KAPPA * (P0 + 2.0 * s0 / r0) + 4.0 * chi / r0 + 2.0 * s0 / r0) / (RHO * r0 * r0);
        let rel = (f.radial.omega_rad_s - w2.sqrt()).abs() / w2.sqrt();
        assert!(rel < 1e-9, "chi={chi} s0={s0}: {} vs {} ({rel:e})", f.radial.omega_rad_s, w2.sqrt());
    }
}

#[test]
fn elastic_branch_shape_frequencies_are_lambs_with_the_tension_at_rest() {
    // an area-only law has no shear stiffness: with b quasi-static the area modulus drops out
    // and ω_k² = (k−1)(k+1)(k+2)σ(R0)/(ρR0³) (Lamb's, with γ = σ(R0))
    let r0 = common::R0;
    for &s0 in &[0.01, 0.05] {
        let f = natural_frequencies(&scene(8, 0.0, 1e6, lipid(CHI, s0, SIGMA_R)), 9).unwrap();
        for m in &f.shape {
            let k = m.k as f64;
            let w2 = (k - 1.0) * (k + 1.0) * (k + 2.0) * s0 / (RHO * r0.powi(3));
            assert!((m.omega_rad_s.powi(2) - w2).abs() < 1e-8 * w2, "k={} s0={s0}: {} vs {}", m.k, m.omega_rad_s.powi(2), w2);
        }
    }
}

#[test]
fn smooth_law_tends_to_the_kinked_one() {
    // the softplus blend differs from the kinked σ by at most s ln 2: the radial orbits converge
    let l = lipid(CHI, SIGMA0, SIGMA_R);
    let run = |law: ShellLaw| {
        let mut s = scene(0, 0.6, 1e6, l);
        s.shell.law = law;
        s.run.duration = 3e-6;
        s.run.sample_interval = 5e-8;
        let mut rs = vec![];
        simulate(&s, &mut |_, row| rs.push(row[0])).unwrap();
        rs
    };
    let kinked = run(ShellLaw::Marmottant(l));
    let dev = |sm: f64| {
        let rs = run(ShellLaw::MarmottantSmooth(Lipid { smoothing: Some(sm), ..l }));
        rs.iter().zip(&kinked).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max) / common::R0
    };
    let (d1, d2) = (dev(4e-3), dev(1e-3));
    println!("max |dR|/R0 smooth vs kinked: s = 4e-3: {d1:e}, s = 1e-3: {d2:e}");
    assert!(d2 < d1 / 2.0 && d2 < 5e-3, "{d1:e} {d2:e}");
}

fn ld(text: &str) -> Result<Scene, magbubble::scene::SceneError> {
    load_str(text, "test", &[] as &[&str])
}

fn err_of(text: &str) -> String {
    ld(text).unwrap_err().to_string()
}

#[test]
fn bad_marmottant_input_is_refused_naming_the_key() {
    let e = err_of("[shell]\nlaw = \"marmottant\"\nelasticity = 0.5\nbuckling_radius = 9e-6\ninitial_tension = 0.01\n");
    assert!(e.contains("shell.buckling_radius") && e.contains("exactly one"), "{e}");
    let e = err_of("[shell]\nlaw = \"marmottant\"\nelasticity = 0.5\nbuckling_radius = 11e-6\ninitial_tension = 0.01\n");
    assert!(e.contains("inconsistent") && e.contains("buckled at rest"), "{e}");
    let e = err_of("[shell]\nlaw = \"marmottant\"\nelasticity = -0.5\n");
    assert!(e.contains("shell.elasticity") && e.contains("> 0"), "{e}");
    let e = err_of("[shell]\nlaw = \"marmottant\"\n");
    assert!(e.contains("shell.elasticity") && e.contains("required"), "{e}");
    let e = err_of("[shell]\nelasticity = 0.5\n");
    assert!(e.contains("shell.elasticity") && e.contains("mooney-rivlin"), "{e}");
    let e = err_of("[shell]\nlaw = \"skalak\"\nrupture_tension = 0.05\n");
    assert!(e.contains("shell.rupture_tension") && e.contains("skalak"), "{e}");
    let e = err_of("[shell]\nlaw = \"marmottant\"\nelasticity = 0.5\nsmoothing = 0.01\n");
    assert!(e.contains("shell.smoothing") && e.contains("marmottant-smooth"), "{e}");
    let e = err_of("[shell]\nlaw = \"marmottant\"\nelasticity = 0.5\ninitial_tension = 0.08\n");
    assert!(e.contains("shell.initial_tension") && e.contains("ruptured at rest"), "{e}");
    let e = err_of("[shell]\nlaw = \"marmottant\"\nelasticity = 0.5\nshear_modulus = 0.3\n");
    assert!(e.contains("shell.shear_modulus"), "{e}");
}

#[test]
fn a_marmottant_scene_resolves_r_b_and_the_equilibrium_gas_pressure() {
    let s = ld("[shell]\nlaw = \"marmottant\"\nelasticity = 0.5\ninitial_tension = 0.02\n").unwrap();
    let l = s.shell.law.lipid().unwrap();
    assert!((l.buckling_radius - 10e-6 / (1.04f64).sqrt()).abs() < 1e-18);
    let m = magbubble::model::Model::from_scene(&s).unwrap();
    let pg0 = m.groups().p_g0_pa;
    assert!((pg0 - (101325.0 + 2.0 * 0.02 / 10e-6)).abs() < 1e-8 * pg0, "{pg0}");
    // R_b given: σ(R0) follows; R_b ≥ R0 is buckled at rest
    let s = ld("[shell]\nlaw = \"marmottant\"\nelasticity = 0.5\nbuckling_radius = 11e-6\n").unwrap();
    assert_eq!(s.shell.law.lipid().unwrap().initial_tension, 0.0);
}

#[test]
fn branch_margins_change_sign_at_the_branch_radii() {
    let s = ld("[shell]\nlaw = \"marmottant\"\nelasticity = 0.5\ninitial_tension = 0.02\n").unwrap();
    let sc = magbubble::model::Scales::from_scene(&s);
    let law = magbubble::model::effects::lipid::LipidLaw::from_scene(&s.shell.law, &sc).unwrap();
    let (rb, rr) = (1.0 / 1.04f64.sqrt(), 1.0 / 1.04f64.sqrt() * (1.0 + 0.072 / 0.5f64).sqrt());
    let m = law.branch_margins(1.0);
    assert!((m[0] - (1.0 - rb)).abs() < 1e-15 && (m[1] - (1.0 - rr)).abs() < 1e-15, "{m:?}");
    assert_eq!(law.tension(0.99 * rb * rb)[0], 0.0);
    assert_eq!(law.tension(1.01 * rr * rr)[0], law.sigma_r);
}

#[test]
fn marmottant_jacobian_is_exact_on_every_branch() {
    // the boundary-layer Jacobian against central differences at states on the buckled,
    // elastic and ruptured branches (R_b = 0.981, R_r = 1.049 R0), kinked, smooth, and kinked with
    // the quadratic coupling (effects/lipid_quadratic.rs)
    use magbubble::integrate::OdeSystem;
    let base = ["modes.max_order=8", "shell.law=\"marmottant\"", "shell.elasticity=0.5", "shell.initial_tension=0.02", "shell.dilatational_viscosity=5e-9", "drive.amplitude=0.5"];
    let mut smooth = base.to_vec();
    smooth[1] = "shell.law=\"marmottant-smooth\"";
    smooth.push("shell.smoothing=0.01");
    let mut quadratic = base.to_vec();
    quadratic.push("modes.coupling=\"quadratic\"");
    for set in [base.to_vec(), smooth, quadratic] {
        let s = magbubble::scene::load("scenes/coil_static.toml", &set).unwrap();
        let model = magbubble::model::Model::from_scene(&s).unwrap();
        let bl = model.boundary_layer().unwrap();
        for &r in &[0.9, 0.995, 1.03, 1.1] {
            let mut y: Vec<f64> = (0..bl.dim()).map(|i| 1e-3 * ((i * 7919) % 13) as f64 - 6e-3).collect();
            y[0] = r;
            y[1] = 0.2;
            let n = y.len();
            let mut an = vec![0.0; n * n];
            assert!(bl.jacobian(0.3, &y, &mut an));
            let fd = crate::equations_jacobian::fd_jacobian(bl, 0.3, &y);
            for i in 0..n {
                let row_max = (0..n).map(|j| (an[i * n + j] * y[j].abs().max(1e-2)).abs()).fold(0.0, f64::max);
                for j in 0..n {
                    let err = (an[i * n + j] - fd[i * n + j]).abs() * y[j].abs().max(1e-2);
                    assert!(err <= 1e-6 * row_max + 1e-9, "{set:?} R={r}: J[{i}][{j}] {} vs fd {}", an[i * n + j], fd[i * n + j]);
                }
            }
        }
    }
}

#[test]
fn the_smooth_law_with_the_quadratic_coupling_is_refused() {
    let s = magbubble::scene::load("scenes/no_field.toml", &["shell.law=\"marmottant-smooth\"", "shell.elasticity=0.5", "modes.coupling=\"quadratic\""]).unwrap();
    let e = magbubble::model::Model::from_scene(&s).unwrap_err().to_string();
    assert!(e.contains("modes.coupling") && e.contains("smooth"), "{e}");
}
