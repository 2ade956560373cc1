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
        --mode serial -o "$T/wide.png" --stats "$T/wide.json" >/dev/null
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
