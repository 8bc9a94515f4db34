// Mooney–Rivlin membrane, eq (2.24) (the paper's law). Parsed by codegen, never compiled.
// Stresses by hyperelastic.rs (eq 2.25), loads by membrane.rs (eqs 2.26–2.29).
// C1, C2 enter the tables ε-scaled: c_i = ε C_i in N/m (FORMULATION §1).

let symbols = [C1, C2];

// Eq (2.24): strain energy.
let W = C1 * (lambda1.powi(2) + lambda2.powi(2) + (lambda1 * lambda2).powi(-2) - 3)
    + C2 * (lambda1.powi(-2) + lambda2.powi(-2) + (lambda1 * lambda2).powi(2) - 3);
