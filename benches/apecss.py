#!/usr/bin/env python3
"""magbubble against APECSS on the radial runs (issue 34): process CPU at equal accuracy.

Called by benches/apecss.sh (which builds both codes):
    apecss.py WORK MAGBUBBLE APECSS_DRIVER REPS [CASE ...]

For each case (R0 = 5 um, f = 1 MHz, 50 periods, Keller-Miksis, polytropic air in water) and
each code, a tolerance ladder is run; the error is |R(t_end) - R_ref| / R0 against the code's own
tight reference. For the targets 1e-6 and 1e-9 the loosest tolerance whose error, and the
errors of every tighter rung, stay below the target is chosen. Then REPS interleaved pairs
(magbubble, APECSS) run at the chosen tolerances and the process CPU (user + system, from
wait4) of each is recorded; the table gives the medians and their ratio. magbubble runs with
dop853, dopri5 and with no method key (the default). Each pair is followed by a process that does
nothing (EMPTY, a C `main` returning 0: the exec, loader and exit every process pays on this
machine); its median over APECSS's is the floor, the smallest ratio any program could reach.
"""
import json
import os
import resource
import statistics
import subprocess
import sys
import time

WORK, MB, DRIVER, EMPTY, REPS = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4], int(sys.argv[5])
ONLY = sys.argv[6:]
R0, F, PERIODS = 5e-6, 1e6, 50
T_END = PERIODS / F
RHO, ETA, P0, C, KAPPA = 1000.0, 1e-3, 101325.0, 1500.0, 1.4
LADDER = [10 ** (-k / 2) for k in range(6, 27)]  # 1e-3 ... 1e-13
TARGETS = [1e-6, 1e-9]
METHODS = ["dop853", "dopri5", None]  # None: no method key (the default)

# name, eps, magbubble [shell] table, APECSS INTERFACE block
SIGMA, C1, C2, KS = 0.072, 0.1, 0.12, 1e-9
CHI_MR = 6 * (C1 + C2) - SIGMA  # same small-strain stiffness as the Mooney-Rivlin membrane
CHI_M, SIGMA0_M = 0.5, 0.02  # the Marmottant case: APECSS's default elasticity, initial tension
CASES = [
    ("free eps=0.1", 0.1,
     f"c1 = 0.0\nc2 = 0.0\nsurface_tension = {SIGMA}\n",
     f"SurfaceTensionCoeff {SIGMA}\n"),
    ("free eps=1.0", 1.0,
     f"c1 = 0.0\nc2 = 0.0\nsurface_tension = {SIGMA}\n",
     f"SurfaceTensionCoeff {SIGMA}\n"),
    ("MR shell vs Marmottant elastic", 0.1,
     f"c1 = {C1}\nc2 = {C2}\nsurface_tension = {SIGMA}\ndilatational_viscosity = {KS}\n",
     f"SurfaceTensionCoeff 1000.0\nLipidCoatingModel Marmottant\nSigmaInit {SIGMA}\n"
     f"Elasticity {CHI_MR}\nDilatationalViscosity {KS}\n"),
    ("Marmottant (both)", 0.1,
     f'law = "marmottant"\nelasticity = {CHI_M}\ninitial_tension = {SIGMA0_M}\n'
     f"rupture_tension = {SIGMA}\ndilatational_viscosity = {KS}\n",
     f"SurfaceTensionCoeff {SIGMA}\nLipidCoatingModel Marmottant\nSigmaInit {SIGMA0_M}\n"
     f"Elasticity {CHI_M}\nDilatationalViscosity {KS}\n"),
]


def slug(name):
    return "".join(ch if ch.isalnum() else "_" for ch in name)


def write_inputs(name, eps, shell, interface):
    s = slug(name)
    with open(f"{WORK}/{s}.toml", "w") as f:
        f.write(f"""[bubble]
radius = {R0}
[shell]
{shell}[gas]
polytropic_exponent = {KAPPA}
[liquid]
density = {RHO}
viscosity = {ETA}
ambient_pressure = {P0}
sound_speed = {C}
[drive]
amplitude = {eps}
frequency_hz = {F}
[modes]
max_order = 0
[run]
duration = {T_END}
sample_interval = {T_END}
""")
    with open(f"{WORK}/{s}.apecss.in", "w") as f:
        f.write(f"""BUBBLE
InitialRadius {R0}
RPModel KM
PressureAmbient {P0}
END
GAS
EoS IG
ReferencePressure {P0}
PolytropicExponent {KAPPA}
END
LIQUID
ReferenceDensity {RHO}
ReferenceSoundSpeed {C}
Viscosity {ETA}
END
INTERFACE
{interface}END
ODESOLVER
Tolerance TOL
END
""")
    return s


def timed(cmd):
    """(stdout, process CPU seconds) of one run."""
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    out, err = p.communicate()
    # communicate() reaps the child; its rusage is read from the children total
    return out, err, p.returncode


def cpu_of(cmd):
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    out, err, rc = timed(cmd)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return out, err, rc, cpu


def mb_cmd(s, method, tol, atol=None):
    cmd = [MB, "run", f"{WORK}/{s}.toml", "--out", f"{WORK}/{s}.mb"]
    if method:
        cmd += ["--set", f"run.integrator.method={method}"]
    cmd += ["--set", f"run.integrator.rtol={tol:.3e}", "--set", f"run.integrator.atol={(atol or tol):.3e}"]
    return cmd


def mb_final(s, method, tol, atol=None):
    out, err, rc = timed(mb_cmd(s, method, tol, atol))
    if rc != 0:
        raise SystemExit(f"magbubble {s} {method} {tol}: exit {rc}\n{out}\n{err}")
    summary = json.load(open(f"{WORK}/{s}.mb/summary.json"))
    if summary["status"] != "completed":
        return float("nan")
    return summary["final_state"]["R"]


def ap_input(s, tol):
    text = open(f"{WORK}/{s}.apecss.in").read().replace("Tolerance TOL", f"Tolerance {tol:.3e}")
    path = f"{WORK}/{s}.{tol:.3e}.apecss"
    with open(path, "w") as f:
        f.write(text)
    return path


def ap_cmd(s, eps, tol):
    return [DRIVER, ap_input(s, tol), str(T_END), str(F), str(eps), str(R0), str(T_END)]


def ap_final(s, eps, tol):
    out, err, rc = timed(ap_cmd(s, eps, tol))
    if rc != 0:
        raise SystemExit(f"APECSS {s} {tol}: exit {rc}\n{err}")
    return float(out.split()[-1])


def choose(errors, target):
    """Loosest rung whose error and every tighter rung's error are <= target."""
    ok = None
    for tol, e in sorted(errors.items()):  # tightest first
        if e <= target:
            ok = tol
        else:
            break
    return ok


def main():
    load = os.getloadavg()[0]
    print(f"# magbubble vs APECSS, {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, load {load:.1f}, "
          f"{REPS} interleaved pairs, R0 = 5 um, f = 1 MHz, {PERIODS} periods")
    rows = []
    for name, eps, shell, interface in CASES:
        if ONLY and not any(o in name for o in ONLY):
            continue
        s = write_inputs(name, eps, shell, interface)
        ref_mb = mb_final(s, "dop853", 1e-14, 1e-16)
        ref_ap = ap_final(s, eps, 1e-14)
        print(f"\n## {name}: R_ref magbubble {ref_mb!r}, APECSS {ref_ap!r}, "
              f"|difference|/R0 = {abs(ref_mb - ref_ap) / R0:.1e}")
        err_ap = {tol: abs(ap_final(s, eps, tol) - ref_ap) / R0 for tol in LADDER}
        err_mb = {m: {tol: abs(mb_final(s, m, tol) - ref_mb) / R0 for tol in LADDER} for m in METHODS}
        for target in TARGETS:
            tol_ap = choose(err_ap, target)
            for m in METHODS:
                tol_mb = choose(err_mb[m], target)
                label = m or "default"
                if tol_ap is None or tol_mb is None:
                    print(f"{name} | {target:.0e} | {label}: no tolerance reaches the target "
                          f"(magbubble {tol_mb}, APECSS {tol_ap})")
                    continue
                cpu_mb, cpu_ap, cpu_0 = [], [], []
                for _ in range(REPS):
                    cpu_mb.append(cpu_of(mb_cmd(s, m, tol_mb))[3])
                    cpu_ap.append(cpu_of(ap_cmd(s, eps, tol_ap))[3])
                    cpu_0.append(cpu_of([EMPTY])[3])
                a, b, z = statistics.median(cpu_mb), statistics.median(cpu_ap), statistics.median(cpu_0)
                rows.append((name, target, label, tol_mb, err_mb[m][tol_mb], a, tol_ap, err_ap[tol_ap], b, z))
                print(f"{name} | {target:.0e} | {label} rtol {tol_mb:.1e} err {err_mb[m][tol_mb]:.1e} "
                      f"CPU {a * 1e3:.2f} ms | APECSS tol {tol_ap:.1e} err {err_ap[tol_ap]:.1e} "
                      f"CPU {b * 1e3:.2f} ms | ratio {a / b:.2f} | empty process {z * 1e3:.2f} ms", flush=True)
    print("\n| case | error | magbubble method | magbubble CPU [ms] | APECSS CPU [ms] | ratio | empty process [ms] | floor |")
    print("|---|---|---|---|---|---|---|---|")
    for name, target, label, tm, em, a, ta, ea, b, z in rows:
        print(f"| {name} | {target:.0e} | {label} (rtol {tm:.0e}) | {a * 1e3:.2f} | {b * 1e3:.2f} (tol {ta:.0e}) "
              f"| {a / b:.2f}× | {z * 1e3:.2f} | {z / b:.2f}× |")


main()
