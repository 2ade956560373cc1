#!/usr/bin/env bash
# wide_csg.sh — a wide CSG node (issue #39): a box minus N small spheres
# (tests/wide_scene.py, default 10^5, an 8 MB scene) at 64x48, serial;
# prints the wall time, the user and system CPU times (less noisy than the
# wall time on a shared machine) and the stats' setup (parse,
# flatten) and tile phase.  With --runs R, R runs and their median and
# range; with --base BIN too, BIN's runs alternated with the measured
# binary's (one before the other, in turn), so that both see the same load.
# Before the wide runs' hierarchy (main at ba2f09d) on the shared 2-core
# build machine: 25.2 s (setup 6.8 s, most of it a quadratic operand
# sort; tiles 18.4 s, ~6 ms a primary ray).  After: 0.79 s (setup 0.73 s,
# mostly parsing the 8 MB scene; tiles 0.043 s); hetero (3 ranks,
# --pass always, the OpenCL pass on PoCL) byte-identical.
# Setup trimmed (2026-11-28, measured at 3d75e5b; the old binary main at
# 4afc94a): equal sibling textures share one entry and one material, the
# parser's tables are adopted by the arena, the BVH build at -O3, a leaner
# lexer.  --runs 20 --base, interleaved, on the shared 2-core machine under
# load 14-19 (other sessions building): wall 2.44 -> 1.32 s (medians;
# 1.78-3.86 and 0.94-2.17), user 0.54 -> 0.375 s, system 0.22 -> 0.07 s,
# setup 2.15 -> 1.13 s, tiles 0.14 -> 0.13 s; images identical.  The same
# render under callgrind: 2.86 -> 2.12 G instructions (parse 1.63 -> 1.24 G,
# the wide run's BVH 0.72 -> 0.48 G, both threads); peak RSS 232 -> 93 MB;
# blob 49.5 -> 16.7 MB (100001 materials -> 2).  Start-up of a serial
# render maps no image module and opens no OpenCL platform or MPI (strace).
# On a quiet machine the old binary took 0.62-0.81 s; that load could not
# be had in this session, so the quiet wall time is still to measure.
# Usage: bench/wide_csg.sh [--runs R] [--base BIN] [N]
#        (CSGTRACE_BIN: the measured binary, default build/csgtrace)
set -eu
cd "$(dirname "$0")/.."
BIN=${CSGTRACE_BIN:-build/csgtrace}
RUNS=1
BASE=
while [ $# -gt 0 ]; do
    case $1 in
    --runs) RUNS=$2; shift 2 ;;
    --base) BASE=$2; shift 2 ;;
    *) break ;;
    esac
done
N=${1:-100000}
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
python3 tests/wide_scene.py difference "$N" "$T/wide.pov"

# one run of $1, labelled $2: a line "label wall user sys setup tiles" in $T/runs
one_run() {
    local start end
    start=$(date +%s.%N)
    /usr/bin/time -f '%U %S' -o "$T/cpu" "$1" render "$T/wide.pov" --width 64 --height 48 \
        --mode serial -o "$T/$2.png" --stats "$T/wide.json" >/dev/null
    end=$(date +%s.%N)
    python3 -c "
import json, sys
j = json.load(open(sys.argv[1]))
user, system = open(sys.argv[5]).read().split()[-2:]
print(sys.argv[2], float(sys.argv[3]) - float(sys.argv[4]), user, system, j['setup_s'],
      j['tile_phase_s'])" "$T/wide.json" "$2" "$end" "$start" "$T/cpu" >>"$T/runs"
}

: >"$T/runs"
for ((r = 0; r < RUNS; r++)); do
    if [ -n "$BASE" ] && [ $((r % 2)) -eq 0 ]; then
        one_run "$BASE" base
        one_run "$BIN" new
    elif [ -n "$BASE" ]; then
        one_run "$BIN" new
        one_run "$BASE" base
    else
        one_run "$BIN" new
    fi
done
if [ -n "$BASE" ]; then
    cmp -s "$T/base.png" "$T/new.png" && echo "images: identical" || echo "images: DIFFER"
fi
python3 - "$T/runs" "$N" "$BIN" "$BASE" <<'EOF'
import statistics, sys
runs = [l.split() for l in open(sys.argv[1])]
for label, binary in (('base', sys.argv[4]), ('new', sys.argv[3])):
    rows = [[float(x) for x in r[1:]] for r in runs if r[0] == label]
    if not rows:
        continue
    cols = list(zip(*rows))
    text = '  '.join('%s %.3f s (%.3f-%.3f)' % (name, statistics.median(c), min(c), max(c))
                     for name, c in zip(('wall', 'user', 'sys', 'setup', 'tiles'), cols))
    print('%s (%s) spheres %s, %d runs, median (min-max): %s'
          % (label, binary, sys.argv[2], len(rows), text))
EOF
