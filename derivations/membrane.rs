// Mooney–Rivlin membrane, eqs (2.24)–(2.28), with FORMULATION §1–2 (F = −div σ/(λ1λ2)).
// Parsed by codegen (syn), never compiled. Every kinematics name (r, theta, lambda1, …) is visible.

let symbols = [C1, C2];

// Eq (2.24): strain energy.
let W = C1 * (lambda1.powi(2) + lambda2.powi(2) + (lambda1 * lambda2).powi(-2) - 3)
    + C2 * (lambda1.powi(-2) + lambda2.powi(-2) + (lambda1 * lambda2).powi(2) - 3);

// Eq (2.25): principal Cauchy stresses σ_i = λ_i ∂W/∂λ_i.
let sigma1 = lambda1 * diff(W, lambda1);
let sigma2 = lambda2 * diff(W, lambda2);

// Exact principal curvatures of the deformed surface (replace the approximations 2.23).
// Meridian: curvature of the plane curve r(Θ) e_r(θ(Θ)), positive for a sphere.
let acc_r = d(g1_r, Theta) - g1_theta * d(theta, Theta);
let acc_theta = d(g1_theta, Theta) + g1_r * d(theta, Theta);
let kappa1 = (g1_r * acc_theta - g1_theta * acc_r) / g1_norm.powi(3);
// Parallel: κ2 = n_ρ / ρ, with ρ the distance from the axis (eq 2.27 in exact form).
let rho = r * sin(theta);
let kappa2 = (n_r * sin(theta) + n_theta * cos(theta)) / rho;

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
