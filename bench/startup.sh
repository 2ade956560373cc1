#!/usr/bin/env bash
# bench/startup.sh — what a process costs before it does any work: the
# wall time and peak RSS of `csgtrace check` on a small scene, the shared
# objects it maps, and the peak RSS of each rank of a small render under
# `mpirun -np 3` (rank 0 the master, which writes the image; 1 and 2
# workers).  Medians with min–max over many runs: the machine may be busy.
#
#   bench/startup.sh [BIN...]        default: build/csgtrace
#   RUNS=100 SCENE=scenes/glass.pov bench/startup.sh old/csgtrace build/csgtrace
#
# Needs hyperfine (apt-get install hyperfine) and GNU time (/usr/bin/time).
set -u
cd "$(dirname "$0")/.."
SCENE=${SCENE:-scenes/showcase.pov}
RUNS=${RUNS:-50}
MPI_RUNS=${MPI_RUNS:-5}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_pml=ob1
for tool in hyperfine /usr/bin/time mpirun; do
    command -v "$tool" >/dev/null || { echo "startup.sh: $tool is missing" >&2; exit 77; }
done
[ $# -gt 0 ] || set -- build/csgtrace
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT

# stats: "median (min–max)" of the numbers on stdin, scaled by $1.
stats() {
    python3 -c '
import statistics, sys
v = sorted(float(x) * float(sys.argv[1]) for x in sys.stdin.read().split())
print(f"{statistics.median(v):.1f} ({v[0]:.1f}–{v[-1]:.1f})")' "$1"
}

printf '%-28s %8s %22s %22s %22s\n' program objects "check wall ms" "check max RSS MiB" "worker max RSS MiB"
for bin in "$@"; do
    objects=$(ldd "$bin" | wc -l)
    hyperfine -N -w 5 -r "$RUNS" --export-json "$T/h.json" "$bin check $SCENE" >/dev/null 2>&1
    wall=$(python3 -c 'import json,sys; print(*json.load(open(sys.argv[1]))["results"][0]["times"])' \
        "$T/h.json" | tr ' ' '\n' | stats 1000)
    for _ in $(seq "$RUNS"); do
        /usr/bin/time -f %M "$bin" check "$SCENE" 2>&1 >/dev/null | tail -1
    done | stats 0.0009765625 >"$T/rss"
    : >"$T/workers"
    for _ in $(seq "$MPI_RUNS"); do
        mpirun -np 3 --oversubscribe --bind-to none sh -c \
            "/usr/bin/time -o $T/rank.\$OMPI_COMM_WORLD_RANK -f %M $bin render $SCENE -o $T/img.png --mode homo" \
            >/dev/null 2>&1
        cat "$T/rank.1" "$T/rank.2" >>"$T/workers"
    done
    printf '%-28s %8s %22s %22s %22s\n' "$bin" "$objects" "$wall" "$(cat "$T/rss")" \
        "$(stats 0.0009765625 <"$T/workers")"
done
