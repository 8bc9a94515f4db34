#!/usr/bin/env bash
# magbubble's Marmottant shell (shell.law = "marmottant", branch switches located as events)
# against APECSS's (Denner & Schenke, https://github.com/polycfd/apecss; `LipidCoatingModel
# Marmottant`, which evaluates the same buckled / elastic / ruptured law from R inside its steps)
# on the same radial physics; the result is in docs/peer-comparison.md, "Marmottant against
# Marmottant". Not part of CI.
#
#   scripts/peer_marmottant.sh APECSS_DIR [MAGBUBBLE]
#
# As scripts/peer_apecss.sh: APECSS's include/ and src/ compiled with gcc and
# scripts/peer/apecss_driver.c; work directory /tmp/magbubble-peer (or $PEER_WORK).
#
# Cases (both codes: Keller-Miksis c = 1500 m/s, polytropic ideal gas kappa = 1.4,
# p_g0 = p0 + 2 sigma(R0)/R0, p_inf = p0 (1 + eps cos 2 pi f t), start at rest, sampled every
# 1 ns): R0 = 2 um, chi = 0.5 N/m, sigma(R0) = 0.02 N/m (R_b = 0.9806 R0), rupture tension
# 0.072 N/m (R_r = 1.0488 R0; APECSS: SurfaceTensionCoeff), kappa_s = 1e-9 kg/s, f = 2.5 MHz,
# eps = 0.05 (elastic throughout), 0.2 and 0.5 (buckled and ruptured in every cycle), 4 us.
set -euo pipefail

apecss=${1:?usage: scripts/peer_marmottant.sh APECSS_DIR [MAGBUBBLE]}
here=$(cd "$(dirname "$0")" && pwd)
mb=${2:-$here/../target/release/magbubble}
work=${PEER_WORK:-/tmp/magbubble-peer}
mkdir -p "$work"
[ -x "$mb" ] || { echo "no magbubble binary at $mb (cargo build --release)" >&2; exit 1; }
[ -f "$apecss/include/apecss.h" ] || { echo "$apecss: not an APECSS checkout (no include/apecss.h)" >&2; exit 1; }
gcc -O2 -I"$apecss/include" "$apecss"/src/*.c "$here/peer/apecss_driver.c" -lm -o "$work/apecss_driver"
echo "APECSS: $(cd "$apecss" && (git rev-parse --short HEAD 2>/dev/null || echo 'no git')) ($apecss)"

r0=2e-6; chi=0.5; sigma0=0.02; sigma_r=0.072; kappa_s=1e-9; f=2.5e6; tend=4e-6; dt_out=1e-9
cat > "$work/marmottant.apecss" <<EOF
BUBBLE
InitialRadius $r0
RPModel KM
PressureAmbient 101325.0
END

GAS
EoS IG
ReferencePressure 101325.0
PolytropicExponent 1.4
END

LIQUID
ReferenceDensity 1000.0
ReferenceSoundSpeed 1500.0
Viscosity 0.001
END

INTERFACE
SurfaceTensionCoeff $sigma_r
LipidCoatingModel Marmottant
SigmaInit $sigma0
Elasticity $chi
DilatationalViscosity $kappa_s
END

ODESOLVER
Tolerance 1.0e-12
END
EOF
cat > "$work/marmottant.toml" <<EOF
[bubble]
radius = $r0
[shell]
c1 = 0.1
c2 = 0.12
law = "marmottant"
elasticity = $chi
initial_tension = $sigma0
rupture_tension = $sigma_r
dilatational_viscosity = $kappa_s
[gas]
polytropic_exponent = 1.4
[liquid]
density = 1000.0
viscosity = 0.001
ambient_pressure = 101325.0
sound_speed = 1500.0
[modes]
max_order = 0
[run]
duration = $tend
sample_interval = $dt_out
[run.integrator]
method = "dopri5"
rtol = 1e-12
atol = 1e-16
EOF

echo "== Marmottant: R0 = 2 um, chi = $chi N/m, sigma(R0) = $sigma0 N/m, sigma_r = $sigma_r N/m, kappa_s = $kappa_s kg/s, KM, f = 2.5 MHz"
for eps in 0.05 0.2 0.5; do
  "$work/apecss_driver" "$work/marmottant.apecss" "$tend" "$f" "$eps" "$r0" "$dt_out" > "$work/marmottant-$eps.apecss.txt" 2> "$work/marmottant-$eps.apecss.log"
  "$mb" run "$work/marmottant.toml" --out "$work/marmottant-$eps.mb" --set "drive.amplitude=$eps" --set "drive.frequency_hz=$f" > "$work/marmottant-$eps.mb.log"
  grep -q '^status: *completed' "$work/marmottant-$eps.mb.log" || { echo "eps=$eps: magbubble did not complete" >&2; cat "$work/marmottant-$eps.mb.log" >&2; exit 1; }
  python3 "$here/peer/compare.py" "marmottant eps=$eps" "$r0" "$work/marmottant-$eps.mb/series.csv" "$work/marmottant-$eps.apecss.txt"
  python3 - "$work/marmottant-$eps.mb/summary.json" <<'PY'
import json, sys
b = json.load(open(sys.argv[1])).get("shell_branches", {})
print(f"   magbubble branches: buckled {b.get('buckled', 0):.3f}, elastic {b.get('elastic', 0):.3f}, ruptured {b.get('ruptured', 0):.3f}, switches {b.get('switches', 0)}")
PY
done
