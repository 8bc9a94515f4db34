//! The scene schema: ONE table of every key a scene may contain, with its unit, default, allowed
//! range, the paper's symbol and a description.
//!
//! It is used by the type walk of a parsed scene (unknown keys, wrong types), by validation
//! (defaults and ranges, [`super::validate`]), by `--set` (which paths exist), by
//! `magbubble scene new|explain` and by `docs/scenes.md` (generated from [`markdown_reference`]).
//! Defaults follow docs/model.md ("Conventions that the paper leaves open") and the paper's
//! figure parameters (R0 = 10 µm, c1 = 0.1 N/m, c2 = 0.12 N/m, ε = 20 nm, χ = 1).

use std::f64::consts::FRAC_PI_2;

/// Largest even shape mode a scene may ask for: the coefficient tables are generated up to
/// `KMAX` (codegen, env `MAGBUBBLE_KMAX`, default 64).
pub const MAX_ORDER_LIMIT: usize = crate::coefficients::KMAX;

/// θc = acos(√(3/7)), the positive root of P¹_4(cos θc) (eq 2.31, docs/model.md defaults table):
/// with it H_4 = 0. Checked against `acos` in the tests.
pub const DEFAULT_COIL_ANGLE: f64 = 0.857_071_947_850_131_1;

/// Default fixed/initial step as a fraction of t* = √(ρR0³/(2c1)) (paper sec. 5.3: Δt′ = 10⁻³).
pub const DT_OVER_TSTAR: f64 = 1e-3;

/// What a key holds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Kind {
    /// A table of keys (`[shell]`, `[run.integrator]`, or an inline table).
    Section,
    /// A real number (TOML float or integer).
    Float,
    /// A TOML integer.
    Int,
    Bool,
    /// A string out of a fixed list.
    Choice(&'static [&'static str]),
    /// A table `{ 2 = 1e-8, 4 = … }` keyed by the even mode number k.
    ModeMap,
    /// A number, or an inline table whose keys are the schema's children of this key
    /// (`current = 100e3` or `current = { amplitude = 150e3, frequency_hz = 5e5 }`).
    FloatOrTable,
    /// A string (a file path).
    Text,
    /// An array of numbers (`angles_deg = [0, 90]`).
    FloatList,
    /// An array of inline tables whose keys are the schema's children of this key
    /// (`components = [{ amplitude = 0.1, frequency_hz = 2e6 }]`).
    TableList,
}

/// The default of a key.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum DefaultValue {
    Float(f64),
    Int(i64),
    Bool(bool),
    Str(&'static str),
    /// Defaults to the value of another key.
    SameAs(&'static str),
    /// Computed from other keys; the text says how.
    Derived(&'static str),
    /// No default: must be given when its section is present. `example` is used by `scene new`.
    Required {
        example: &'static str,
    },
    /// An optional section: absent means the effect is off.
    Absent,
    /// An empty mode map (all zero).
    Empty,
    /// A section that always applies (absent: all its keys take their defaults).
    Present,
}

/// The allowed values of a number.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Range {
    /// Any finite value (not inf/NaN).
    Finite,
    Positive,
    NonNegative,
    /// lo < x (or ≤ when `lo_incl`), x < hi (or ≤ when `hi_incl`).
    Between {
        lo: f64,
        hi: f64,
        lo_incl: bool,
        hi_incl: bool,
    },
    /// Integer in lo..=hi.
    IntBetween(i64, i64),
    /// Even integer in 0..=hi.
    EvenUpTo(i64),
    /// Not a number: no range (sections, booleans, strings, mode maps).
    None,
}

impl Range {
    /// Whether `x` is allowed.
    pub fn admits(&self, x: f64) -> bool {
        if !x.is_finite() {
            return false;
        }
        match *self {
            Range::Finite | Range::None => true,
            Range::Positive => x > 0.0,
            Range::NonNegative => x >= 0.0,
            Range::Between {
                lo,
                hi,
                lo_incl,
                hi_incl,
            } => {
                (if lo_incl { x >= lo } else { x > lo }) && (if hi_incl { x <= hi } else { x < hi })
            }
            Range::IntBetween(lo, hi) => x.fract() == 0.0 && x >= lo as f64 && x <= hi as f64,
            Range::EvenUpTo(hi) => {
                x.fract() == 0.0 && x >= 0.0 && x <= hi as f64 && (x as i64) % 2 == 0
            }
        }
    }

    /// The range as an error message says it ("must be > 0").
    pub fn describe(&self) -> String {
        match *self {
            Range::Finite => "a finite number".into(),
            Range::Positive => "> 0".into(),
            Range::NonNegative => ">= 0".into(),
            Range::Between {
                lo,
                hi,
                lo_incl,
                hi_incl,
            } => {
                let l = if lo_incl { "[" } else { "(" };
                let h = if hi_incl { "]" } else { ")" };
                let hi = if hi == f64::INFINITY {
                    "inf".to_string()
                } else if hi == FRAC_PI_2 {
                    "pi/2".to_string()
                } else {
                    fmt_num(hi)
                };
                format!("in {l}{}, {hi}{h}", fmt_num(lo))
            }
            Range::IntBetween(lo, i64::MAX) => format!("an integer >= {lo}"),
            Range::IntBetween(lo, hi) => format!("an integer in {lo}..={hi}"),
            Range::EvenUpTo(hi) => format!("an even integer in 0..={hi} (KMAX)"),
            Range::None => String::new(),
        }
    }
}

/// One key of the schema.
#[derive(Debug, Clone, Copy)]
pub struct Param {
    /// Dotted path, e.g. `shell.c1`.
    pub key: &'static str,
    pub kind: Kind,
    /// SI unit ("" for dimensionless).
    pub unit: &'static str,
    pub default: DefaultValue,
    pub range: Range,
    /// The paper's symbol (and equation).
    pub symbol: &'static str,
    pub doc: &'static str,
}

const fn p(
    key: &'static str,
    kind: Kind,
    unit: &'static str,
    default: DefaultValue,
    range: Range,
    symbol: &'static str,
    doc: &'static str,
) -> Param {
    Param {
        key,
        kind,
        unit,
        default,
        range,
        symbol,
        doc,
    }
}

const fn section(key: &'static str, default: DefaultValue, doc: &'static str) -> Param {
    p(key, Kind::Section, "", default, Range::None, "", doc)
}

use DefaultValue as D;
use Kind as K;
use Range as Rg;

const OPEN_UNIT: Range = Rg::Between {
    lo: 0.0,
    hi: 1.0,
    lo_incl: true,
    hi_incl: false,
};

/// Every key of a scene, sections first in the order `scene new` writes them.
#[rustfmt::skip]
pub static SCHEMA: &[Param] = &[
    section("bubble", D::Present, "The bubble: its reference radius and initial state."),
    p("bubble.radius", K::Float, "m", D::Float(10e-6), Rg::Positive, "R_0",
      "Reference (natural, unstressed) radius of the bubble."),
    section("bubble.initial", D::Present,
      "Initial state. Default: at rest, R = R0, dR/dt = 0, a_k = da_k/dt = b_k = 0."),
    p("bubble.initial.radius", K::Float, "m", D::SameAs("bubble.radius"), Rg::Positive, "R(0)",
      "Initial radius."),
    p("bubble.initial.velocity", K::Float, "m/s", D::Float(0.0), Rg::Finite, "dR/dt(0)",
      "Initial radial velocity."),
    p("bubble.initial.seed", K::Choice(&["given", "thermal"]), "", D::Str("given"), Rg::None, "",
      "`given`: the shape modes start at bubble.initial.a / b (unset: 0; a field or the coupling feeds them, \
       possibly at amplitudes like 1e-38 m, which then set a blow-up time). `thermal`: every a_k not set in \
       bubble.initial.a starts at its equipartition amplitude sqrt(k_B T / K_k), K_k the mode's stiffness at \
       R0 and T = liquid.temperature (docs/model.md, \"Thermal seed\")."),
    p("bubble.initial.a", K::ModeMap, "m", D::Empty, Rg::Finite, "a_k(0) (eq 2.14)",
      "Initial normal shape amplitudes, keyed by even k with 2 <= k <= modes.max_order, e.g. { 2 = 1e-8 }."),
    p("bubble.initial.a_velocity", K::ModeMap, "m/s", D::Empty, Rg::Finite, "da_k/dt(0)",
      "Initial normal shape velocities, keyed like `a`."),
    p("bubble.initial.b", K::ModeMap, "m", D::Empty, Rg::Finite, "b_k(0) (eq 2.14)",
      "Initial tangential amplitudes, keyed like `a`."),
    section("shell", D::Present, "The lipid shell: Mooney-Rivlin membrane loaded with nanoparticles."),
    p("shell.c1", K::Float, "N/m", D::Float(0.1), Rg::NonNegative, "c_1 = eps C_1 (sec 5.3)",
      "First Mooney-Rivlin constant times the thickness. Sets the time scale t* = sqrt(rho R0^3/(2 c1)). \
       c1 = c2 = 0: a free gas bubble (no membrane term; t* = R0 sqrt(rho/p0), docs/model.md)."),
    p("shell.c2", K::Float, "N/m", D::Float(0.12), Rg::NonNegative, "c_2 = eps C_2 (sec 5.3)",
      "Second Mooney-Rivlin constant times the thickness (alpha = c2/c1); must be 0 when c1 = 0."),
    p("shell.thickness", K::Float, "m", D::Float(20e-9), Rg::Positive, "eps",
      "Shell thickness; the interface susceptibility is chi_s = eps chi (docs/model.md §1)."),
    p("shell.susceptibility", K::Float, "", D::Float(1.0), Rg::Finite, "chi",
      "Magnetic susceptibility of the nanoparticle-laden shell (negative: diamagnetic)."),
    p("shell.form", K::Choice(&["paper", "tension"]), "", D::Str("paper"), Rg::None, "eqs 2.26-2.29",
      "Membrane load: `paper` = divergence of the Cauchy stress (the paper's); `tension` = divergence of \
       the tension eps sigma/alpha (docs/model.md §2, audit 9)."),
    p("shell.law", K::Choice(&["mooney-rivlin", "skalak", "marmottant", "marmottant-smooth", "sarkar", "church-hoff", "tension-curve"]), "", D::Str("mooney-rivlin"), Rg::None,
      "eq 2.24 / Skalak 1973 / Marmottant 2005",
      "Elastic law of the membrane (derivations/shell/): `mooney-rivlin` with c1, c2; `skalak` with \
       shear_modulus and area_dilatation; `marmottant` (buckled / elastic / ruptured lipid monolayer, \
       tension form whatever shell.form says) with elasticity, buckling_radius or initial_tension, \
       rupture_tension; `marmottant-smooth` the same with a smooth tension (smoothing); `sarkar` (the \
       exponential elasticity model of Paul et al. 2010, area-only) with elasticity, elasticity_decay, \
       reference_tension; `church-hoff` (Church 1995, Hoff et al. 2000's thin shell, radial only: \
       modes.max_order = 0) with modulus, viscosity, thickness; `tension-curve` (a measured sigma(A/A0), \
       monotone PCHIP interpolation) with tension_file. c1 still sets the time scale t* \
       (docs/model.md, \"Lipid shells\")."),
    p("shell.shear_modulus", K::Float, "N/m", D::Derived("2 (c1 + c2), the small-strain shear modulus of the Mooney-Rivlin membrane"),
      Rg::Positive, "G_s", "Skalak shear modulus (shell.law = \"skalak\" only)."),
    p("shell.area_dilatation", K::Float, "", D::Float(1.0), Rg::NonNegative, "C",
      "Skalak area-dilatation parameter: small-strain area modulus K = G_s (1 + 2C); C = 1 gives the \
       Mooney-Rivlin K = 6 (c1 + c2) when G_s = 2 (c1 + c2) (shell.law = \"skalak\" only)."),
    p("shell.elasticity", K::Float, "N/m", D::Derived("none: required with shell.law = \"marmottant\", \"marmottant-smooth\" or \"sarkar\""),
      Rg::Positive, "chi", "Marmottant elastic modulus: sigma(R) = chi (R^2/R_b^2 - 1) on the elastic branch (marmottant laws); \
       E0^s of shell.law = \"sarkar\"."),
    p("shell.buckling_radius", K::Float, "m", D::Derived("R0 / sqrt(1 + sigma(R0)/chi) from shell.initial_tension; R0 when neither is given"),
      Rg::Positive, "R_b", "Marmottant buckling radius: sigma = 0 for R < R_b. Give this or shell.initial_tension, not both \
       (marmottant laws only)."),
    p("shell.initial_tension", K::Float, "N/m", D::Derived("chi (R0^2/R_b^2 - 1) from shell.buckling_radius, 0 when R_b >= R0"),
      Rg::NonNegative, "sigma(R0)", "Marmottant tension at rest, below shell.rupture_tension; sets R_b = R0/sqrt(1 + sigma(R0)/chi) \
       and the equilibrium gas pressure p0 + 2 sigma(R0)/R0 (marmottant laws only)."),
    p("shell.rupture_tension", K::Float, "N/m", D::Derived("0.072 (water)"), Rg::Positive, "sigma_r",
      "Marmottant ruptured branch: sigma = sigma_r for R > R_r = R_b sqrt(1 + sigma_r/chi), reversibly (the \
       break-up tension taken equal to sigma_r, as in APECSS; marmottant laws only)."),
    p("shell.smoothing", K::Float, "N/m", D::Derived("0.005"), Rg::Positive, "s",
      "Tension width of marmottant-smooth: sigma = s [softplus(x/s) - softplus((x - sigma_r)/s)], x = chi (R^2/R_b^2 - 1), \
       i.e. the area modulus blends by tanh over s (marmottant-smooth only)."),
    p("shell.elasticity_decay", K::Float, "", D::Derived("0 (a constant E^s: Sarkar et al. 2005's viscoelastic model)"), Rg::NonNegative, "alpha^s",
      "Exponential elasticity model: E^s = E0^s exp(-alpha^s beta), beta = R^2/R_E^2 - 1 (shell.law = \"sarkar\" only; \
       E0^s is shell.elasticity)."),
    p("shell.reference_tension", K::Float, "N/m", D::Derived("0"), Rg::NonNegative, "gamma_0",
      "Exponential elasticity model: tension gamma0 + E^s beta; R_E is set so that it vanishes at R0 (no net tension at \
       rest, p_g0 = p0) (shell.law = \"sarkar\" only)."),
    p("shell.tension_file", K::Text, "", D::Absent, Rg::None, "sigma(A/A0)",
      "CSV of a measured tension curve (shell.law = \"tension-curve\" only): a header with the columns area_ratio \
       (A/A0 = R^2/R0^2, strictly increasing) and tension [N/m] (non-decreasing), at least 3 rows; interpolated by \
       PCHIP (Fritsch-Carlson monotone cubic), constant beyond the ends, each knot a branch switch of the run \
       (docs/model.md, \"Lipid shells: tension curve\"). A relative path is read from the scene file's directory."),
    p("shell.modulus", K::Float, "Pa", D::Derived("none: required with shell.law = \"church-hoff\""), Rg::Positive, "G_s",
      "Church-Hoff shell: shear modulus of the shell material (a bulk modulus, not N/m); radial pressure \
       12 G_s d R0^2/R^3 (1 - R0/R) with d = shell.thickness (shell.law = \"church-hoff\" only)."),
    p("shell.viscosity", K::Float, "Pa s", D::Derived("0"), Rg::NonNegative, "eta_s",
      "Church-Hoff shell: shear viscosity of the shell material; radial pressure 12 eta_s d R0^2 (dR/dt)/R^4 \
       (shell.law = \"church-hoff\" only)."),
    p("shell.bending_modulus", K::Float, "J", D::Float(0.0), Rg::NonNegative, "k_b",
      "Helfrich bending stiffness (zero spontaneous curvature): normal load (k-1)k(k+1)(k+2) k_b a_k/R^4 \
       on each mode, no radial load. 0 = off."),
    p("shell.shear_viscosity", K::Float, "Pa s m", D::Float(0.0), Rg::NonNegative, "mu_s",
      "Surface shear viscosity of a Kelvin-Voigt shell (derivations/shell/viscous.rs, tension form). \
       Its loads act on the shape modes only (boundary-layer closure; not with modes.viscous = \"vorticity\"). 0 = off."),
    p("shell.dilatational_viscosity", K::Float, "kg/s", D::Float(0.0), Rg::NonNegative, "kappa_s",
      "Surface dilatational viscosity (Marmottant-type): radial load 4 kappa_s (dR/dt)/R^2 and its shape-mode \
       loads (boundary-layer closure; not with modes.viscous = \"vorticity\" and shape modes). 0 = off."),
    p("shell.surface_tension", K::Float, "N/m", D::Float(0.0), Rg::NonNegative, "gamma",
      "Isotropic surface tension: 2 gamma/R in the radial balance, Lamb's (k-1)(k+2) gamma/R^2 a_k on \
       each mode (tension form, derivations/shell/surface_tension.rs). 0 = off."),
    section("gas", D::Present, "Polytropic gas and vapour: p_in = p_v + p_g0 (R0/R)^(3 kappa)."),
    p("gas.polytropic_exponent", K::Float, "", D::Float(1.4), Rg::Positive, "kappa",
      "Polytropic exponent (1 = isothermal, 1.4 = adiabatic air)."),
    p("gas.reference_pressure", K::Float, "Pa",
      D::Derived("equilibrium at R0: p0 - p_v + 2 gamma/R0 + membrane prestress (= p0 without them)"),
      Rg::Positive, "p_g0",
      "Gas pressure at R = R0. Default: the bubble at rest at R0 is in equilibrium (docs/model.md, \
       \"Liquid and gas effects\"); a value given here overrides the rule. The run summary reports the \
       value used (groups.p_g0_pa, groups.p_g0_rule)."),
    p("gas.vapour_pressure", K::Float, "Pa", D::Float(0.0), Rg::NonNegative, "p_v",
      "Vapour pressure inside the bubble (constant; 0 = off, no term assembled)."),
    p("gas.thermal", K::Choice(&["polytropic", "prosperetti", "reduced"]), "", D::Str("polytropic"), Rg::None,
      "Prosperetti 1977; Preston et al. 2007",
      "Heat exchange of the gas: `polytropic` = (R0/R)^(3 kappa) with gas.polytropic_exponent; `prosperetti` = \
       Prosperetti's linear theory at the drive frequency (undriven: the radial natural frequency): \
       (R0/R)^(3 kappa_eff) and a thermal damping -4 mu_th (dR/dt)/R, from thermal_diffusivity and \
       heat_capacity_ratio (docs/model.md, \"Thermal damping\"); `reduced` = the nonlinear reduced \
       heat-transfer model of Preston, Colonius & Brennen 2007: the bubble pressure p_b is a state \
       variable (a p_b column in series.csv) with a heat flux whose small-amplitude limit is \
       Prosperetti's at the same frequency (docs/model.md, \"Reduced thermal model\"); with shape modes \
       the boundary-layer closure and the linear coupling."),
    p("gas.thermal_diffusivity", K::Float, "m^2/s", D::Derived("2.0e-5 (air at 20 C, 1 atm)"), Rg::Positive, "D_g",
      "Thermal diffusivity K/(rho_g c_p) of the gas at rest (gas.thermal = \"prosperetti\" or \"reduced\" only)."),
    p("gas.heat_capacity_ratio", K::Float, "", D::Derived("1.4 (air)"), Rg::Positive, "gamma",
      "Ratio of specific heats c_p/c_v of the gas (gas.thermal = \"prosperetti\" or \"reduced\" only; the adiabatic limit of kappa_eff)."),
    section("liquid", D::Present, "The surrounding liquid (default: water)."),
    p("liquid.density", K::Float, "kg/m^3", D::Float(1000.0), Rg::Positive, "rho", "Liquid density."),
    p("liquid.viscosity", K::Float, "Pa s", D::Float(1e-3), Rg::Positive, "eta", "Dynamic viscosity."),
    p("liquid.ambient_pressure", K::Float, "Pa", D::Float(101325.0), Rg::Positive, "p_0",
      "Ambient pressure."),
    p("liquid.temperature", K::Float, "K", D::Float(293.15), Rg::Positive, "T",
      "Temperature of the liquid and the shell: sets the thermal seed (bubble.initial.seed = \"thermal\") only."),
    p("liquid.sound_speed", K::Float, "m/s", D::Absent, Rg::Positive, "c",
      "Speed of sound: given, the radial equation is Keller-Miksis (liquid compressibility, acoustic \
       radiation damping; shape modes stay incompressible). Absent: the incompressible equation (2.62)."),
    section("drive", D::Absent,
      "Acoustic drive p_inf(t) = p0 + p_a(t) (docs/model.md, \"Drives\"): tones w(tau/L) sum eps_i p0 cos(2 pi f_i tau + phi_i) \
       under an envelope w (tau: time since the burst's start; tau = t when continuous), or a measured waveform \
       (drive.file). The default, p0 (1 + eps_p cos(2 pi f_d t)), is the paper's. Absent or amplitude = 0: no drive."),
    p("drive.amplitude", K::Float, "", D::Required { example: "0.5" }, Rg::NonNegative, "eps_p",
      "Relative pressure amplitude of the main tone (required unless drive.file is given; not with drive.file)."),
    p("drive.frequency_hz", K::Float, "Hz", D::Float(1e6), Rg::Positive, "f_d (omega_d = 2 pi f_d)",
      "Drive frequency (the paper's \"omega_d = 1 MHz\" is read as f_d = 1 MHz, docs/model.md audit 15)."),
    p("drive.phase", K::Float, "rad", D::Float(0.0), Rg::Finite, "phi",
      "Phase of the main tone: eps_p p0 cos(2 pi f_d tau + phi)."),
    p("drive.envelope", K::Choice(&["continuous", "rectangular", "hann", "gaussian", "tukey"]), "", D::Str("continuous"), Rg::None, "w",
      "Burst envelope: continuous (no burst), rectangular, hann (sin^2), gaussian (FWHM = cycles periods, truncated at +-4 sigma, \
       so the burst lasts 3.397 cycles/f_d), tukey (tapered cosine). Zero outside the burst."),
    p("drive.cycles", K::Float, "", D::Absent, Rg::Positive, "N_c",
      "Burst length in periods of drive.frequency_hz (the Gaussian's FWHM); required with any envelope but continuous."),
    p("drive.delay", K::Float, "s", D::Float(0.0), Rg::NonNegative, "t_0",
      "Start of the (first) burst."),
    p("drive.tukey_fraction", K::Float, "", D::Float(0.5), Rg::Between { lo: 0.0, hi: 1.0, lo_incl: true, hi_incl: true }, "alpha",
      "Tapered fraction of the Tukey envelope (0: rectangular, 1: Hann)."),
    p("drive.repeat_hz", K::Float, "Hz", D::Absent, Rg::Positive, "PRF",
      "Pulse-repetition frequency: a train of bursts every 1/repeat_hz from drive.delay (absent: one burst)."),
    p("drive.components", K::TableList, "", D::Absent, Rg::None, "",
      "Further tones under the same envelope, [{ amplitude, frequency_hz, phase }, ...] (dual frequency, harmonics; \
       pulse inversion: phase = pi)."),
    p("drive.components.amplitude", K::Float, "", D::Required { example: "0.1" }, Rg::NonNegative, "eps_i",
      "Relative pressure amplitude of the tone."),
    p("drive.components.frequency_hz", K::Float, "Hz", D::Required { example: "2e6" }, Rg::Positive, "f_i",
      "Frequency of the tone."),
    p("drive.components.phase", K::Float, "rad", D::Float(0.0), Rg::Finite, "phi_i", "Phase of the tone."),
    p("drive.file", K::Text, "", D::Absent, Rg::None, "p_a(t)",
      "A CSV file with columns t [s] and p [Pa] (relative paths: from the scene file's directory), instead of amplitude: \
       p_a is interpolated linearly (error <= h^2 max|p''|/8 on a knot interval h), zero outside [t_first, t_last]; \
       its knots are stop times of the integration."),
    p("drive.file_scale", K::Float, "", D::Float(1.0), Rg::Finite, "s", "Factor on the file's pressures."),
    section("echo", D::Absent,
      "The echo (docs/model.md, \"Echo\"): run writes echo.csv (the scattered pressure at each point) and spectrum.csv, \
       and summary.json an `echo` object. Absent: no echo."),
    p("echo.distance", K::Float, "m", D::Float(0.05), Rg::Positive, "r",
      "Distance of the points from the bubble's centre (outside the bubble). Within 10 R0 the near field \
       (unsteady Bernoulli with every mode's potential), beyond it the far field rho V''/(4 pi r)."),
    p("echo.angles_deg", K::FloatList, "deg", D::Derived("[0]"), Rg::None, "theta",
      "Polar angles of the points from the symmetry axis, in [0, 180]; one echo column each."),
    p("echo.window", K::FloatList, "s", D::Absent, Rg::None, "[t_0, t_1]",
      "Time window of the spectrum (default: the whole run)."),
    section("field", D::Absent,
      "Magnetic field: at most one of [field.coil] and [field.dipole]. Absent: no magnetic term."),
    section("field.coil", D::Absent,
      "Two opposed coils (eqs 2.30-2.33): H_2n = -(I/a) N1 sin(theta_c) P^1_2n(cos theta_c)."),
    p("field.coil.turns", K::Float, "", D::Float(1000.0), Rg::Positive, "N_1", "Number of turns."),
    p("field.coil.distance", K::Float, "m", D::Float(0.1), Rg::Positive, "a",
      "Coil distance (mean distance when it oscillates); docs/model.md default 0.1 m."),
    p("field.coil.angle", K::Float, "rad", D::Float(DEFAULT_COIL_ANGLE),
      Rg::Between { lo: 0.0, hi: FRAC_PI_2, lo_incl: false, hi_incl: true }, "theta_c",
      "Coil angle; default acos(sqrt(3/7)), the positive root of P^1_4, so that H_4 = 0."),
    p("field.coil.current", K::FloatOrTable, "A", D::Required { example: "100e3" }, Rg::Finite,
      "I, or I_0 cos(2 pi f_2 t)",
      "Static current (a number), or an alternating one { amplitude = I0, frequency_hz = f2 }."),
    p("field.coil.current.amplitude", K::Float, "A", D::Required { example: "150e3" }, Rg::Finite, "I_0",
      "Amplitude of the alternating current."),
    p("field.coil.current.frequency_hz", K::Float, "Hz", D::Required { example: "5e5" }, Rg::Positive,
      "f_2", "Frequency of the alternating current."),
    section("field.coil.distance_oscillation", D::Absent,
      "Oscillating coil distance a(t) = a (1 + beta cos(2 pi f_3 t)), e.g. { amplitude = 0.1, frequency_hz = 5e5 }."),
    p("field.coil.distance_oscillation.amplitude", K::Float, "", D::Required { example: "0.1" }, OPEN_UNIT,
      "beta", "Relative amplitude of the distance oscillation."),
    p("field.coil.distance_oscillation.frequency_hz", K::Float, "Hz", D::Required { example: "5e5" },
      Rg::Positive, "f_3", "Frequency of the distance oscillation."),
    p("field.coil.include_h4", K::Bool, "", D::Bool(false), Rg::None, "H_4",
      "Keep the H_4 term of the Boridy expansion (matters only when theta_c is not a root of P^1_4)."),
    section("field.dipole", D::Absent, "Two dipoles placed symmetrically on the axis (eqs 2.34-2.38)."),
    p("field.dipole.moment", K::Float, "A m^2", D::Required { example: "1.0" }, Rg::Finite, "M",
      "Dipole moment."),
    p("field.dipole.distance", K::Float, "m", D::Float(0.01), Rg::Positive, "z",
      "Distance of each dipole from the bubble centre (must exceed bubble.radius)."),
    section("modes", D::Present, "Which shape modes are simulated and how viscosity is closed."),
    p("modes.max_order", K::Int, "", D::Int(16), Rg::EvenUpTo(MAX_ORDER_LIMIT as i64), "N",
      "Largest even shape mode; modes k = 2, 4, ..., N. 0 = radial only (Rayleigh-Plesset)."),
    p("modes.viscous", K::Choice(&["boundary-layer", "vorticity"]), "", D::Str("boundary-layer"), Rg::None,
      "sec 3 / sec 5", "Viscous closure: boundary-layer approximation (docs/model.md §4.3) or the full \
       toroidal-vorticity PDE (sec 4.2)."),
    p("modes.boundary_layer_frequency", K::Choice(&["auto", "natural"]), "", D::Str("auto"), Rg::None,
      "omega in delta_k (eq 3.1)", "Frequency of delta_k = min(sqrt(nu/omega), R/(2k)): `auto` = omega_d \
       when driven, omega_k otherwise; `natural` = omega_k always (docs/model.md audit 13)."),
    p("modes.coupling", K::Choice(&["linear", "quadratic"]), "", D::Str("linear"), Rg::None,
      "issue 12", "Order of the shape-mode equations: `linear` (the paper's) or `quadratic` (plus the \
       second-order mode coupling of the potential flow and the second-order loads of the membrane, bending \
       and shell viscosity, docs/model.md \"Quadratic mode coupling\"; either viscous closure (the liquid's \
       viscous terms stay linear); incompressible liquid)."),
    p("modes.credible_amplitude", K::Float, "", D::Float(0.1), Rg::Positive, "issue 12",
      "With `modes.coupling = \"quadratic\"`: the run stops as `out_of_credible_range` (with the mode and \
       the time) when max_k |a_k|/R0 exceeds this, the range where second order is credible (docs/model.md \
       \"Quadratic mode coupling\"); raise it to follow the run further. Ignored by linear runs."),
    section("vorticity", D::Present, "Radial grid y = r/R in [1, y_max] of the vorticity PDE (modes.viscous = \"vorticity\")."),
    p("vorticity.y_max", K::Float, "", D::Float(3.0),
      Rg::Between { lo: 1.0, hi: f64::INFINITY, lo_incl: false, hi_incl: false }, "Y_max",
      "Outer edge of the grid, in units of R (T_k = 0 there)."),
    p("vorticity.points", K::Int, "", D::Int(201), Rg::IntBetween(5, 100_000), "",
      "Number of grid points, both ends included."),
    p("vorticity.stretching", K::Float, "", D::Float(20.0),
      Rg::Between { lo: 1.0, hi: f64::INFINITY, lo_incl: true, hi_incl: false }, "",
      "Ratio of the last to the first spacing (1 = uniform; > 1 clusters points at the wall)."),
    p("vorticity.scheme", K::Choice(&["monolithic", "staggered"]), "", D::Str("monolithic"), Rg::None,
      "sec 5", "`monolithic`: method of lines, all nodes in one implicit system; `staggered`: the paper's \
       loosely coupled scheme (RK + backward Euler for T_k)."),
    section("run", D::Present, "The run: duration, output sampling, blow-up criterion."),
    p("run.duration", K::Float, "s", D::Float(100e-6), Rg::Positive, "", "Simulated time."),
    p("run.sample_interval", K::Float, "s", D::Float(1e-8), Rg::Positive, "",
      "Interval between rows of series.csv (must not exceed run.duration)."),
    p("run.max_output_bytes", K::Float, "bytes", D::Float(1e9), Rg::Positive, "",
      "Largest estimated size of series.csv ((duration/sample_interval + 1) rows of max_order + 2 numbers, \
       24 bytes each); a scene above it is refused before running."),
    p("run.blow_up_threshold", K::Float, "", D::Float(0.5), Rg::Positive, "",
      "The run stops as `blow_up` when max_k |a_k|/R0 or |b_k|/R0 exceeds this (or R leaves (0, inf))."),
    section("run.integrator", D::Present, "The time integrator and its settings."),
    p("run.integrator.method", K::Choice(&["auto", "radau5", "rk4", "dopri5", "dop853", "rosenbrock23"]), "", D::Str("auto"),
      Rg::None, "", "`auto` (per run from the Jacobian's spectral radius at the initial state against DOP853's \
       step for rtol: `dop853` when non-stiff, `radau5` when stiff; summary.json `integrator` says which and why), \
       `radau5` (implicit Radau IIA, stiff), `rk4` (fixed step, the paper's), `dopri5` / \
       `dop853` (adaptive explicit Dormand-Prince), `rosenbrock23` (linearly implicit ode23s, order 2)."),
    p("run.integrator.rtol", K::Float, "", D::Float(1e-6),
      Rg::Between { lo: 1e-14, hi: 0.1, lo_incl: true, hi_incl: true }, "",
      "Relative tolerance (adaptive methods)."),
    p("run.integrator.atol", K::Float, "", D::Float(1e-9), Rg::Positive, "",
      "Absolute tolerance on the integrator's nondimensional state (lengths / R0, docs/model.md §4.5)."),
    p("run.integrator.dt", K::Float, "s", D::Derived("1e-3 t*, t* = sqrt(rho R0^3 / (2 c1)) (free bubble: R0 sqrt(rho/p0))"), Rg::Positive,
      "Delta t", "Fixed step of rk4 and of the staggered vorticity scheme; initial step otherwise \
       (must not exceed run.duration). Not given: rk4 takes the smaller of 1e-3 t* and half its stability \
       interval over the Jacobian's spectral radius at the initial state."),
    p("run.integrator.max_steps", K::Int, "", D::Int(50_000_000), Rg::IntBetween(1, i64::MAX), "",
      "Hard cap on the number of steps; a run that needs more fails with that reason."),
    section("population", D::Absent,
      "A polydisperse suspension (issue 33; docs/population.md) for `magbubble population` and `attenuation`: \
       the size distribution of bubble.radius, its quadrature (equal-probability bins in ln R0, each bin's \
       node at its median quantile, weight 1/bins) and the number concentration. Each bin is the scene with \
       bubble.radius = the bin's radius; every other key stays as written (shell thickness, c1, c2, initial \
       tension, surface tension fixed) unless listed in scale_with_radius. Absent: a single bubble."),
    p("population.distribution", K::Choice(&["lognormal", "file"]), "", D::Str("lognormal"), Rg::None, "n(R0)",
      "`lognormal`: ln R0 normal with median ln(median_radius) and standard deviation ln(geometric_std); `file`: \
       the rows of population.file are the bins."),
    p("population.median_radius", K::Float, "m", D::SameAs("bubble.radius"), Rg::Positive, "R_med",
      "Median radius of the lognormal distribution (distribution = \"lognormal\" only)."),
    p("population.geometric_std", K::Float, "", D::Float(1.5),
      Rg::Between { lo: 1.0, hi: f64::INFINITY, lo_incl: true, hi_incl: false }, "sigma_g",
      "Geometric standard deviation exp(sd of ln R0) of the lognormal distribution (1: every bin at the median; \
       distribution = \"lognormal\" only)."),
    p("population.bins", K::Int, "", D::Int(64), Rg::IntBetween(1, 100_000), "N_b",
      "Bins of the lognormal distribution: bin i covers the quantiles [i/N_b, (i+1)/N_b], node at the quantile \
       (i + 1/2)/N_b, weight 1/N_b (distribution = \"lognormal\" only)."),
    p("population.file", K::Text, "", D::Absent, Rg::None, "",
      "A CSV with columns radius [m] and weight [-] (relative paths: from the scene file's directory); one bin \
       per row, weights normalised to sum 1 (distribution = \"file\" only)."),
    p("population.concentration", K::Float, "bubbles/mL", D::Absent, Rg::Positive, "n",
      "Number of bubbles per millilitre of suspension (needed by `attenuation`)."),
    p("population.scale_with_radius", K::Text, "", D::Derived("none"), Rg::None, "",
      "Comma-separated numeric scene keys scaled in proportion to the bin's radius (value x R_bin / bubble.radius), \
       e.g. \"shell.thickness\"; a key must be given in the scene to be scaled. Default: none."),
];

/// The schema entry of a dotted key.
pub fn param(key: &str) -> Option<&'static Param> {
    SCHEMA.iter().find(|p| p.key == key)
}

/// The direct children of a section (or of a `FloatOrTable` key).
pub fn children(parent: &str) -> impl Iterator<Item = &'static Param> + '_ {
    SCHEMA.iter().filter(move |p| match p.key.rsplit_once('.') {
        Some((head, _)) => head == parent,
        None => parent.is_empty(),
    })
}

/// The last segment of a key.
pub fn leaf_name(key: &str) -> &str {
    key.rsplit_once('.').map_or(key, |(_, l)| l)
}

/// A number as a scene would write it: plain in [1e-3, 1e6), exponent form otherwise.
pub fn fmt_num(x: f64) -> String {
    if x == 0.0 || (1e-3..1e6).contains(&x.abs()) || !x.is_finite() {
        format!("{x:?}")
    } else {
        format!("{x:e}")
    }
}

/// A computed number to 6 significant digits, trailing zeros dropped (`10.1325`, `4.47214e-310`,
/// `1e14`): for derived quantities, where the last bits of a float are noise.
pub fn fmt_sig(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x:?}");
    }
    let e = x.abs().log10().floor();
    if (-3.0..6.0).contains(&e) {
        let decimals = (5.0 - e).max(0.0) as usize;
        let t = format!("{x:.decimals$}");
        if t.contains('.') { t.trim_end_matches('0').trim_end_matches('.').to_string() } else { t }
    } else {
        let t = format!("{x:.5e}");
        let (m, exp) = t.split_once('e').expect("exponent form");
        let m = if m.contains('.') { m.trim_end_matches('0').trim_end_matches('.') } else { m };
        format!("{m}e{exp}")
    }
}

impl DefaultValue {
    /// The default as `scene explain` prints it.
    pub fn describe(&self) -> String {
        match *self {
            D::Float(x) => fmt_num(x),
            D::Int(i) => i.to_string(),
            D::Bool(b) => b.to_string(),
            D::Str(s) => format!("\"{s}\""),
            D::SameAs(k) => format!("= {k}"),
            D::Derived(t) => t.to_string(),
            D::Required { .. } => "required".into(),
            D::Absent => "absent (off)".into(),
            D::Empty => "{} (all zero)".into(),
            D::Present => "always present".into(),
        }
    }
}
