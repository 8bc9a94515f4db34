// Isotropic surface tension γ [N/m]: a membrane whose tension is γ in every direction and state,
// W = γ λ1 λ2 per reference area (the energy γ per deformed area). Parsed by codegen, never compiled.
// σ_i = λ_i ∂W/∂λ_i = γ λ1 λ2, i.e. τ_i = γ: the tension form gives F_n = γ(κ1 + κ2) (Laplace,
// 2γ/R and Lamb's (k−1)(k+2)γ/R² a_k) and F_t = 0. The paper's form (divergence of σ instead of
// σ/α) gives a spurious tangential load; the runtime uses the tension form for γ.

let symbols = [gamma];

let W = gamma * lambda1 * lambda2;
