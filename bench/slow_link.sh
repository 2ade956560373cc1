#!/usr/bin/env bash
# bench/slow_link.sh — a slow link rehearsed on one machine (as root): two
# network namespaces joined by a veth pair whose both ends are shaped by
# tc (tbf) to RATE, rank 0 alone in one, the NP - 1 workers in the other
# (docs/parallel.md, "Across hosts"; bench/sim/netns_agent.sh), every
# message over TCP.  Renders the spheres of issue 35 (gen spheres --count 50
# --occupancy 0.5 --seed 1) at SIZE x SIZE in each configuration
# MODE:COMPRESS:RECORDS (csgtrace --mode, --compress, --hit-records), ROUNDS
# interleaved rounds, and prints a CSV row per configuration: medians of
# the wall and the tile phase with their ranges, bytes each way, the
# results' format and the link rank 0 measured at start.
#   RATE=30mbit SIZE=1024 ROUNDS=3 NP=3 CONFIGS="homo:off:send homo:on:send" \
#       bench/slow_link.sh OUTDIR > rows.csv
# 30 Mbit/s for 2 workers is a gigabit link's share of 64 workers (15.6
# Mbit/s each).  bench/SCALE.md, "Results on a slow link", has a run.
set -u
ROOT=$(cd "$(dirname "$0")/.." && pwd)
OUT=${1:?usage: bench/slow_link.sh OUTDIR}
RATE=${RATE:-30mbit} ROUNDS=${ROUNDS:-3} SIZE=${SIZE:-1024} NP=${NP:-3}
CONFIGS=${CONFIGS:-"homo:off:send homo:auto:auto hetero:off:send hetero:auto:auto"}
[ "$(id -u)" = 0 ] || { echo "bench/slow_link.sh: needs root (ip netns, tc)" >&2; exit 2; }
[[ "$RATE" =~ ^[0-9]+[kmg]bit$ && "$SIZE" =~ ^[1-9][0-9]{0,4}$ && "$ROUNDS" =~ ^[1-9][0-9]?$ &&
   "$NP" =~ ^[2-9]$ ]] || { echo "bench/slow_link.sh: RATE (e.g. 30mbit), SIZE, ROUNDS, NP (2-9)" >&2; exit 2; }
mkdir -p "$OUT"
"$ROOT/build/csgtrace" gen spheres --count 50 --occupancy 0.5 --seed 1 --width 2048 --height 2048 \
    -o "$OUT/scene.pov" >/dev/null || exit 1
cleanup() { ip netns del csgA 2>/dev/null; ip netns del csgB 2>/dev/null; }
cleanup
trap cleanup EXIT
ip netns add csgA && ip netns add csgB &&
    ip link add vA type veth peer name vB &&
    ip link set vA netns csgA && ip link set vB netns csgB &&
    ip -n csgA addr add 10.77.0.1/24 dev vA && ip -n csgB addr add 10.77.0.2/24 dev vB &&
    ip -n csgA link set lo up && ip -n csgB link set lo up &&
    ip -n csgA link set vA up && ip -n csgB link set vB up &&
    ip netns exec csgA tc qdisc add dev vA root tbf rate "$RATE" burst 32kbit latency 50ms &&
    ip netns exec csgB tc qdisc add dev vB root tbf rate "$RATE" burst 32kbit latency 50ms ||
    { echo "bench/slow_link.sh: the namespaces could not be made" >&2; exit 1; }
printf '10.77.0.1 slots=1\n10.77.0.2 slots=%d\n' $((NP - 1)) >"$OUT/hosts"
cd "$ROOT"
for round in $(seq 1 "$ROUNDS"); do
    for cfg in $CONFIGS; do
        IFS=: read -r mode compress records <<<"$cfg"
        name=$mode-$compress-$records
        ip netns exec csgA mpirun --allow-run-as-root --oversubscribe --bind-to none \
            --hostfile "$OUT/hosts" -np "$NP" --mca plm_rsh_agent "$ROOT/bench/sim/netns_agent.sh" \
            --mca pml ob1 --mca btl tcp,self --mca btl_tcp_if_include 10.77.0.0/24 \
            --mca oob_tcp_if_include 10.77.0.0/24 -x POCL_CACHE_DIR="$ROOT/build/pocl-cache" \
            build/csgtrace render "$OUT/scene.pov" --width "$SIZE" --height "$SIZE" --mode "$mode" \
            --compress "$compress" --hit-records "$records" -o "$OUT/$name.png" \
            --stats "$OUT/r$round-$name.json" >"$OUT/r$round-$name.log" 2>&1 ||
            echo "bench/slow_link.sh: $cfg, round $round failed ($OUT/r$round-$name.log)" >&2
    done
done
python3 - "$OUT" $CONFIGS <<'PY'
import glob, json, statistics, sys
out = sys.argv[1]
print("config,rounds,result_pixels,link_mbps,wall_s,wall_min,wall_max,tile_phase_s,"
      "tile_min,tile_max,bytes_received,bytes_sent")
for cfg in sys.argv[2:]:
    runs = [json.load(open(f)) for f in sorted(glob.glob(f"{out}/r*-{cfg.replace(':', '-')}.json"))]
    if not runs:
        print(f"{cfg},0,,,,,,,,,,")
        continue
    w = [r["wall_s"] for r in runs]
    t = [r["tile_phase_s"] for r in runs]
    print(f"{cfg},{len(runs)},{runs[0]['result_pixels']},{statistics.median(r['link_mbps'] for r in runs):.1f},"
          f"{statistics.median(w):.3f},{min(w):.3f},{max(w):.3f},{statistics.median(t):.3f},"
          f"{min(t):.3f},{max(t):.3f},{runs[0]['bytes_received']},{runs[0]['bytes_sent']}")
PY
