#!/usr/bin/env bash
# magbubble against the C code APECSS (Denner & Schenke, https://github.com/polycfd/apecss) on
# the radial runs of issue 34: process CPU at equal accuracy (errors 1e-6 and 1e-9 against each
# code's own tight reference), interleaved pairs, medians, ratios. Not part of CI.
#
#   benches/apecss.sh APECSS [CASE ...]
#
# APECSS: a checkout (with include/apecss.h and src/) or a git directory of one (its include/
# and src/ are extracted). Compiled with gcc -O3 together with scripts/peer/apecss_driver.c (no
# cmake). CASE: a substring of a case name to run only some ("free", "MR", "Marmottant").
# Environment: REPS (default 7) interleaved pairs per row; WORK (default /tmp/magbubble-apecss);
# MAGBUBBLE (default: cargo build --release, target/release/magbubble). Also times an empty C
# program beside each pair: the process floor of this machine (apecss.py's docstring).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
src=${1:?usage: benches/apecss.sh APECSS_CHECKOUT_OR_GIT_DIR [CASE ...]}
shift
work=${WORK:-/tmp/magbubble-apecss}
reps=${REPS:-7}
mkdir -p "$work"

if [ -f "$src/include/apecss.h" ]; then
  tree=$src
elif git --git-dir="$src" rev-parse --verify -q HEAD > /dev/null; then
  tree=$work/apecss
  rm -rf "$tree" && mkdir -p "$tree"
  # (a mirror may lack unrelated blobs, e.g. example data: only include/ and src/ are read)
  git --git-dir="$src" archive HEAD include src 2> "$work/git-archive.log" | tar -x -C "$tree"
  echo "APECSS $(git --git-dir="$src" log -1 --format='%h %cs %s' HEAD) (from $src)"
else
  echo "$src: neither an APECSS checkout (no include/apecss.h) nor a git directory" >&2
  exit 1
fi
gcc -O3 -I"$tree/include" "$tree"/src/*.c "$root/scripts/peer/apecss_driver.c" -lm -o "$work/apecss_driver"
# the floor: a process that does nothing (exec, loader, exit)
printf 'int main(void) { return 0; }\n' > "$work/empty.c"
gcc -O2 "$work/empty.c" -o "$work/empty"

if [ -z "${MAGBUBBLE:-}" ]; then
  (cd "$root" && cargo build --release --quiet)
  MAGBUBBLE=$root/target/release/magbubble
fi
exec python3 "$root/benches/apecss.py" "$work" "$MAGBUBBLE" "$work/apecss_driver" "$work/empty" "$reps" "$@"
