// Viscous (Kelvin–Voigt) shell: a Boussinesq–Scriven surface viscous stress, τ = (κ_s − μ_s)(tr D) I
// + 2μ_s D, with D the surface rate of deformation, principal values d_i = λ̇_i/λ_i. μ_s: surface
// shear viscosity [Pa s m]; κ_s: surface dilatational viscosity [kg/s] (de Jong; Marmottant et
// al. 2005: radial load 4κ_s Ṙ/R²). Parsed by codegen, never compiled. `rate` is the time
// derivative at fixed material point (R → Ṙ, a_k → ȧ_k, b_k → ḃ_k). The elastic part of a
// Kelvin–Voigt shell is any elastic law; this law is its viscous part, added to it.

let symbols = [mu_s, kappa_s];

let d1 = rate(lambda1) / lambda1;
let d2 = rate(lambda2) / lambda2;
// principal tensions τ1 = κ_s(d1 + d2) + μ_s(d1 − d2), τ2 likewise; σ_i = λ1λ2 τ_i (membrane.rs)
let sigma1 = lambda1 * lambda2 * (kappa_s * (d1 + d2) + mu_s * (d1 - d2));
let sigma2 = lambda1 * lambda2 * (kappa_s * (d1 + d2) + mu_s * (d2 - d1));
