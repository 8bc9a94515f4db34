// Kinematics of the bubble surface, eqs (2.14)–(2.21) of the paper, in their EXACT forms.
// Parsed by codegen (syn), never compiled or executed: the engine linearizes in a_k, b_k.
// Built-ins: R, R0 (current and reference radius), Theta (material angle Θ), a_k, b_k (mode
// amplitudes), P(k) = P_k(cos Θ), P1(k) = dP_k/dΘ (Condon–Shortley, FORMULATION §1).

// Eq (2.14): the material point (R0, Θ) moves to (r, θ).
let r = R + a_k * P(k);
let theta = Theta + b_k / R * P1(k);

// Eq (2.16): meridian tangent g1 = x_Θ = r_Θ e_r + r θ_Θ e_θ (components in the deformed frame).
let g1_r = d(r, Theta);
let g1_theta = r * d(theta, Theta);
let g1_norm = sqrt(g1_r.powi(2) + g1_theta.powi(2));

// Eq (2.20), first (exact) expressions of the principal stretches.
let lambda1 = g1_norm / R0;
let lambda2 = r * sin(theta) / (R0 * sin(Theta));

// Eq (2.21), exact: unit tangent (towards increasing Θ) and outward normal.
let t_r = g1_r / g1_norm;
let t_theta = g1_theta / g1_norm;
let n_r = t_theta;
let n_theta = -t_r;

// Exact principal curvatures of the deformed surface (replace the approximations 2.23), for the
// shell laws. Meridian: curvature of the plane curve r(Θ) e_r(θ(Θ)), positive for a sphere.
let acc_r = d(g1_r, Theta) - g1_theta * d(theta, Theta);
let acc_theta = d(g1_theta, Theta) + g1_r * d(theta, Theta);
let kappa1 = (g1_r * acc_theta - g1_theta * acc_r) / g1_norm.powi(3);
// Parallel: κ2 = n_ρ / ρ, with ρ the distance from the axis (eq 2.27 in exact form).
let rho = r * sin(theta);
let kappa2 = (n_r * sin(theta) + n_theta * cos(theta)) / rho;

// Eq (2.39): the area factor 1/(λ1 λ2), applied once to the magnetic force.
let area = 1 / (lambda1 * lambda2);
