#!/usr/bin/env bash
# bench/sim/validate.sh — the simulator against reality on this machine:
# real renders with 1..3 workers (mpirun, oversubscribed: the ranks may
# outnumber the cores) and the simulation of the same configuration from
# the run's own tile log (bench/sim/costmap.py: each part's CPU time, so
# that the simulation, which shares local.xml's two cores among the ranks
# itself, does not count the sharing twice).  Prints a CSV, a row a run
# (REPEATS runs a point): workers, mode, tile, the real tile phase, the
# simulated makespan, their difference, the load.  Hetero runs the paper's
# scheme on both sides (--fill off: the map then holds shading costs
# only).  WORKERS (default "1 2 3") and MODES (default "homo hetero")
# choose the points; SIZE and TILE the image.  The large-message protocol
# (bench/SCALE.md, "The protocol modelled"): MPI_ARGS, words added to
# mpirun's (e.g. "--mca btl_vader_single_copy_mechanism none"), SIM_ARGS to
# simulate.sh's (e.g. "--runtime legacy" with CSGTRACE_BIN, a build from
# before 2026-11-28; "--sender-progress no" for a transport with single copy).
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
REPEATS=${REPEATS:-3}
# the image (SIZE x SIZE) and its tiles: 384 and 16, the paper's size, by
# default; a frame of ~0.1 s there, so SIZE=1024 TILE=32 gives the
# comparison a second of work
SIZE=${SIZE:-384}
TILE=${TILE:-16}
WORKERS=${WORKERS:-1 2 3}
MODES=${MODES:-homo hetero}
# rank 0's own work on the results (bench/SCALE.md, "the master's own
# work" and "the store thread"): measured on this machine, charged in the
# simulation: a part, a pixel and a message in the loop, a pixel on the
# store thread (2.3 ns: one part a RESULT, as these runs send them, the
# image in huge pages; bench/SCALE.md, sixth section)
PART_US=${MASTER_PART_US:-0.20}
MESSAGE_US=${MASTER_MESSAGE_US:-0.75}
STORE_NS=${MASTER_STORE_NS:-2.3}
# the platform: this machine (local: 2 cores shared by every rank) or the
# InfiniBand cluster (ib: a host a rank)
NETWORK=${NETWORK:-local}
[[ "$NETWORK" =~ ^(local|ib)$ ]] || { echo "NETWORK: local or ib" >&2; exit 2; }
PIXEL_NS=${MASTER_PIXEL_NS:-0.42}
# what a nap that runs out costs its rank's CPU (measured here: 6.4 us;
# bench/SCALE.md, sixth section); NAP_US=0: not charged
NAP_US=${NAP_US:-6.4}
[[ "$REPEATS" =~ ^[1-9]$ ]] || { echo "REPEATS: 1..9" >&2; exit 2; }
[[ "$SIZE" =~ ^[1-9][0-9]{1,3}$ ]] || { echo "SIZE: 10..9999" >&2; exit 2; }
[[ "$TILE" =~ ^(8|16|32|64|128)$ ]] || { echo "TILE: 8, 16, 32, 64 or 128" >&2; exit 2; }
[[ "$WORKERS" =~ ^[1-9]( [1-9])*$ ]] || { echo "WORKERS: digits 1..9, space-separated" >&2; exit 2; }
[[ "$MODES" =~ ^(homo|hetero)( (homo|hetero))*$ ]] || { echo "MODES: homo and/or hetero" >&2; exit 2; }
BIN=${CSGTRACE_BIN:-$ROOT/build/csgtrace}
read -r -a mpi_args <<<"${MPI_ARGS:-}"
read -r -a sim_args <<<"${SIM_ARGS:-}"
WORK=$ROOT/build/sim/validate
mkdir -p "$WORK"
SCENE=$WORK/spheres50.pov
[ -f "$SCENE" ] || "$ROOT/build/csgtrace" gen spheres --count 50 --occupancy 0.5 --seed 1 -o "$SCENE" >&2
echo "workers,mode,tile,real_s,sim_s,diff_pct,load1"
key=$(sha256sum "$SCENE" | cut -c1-16)
for mode in $MODES; do for w in $WORKERS; do for _ in $(seq "$REPEATS"); do
    sched=$([ $mode = homo ] && echo raster || echo cost)
    OMPI_MCA_pml=ob1 mpirun --allow-run-as-root --oversubscribe --bind-to none -np $((w + 1)) \
        "${mpi_args[@]}" "$BIN" render "$SCENE" -o "$WORK/img.png" --mode $mode --width $SIZE \
        --height $SIZE --tile $TILE --schedule $sched --fill off --stats "$WORK/real.json" \
        --tile-log "$WORK/real.log" >/dev/null 2>&1
    mkdir -p "$WORK/maps"
    python3 "$ROOT/bench/sim/costmap.py" "$WORK/maps/$key-$mode.costs" "$WORK/real.json" "$WORK/real.log"
    SIM_MAPS=$WORK/maps "$ROOT/bench/simulate.sh" "$SCENE" --workers $w --mode $mode \
        --schedule $sched --tile $TILE --network "$NETWORK" --size ${SIZE}x$SIZE --fill off \
        --master-part-us "$PART_US" --master-pixel-ns "$PIXEL_NS" \
        --master-message-us "$MESSAGE_US" --master-store-ns "$STORE_NS" --nap-us "$NAP_US" \
        "${sim_args[@]}" --stats "$WORK/sim.json" >/dev/null
    python3 - "$WORK/real.json" "$WORK/sim.json" "$w" "$mode" "$TILE" <<'PY'
import json, os, sys
r, d = json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))
real = r["primary_s"] + r["pipelined_s"] + r["secondary_s"]
sim = d["makespan_s"]
print(f"{sys.argv[3]},{sys.argv[4]},{sys.argv[5]},{real:.4f},{sim:.4f},{100*(sim-real)/real:+.1f},"
      f"{os.getloadavg()[0]:.2f}", flush=True)
PY
done; done; done
