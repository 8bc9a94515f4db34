#!/usr/bin/env bash
# Side-by-side CPU time of the current magbubble against a reference commit (issue 16's
# performance table; results in docs/performance.md).
#
#   benches/compare.sh [--runs-only] [--repeat N]
#
# Builds the reference commit (REF, default e55fb60) in a git worktree under WORK (default a
# temp dir) with its own --target-dir, builds the current tree (cargo build --release), then
# runs every workload with both binaries (same scene, same accuracy, outputs in WORK) and prints
# user+system CPU seconds (/usr/bin/time) and the ratio reference/current. A workload is timed
# REPEAT times (default 3 for the two `run` rows, 1 for the long ones) and the minimum kept.
# --runs-only: only the two `run` workloads (about a minute instead of several).
# Keep WORK to reuse the reference build: WORK=/tmp/mb-bench benches/compare.sh
set -euo pipefail

REF=${REF:-e55fb60}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
WORK=${WORK:-$(mktemp -d /tmp/magbubble-bench.XXXXXX)}
RUNS_ONLY=0
REPEAT_RUN=3
while [ $# -gt 0 ]; do
    case "$1" in
        --runs-only) RUNS_ONLY=1 ;;
        --repeat) REPEAT_RUN=$2; shift ;;
        -h|--help) sed -n '2,14p' "$0"; exit 0 ;;
        *) echo "unknown argument $1" >&2; exit 2 ;;
    esac
    shift
done
[ -x /usr/bin/time ] || { echo "needs /usr/bin/time (apt-get install time)" >&2; exit 1; }
mkdir -p "$WORK"

# the reference binary, in its own worktree and target directory
if [ ! -x "$WORK/target-ref/release/magbubble" ]; then
    if [ ! -d "$WORK/ref" ]; then
        git -C "$ROOT" worktree add --detach "$WORK/ref" "$REF" >/dev/null
    fi
    echo "building $REF in $WORK/ref ..." >&2
    (cd "$WORK/ref" && cargo build --release --bin magbubble --target-dir "$WORK/target-ref" >&2)
fi
echo "building the current tree ..." >&2
(cd "$ROOT" && cargo build --release --bin magbubble >&2)
OLD="$WORK/target-ref/release/magbubble"
NEW="$ROOT/target/release/magbubble"

# CPU seconds (user + system) of one command, run in the source tree of its binary.
cpu() {
    local dir=$1; shift
    local f="$WORK/time.$$"
    (cd "$dir" && /usr/bin/time -f "%U %S" -o "$f" "$@" >/dev/null 2>&1) || echo "  (exit status $? of: $*)" >&2
    awk '{ printf "%.3f", $1 + $2 }' "$f"
}

best() {
    local n=$1; shift
    local b=""
    for _ in $(seq "$n"); do
        local t
        t=$(cpu "$@")
        if [ -z "$b" ] || awk "BEGIN { exit !($t < $b) }"; then b=$t; fi
    done
    echo "$b"
}

# name | repeat | arguments (the output directory is appended per binary) | extra arguments of
# the current binary only (the stability default --tol became relative after e55fb60, whose
# absolute 1e-3 is --abs-tol 1e-3 now: the same search tolerance)
WORKLOADS=(
    "run coil_static (BL, k<=16)|$REPEAT_RUN|run scenes/coil_static.toml --set drive.amplitude=0.2 --out"
    "run no_field vorticity (monolithic)|$REPEAT_RUN|run scenes/no_field.toml --set drive.amplitude=0.2 --set modes.viscous=vorticity --out"
)
if [ "$RUNS_ONLY" = 0 ]; then
    WORKLOADS+=(
        "stability coil_static k<=16|1|stability scenes/coil_static.toml --freq 0.5e6:6e6:64 --set modes.max_order=16 --out|--abs-tol 1e-3"
        "stability no_field k<=32|1|stability scenes/no_field.toml --freq 0.5e6:6e6:64 --set modes.max_order=32 --out|--abs-tol 1e-3"
        "figure 6 (full resolution)|1|figure 6 --out"
    )
fi

printf "%-38s %12s %12s %8s\n" "workload" "$REF [s]" "current [s]" "ratio"
for w in "${WORKLOADS[@]}"; do
    IFS='|' read -r name rep args extra <<<"$w"
    # shellcheck disable=SC2086
    t_old=$(best "$rep" "$WORK/ref" "$OLD" $args "$WORK/out-old")
    # shellcheck disable=SC2086
    t_new=$(best "$rep" "$ROOT" "$NEW" $args "$WORK/out-new" $extra)
    ratio=$(awk "BEGIN { if ($t_new > 0) printf \"%.1f\", $t_old / $t_new; else print \"inf\" }")
    printf "%-38s %12s %12s %7sx\n" "$name" "$t_old" "$t_new" "$ratio"
    # keep the last outputs of each workload for comparing the answers (out-old.N, out-new.N)
    i=$(( ${i:-0} + 1 ))
    rm -rf "$WORK/out-old.$i" "$WORK/out-new.$i"
    mv "$WORK/out-old" "$WORK/out-old.$i"
    mv "$WORK/out-new" "$WORK/out-new.$i"
done
echo "(reference worktree and build kept in $WORK; remove with: git worktree remove --force $WORK/ref)" >&2
