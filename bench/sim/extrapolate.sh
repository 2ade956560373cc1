#!/usr/bin/env bash
# bench/sim/extrapolate.sh — issue 35's scale targets, simulated with the
# model validated against the node (bench/sim/node_validate.py): the
# node's own cost maps (a real 15-worker run's tile logs, scaling/*.jsonl)
# scaled to 4096x4096, the pass at the H200's measured rate (the map's),
# today's runtime, Open MPI's protocol as each network has it
# (bench/simulate.sh: --eager-bytes, --sender-progress defaults).
# Writes CSV rows to stdout: network, workers, relays, mode, tile, makespan,
# efficiency, master_busy, tail_s, ramp_s, bytes the master sent/received.
#   POINTS="ib:64:0:homo ..." [SCHEDULE=raster|cost|tail] [PIECES=auto|1|4|16|64] bench/sim/extrapolate.sh > out.csv
# PIXELS=rgb8z (csgtrace --compress on) with WIRE_MAP (the compressed bytes a
# tile, bench/sim/costmap.py --column wire_bytes), COMPRESS_NS, DECOMPRESS_NS
# (bench/compress_tiles.c); RECORDS=retrace (csgtrace --hit-records
# retrace: hetero's workers trace their primary rays, no records sent).
# JITTERS="0 0.1 0.2 0.3" runs each point once a value: rank 0 charged
# that many microseconds more a RESULT message (--master-message-us), far
# below what any measurement resolves (an item costs 350 us in the
# median), so the rows' spread is the schedule's sensitivity to timing
# (bench/SCALE.md, *the results' headers*: which tile ends last moves with
# any change); each row ends with its jitter, and stderr gets each point's
# median and range.  Default "0": one run, as before.
# MASTER_COSTS=yes charges rank 0's own work as bench/SCALE.md measured it
# (*the master's own work*, master_cost.sh): its loop 0.75 us a RESULT +
# 0.20 us a part + 0.42 ns a pixel, each store thread 5.4 ns a pixel, with
# STORE_THREADS of them (default auto, csgtrace's default: one a 64
# workers; 1 until 2026-11-29, late); without it rank 0
# costs only its messages, as every row before 2026-11-29 (night).
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
NODE=${NODE:-$ROOT/../shared/node/h200-2026-11-28}
TILE=${TILE:-32}
SCHEDULE=${SCHEDULE:-raster}
POINTS=${POINTS:-"ib:64:0:homo ib:64:0:hetero ib:256:16:homo ib:256:16:hetero ib:1024:32:homo ib:1024:32:hetero gige:64:0:hetero gige:64:0:homo"}
TIMEOUT=${POINT_TIMEOUT:-900}
JITTERS=${JITTERS:-0}
PIXELS=${PIXELS:-rgb8} RECORDS=${RECORDS:-send} PIECES=${PIECES:-auto}
wire=(--pixels "$PIXELS" --pieces "$PIECES")
[ -n "${WIRE_MAP:-}" ] && wire+=(--wire-map "$WIRE_MAP")
[ -n "${COMPRESS_NS:-}" ] && wire+=(--compress-ns "$COMPRESS_NS")
[ -n "${DECOMPRESS_NS:-}" ] && wire+=(--decompress-ns "$DECOMPRESS_NS")
[ "$RECORDS" = send ] || wire+=(--hit-records "$RECORDS")
MASTER_COSTS=${MASTER_COSTS:-no} STORE_THREADS=${STORE_THREADS:-auto}
[[ "$MASTER_COSTS" =~ ^(yes|no)$ ]] || { echo "MASTER_COSTS: yes or no" >&2; exit 2; }
message_us=0
if [ "$MASTER_COSTS" = yes ]; then
    message_us=0.75
    wire+=(--master-part-us 0.20 --master-pixel-ns 0.42 --master-store-ns 5.4
           --store-threads "$STORE_THREADS")
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$ROOT/build/csgtrace" gen spheres --count 50 --occupancy 0.5 --seed 1 --width 2048 --height 2048 \
    -o "$work/s50.pov" >/dev/null 2>&1
for mode in homo hetero; do
    python3 "$ROOT/bench/sim/costmap.py" "$work/$mode.costs" "$NODE/scaling/${mode}16.json" \
        "$NODE/scaling/${mode}16.jsonl"
done
echo "network,workers,relays,mode,tile,makespan_s,efficiency,efficiency_ranks,master_busy,tail_s,ramp_s,bytes_sent,bytes_received,jitter_us"
for p in $POINTS; do
    IFS=: read -r net workers relays mode <<<"$p"
    [[ "$net" =~ ^(ib|gige)$ && "$workers" =~ ^[0-9]+$ && "$relays" =~ ^[0-9]+$ && "$mode" =~ ^(homo|hetero)$ ]] ||
        { echo "bad point '$p'" >&2; exit 2; }
    fill=()
    [ "$mode" = hetero ] && fill=(--fill-map "$work/homo.costs")
    : >"$work/point.csv"
    for jitter in $JITTERS; do
        if timeout "$TIMEOUT" "$ROOT/bench/simulate.sh" "$work/s50.pov" --workers "$workers" \
            --mode "$mode" --network "$net" --size 4096x4096 --tile "$TILE" --relays "$relays" \
            --schedule "$SCHEDULE" --map "$work/$mode.costs" "${fill[@]}" "${wire[@]}" \
            --master-message-us "$(printf %.3f "$(echo "$message_us + $jitter" | bc -l)")" --stats "$work/p.json" >/dev/null 2>"$work/err"; then
            python3 - "$work/p.json" "$net" "$jitter" <<'PY' | tee -a "$work/point.csv"
import json, sys
d = json.load(open(sys.argv[1]))
print(f"{sys.argv[2]},{d['workers']},{d['relays']},{d['mode']},{d['tile']},{d['makespan_s']:.5f},"
      f"{d['efficiency']:.4f},{d['efficiency_ranks']:.4f},{d['master_busy']:.3f},{d['tail_s']:.5f},"
      f"{d['ramp_s']:.5f},{d['bytes_sent']},{d['bytes_received']},{sys.argv[3]}", flush=True)
PY
        else
            echo "$net,$workers,$relays,$mode,$TILE,,,,,,,,,$jitter # failed or past ${TIMEOUT} s: $(tail -1 "$work/err")"
        fi
    done
    python3 - "$work/point.csv" "$p" >&2 <<'PY'
import csv, statistics, sys
effs = sorted(float(r[6]) for r in csv.reader(open(sys.argv[1])) if len(r) > 6 and r[6])
if len(effs) > 1:
    print(f"# {sys.argv[2]}: efficiency median {100 * statistics.median(effs):.1f} % "
          f"({100 * effs[0]:.1f}-{100 * effs[-1]:.1f} %, {len(effs)} runs)")
PY
done
