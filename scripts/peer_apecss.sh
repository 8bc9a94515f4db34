#!/usr/bin/env bash
# Side-by-side runs of magbubble and the public bubble code APECSS (Denner & Schenke,
# https://github.com/polycfd/apecss) on the same radial cases; the results are in
# docs/peer-comparison.md.
#
#   scripts/peer_apecss.sh APECSS_DIR [MAGBUBBLE]
#
# APECSS_DIR: a checkout of APECSS (its include/ and src/ are compiled with gcc together with
# scripts/peer/apecss_driver.c; no cmake needed). MAGBUBBLE: the binary (default
# target/release/magbubble). Nothing of APECSS is part of this repository; the work directory
# (default /tmp/magbubble-peer, or $PEER_WORK) holds the build and the series.
#
# Cases (both codes: Keller-Miksis, polytropic ideal gas, p_g0 = p0 + 2 sigma0/R0, drive
# p_inf = p0 (1 + eps cos 2 pi f t), start at rest; sampled every 1 ns at the same times):
#   free  — air bubble R0 = 5 um, surface tension 0.072 N/m, no shell, f = 500 kHz,
#           eps = 0.1, 0.5, 1.0, and a ring-down from R(0) = 1.01 R0;
#   lipid — R0 = 2 um, magbubble's Mooney-Rivlin membrane (c1 = 0.1, c2 = 0.12 N/m) + tension
#           sigma0 = 0.072 N/m against APECSS's Marmottant shell in its elastic branch with the
#           same small-strain stiffness (chi = 6 (c1 + c2) - sigma0, sigma_init = sigma0, rupture
#           tension out of reach), dilatational viscosity kappa_s = 1e-9 kg/s in both,
#           f = 2.5 MHz, eps = 0.02, 0.05, 0.1, and a ring-down from R(0) = 1.005 R0.
set -euo pipefail

apecss=${1:?usage: scripts/peer_apecss.sh APECSS_DIR [MAGBUBBLE]}
here=$(cd "$(dirname "$0")" && pwd)
mb=${2:-$here/../target/release/magbubble}
work=${PEER_WORK:-/tmp/magbubble-peer}
mkdir -p "$work"
[ -x "$mb" ] || { echo "no magbubble binary at $mb (cargo build --release)" >&2; exit 1; }
[ -f "$apecss/include/apecss.h" ] || { echo "$apecss: not an APECSS checkout (no include/apecss.h)" >&2; exit 1; }

gcc -O2 -I"$apecss/include" "$apecss"/src/*.c "$here/peer/apecss_driver.c" -lm -o "$work/apecss_driver"
echo "APECSS: $(cd "$apecss" && (git rev-parse --short HEAD 2>/dev/null || echo 'no git')) ($apecss)"

dt_out=1e-9
rho=1000.0; eta=0.001; p0=101325.0; c=1500.0; kappa=1.4
kappa_s=${KAPPA_S:-1e-9}   # the lipid shell's dilatational viscosity [kg/s]

# apecss_options NAME R0 SIGMA0 CHI KAPPA_S
apecss_options() {
  local interface="SurfaceTensionCoeff $3"
  if [ "$4" != 0 ]; then
    interface="SurfaceTensionCoeff 1000.0
LipidCoatingModel Marmottant
SigmaInit $3
Elasticity $4
DilatationalViscosity $5"
  fi
  cat > "$work/$1.apecss" <<EOF
BUBBLE
InitialRadius $2
RPModel KM
PressureAmbient $p0
END

GAS
EoS IG
ReferencePressure $p0
PolytropicExponent $kappa
END

LIQUID
ReferenceDensity $rho
ReferenceSoundSpeed $c
Viscosity $eta
END

INTERFACE
$interface
END

ODESOLVER
Tolerance 1.0e-12
END
EOF
}

# magbubble_scene NAME R0 SIGMA0 C1 C2 KAPPA_S
magbubble_scene() {
  cat > "$work/$1.toml" <<EOF
[bubble]
radius = $2
[shell]
c1 = $4
c2 = $5
surface_tension = $3
dilatational_viscosity = $6
[gas]
polytropic_exponent = $kappa
[liquid]
density = $rho
viscosity = $eta
ambient_pressure = $p0
sound_speed = $c
[modes]
max_order = 0
[run]
duration = 1e-5
sample_interval = $dt_out
[run.integrator]
method = "dopri5"
rtol = 1e-12
atol = 1e-16
EOF
}

# one NAME R0 F EPS RINIT TEND [ringdown]
one() {
  local name=$1 r0=$2 f=$3 eps=$4 rinit=$5 tend=$6 label
  label="$name eps=$eps"
  [ "${7:-}" = ringdown ] && label="$name ring-down"
  "$work/apecss_driver" "$work/$name.apecss" "$tend" "$f" "$eps" "$rinit" "$dt_out" > "$work/$name-$eps.apecss.txt" 2> "$work/$name-$eps.apecss.log"
  local drive=(--set "drive.amplitude=$eps" --set "drive.frequency_hz=$f")
  [ "$eps" = 0 ] && drive=()
  "$mb" run "$work/$name.toml" --out "$work/$name-$eps.mb" --set "run.duration=$tend" \
    --set "bubble.initial.radius=$rinit" "${drive[@]}" > "$work/$name-$eps.mb.log"
  grep -q '^status: *completed' "$work/$name-$eps.mb.log" || { echo "$label: magbubble did not complete:" >&2; cat "$work/$name-$eps.mb.log" >&2; exit 1; }
  python3 "$here/peer/compare.py" "$label" "$r0" "$work/$name-$eps.mb/series.csv" "$work/$name-$eps.apecss.txt" ${7:-}
}

echo "== free bubble: R0 = 5 um, sigma = 0.072 N/m, KM c = 1500 m/s, f = 500 kHz"
apecss_options free 5e-6 0.072 0 0
magbubble_scene free 5e-6 0.072 0.0 0.0 0.0
"$mb" modes "$work/free.toml" > "$work/free.modes"; head -1 "$work/free.modes"
one free 5e-6 5e5 0 5.05e-6 5e-6 ringdown
for eps in 0.1 0.5 1.0; do one free 5e-6 5e5 "$eps" 5e-6 1e-5; done

echo "== lipid shell: R0 = 2 um, MR c1 = 0.1, c2 = 0.12 N/m + sigma0 = 0.072 N/m vs Marmottant chi = 1.248 N/m, kappa_s = $kappa_s kg/s, f = 2.5 MHz"
apecss_options lipid 2e-6 0.072 1.248 "$kappa_s"
magbubble_scene lipid 2e-6 0.072 0.1 0.12 "$kappa_s"
"$mb" modes "$work/lipid.toml" > "$work/lipid.modes"; head -1 "$work/lipid.modes"
one lipid 2e-6 2.5e6 0 2.01e-6 2e-6 ringdown
for eps in 0.02 0.05 0.1; do one lipid 2e-6 2.5e6 "$eps" 2e-6 4e-6; done
