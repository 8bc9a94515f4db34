// Second-order (quadratic) mode coupling of a free bubble (issue 12; docs/model.md, "Quadratic
// mode coupling"). Parsed by codegen, never compiled. The engine (codegen/src/derive/quadratic.rs)
// states the potential flow itself, as it states the ponderomotive force of a field spec: the
// surface r = R + Σ a_n P_n(cos θ) (Eulerian shape amplitudes), φ = −R²Ṙ/r + Σ c_n r^{−(n+1)} P_n
// + Σ d_j r^{−(j+1)} P_j, the kinematic condition ∂f/∂t = φ_r − φ_θ f_θ/r² and the dynamic one
// ρ(φ_t + ½|∇φ|²) + p_g(V) − γ(κ1 + κ2) − p∞ = 0 on the exact surface, both to second order,
// c and d eliminated order by order. This spec selects the pieces; each must be one the engine
// knows (anything else is an error, so a new piece cannot be silently ignored).

// The liquid: incompressible, inviscid (potential flow). Viscous stresses stay linear (the
// runtime's closures); their second-order terms are not derived.
let liquid = inviscid;
// The interface: an isotropic surface tension gamma, with the exact curvatures of r = f(θ).
let interface = surface_tension;
// The gas: polytropic, p_g(R) (V_R/V)^kappa at the exact volume V = (2π/3)∫(R + ζ)³ dx.
let gas = polytropic;
