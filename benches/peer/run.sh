#!/usr/bin/env bash
# Peer comparison (issue 6, part 2; not part of CI): magbubble vs SciPy solve_ivp on the same
# scene (no field; radial only or boundary-layer shape modes), speed ratio at equal accuracy.
# Usage: [DURATION=20e-6] [OUT=dir] benches/peer/run.sh [SCENE]   (default: scenes/radial_only.toml)
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
scene="${1:-$root/scenes/radial_only.toml}"
out="${OUT:-$root/out/peer}"
duration="${DURATION:-100e-6}"
samples=1000
python3 -c "import scipy, numpy" 2>/dev/null || python3 -m pip install --user scipy numpy
python3 -c "import tomllib" 2>/dev/null || python3 -c "import tomli" 2>/dev/null || python3 -m pip install --user tomli
(cd "$root" && cargo build --release --quiet)
mkdir -p "$out"
# magbubble: the accuracy study on the same duration and sample grid (1000 samples)
"$root/target/release/magbubble" accuracy "$scene" --duration "$duration" --repeats 3 --out "$out/magbubble" | tee "$out/magbubble.txt"
# the membrane loads are read from magbubble's generated tables (newest build)
coeffs="$(ls -t "$root"/target/release/build/magbubble-*/out/coefficients.rs | head -1)"
python3 "$root/benches/peer/bl_model.py" "$scene" "$duration" "$samples" "$out/scipy.csv" "$coeffs" | tee "$out/scipy.txt"
# the two references must agree, or the errors are not comparable
"$root/target/release/magbubble" run "$scene" --out "$out/ref" --set run.integrator.method=rk4 \
    --set run.integrator.dt=1e-10 --set run.sample_interval="$(python3 -c "print($duration / $samples)")" \
    --set run.duration="$duration" > /dev/null
python3 - "$out/ref/series.csv" "$out/scipy.csv.ref.csv" <<'PY'
import csv, sys
a = list(csv.DictReader(open(sys.argv[1])))
b = list(csv.DictReader(open(sys.argv[2])))
n = min(len(a), len(b))
cols = [c for c in b[0] if c != "t"]
d = max(abs(float(x[c]) - float(y[c])) for x, y in zip(a[:n], b[:n]) for c in cols) / float(a[0]["R"])
print(f"references: {n} common samples, max over R, a_k of |magbubble - scipy| / R0 = {d:.2e}")
PY
python3 "$root/benches/peer/ratio.py" "$out/magbubble/accuracy.csv" "$out/scipy.csv"
