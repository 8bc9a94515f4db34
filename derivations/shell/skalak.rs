// Skalak membrane (Skalak, Tozeren, Zarda & Chien 1973; used for encapsulated bubbles by
// Tsiglifis & Pelekasis 2011): strain energy per reference area, G_s the shear modulus [N/m],
// C the area-dilatation parameter [–]; small strain: area-dilatation modulus K = G_s (1 + 2C).
// Parsed by codegen, never compiled. The spec states W only: stresses by hyperelastic.rs
// (σ_i = λ_i ∂W/∂λ_i), loads by membrane.rs.

let symbols = [Gs, C];

let I1 = lambda1.powi(2) + lambda2.powi(2) - 2;
let I2 = (lambda1 * lambda2).powi(2) - 1;
let W = Gs / 4 * (I1.powi(2) + 2 * I1 - 2 * I2 + C * I2.powi(2));
