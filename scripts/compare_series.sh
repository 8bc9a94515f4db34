#!/usr/bin/env bash
# Effects off, bit for bit (issue 10): runs every shipped scene (scenes/*.toml, scenes/hard/*.toml)
# with a baseline binary and with this tree's binary and compares series.csv byte for byte.
# Usage: scripts/compare_series.sh BASELINE_BINARY [NEW_BINARY]
# (baseline: the binary built at the commit the effect work started from, e.g. 602e20a).
set -u
base=$1; new=${2:-target/release/magbubble}
tmp=$(mktemp -d); fail=0
for s in scenes/*.toml scenes/hard/*.toml; do
  grep -q "sound_speed\|c1 = 0.0\|vapour_pressure\|envelope\|^file\|components\|marmottant\|tension-curve" "$s" && continue   # the new effect scenes (issue 10, issue 30, issue 31)
  n=$(echo "$s" | tr / _)
  "$base" run "$s" --out "$tmp/a_$n" >/dev/null 2>&1; ra=$?
  "$new" run "$s" --out "$tmp/b_$n" >/dev/null 2>&1; rb=$?
  if [ $ra -ne $rb ]; then echo "DIFF exit $s: $ra vs $rb"; fail=1; continue; fi
  if [ $ra -ne 0 ]; then echo "both fail: $s"; continue; fi
  if cmp -s "$tmp/a_$n/series.csv" "$tmp/b_$n/series.csv"; then echo "identical: $s"; else echo "DIFF: $s"; fail=1; fi
done
rm -rf "$tmp"; exit $fail
