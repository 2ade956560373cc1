#!/usr/bin/env bash
# bench/sim/validate.sh — the simulator against reality on this machine:
# real renders with 1..3 workers (mpirun, oversubscribed: the ranks may
# outnumber the cores) and the simulation of the same configuration from
# the cost map bench/simulate.sh records.  Prints a CSV: workers, mode,
# real tile_phase_s (median of REPEATS), simulated makespan_s, difference.
# Hetero runs the paper's scheme on both sides (--fill off: the map then
# holds shading costs only).  WORKERS (default "1 2 3") and MODES (default
# "homo hetero") choose the points.
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
REPEATS=${REPEATS:-3}
WORKERS=${WORKERS:-1 2 3}
MODES=${MODES:-homo hetero}
# rank 0's own work on the results (bench/SCALE.md, "the master's own
# work" and "the store thread"): measured on this machine, charged in the
# simulation: a part, a pixel and a message in the loop, a pixel on the
# store thread
PART_US=${MASTER_PART_US:-0.20}
MESSAGE_US=${MASTER_MESSAGE_US:-0.75}
STORE_NS=${MASTER_STORE_NS:-5.4}
# the platform: this machine (local: 2 cores shared by every rank) or the
# InfiniBand cluster (ib: a host a rank)
NETWORK=${NETWORK:-local}
[[ "$NETWORK" =~ ^(local|ib)$ ]] || { echo "NETWORK: local or ib" >&2; exit 2; }
PIXEL_NS=${MASTER_PIXEL_NS:-0.42}
[[ "$REPEATS" =~ ^[1-9]$ ]] || { echo "REPEATS: 1..9" >&2; exit 2; }
[[ "$WORKERS" =~ ^[1-9]( [1-9])*$ ]] || { echo "WORKERS: digits 1..9, space-separated" >&2; exit 2; }
[[ "$MODES" =~ ^(homo|hetero)( (homo|hetero))*$ ]] || { echo "MODES: homo and/or hetero" >&2; exit 2; }
WORK=$ROOT/build/sim/validate
mkdir -p "$WORK"
SCENE=$WORK/spheres50.pov
[ -f "$SCENE" ] || "$ROOT/build/csgtrace" gen spheres --count 50 --occupancy 0.5 --seed 1 -o "$SCENE" >&2
echo "workers,mode,tile,real_s,sim_s,diff_pct,load1"
key=$(sha256sum "$SCENE" | cut -c1-16)
for mode in $MODES; do for w in $WORKERS; do for _ in $(seq "$REPEATS"); do
    sched=$([ $mode = homo ] && echo raster || echo cost)
    OMPI_MCA_pml=ob1 mpirun --allow-run-as-root --oversubscribe --bind-to none -np $((w + 1)) \
        "$ROOT/build/csgtrace" render "$SCENE" -o "$WORK/img.png" --mode $mode --width 384 \
        --height 384 --tile 16 --schedule $sched --fill off --stats "$WORK/real.json" \
        --tile-log "$WORK/real.log" >/dev/null 2>&1
    mkdir -p "$WORK/maps"
    python3 "$ROOT/bench/sim/costmap.py" "$WORK/maps/$key-$mode.costs" "$WORK/real.json" "$WORK/real.log"
    SIM_MAPS=$WORK/maps "$ROOT/bench/simulate.sh" "$SCENE" --workers $w --mode $mode \
        --schedule $sched --tile 16 --network "$NETWORK" --size 384x384 --fill off \
        --master-part-us "$PART_US" --master-pixel-ns "$PIXEL_NS" \
        --master-message-us "$MESSAGE_US" --master-store-ns "$STORE_NS" \
        --stats "$WORK/sim.json" >/dev/null
    python3 - "$WORK/real.json" "$WORK/sim.json" "$w" "$mode" <<'PY'
import json, os, sys
r, d = json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))
real = r["primary_s"] + r["pipelined_s"] + r["secondary_s"]
sim = d["makespan_s"]
print(f"{sys.argv[3]},{sys.argv[4]},16,{real:.4f},{sim:.4f},{100*(sim-real)/real:+.1f},"
      f"{os.getloadavg()[0]:.2f}", flush=True)
PY
done; done; done
