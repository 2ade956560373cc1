#!/usr/bin/env bash
# bench/sim/master_cost.sh — the simulated cluster with rank 0's own work on
# each result charged (bench/simulate.sh --master-part-us A
# --master-pixel-ns B; bench/SCALE.md, "the master's own work").
#
#   bench/sim/master_cost.sh A B [M C]   A us a RESULT part, B ns a pixel,
#                                        M us a RESULT message, C ns a pixel
#                                        on the store thread (0: none)
#   MASTER_STORE_THREADS=N (default 1): so many store threads, each at C
#
# The points of bench/sim/relays.sh that decide the issue's targets:
# 256 workers hetero raster with one master and with 16 relays on the
# three scenes, 64 workers (one master, 4 relays), 16 workers, and homo at
# 256 (seed 1) (MASTER_COST_MORE=1: more, below), 4096x4096, tile 32,
# InfiniBand, the pass at 145 Mrays/s with the fill.  Rows are appended to
# $MASTER_COST_CSV (default bench/results-scale/master_cost.csv, header
# written when the file is new); POINT_TIMEOUT (default 900 s) bounds each run.
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
CSV=${MASTER_COST_CSV:-$ROOT/bench/results-scale/master_cost.csv}
WORK=${SCALE_WORK:-$ROOT/build/sim/scale}
POINT_TIMEOUT=${POINT_TIMEOUT:-900}
export SIM_MAP_RENDERS=${SIM_MAP_RENDERS:-10}
[ $# -eq 2 ] || [ $# -eq 4 ] || { echo "usage: bench/sim/master_cost.sh PART_US PIXEL_NS [MESSAGE_US STORE_NS]" >&2; exit 2; }
PART_US=$1 PIXEL_NS=$2 MESSAGE_US=${3:-0} STORE_NS=${4:-0}
STORE_THREADS=${MASTER_STORE_THREADS:-1}
[[ "$STORE_THREADS" =~ ^[1-8]$ ]] || { echo "MASTER_STORE_THREADS: 1..8" >&2; exit 2; }
[[ "$POINT_TIMEOUT" =~ ^[1-9][0-9]*$ ]] || { echo "POINT_TIMEOUT: seconds" >&2; exit 2; }
mkdir -p "$(dirname "$CSV")" "$WORK"
source "$ROOT/bench/sim/scenes.sh"
sim_scenes "$WORK"
[ -f "$CSV" ] || echo "probe_growth,part_us,pixel_ns,message_us,store_ns,seed,workers,relays,mode,schedule,makespan_s,serial_s,efficiency,efficiency_ranks,master_busy,tail_s,tile_messages,store_threads" >"$CSV"

# point SEED WORKERS RELAYS MODE [SCHEDULE]
point() {
    local json pass=() schedule=${5:-raster}
    json=$(mktemp "$WORK/master_cost.XXXXXX.json")
    [ "$4" = hetero ] && pass=(--pass-rate 145 --fill on) || pass=(--fill off)
    timeout "$POINT_TIMEOUT" "$ROOT/bench/simulate.sh" "$WORK/spheres50-s$1.pov" \
        --size 4096x4096 --workers "$2" --relays "$3" --network ib --mode "$4" --schedule "$schedule" \
        --tile 32 "${pass[@]}" --master-part-us "$PART_US" --master-pixel-ns "$PIXEL_NS" \
        --master-message-us "$MESSAGE_US" --master-store-ns "$STORE_NS" \
        --store-threads "$STORE_THREADS" --stats "$json" </dev/null >/dev/null 2>>"$WORK/master_cost-errors.log" || true
    python3 - "$json" "$CSV" "$PART_US" "$PIXEL_NS" "$MESSAGE_US" "$STORE_NS" "$1" "$2" "$3" "$4" \
        "$schedule" <<'PY'
import json, os, sys
path, csv, part, pixel, message, store, seed, workers, relays, mode, schedule = sys.argv[1:]
d = json.load(open(path)) if os.path.getsize(path) else {}
row = [os.environ.get("SIM_PROBE_GROWTH", "no"), part, pixel, message, store, seed, workers, relays, mode, schedule] + [str(d.get(k, "")) for k in
       ("makespan_s", "serial_s", "efficiency", "efficiency_ranks", "master_busy", "tail_s",
        "tile_messages", "master_store_threads")]
with open(csv, "a") as f:
    f.write(",".join(row) + "\n")
PY
    rm -f "$json"
}

for seed in 1 2 3; do
    point $seed 256 0 hetero
    point $seed 256 16 hetero
done
point 1 64 0 hetero
point 1 64 4 hetero
point 1 16 0 hetero
point 1 256 0 homo
point 1 256 16 homo
# MASTER_COST_MORE=1: the cost-ranked order against raster's at 256
# workers, and 1024 workers with one master and with 32 relays
if [ "${MASTER_COST_MORE:-0}" = 1 ]; then
    for seed in 1 2 3; do
        point $seed 256 0 hetero cost
        point $seed 256 16 hetero cost
    done
    point 1 1024 0 hetero
    point 1 1024 32 hetero
fi
