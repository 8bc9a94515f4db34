// Loads of an energy that depends on the shape only, w_area per unit deformed area (bending), by
// its first variation (the engine's `vary`: Euler–Lagrange in r at fixed Θ, by parts).
// Parsed by codegen, never compiled.
// E = 2π ∫ w_area dA, dA = ρ |g1| dΘ per radian of azimuth. A variation δr at fixed Θ moves the
// point by δr e_r, normal part n_r δr; δE = ∫ S_n δn dA defines the normal load S_n (positive
// when it resists an outward bulge, as S1 of eq 2.29). A tangential displacement only
// re-parametrizes the surface, so the tangential load of a shape energy is zero.

let density = w_area * rho * g1_norm;
let paper_n = vary(density, r) / (n_r * rho * g1_norm);
let paper_t = 0;
let tension_n = paper_n;
let tension_t = paper_t;
