#!/usr/bin/env python3
"""Peer implementation of magbubble's boundary-layer model in SciPy (issue 6, part 2).

SI units, scenes without a magnetic field, shell.form = "paper":

* radial (FORMULATION sec 4.1, paper eq 2.62 corrected):
    rho (R R'' + 3/2 R'^2) = p_g0 (R0/R)^(3 kappa) - p_inf(t) - 4 eta R'/R - S0(R),
    p_inf = p0 (1 + eps_p cos(2 pi f_d t));
* shape modes k = 2, 4, ..., N with the boundary-layer closure (FORMULATION sec 4.3, paper
  eqs 3.1-3.2 corrected; the same formulas as runtime/model/boundary_layer.rs).

The membrane loads S0, S1, S2, S11, S12 are not typed in: they are read from the doc lines
(`/// S1 = ...`) of magbubble's generated coefficients.rs (`--coefficients PATH`, found by run.sh).

Usage: bl_model.py SCENE.toml DURATION SAMPLES OUT.csv COEFFICIENTS.rs
Writes rows: method,rtol,error,wall_seconds,nfev, where error = max_i max(|R - R_ref|,
max_k |a_k - a_k,ref|)/R0 on the sample grid t_i = i DURATION/SAMPLES, against SciPy DOP853 at
rtol 1e-13 (its own error is printed as the difference to rtol 1e-12). Wall time = median of 3.
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
    if "field" in s or s.get("shell", {}).get("form", "paper") != "paper":
        raise SystemExit(f"{path}: the peer covers scenes without a field and with shell.form = paper")
    modes = s.get("modes", {})
    if modes.get("viscous", "boundary-layer") != "boundary-layer":
        raise SystemExit(f"{path}: the peer implements the boundary-layer closure only")
    liquid, gas = s.get("liquid", {}), s.get("gas", {})
    init = s["bubble"].get("initial", {})
    p0 = liquid.get("ambient_pressure", 101325.0)
    drive = s.get("drive", {})
    return dict(
        R0=s["bubble"]["radius"], c1=s["shell"]["c1"], c2=s["shell"]["c2"],
        rho=liquid.get("density", 1000.0), eta=liquid.get("viscosity", 1e-3), p0=p0,
        pg0=gas.get("reference_pressure", p0), kappa=gas.get("polytropic_exponent", 1.4),
        eps=drive.get("amplitude", 0.0), w=2 * math.pi * drive.get("frequency_hz", 0.0),
        N=modes.get("max_order", 16), bl_freq=modes.get("boundary_layer_frequency", "auto"),
        R_init=init.get("radius", s["bubble"]["radius"]), Rd_init=init.get("velocity", 0.0),
        a_init={int(k): v for k, v in init.get("a", {}).items()},
        ad_init={int(k): v for k, v in init.get("a_velocity", {}).items()},
        b_init={int(k): v for k, v in init.get("b", {}).items()},
    )


def membrane(coefficients):
    """The paper-form membrane loads as functions of (R, R0, C1, C2, n), from the generated file."""
    text = open(coefficients).read()
    paper = text[text.index("pub mod paper"):text.index("pub mod tension")]
    loads = {}
    for line in paper.splitlines():
        line = line.strip()
        for name in ("S0", "S1", "S2", "S11", "S12"):
            if line.startswith(f"/// {name} = "):
                expr = line.split(" = ", 1)[1].replace("^", "**")
                loads[name] = eval(f"lambda R, R0, C1, C2, n: {expr}")
    return loads


def make_rhs(p, S):
    R0, c1, c2, rho, eta, p0, pg0, k3, eps, w = (p[k] for k in ("R0", "c1", "c2", "rho", "eta", "p0", "pg0", "kappa", "eps", "w"))
    k3 = 3 * k3
    k = np.arange(2, p["N"] + 1, 2, dtype=float)
    n = k * (k + 1)
    kp1 = k + 1
    nu = eta / rho
    if p["bl_freq"] == "auto" and eps != 0.0:
        omega = np.full_like(k, w)
    else:  # FORMULATION sec 4.4 (corrected 3.10)
        omega = np.sqrt(12 * (c1 + c2) * (k - 1) * (k + 1) * (k + 2) / (rho * R0**3 * (2 * k * k + 2 * k - 1)))
    vlen = np.sqrt(nu / omega)

    def rhs(t, y):
        R, Rd = y[0], y[1]
        pinf = p0 * (1 + eps * math.cos(w * t))
        Rdd = (pg0 * (R0 / R) ** k3 - pinf - 4 * eta * Rd / R - S["S0"](R, R0, c1, c2, 0.0)) / (rho * R) - 1.5 * Rd * Rd / R
        if len(k) == 0:
            return [Rd, Rdd]
        a, ad, b = y[2::3], y[3::3], y[4::3]
        gn = S["S1"](R, R0, c1, c2, n) * a + S["S2"](R, R0, c1, c2, n) * b
        gt = S["S11"](R, R0, c1, c2, n) * a + S["S12"](R, R0, c1, c2, n) * b
        delta = np.minimum(vlen, R / (2 * k))
        tw = (2 * (k + 2) * ad / kp1 + 2 * (1 - k) * Rd * a / (kp1 * R) - R * gt / eta) / (1 + 2 * delta / R)
        bd = Rd * b / R - ad / kp1 - 2 * Rd * a / (kp1 * R) + delta * tw / R
        add = -(3 * Rd * ad - (k - 1) * Rdd * a) / R - kp1 / (rho * R) * (
            2 * eta * (k + 2) * ad / R + 4 * eta * (k - 1) * Rd * a / (R * R) + (k * eta * tw / R) * (1 - 2 * kp1 * delta / R) + gn)
        dy = np.empty_like(y)
        dy[0], dy[1] = Rd, Rdd
        dy[2::3], dy[3::3], dy[4::3] = ad, add, bd
        return dy

    return rhs


def initial(p):
    y0 = [p["R_init"], p["Rd_init"]]
    for k in range(2, p["N"] + 1, 2):
        y0 += [p["a_init"].get(k, 0.0), p["ad_init"].get(k, 0.0), p["b_init"].get(k, 0.0)]
    return np.array(y0)


def solve(rhs, p, t_eval, method, rtol, atol):
    y0 = initial(p)
    return solve_ivp(rhs, (0.0, t_eval[-1]), y0, method=method, t_eval=t_eval, rtol=rtol, atol=atol)


def main():
    scene, duration, samples, out, coefficients = sys.argv[1], float(sys.argv[2]), int(sys.argv[3]), sys.argv[4], sys.argv[5]
    p = params(scene)
    rhs = make_rhs(p, membrane(coefficients))
    t_eval = np.linspace(0.0, duration, samples + 1)
    R0 = p["R0"]
    # atol on R [m]: 1e-3 rtol R0, as magbubble's accuracy study (atol = 1e-3 rtol on R/R0);
    # on R' [m/s] scaled by R0/t*.
    tstar = math.sqrt(p["rho"] * R0**3 / (2 * p["c1"]))
    # same scaling for (a_k, a_k', b_k)
    scale = np.array([R0, R0 / tstar] + [R0, R0 / tstar, R0] * (p["N"] // 2))
    atol = lambda r: 1e-3 * r * scale
    # compared columns: R and every a_k (rows of sol.y)
    cols = [0] + list(range(2, 2 + 3 * (p["N"] // 2), 3))

    def err(y, yref):
        return float(np.max(np.abs(y[cols] - yref[cols])) / R0)
    ref = solve(rhs, p, t_eval, "DOP853", 1e-13, atol(1e-13))
    ref2 = solve(rhs, p, t_eval, "DOP853", 1e-12, atol(1e-12))
    ref_err = err(ref2.y, ref.y)
    print(f"peer reference: SciPy DOP853 rtol 1e-13, estimated error {ref_err:.2e}")
    rows = []
    for method in ("RK45", "DOP853", "Radau", "LSODA"):
        for rtol in (1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9):
            walls = []
            for _ in range(3):
                t0 = time.perf_counter()
                sol = solve(rhs, p, t_eval, method, rtol, atol(rtol))
                walls.append(time.perf_counter() - t0)
            e = err(sol.y, ref.y) if sol.success and sol.y.shape[1] == len(t_eval) else float("inf")
            rows.append((method, rtol, e, statistics.median(walls), sol.nfev))
            print(f"{method:>7} rtol {rtol:.0e}: error {e:.3e}, {statistics.median(walls):.4f} s, {sol.nfev} rhs")
    with open(out, "w") as f:
        f.write("method,rtol,error,wall_seconds,nfev\n")
        for r in rows:
            f.write(",".join(str(x) for x in r) + "\n")
    names = ["R"] + [f"a{k}" for k in range(2, p["N"] + 1, 2)]
    np.savetxt(out + ".ref.csv", np.column_stack([t_eval] + [ref.y[c] for c in cols]), delimiter=",",
               header=",".join(["t"] + names), comments="")


if __name__ == "__main__":
    main()
