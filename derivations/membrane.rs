// Membrane equilibrium, eqs (2.26)–(2.28) with FORMULATION §1–2: F = −div σ/(λ1λ2), for the
// principal stresses σ1, σ2 of a shell law (σ_i = λ1λ2 τ_i, τ_i the tensions in N/m; ε-scaled).
// Parsed by codegen (syn), never compiled. Sees the kinematics (r, theta, lambda1, kappa1, rho, …)
// and the law's definitions (`sigma1`, `sigma2`, from the law or from hyperelastic.rs).

// Arclength derivative d/ds = (1/|g1|) d/dΘ.
let dsigma1_ds = d(sigma1, Theta) / g1_norm;
let drho_ds = d(rho, Theta) / g1_norm;

// Eq (2.26) with FORMULATION §1: F = −(div σ)/(λ1 λ2).
let alpha = lambda1 * lambda2;
let paper_n = (kappa1 * sigma1 + kappa2 * sigma2) / alpha;
let paper_t = -(dsigma1_ds + drho_ds / rho * (sigma1 - sigma2)) / alpha;

// FORMULATION §2, tension form: the divergence acts on σ/α (α = λ1 λ2); F_n is unchanged.
let tension_n = paper_n;
let tension_t = -(d(sigma1 / alpha, Theta) / g1_norm + drho_ds / rho * (sigma1 - sigma2) / alpha);
