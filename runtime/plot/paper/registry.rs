//! The table of the paper's figures 3–16: scene, curves, recipe. The curve values the paper
//! does not list (χ, M, currents, f2) are our choice and are named in each scene's comment.

use super::{PaperFigure, Recipe, StabilitySpec, TimeSeriesSpec, Variant};

/// Critical ε_p against the drive frequency 0.2…6 MHz (0.1 MHz steps, so an alternating
/// current of 0.25, 0.5 or 1 MHz stays commensurate); quick: 6 points, 0.5…3 MHz.
const PRESSURE: StabilitySpec = StabilitySpec {
    families: &[],
    panels: &[],
    freq_key: "drive.frequency_hz",
    freqs: (0.2e6, 6.0e6, 59),
    quick_freqs: (0.5e6, 3.0e6, 6),
    vary: "drive.amplitude",
    range: (0.0, 1.0),
    vary_label: "critical ε_p [–]",
    vary_scale: 1.0,
    omega_k: false,
    nondimensional: false,
    first_mode: false,
    multiplier: false,
};

/// Critical current amplitude I0 (0…400 kA) against the current frequency f2 (fig 9).
const CURRENT: StabilitySpec = StabilitySpec {
    freq_key: "field.coil.current.frequency_hz",
    freqs: (0.1e6, 3.0e6, 30),
    quick_freqs: (0.5e6, 2.0e6, 4),
    vary: "field.coil.current.amplitude",
    range: (0.0, 400e3),
    vary_label: "critical I0 [kA]",
    vary_scale: 1e-3,
    ..PRESSURE
};

const fn v(label: &'static str, overrides: &'static [&'static str]) -> Variant {
    Variant { label, overrides }
}

/// The registry, figures 3 to 16 in order.
pub static FIGURES: &[PaperFigure] = &[
    PaperFigure {
        number: 3,
        scene: "fig03_convergence.toml",
        shows: "error of the structure (e_s) and the fluid (e_f) against the time step Δt', log–log",
        paper: "observed orders 1.995 (e_s) and 2.065 (e_f) for the staggered scheme; Δt' = 1e-3 chosen",
        recipe: Recipe::Convergence,
    },
    PaperFigure {
        number: 4,
        scene: "fig04_compare.toml",
        shows: "full vorticity model against the boundary-layer approximation, a_k(t)",
        paper: "oscillation patterns and mean amplitudes agree, the maximum amplitude differs slightly",
        recipe: Recipe::Compare,
    },
    PaperFigure {
        number: 5,
        scene: "fig05_modes.toml",
        shows: "critical ε_p against f_d for 12…32 modes; first unstable mode against f_d",
        paper: "the critical curve converges above 16 modes up to 6 MHz; the first unstable mode moves to higher k with frequency",
        recipe: Recipe::Stability(StabilitySpec {
            families: &[
                v("12 modes", &["modes.max_order=12"]),
                v("16 modes", &["modes.max_order=16"]),
                v("20 modes", &["modes.max_order=20"]),
                v("24 modes", &["modes.max_order=24"]),
                v("28 modes", &["modes.max_order=28"]),
                v("32 modes", &["modes.max_order=32"]),
            ],
            omega_k: false,
            nondimensional: false,
            first_mode: true,
            multiplier: false,
            ..PRESSURE
        }),
    },
    PaperFigure {
        number: 6,
        scene: "fig06_current.toml",
        shows: "ω_k against k, critical ε_p and max Floquet multiplier against f_d, several static currents",
        paper: "a static current barely changes ω_k, the critical curve or the max multiplier",
        recipe: Recipe::Stability(StabilitySpec {
            families: &[
                v("I = 0", &["field.coil.current=0.0"]),
                v("I = 100 kA", &["field.coil.current=100e3"]),
                v("I = 200 kA", &["field.coil.current=200e3"]),
            ],
            omega_k: true,
            nondimensional: false,
            first_mode: false,
            multiplier: true,
            ..PRESSURE
        }),
    },
    PaperFigure {
        number: 7,
        scene: "fig07_radius.toml",
        shows: "ω_k t* against k (collapses in R0) and critical ε_p against ω_d t*, several R0",
        paper: "ω_k t* collapses onto one curve for every R0; the critical curves do not collapse",
        recipe: Recipe::Stability(StabilitySpec {
            families: &[
                v("R0 = 10 µm", &["bubble.radius=10e-6"]),
                v("R0 = 15 µm", &["bubble.radius=15e-6"]),
                v("R0 = 20 µm", &["bubble.radius=20e-6"]),
            ],
            omega_k: true,
            nondimensional: true,
            ..PRESSURE
        }),
    },
    PaperFigure {
        number: 8,
        scene: "fig08_c1.toml",
        shows: "ω_k against k and critical ε_p against f_d, several c1",
        paper: "ω_k curves do not collapse when c1 varies (α = c2/c1 changes); the critical curves shift",
        recipe: Recipe::Stability(StabilitySpec {
            families: &[
                v("c1 = 0.05 N/m", &["shell.c1=0.05"]),
                v("c1 = 0.1 N/m", &["shell.c1=0.1"]),
                v("c1 = 0.2 N/m", &["shell.c1=0.2"]),
                v("c1 = 0.5 N/m", &["shell.c1=0.5"]),
            ],
            omega_k: true,
            ..PRESSURE
        }),
    },
    PaperFigure {
        number: 9,
        scene: "fig09_current_frequency.toml",
        shows: "critical current amplitude I0 against the current frequency f2 at ε_p = 0, several R0",
        paper: "instability mainly at high I0 (133–266 kA range), dips only at low f2; larger R0 lowers the critical I0",
        recipe: Recipe::Stability(StabilitySpec {
            families: &[
                v("R0 = 10 µm", &["bubble.radius=10e-6"]),
                v("R0 = 15 µm", &["bubble.radius=15e-6"]),
                v("R0 = 20 µm", &["bubble.radius=20e-6"]),
            ],
            ..CURRENT
        }),
    },
    PaperFigure {
        number: 10,
        scene: "fig10_alternating.toml",
        shows: "critical ε_p against f_d with an alternating current: several I0 at f2 = 0.5 MHz, several f2 at I0 = 150 kA",
        paper: "frequency and amplitude of the current change the critical curve little, mostly at high f_d",
        recipe: Recipe::Stability(StabilitySpec {
            families: &[
                v("I0 = 100 kA, f2 = 0.5 MHz", &["field.coil.current={ amplitude = 100e3, frequency_hz = 5e5 }"]),
                v("I0 = 150 kA, f2 = 0.5 MHz", &["field.coil.current={ amplitude = 150e3, frequency_hz = 5e5 }"]),
                v("I0 = 150 kA, f2 = 0.25 MHz", &["field.coil.current={ amplitude = 150e3, frequency_hz = 2.5e5 }"]),
                v("I0 = 150 kA, f2 = 1 MHz", &["field.coil.current={ amplitude = 150e3, frequency_hz = 1e6 }"]),
            ],
            panels: &[("f2 = 0.5 MHz", &[0, 1]), ("I0 = 150 kA", &[2, 1, 3])], ..PRESSURE
        }),
    },
    PaperFigure {
        number: 11,
        scene: "fig11_dipole.toml",
        shows: "dipole: critical ε_p against f_d for several M (z = 0.01 m) and several z (M = 1 A m²)",
        paper: "larger M or smaller z lowers the critical pressure; halving z multiplies the forcing ~200×",
        recipe: Recipe::Stability(StabilitySpec {
            families: &[
                v("M = 0.1 A m²", &["field.dipole.moment=0.1"]),
                v("M = 1 A m², z = 10 mm", &["field.dipole.moment=1.0"]),
                v("M = 5 A m²", &["field.dipole.moment=5.0"]),
                v("M = 10 A m²", &["field.dipole.moment=10.0"]),
                v("z = 7.5 mm", &["field.dipole.distance=0.0075"]),
                v("z = 5 mm", &["field.dipole.distance=0.005"]),
            ],
            panels: &[("z = 0.01 m", &[0, 1, 2, 3]), ("M = 1 A m²", &[1, 4, 5])], ..PRESSURE
        }),
    },
    PaperFigure {
        number: 12,
        scene: "fig12_chi.toml",
        shows: "R(t) and a_2(t) over {duration} for several susceptibilities χ (coil, I = {current})",
        paper: "R(t) is unaffected by χ; the a_2 amplitude grows with χ (bounded oscillations over 2000 µs)",
        recipe: Recipe::TimeSeries(TimeSeriesSpec {
            variants: &[
                v("χ = 1", &["shell.susceptibility=1.0"]),
                v("χ = 5", &["shell.susceptibility=5.0"]),
                v("χ = 10", &["shell.susceptibility=10.0"]),
            ],
            radius: true,
            shapes: &["a_2"],
            phase_portrait: false,
        }),
    },
    PaperFigure {
        number: 13,
        scene: "fig13_radius.toml",
        shows: "R(t) and a_2(t) over {duration} for R0 = 10, 15, 20 µm (χ = 1)",
        paper: "R oscillates less for larger R0; the a_2 amplitude grows about 2.25× (15 µm) and 4× (20 µm)",
        recipe: Recipe::TimeSeries(TimeSeriesSpec {
            variants: &[
                v("R0 = 10 µm", &["bubble.radius=10e-6"]),
                v("R0 = 15 µm", &["bubble.radius=15e-6"]),
                v("R0 = 20 µm", &["bubble.radius=20e-6"]),
            ],
            radius: true,
            shapes: &["a_2"],
            phase_portrait: false,
        }),
    },
    PaperFigure {
        number: 14,
        scene: "fig14_current_frequency.toml",
        shows: "a_2(t) for several frequencies f2 of an alternating current (I0 = 150 kA, f1 = 1 MHz)",
        paper: "f2 = 0.5 f1 gives the largest a_2; the frequency has only a slight influence",
        recipe: Recipe::TimeSeries(TimeSeriesSpec {
            variants: &[
                v("f2 = 0.25 f1", &["field.coil.current={ amplitude = 150e3, frequency_hz = 2.5e5 }"]),
                v("f2 = 0.5 f1", &["field.coil.current={ amplitude = 150e3, frequency_hz = 5e5 }"]),
                v("f2 = f1", &["field.coil.current={ amplitude = 150e3, frequency_hz = 1e6 }"]),
                v("f2 = 2 f1", &["field.coil.current={ amplitude = 150e3, frequency_hz = 2e6 }"]),
            ],
            radius: false,
            shapes: &["a_2"],
            phase_portrait: false,
        }),
    },
    PaperFigure {
        number: 15,
        scene: "fig15_quasiperiodic.toml",
        shows: "a_2(t) and its phase portrait for f2 = 1.777 f1 (quasi-periodic / chaotic)",
        paper: "quasi-periodic / chaotic a_2 for an incommensurate f2",
        recipe: Recipe::TimeSeries(TimeSeriesSpec {
            variants: &[v("f2 = 1.777 f1", &[])],
            radius: false,
            shapes: &["a_2"],
            phase_portrait: true,
        }),
    },
    PaperFigure {
        number: 16,
        scene: "fig16_dipole.toml",
        shows: "dipole: R(t), a_2(t), a_4(t) over {duration} for several moments M (χ = 5, z = 0.01 m)",
        paper: "larger M slightly increases R's amplitude and strongly increases a_2 (forcing ∝ M²)",
        recipe: Recipe::TimeSeries(TimeSeriesSpec {
            variants: &[
                v("M = 0.1 A m²", &["field.dipole.moment=0.1"]),
                v("M = 1 A m²", &["field.dipole.moment=1.0"]),
                v("M = 10 A m²", &["field.dipole.moment=10.0"]),
            ],
            radius: true,
            shapes: &["a_2", "a_4"],
            phase_portrait: false,
        }),
    },
];
