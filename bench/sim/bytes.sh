#!/usr/bin/env bash
# bench/sim/bytes.sh — results in the output's precision: RGB floats (12
# bytes a pixel, what every render sent before 2026-11-25 and what an EXR
# render sends) against the 8-bit file's bytes (3 a pixel: a PNG render),
# on the simulated clusters (bench/simulate.sh --pixels; bench/SCALE.md).
#
#   bench/sim/bytes.sh [PART]      PART: all (default), or one of
#                                  ib gige ib-1024
#
# Every point runs twice, --pixels float then --pixels rgb8, on the same
# cost map and the same binary, so each pair is a before/after; batches
# auto, hetero's pass at the H100's 145 Mrays/s (bench/sim/batch.sh).
# Rows are appended to $BYTES_CSV (default bench/results-scale/bytes.csv,
# header written when the file is new); POINT_TIMEOUT (default 600 s)
# bounds each run.
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
CSV=${BYTES_CSV:-$ROOT/bench/results-scale/bytes.csv}
WORK=${SCALE_WORK:-$ROOT/build/sim/scale}
POINT_TIMEOUT=${POINT_TIMEOUT:-600}
PART=${1:-all}
[[ "$POINT_TIMEOUT" =~ ^[1-9][0-9]*$ ]] || { echo "POINT_TIMEOUT: seconds" >&2; exit 2; }
[[ "$PART" =~ ^(all|ib|gige|ib-1024)$ ]] || { echo "PART: see the header" >&2; exit 2; }
mkdir -p "$(dirname "$CSV")" "$WORK"
SCENE=$WORK/spheres50.pov
[ -f "$SCENE" ] || "$ROOT/build/csgtrace" gen spheres --count 50 --occupancy 0.5 --seed 1 -o "$SCENE"
[ -f "$CSV" ] || echo "workers,network,mode,schedule,tile,pass_rate,pixels,batch,tile_messages,items,bytes_received,makespan_s,serial_s,pass_s,efficiency,master_busy,sim_wall_s" >"$CSV"

# point WORKERS NETWORK MODE TILE PIXELS
point() {
    local json sched=raster rate=0 t0 t1
    json=$(mktemp "$WORK/bytes.XXXXXX.json")
    [ "$3" = hetero ] && sched=cost rate=145
    t0=$(date +%s.%N)
    timeout "$POINT_TIMEOUT" "$ROOT/bench/simulate.sh" "$SCENE" --size 4096x4096 --workers "$1" \
        --network "$2" --mode "$3" --schedule $sched --tile "$4" --pass-rate $rate --pixels "$5" \
        --stats "$json" >/dev/null 2>>"$WORK/bytes-errors.log" || true
    t1=$(date +%s.%N)
    python3 - "$json" "$CSV" "$(echo "$t1 - $t0" | bc)" "$sched" "$rate" "$@" <<'PY'
import json, os, sys
path, csv, wall, sched, rate, workers, net, mode, tile, pixels = sys.argv[1:]
d = json.load(open(path)) if os.path.getsize(path) else {}
row = [workers, net, mode, sched, tile, rate, pixels] + [str(d.get(k, "")) for k in
       ("batch", "tile_messages", "items", "bytes_received", "makespan_s", "serial_s", "pass_s",
        "efficiency", "master_busy")] + [wall]
open(csv, "a").write(",".join(row) + "\n")
print(",".join(row), flush=True)
PY
    rm -f "$json"
}

pair() { point "$@" float; point "$@" rgb8; }

if [ "$PART" = all ] || [ "$PART" = ib ]; then
    for mode in homo hetero; do for w in 64 256; do for t in 64 32; do
        pair "$w" ib "$mode" "$t"
    done; done; done
fi
if [ "$PART" = all ] || [ "$PART" = gige ]; then
    for t in 64 32; do for mode in homo hetero; do for w in 64 256; do
        pair "$w" gige "$mode" "$t"
    done; done; done
fi
if [ "$PART" = all ] || [ "$PART" = ib-1024 ]; then
    for mode in homo hetero; do pair 1024 ib "$mode" 64; done
fi
