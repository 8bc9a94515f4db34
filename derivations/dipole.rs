// Two dipoles placed symmetrically: far-field h = 6 M ρ / z⁴ e_ρ (eq 2.36), ρ = r sin θ.
// Parsed by codegen (syn), never compiled.

let symbols = [mu0, chi_s, M, z];
let amplitudes = [M];

// Eq (2.36) in spherical components: e_ρ = sin θ e_r + cos θ e_θ.
let rho = r * sin_t;
let h_rho = 6 * M * rho / z.powi(4);
let h_r = h_rho * sin_t;
let h_theta = h_rho * cos_t;

// Eq (2.37): F = μ0 χ_s (∇h)·h.
let susceptibility = mu0 * chi_s;

// Tabulation unit (appendix B, dimension corrected): ℋ = −36 μ0 χ_s M² R0² / (z⁸ R²).
let unit = -36;
