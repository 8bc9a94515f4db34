// Bending stiffness k_b [J]: the Helfrich (1973) energy with zero spontaneous curvature, per unit
// deformed area, w = (k_b/2)(κ1 + κ2)² (the Gaussian-curvature term k̄ κ1κ2 integrates to the
// constant 4πk̄ on a closed surface, Gauss–Bonnet, and loads nothing). Parsed by codegen, never
// compiled. Loads by shape.rs: the first variation of ∫ w dA (no reference curvature, so no
// prestress: a sphere of any radius has the same energy 8πk_b and S0 = 0).

let symbols = [kb];

let w_area = kb / 2 * (kappa1 + kappa2).powi(2);
