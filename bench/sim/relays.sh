#!/usr/bin/env bash
# bench/sim/relays.sh — a second level of masters (csgtrace --relays K)
# against the single master, on the simulated InfiniBand cluster
# (bench/simulate.sh; bench/SCALE.md, "Relays").
#
#   bench/sim/relays.sh [PART]     PART: all (default), 256, 64 or 1024
#
# Three scenes (csgtrace gen spheres --count 50 --occupancy 0.5 --seed
# 1|2|3: the 256-worker efficiency swings by several points with the scene,
# so one scene says little), 4096x4096, tile 32, the pass at the H100's
# measured rate (145 Mrays/s, bench/GPU.md) with the fill, homo without a
# pass.  Each scene runs with K = 0 (one master) and with relays, on the
# same cost map.  Rows are appended to $RELAYS_CSV (default
# bench/results-scale/relays.csv, header written when the file is new);
# POINT_TIMEOUT (default 600 s) bounds each run.  The cost maps are
# recorded once (SIM_MAP_RENDERS, default 10, real renders each).
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
CSV=${RELAYS_CSV:-$ROOT/bench/results-scale/relays.csv}
WORK=${SCALE_WORK:-$ROOT/build/sim/scale}
POINT_TIMEOUT=${POINT_TIMEOUT:-600}
PART=${1:-all}
export SIM_MAP_RENDERS=${SIM_MAP_RENDERS:-10}
[[ "$POINT_TIMEOUT" =~ ^[1-9][0-9]*$ ]] || { echo "POINT_TIMEOUT: seconds" >&2; exit 2; }
[[ "$PART" =~ ^(all|256|64|1024)$ ]] || { echo "PART: all, 256, 64 or 1024" >&2; exit 2; }
mkdir -p "$(dirname "$CSV")" "$WORK"
source "$ROOT/bench/sim/scenes.sh"
sim_scenes "$WORK"
[ -f "$CSV" ] || echo "seed,workers,relays,mode,schedule,tile,makespan_s,serial_s,efficiency,efficiency_ranks,tile_messages,items,tail_s,master_busy,sim_wall_s" >"$CSV"

# point SEED WORKERS RELAYS MODE SCHEDULE TILE
point() {
    local json t0 t1 pass=()
    json=$(mktemp "$WORK/relays.XXXXXX.json")
    [ "$4" = hetero ] && pass=(--pass-rate 145 --fill on) || pass=(--fill off)
    t0=$(date +%s.%N)
    timeout "$POINT_TIMEOUT" "$ROOT/bench/simulate.sh" "$WORK/spheres50-s$1.pov" \
        --size 4096x4096 --workers "$2" --relays "$3" --network ib --mode "$4" --schedule "$5" \
        --tile "$6" "${pass[@]}" --stats "$json" </dev/null >/dev/null \
        2>>"$WORK/relays-errors.log" || true
    t1=$(date +%s.%N)
    python3 - "$json" "$CSV" "$(echo "$t1 - $t0" | bc)" "$@" <<'PY'
import json, os, sys
path, csv, wall, seed, workers, relays, mode, sched, tile = sys.argv[1:]
d = json.load(open(path)) if os.path.getsize(path) else {}
row = [seed, workers, relays, mode, sched, tile] + [str(d.get(k, "")) for k in
       ("makespan_s", "serial_s", "efficiency", "efficiency_ranks", "tile_messages", "items",
        "tail_s", "master_busy")] + [wall]
open(csv, "a").write(",".join(row) + "\n")
print(",".join(row), flush=True)
PY
    rm -f "$json"
}

if [ "$PART" = all ] || [ "$PART" = 256 ]; then
    for seed in 1 2 3; do
        for k in 0 8 16 32; do
            point $seed 256 $k hetero raster 32
            point $seed 256 $k hetero cost 32
        done
        for k in 0 16; do point $seed 256 $k homo raster 32; done
    done
fi
if [ "$PART" = all ] || [ "$PART" = 64 ]; then
    for k in 0 4; do point 1 64 $k hetero raster 32; done
fi
if [ "$PART" = all ] || [ "$PART" = 1024 ]; then
    for k in 0 32 64; do point 1 1024 $k hetero raster 32; done
    point 1 1024 32 hetero raster 64
    for k in 0 32; do point 1 1024 $k homo raster 32; done
fi
