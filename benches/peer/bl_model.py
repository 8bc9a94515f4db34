#!/usr/bin/env python3
"""Peer implementation of magbubble's model in SciPy (issue 6, part 2) -- radial part only.

Implements FORMULATION sec 4.1 (paper eq 2.62 corrected), in SI units, for scenes without
shape modes (modes.max_order = 0) and without a field:

    rho (R R'' + 3/2 R'^2) = p_g0 (R0/R)^(3 kappa) - p_inf(t) - 4 eta R'/R - S0(R),
    p_inf = p0 (1 + eps_p cos(2 pi f_d t)),
    S0 = -4 c1 R0^6/R^7 + 4 c1/R - 4 c2 R0^4/R^5 + 4 c2 R/R0^2   (shell.form = "paper").

The shape modes of the boundary-layer model (FORMULATION sec 4.3) are NOT implemented here
(they need the generated coupling tables); see docs/accuracy.md.

Usage: bl_model.py SCENE.toml DURATION SAMPLES OUT.csv
Writes rows: method,rtol,error,wall_seconds,nfev, where error = max_i |R - R_ref|/R0 on the
sample grid t_i = i DURATION/SAMPLES, against SciPy DOP853 at rtol 1e-13 (its own error is
printed as the difference to rtol 1e-12). Wall time = median of 3 runs.
"""
import math
import statistics
import sys
import time

try:
    import tomllib
except ImportError:  # Python < 3.11
    import tomli as tomllib
import numpy as np
from scipy.integrate import solve_ivp


def params(path):
    with open(path, "rb") as f:
        s = tomllib.load(f)
    if s.get("modes", {}).get("max_order", 16) != 0 or "field" in s:
        raise SystemExit(f"{path}: the peer covers radial-only scenes without a field (modes.max_order = 0)")
    liquid, gas = s.get("liquid", {}), s.get("gas", {})
    p0 = liquid.get("ambient_pressure", 101325.0)
    drive = s.get("drive", {})
    return dict(
        R0=s["bubble"]["radius"], c1=s["shell"]["c1"], c2=s["shell"]["c2"],
        rho=liquid.get("density", 1000.0), eta=liquid.get("viscosity", 1e-3), p0=p0,
        pg0=gas.get("reference_pressure", p0), kappa=gas.get("polytropic_exponent", 1.4),
        eps=drive.get("amplitude", 0.0), w=2 * math.pi * drive.get("frequency_hz", 0.0),
    )


def make_rhs(p):
    R0, c1, c2, rho, eta, p0, pg0, k3, eps, w = (p[k] for k in ("R0", "c1", "c2", "rho", "eta", "p0", "pg0", "kappa", "eps", "w"))
    k3 = 3 * k3

    def rhs(t, y):
        R, Rd = y
        s0 = -4 * c1 * R0**6 / R**7 + 4 * c1 / R - 4 * c2 * R0**4 / R**5 + 4 * c2 * R / R0**2
        pinf = p0 * (1 + eps * math.cos(w * t))
        Rdd = (pg0 * (R0 / R) ** k3 - pinf - 4 * eta * Rd / R - s0) / (rho * R) - 1.5 * Rd * Rd / R
        return [Rd, Rdd]

    return rhs


def solve(rhs, p, t_eval, method, rtol, atol):
    y0 = [p["R0"], 0.0]
    return solve_ivp(rhs, (0.0, t_eval[-1]), y0, method=method, t_eval=t_eval, rtol=rtol, atol=atol)


def main():
    scene, duration, samples, out = sys.argv[1], float(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
    p = params(scene)
    rhs = make_rhs(p)
    t_eval = np.linspace(0.0, duration, samples + 1)
    R0 = p["R0"]
    # atol on R [m]: 1e-3 rtol R0, as magbubble's accuracy study (atol = 1e-3 rtol on R/R0);
    # on R' [m/s] scaled by R0/t*.
    tstar = math.sqrt(p["rho"] * R0**3 / (2 * p["c1"]))
    atol = lambda r: [1e-3 * r * R0, 1e-3 * r * R0 / tstar]
    ref = solve(rhs, p, t_eval, "DOP853", 1e-13, atol(1e-13))
    ref2 = solve(rhs, p, t_eval, "DOP853", 1e-12, atol(1e-12))
    ref_err = float(np.max(np.abs(ref2.y[0] - ref.y[0])) / R0)
    print(f"peer reference: SciPy DOP853 rtol 1e-13, estimated error {ref_err:.2e}")
    rows = []
    for method in ("RK45", "DOP853", "Radau", "LSODA"):
        for rtol in (1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9):
            walls = []
            for _ in range(3):
                t0 = time.perf_counter()
                sol = solve(rhs, p, t_eval, method, rtol, atol(rtol))
                walls.append(time.perf_counter() - t0)
            err = float(np.max(np.abs(sol.y[0] - ref.y[0])) / R0) if sol.success and sol.y.shape[1] == len(t_eval) else float("inf")
            rows.append((method, rtol, err, statistics.median(walls), sol.nfev))
            print(f"{method:>7} rtol {rtol:.0e}: error {err:.3e}, {statistics.median(walls):.4f} s, {sol.nfev} rhs")
    with open(out, "w") as f:
        f.write("method,rtol,error,wall_seconds,nfev\n")
        for r in rows:
            f.write(",".join(str(x) for x in r) + "\n")
    np.savetxt(out + ".ref.csv", np.column_stack([t_eval, ref.y[0]]), delimiter=",", header="t,R", comments="")


if __name__ == "__main__":
    main()
