// Marmottant, Van der Meer, Emmer, Versluis, de Jong, Hilgenfeldt & Lohse 2005 (JASA 118, 3499),
// eq 1, elastic branch, as an isotropic surface energy per reference area W(J), J = λ1λ2 = A/A0:
// the tension (force per current length) τ = dW/dJ = chib J − chi, i.e. σ(R) = χ(R²/R_b² − 1)
// with chi = χ and chib = χ R0²/R_b² [N/m]. Parsed by codegen, never compiled; stresses by
// hyperelastic.rs, loads by membrane.rs (tension form; the runtime uses only that form).
// The law's other branches need no spec (docs/model.md, "Lipid shells: Marmottant"): buckled,
// W = const (τ = 0); ruptured, W = σ_r J (τ = σ_r), this spec with chib = 0, chi = −σ_r. Any
// isotropic W(J) has loads linear in (W′, J W″) at J, so this two-symbol spec is the basis
// from which the runtime builds every branch and the smooth variant.

let symbols = [chi, chib];

let J = lambda1 * lambda2;
let W = chib / 2 * J.powi(2) - chi * J;
