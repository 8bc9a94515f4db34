// Fixture: a field whose magnitude grows linearly along the axis, h = G r cos θ e_z.
let symbols = [mu0, chi_s, G];
let amplitudes = [G];
let h_z = G * r * cos_t;
let h_r = h_z * cos_t;
let h_theta = -h_z * sin_t;
let susceptibility = mu0 * chi_s;
let unit = 1;
