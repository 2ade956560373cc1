#!/usr/bin/env bash
# bench/scale.sh — `make bench-scale`: the simulated grid (bench/simulate.sh)
# into bench/results-scale/scale.csv, then plots and bench/SCALE.md tables
# (bench/scale_report.py).
#
# Pruned to what runs in about half an hour on 2 shared cores (the
# simulation's own cost grows with items x workers): 4096x4096 with tiles
# 32, 64, 128 at 16..1024 workers on both networks (homo raster, hetero
# cost); the four schedulers at 256 workers; 384 and 1536 at 64 workers;
# the measured pass against a device 100 times faster.  Tiles 8 and 16 at
# 4096x4096 (65536 to 262144 items) are left out: one point takes minutes.
# Every point runs under `timeout` (POINT_TIMEOUT, 240 s); one that ran
# out is recorded with an empty makespan.  SCALE_QUICK=1: a handful.
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
OUT=${SCALE_OUT:-$ROOT/bench/results-scale}
WORK=${SCALE_WORK:-$ROOT/build/sim/scale}
POINT_TIMEOUT=${POINT_TIMEOUT:-240}
[[ "$POINT_TIMEOUT" =~ ^[1-9][0-9]*$ ]] || { echo "POINT_TIMEOUT: seconds" >&2; exit 2; }
mkdir -p "$OUT" "$WORK"
SCENE=$WORK/spheres50.pov
[ -f "$SCENE" ] || "$ROOT/build/csgtrace" gen spheres --count 50 --occupancy 0.5 --seed 1 -o "$SCENE"
CSV=$OUT/scale.csv
echo "size,workers,network,mode,schedule,tile,pass_scale,makespan_s,serial_s,efficiency,master_busy,pass_s,items,sim_wall_s" >"$CSV"

# point SIZE WORKERS NETWORK MODE SCHEDULE TILE PASS_SCALE
point() {
    local json=$WORK/p.json t0 t1
    rm -f "$json"
    t0=$(date +%s.%N)
    timeout "$POINT_TIMEOUT" "$ROOT/bench/simulate.sh" "$SCENE" --size "$1x$1" --workers "$2" \
        --network "$3" --mode "$4" --schedule "$5" --tile "$6" --pass-scale "$7" --stats "$json" \
        >/dev/null 2>>"$WORK/errors.log" || true
    t1=$(date +%s.%N)
    python3 - "$json" "$CSV" "$(echo "$t1 - $t0" | bc)" "$@" <<'PY'
import json, os, sys
path, csv, wall, size, workers, net, mode, sched, tile, ps = sys.argv[1:]
d = json.load(open(path)) if os.path.exists(path) else {}
row = [size, workers, net, mode, sched, tile, ps] + [str(d.get(k, "")) for k in
       ("makespan_s", "serial_s", "efficiency", "master_busy", "pass_s", "items")] + [wall]
open(csv, "a").write(",".join(row) + "\n")
print(",".join(row), flush=True)
PY
}

WORKERS=(16 64 256 1024) TILES=(128 64 32)
[ "${SCALE_QUICK:-0}" = 1 ] && WORKERS=(16 64) TILES=(64)
# the schedulers at 256 workers (4096, InfiniBand, tile 64)
for s in raster static tail; do point 4096 256 ib homo $s 64 1; done
for s in raster cost static tail; do point 4096 256 ib hetero $s 64 0.01; done
# the measured pass (PoCL, 2 CPU cores) against a 100x faster device
point 4096 64 ib hetero cost 64 1
# sizes at 64 workers
for n in 384 1536; do for m in homo hetero; do
    point "$n" 64 ib "$m" "$([ $m = homo ] && echo raster || echo cost)" 16 0.01; done; done
# the main grid: tile x workers x network, 4096
for net in ib gige; do for t in "${TILES[@]}"; do for w in "${WORKERS[@]}"; do
    point 4096 "$w" "$net" homo raster "$t" 1
    point 4096 "$w" "$net" hetero cost "$t" 0.01
done; done; done
python3 "$ROOT/bench/scale_report.py" "$CSV" "$OUT"
