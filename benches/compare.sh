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
# The BL `run` row is timed as a batch of BATCH consecutive runs (default 10; the monolithic row
# 3) under one /usr/bin/time, divided by the batch: /usr/bin/time counts in 10 ms steps, ±15 %
# of a 35 ms run, and a batch of ten resolves 1 ms. The binaries alternate (old, new, old, ...).
# The BL row again with 101 samples instead of 10,001 (the same steps, interpolated) separates
# the integration from the cost of formatting and writing the 3.9 MB series.csv.
# --runs-only: only the `run` workloads (about a minute instead of several).
# Keep WORK to reuse the reference build: WORK=/tmp/mb-bench benches/compare.sh
set -euo pipefail

REF=${REF:-e55fb60}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
WORK=${WORK:-$(mktemp -d /tmp/magbubble-bench.XXXXXX)}
RUNS_ONLY=0
REPEAT_RUN=3
BATCH=${BATCH:-10}
while [ $# -gt 0 ]; do
    case "$1" in
        --runs-only) RUNS_ONLY=1 ;;
        --repeat) REPEAT_RUN=$2; shift ;;
        -h|--help) sed -n '2,19p' "$0"; exit 0 ;;
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

# CPU seconds (user + system) of one command, run in the source tree of its binary; with
# N > 1 the mean over N consecutive runs timed together (their children's CPU, one clock).
cpu() {
    local n=$1 dir=$2; shift 2
    local f="$WORK/time.$$"
    # shellcheck disable=SC2016
    (cd "$dir" && /usr/bin/time -f "%U %S" -o "$f" bash -c 'n=$1; shift; for _ in $(seq "$n"); do "$@" >/dev/null 2>&1 || exit $?; done' _ "$n" "$@") \
        || echo "  (exit status $? of: $*)" >&2
    awk -v n="$n" '{ printf "%.4f", ($1 + $2) / n }' "$f"
}

# name | repeat | batch | arguments (the output directory is appended per binary) | extra
# arguments of the current binary only (the stability default --tol became relative after
# e55fb60, whose absolute 1e-3 is --abs-tol 1e-3 now: the same search tolerance)
WORKLOADS=(
    "run coil_static (BL, k<=16)|$REPEAT_RUN|$BATCH|run scenes/coil_static.toml --set drive.amplitude=0.2 --out"
    "  the same, 101 samples (no CSV cost)|$REPEAT_RUN|$BATCH|run scenes/coil_static.toml --set drive.amplitude=0.2 --set run.sample_interval=1e-6 --out"
    "run no_field vorticity (monolithic)|$REPEAT_RUN|3|run scenes/no_field.toml --set drive.amplitude=0.2 --set modes.viscous=vorticity --out"
)
if [ "$RUNS_ONLY" = 0 ]; then
    WORKLOADS+=(
        "stability coil_static k<=16|1|1|stability scenes/coil_static.toml --freq 0.5e6:6e6:64 --set modes.max_order=16 --out|--abs-tol 1e-3"
        "stability no_field k<=32|1|1|stability scenes/no_field.toml --freq 0.5e6:6e6:64 --set modes.max_order=32 --out|--abs-tol 1e-3"
        "figure 6 (full resolution)|1|1|figure 6 --out"
    )
fi

# the smaller of a and b
min() { if [ -z "$1" ] || awk "BEGIN { exit !($2 < $1) }"; then echo "$2"; else echo "$1"; fi; }

printf "%-38s %12s %12s %8s\n" "workload" "$REF [s]" "current [s]" "ratio"
for w in "${WORKLOADS[@]}"; do
    IFS='|' read -r name rep batch args extra <<<"$w"
    t_old="" t_new=""
    for _ in $(seq "$rep"); do
        # shellcheck disable=SC2086
        t_old=$(min "$t_old" "$(cpu "$batch" "$WORK/ref" "$OLD" $args "$WORK/out-old")")
        # shellcheck disable=SC2086
        t_new=$(min "$t_new" "$(cpu "$batch" "$ROOT" "$NEW" $args "$WORK/out-new" $extra)")
    done
    ratio=$(awk "BEGIN { if ($t_new > 0) printf \"%.2f\", $t_old / $t_new; else print \"inf\" }")
    printf "%-38s %12s %12s %7sx\n" "$name" "$t_old" "$t_new" "$ratio"
    # keep the last outputs of each workload for comparing the answers (out-old.N, out-new.N)
    i=$(( ${i:-0} + 1 ))
    rm -rf "$WORK/out-old.$i" "$WORK/out-new.$i"
    mv "$WORK/out-old" "$WORK/out-old.$i"
    mv "$WORK/out-new" "$WORK/out-new.$i"
done
echo "(reference worktree and build kept in $WORK; remove with: git worktree remove --force $WORK/ref)" >&2
