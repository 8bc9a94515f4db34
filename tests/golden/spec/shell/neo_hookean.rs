// Fixture: a neo-Hookean membrane (C2 = 0 form of eq 2.24), stresses by hyperelastic.rs.
let symbols = [C1];
let W = C1 * (lambda1.powi(2) + lambda2.powi(2) + (lambda1 * lambda2).powi(-2) - 3);
