// Stresses of a hyperelastic shell law, eq (2.25): σ_i = λ_i ∂W/∂λ_i, for a law that states its
// strain energy W (per reference area, ε-scaled: N/m) only. Parsed by codegen, never compiled.
// `diff` differentiates through the law's intermediate definitions (e.g. Skalak's I1, I2).

let sigma1 = lambda1 * diff(W, lambda1);
let sigma2 = lambda2 * diff(W, lambda2);
