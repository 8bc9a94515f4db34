// Coil field for a general coil angle θc: the H2 and H4 terms of the Boridy expansion (eq 2.30),
// h_r = Σ H_n (r/a)^(n−1) P_n(cos θ), h_θ = Σ (H_n/n) (r/a)^(n−1) P^1_n(cos θ), n = 2, 4,
// with P^1_n(cos θ) = dP_n/dθ = −sin θ P_n'(cos θ) (Condon–Shortley; eq 2.32 for n = 2).
// Parsed by codegen (syn), never compiled. Components: H2², H2·H4, H4².

let symbols = [mu0, chi_s, H2, H4, a];
let amplitudes = [H2, H4];

// P_2, P_4 and their θ-derivatives at the field point.
let p2 = (3 * cos_t.powi(2) - 1) / 2;
let p4 = (35 * cos_t.powi(4) - 30 * cos_t.powi(2) + 3) / 8;
let p2_1 = -sin_t * 3 * cos_t;
let p4_1 = -sin_t * (35 * cos_t.powi(3) - 15 * cos_t) / 2;

// Eq (2.30), terms n = 2 and n = 4.
let h_r = H2 * (r / a) * p2 + H4 * (r / a).powi(3) * p4;
let h_theta = H2 / 2 * (r / a) * p2_1 + H4 / 4 * (r / a).powi(3) * p4_1;

let susceptibility = mu0 * chi_s;

// Tabulation unit: ℋ_c = (1/4) × (the component's symbols) × R0²/R², as for the paper's coil.
let unit = 1 / 4;
