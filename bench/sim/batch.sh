#!/usr/bin/env bash
# bench/sim/batch.sh — batched work items (csgtrace --batch) against one
# item a message, with the OpenCL pass at the H100's measured rate, on the
# simulated clusters (bench/simulate.sh; bench/SCALE.md, "Batches").
#
#   bench/sim/batch.sh [PART]      PART: all (default), or one of
#                                  hetero-ib hetero-gige homo-ib kernel-ib
#
# Every point runs twice, --batch 1 (the protocol before batches) and
# --batch auto, on the same cost map, so each pair is a before/after.
# Rows are appended to $BATCH_CSV (default bench/results-scale/batch.csv,
# header written when the file is new); POINT_TIMEOUT (default 300 s)
# bounds each run.  Two PARTs can run side by side (one core each).
#
# The pass: --pass-rate 145 Mrays/s, csgtrace compare's whole OpenCL pass
# (slices + records back to the host) on the H100 at 1536x1536, 50
# spheres (bench/GPU.md): 4096 x 4096 / 145e6 = 0.116 s.  kernel-ib uses
# 596 Mrays/s instead (the primary-pass harness, kernel only, 1024x1024:
# 0.028 s), the bracket's other end.
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
CSV=${BATCH_CSV:-$ROOT/bench/results-scale/batch.csv}
WORK=${SCALE_WORK:-$ROOT/build/sim/scale}
POINT_TIMEOUT=${POINT_TIMEOUT:-300}
PART=${1:-all}
[[ "$POINT_TIMEOUT" =~ ^[1-9][0-9]*$ ]] || { echo "POINT_TIMEOUT: seconds" >&2; exit 2; }
[[ "$PART" =~ ^(all|hetero-ib|hetero-gige|homo-ib|kernel-ib)$ ]] || { echo "PART: see the header" >&2; exit 2; }
mkdir -p "$(dirname "$CSV")" "$WORK"
SCENE=$WORK/spheres50.pov
[ -f "$SCENE" ] || "$ROOT/build/csgtrace" gen spheres --count 50 --occupancy 0.5 --seed 1 -o "$SCENE"
[ -f "$CSV" ] || echo "workers,network,mode,schedule,tile,pass_rate,batch_asked,batch,tile_messages,items,makespan_s,serial_s,pass_s,efficiency,master_busy,sim_wall_s" >"$CSV"

# point WORKERS NETWORK MODE TILE PASS_RATE BATCH
point() {
    local json
    json=$(mktemp "$WORK/batch.XXXXXX.json")
    local sched=raster t0 t1
    [ "$3" = hetero ] && sched=cost
    t0=$(date +%s.%N)
    timeout "$POINT_TIMEOUT" "$ROOT/bench/simulate.sh" "$SCENE" --size 4096x4096 --workers "$1" \
        --network "$2" --mode "$3" --schedule $sched --tile "$4" --pass-rate "$5" --batch "$6" \
        --stats "$json" >/dev/null 2>>"$WORK/batch-errors.log" || true
    t1=$(date +%s.%N)
    python3 - "$json" "$CSV" "$(echo "$t1 - $t0" | bc)" "$sched" "$@" <<'PY'
import json, os, sys
path, csv, wall, sched, workers, net, mode, tile, rate, batch = sys.argv[1:]
d = json.load(open(path)) if os.path.getsize(path) else {}
row = [workers, net, mode, sched, tile, rate, batch] + [str(d.get(k, "")) for k in
       ("batch", "tile_messages", "items", "makespan_s", "serial_s", "pass_s", "efficiency",
        "master_busy")] + [wall]
open(csv, "a").write(",".join(row) + "\n")
print(",".join(row), flush=True)
PY
    rm -f "$json"
}

pair() { point "$@" 1; point "$@" auto; }

# (1024 workers at tile 32 with --batch 1: 16384 single items, minutes of
# simulation on a loaded machine: left out, auto only.)
if [ "$PART" = all ] || [ "$PART" = hetero-ib ]; then
    for w in 64 256; do for t in 64 32; do pair "$w" ib hetero "$t" 145; done; done
    pair 1024 ib hetero 64 145
    point 1024 ib hetero 32 145 auto
fi
if [ "$PART" = all ] || [ "$PART" = hetero-gige ]; then
    for w in 64 256 1024; do pair "$w" gige hetero 64 145; done
fi
if [ "$PART" = all ] || [ "$PART" = homo-ib ]; then
    for t in 64 32; do pair 256 ib homo "$t" 0; done
    point 1024 ib homo 32 0 auto
fi
if [ "$PART" = all ] || [ "$PART" = kernel-ib ]; then
    for t in 64 32; do pair 256 ib hetero "$t" 596; done
fi
