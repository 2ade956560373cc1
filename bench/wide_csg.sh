#!/usr/bin/env bash
# wide_csg.sh — a wide CSG node (issue #39): a box minus N small spheres
# (tests/wide_scene.py, default 10^5) at 64x48, serial; prints the wall
# time and the stats' setup (parse, flatten) and tile phase.
# Before the wide runs' hierarchy (main at ba2f09d) on the shared 2-core
# build machine: 25.2 s (setup 6.8 s, most of it a quadratic operand
# sort; tiles 18.4 s, ~6 ms a primary ray).  After: 0.79 s (setup 0.73 s,
# mostly parsing the 8 MB scene; tiles 0.043 s); hetero (3 ranks,
# --pass always, the OpenCL pass on PoCL) byte-identical.
# Usage: bench/wide_csg.sh [N]   (CSGTRACE_BIN: default build/csgtrace)
set -eu
cd "$(dirname "$0")/.."
BIN=${CSGTRACE_BIN:-build/csgtrace}
N=${1:-100000}
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
python3 tests/wide_scene.py difference "$N" "$T/wide.pov"
start=$(date +%s.%N)
"$BIN" render "$T/wide.pov" --width 64 --height 48 --mode serial -o "$T/wide.png" \
    --stats "$T/wide.json" >/dev/null
end=$(date +%s.%N)
python3 -c "
import json, sys
j = json.load(open(sys.argv[1]))
print('spheres %s  wall %.3f s  setup %.3f s  tiles %.3f s' % (sys.argv[2], float(sys.argv[3]),
      j['setup_s'], j['tile_phase_s']))" "$T/wide.json" "$N" "$(echo "$end - $start" | bc)"
