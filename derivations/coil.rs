// The paper's coil field: two opposed coils, Boridy expansion (eqs 2.30–2.32) with θc a root of
// P^1_4 so that H4 = 0. Parsed by codegen (syn), never compiled.
// Built-ins: the field point r, cos_t = cos θ, sin_t = sin θ. The engine computes the force
// F = μ0 χ_s (∇h)·h (eq 2.33), the rotation (2.39), the area factor, and the projections.

let symbols = [mu0, chi_s, H2, a];
// One table component per product of two field amplitudes.
let amplitudes = [H2];

// Eq (2.32).
let h_r = H2 * r / (2 * a) * (3 * cos_t.powi(2) - 1);
let h_theta = H2 * r / (2 * a) * (-3 * sin_t * cos_t);

// Eq (2.33): F = μ0 χ_s (∇h)·h, χ_s = ε χ the interface susceptibility (FORMULATION §1).
let susceptibility = mu0 * chi_s;

// Tabulation unit (appendix A): ℋ = (1/4) μ0 χ_s H2² R0² / (a² R²).
let unit = 1 / 4;
