#!/usr/bin/env bash
# bench/simulate.sh — one point of the simulated cluster (make sim; bench/SCALE.md).
#
#   bench/simulate.sh SCENE --workers N --mode homo|hetero [--schedule S]
#       [--tile T] [--network gige|ib|local] [--size WxH] [--pass-scale F | --pass-rate M]
#       [--batch N|auto] [--pixels rgb8|float] [--fill on|off] [--relays K]
#       [--master-part-us A --master-pixel-ns B] --stats F.json
#
# 1. A cost map of SCENE for the mode, cached in build/sim/maps (keyed by the
#    scene's sha256): three ($SIM_MAP_RENDERS) real renders at 384x384, tile 8, raster, 1 master
#    + 1 worker (mpirun -np 2), their tile logs reduced by bench/sim/costmap.py
#    (each cell's minimum: preemption on a shared machine only adds).
#    Other sizes scale this map (workers/tile_sim.h): a pixel of a 4096x4096
#    image costs what the recorded pixel under it cost, the pass scales with
#    the pixel count.  Not a real 4096x4096 render: an estimate from 384x384.
#    Hetero maps are recorded with --fill off (every cell's cost is its
#    shading); hetero with the fill (the default, --fill on: csgtrace's)
#    also needs the homo map: what a tile rendered whole costs.
# 2. build/sim/csgsim under smpirun on bench/sim/<network>.xml, N + 1 ranks
#    (local: this 2-core machine, every rank on its one host)
#    (N + K + 1 with --relays K: K relays, each the master of N / K of the
#    N workers, host/relay.h).
# 3. F.json: the driver's object plus network and pass_scale.
# --pass-scale F (default 1) multiplies the measured OpenCL pass (hetero):
# 1 is PoCL on this machine's 2 CPU cores; 0.01 stands for a device 100
# times faster (a GPU-class accelerator): a hypothesis, labelled as such.
# --pass-rate M (Mrays/s) replaces it by a measured device rate: the pass
# takes W x H / (M x 1e6) seconds (bench/GPU.md: the H100's rates).
# --batch N|auto: the master's batch limit (csgtrace --batch; default auto).
# --pixels rgb8|float: what a RESULT carries a pixel: rgb8 (default) is a
# render to an 8-bit file (PNG, ...: 3 bytes), float one to EXR (12 bytes,
# as every render sent before 2026-11-25).
# --master-part-us A, --master-pixel-ns B: the master's own work on each
# RESULT part of P pixels, A us + P x B ns (checking, storing the pixels,
# queuing the journal), executed on its host; default 0 (only MPI's
# per-message costs below).  bench/SCALE.md has the values measured here.
# Arguments are checked against fixed patterns and passed as separate words;
# nothing from them is ever evaluated.
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
CSGTRACE=${CSGTRACE:-$ROOT/build/csgtrace}
CSGSIM=${CSGSIM:-$ROOT/build/sim/csgsim}
MAPS=${SIM_MAPS:-$ROOT/build/sim/maps}
REC_SIZE=384 REC_TILE=8
# Renders the cost map is recorded from (each cell's minimum): 3, or
# $SIM_MAP_RENDERS (10 for the map of bench/SCALE.md's 8-bit section: three
# left cells 22 times the mean on a machine at load 10).
MAP_RENDERS=${SIM_MAP_RENDERS:-3}
[[ "$MAP_RENDERS" =~ ^[1-9][0-9]?$ ]] || { echo "bench/simulate.sh: SIM_MAP_RENDERS: 1..99" >&2; exit 2; }

die() { echo "bench/simulate.sh: $*" >&2; exit 2; }
SCENE="" WORKERS="" MODE="" SCHEDULE="" TILE=32 NETWORK=gige SIZE=384x384 STATS="" PASS_SCALE=1 PASS_RATE=0 BATCH=auto PIXELS=rgb8 FILL=on RELAYS=0
PART_US=0 PIXEL_NS=0
[ $# -ge 1 ] || die "usage: SCENE --workers N --mode homo|hetero [--schedule S] [--tile T] [--network gige|ib|local] [--size WxH] --stats F.json"
SCENE=$1; shift
while [ $# -gt 0 ]; do
    [ $# -ge 2 ] || die "$1 needs a value"
    case "$1" in
    --workers) WORKERS=$2 ;;
    --mode) MODE=$2 ;;
    --schedule) SCHEDULE=$2 ;;
    --tile) TILE=$2 ;;
    --network) NETWORK=$2 ;;
    --size) SIZE=$2 ;;
    --stats) STATS=$2 ;;
    --pass-scale) PASS_SCALE=$2 ;;
    --pass-rate) PASS_RATE=$2 ;;
    --batch) BATCH=$2 ;;
    --pixels) PIXELS=$2 ;;
    --fill) FILL=$2 ;;
    --relays) RELAYS=$2 ;;
    --master-part-us) PART_US=$2 ;;
    --master-pixel-ns) PIXEL_NS=$2 ;;
    *) die "unknown option '$1'" ;;
    esac
    shift 2
done
[ -f "$SCENE" ] || die "no scene file '$SCENE'"
[[ "$WORKERS" =~ ^[1-9][0-9]{0,3}$ ]] && [ "$WORKERS" -le 1024 ] || die "--workers: 1..1024"
[[ "$MODE" =~ ^(homo|hetero)$ ]] || die "--mode: homo or hetero"
[ -n "$SCHEDULE" ] || { [ "$MODE" = hetero ] && SCHEDULE=cost || SCHEDULE=raster; }
[[ "$SCHEDULE" =~ ^(raster|cost|static|tail)$ ]] || die "--schedule: raster, cost, static or tail"
[[ "$TILE" =~ ^[1-9][0-9]{0,3}$ ]] || die "--tile: 1..9999"
[[ "$NETWORK" =~ ^(gige|ib|local)$ ]] || die "--network: gige, ib or local"
[[ "$SIZE" =~ ^([1-9][0-9]{0,4})x([1-9][0-9]{0,4})$ ]] || die "--size: WxH"
WIDTH=${BASH_REMATCH[1]} HEIGHT=${BASH_REMATCH[2]}
[[ "$PASS_SCALE" =~ ^(0|[1-9][0-9]*)?(\.[0-9]{1,6})?$ && "$PASS_SCALE" =~ [1-9] ]] || die "--pass-scale: a positive decimal number"
[[ "$PASS_RATE" =~ ^(0|[1-9][0-9]*)?(\.[0-9]{1,6})?$ ]] || die "--pass-rate: Mrays/s, a decimal number"
[[ "$BATCH" =~ ^(auto|[1-9][0-9]?)$ ]] || die "--batch: auto or 1..99"
[[ "$PIXELS" =~ ^(rgb8|float)$ ]] || die "--pixels: rgb8 or float"
[[ "$FILL" =~ ^(on|off)$ ]] || die "--fill: on or off"
[[ "$RELAYS" =~ ^(0|[1-9][0-9]{0,2})$ ]] && [ "$RELAYS" -le 127 ] && [ "$RELAYS" -le "$WORKERS" ] || die "--relays: 0..min(127, workers)"
[[ "$PART_US" =~ ^(0|[1-9][0-9]{0,3})(\.[0-9]{1,3})?$ ]] || die "--master-part-us: microseconds, 0..9999.999"
[[ "$PIXEL_NS" =~ ^(0|[1-9][0-9]{0,3})(\.[0-9]{1,3})?$ ]] || die "--master-pixel-ns: nanoseconds, 0..9999.999"
[ -n "$STATS" ] || die "--stats FILE.json is required"
[ -x "$CSGSIM" ] || die "$CSGSIM missing: make sim"

# 1. the cost maps (recorded once per scene and mode)
key=$(sha256sum "$SCENE" | cut -c1-16)
rec=""
# ensure_map MODE: $MAPS/KEY-MODE.costs, recorded when missing.
ensure_map() {
    local mode=$1 map=$MAPS/$key-$1.costs fill=()
    [ -f "$map" ] && return 0
    [ -x "$CSGTRACE" ] || die "$CSGTRACE missing: make"
    [ "$mode" = hetero ] && fill=(--fill off)
    mkdir -p "$MAPS"
    rec=$(mktemp -d)
    trap 'rm -rf "$rec"' EXIT
    local pairs=()
    for k in $(seq "$MAP_RENDERS"); do # each cell's minimum (costmap.py)
        OMPI_MCA_pml=ob1 mpirun --allow-run-as-root --oversubscribe --bind-to none -np 2 \
            "$CSGTRACE" render "$SCENE" -o "$rec/img.png" --mode "$mode" --width $REC_SIZE \
            --height $REC_SIZE --tile $REC_TILE --schedule raster "${fill[@]}" \
            --stats "$rec/$k.json" --tile-log "$rec/$k.log" >&2
        pairs+=("$rec/$k.json" "$rec/$k.log")
    done
    python3 "$ROOT/bench/sim/costmap.py" "$rec/map" "${pairs[@]}"
    mv "$rec/map" "$map"
    rm -rf "$rec"
    rec=""
}
ensure_map "$MODE"
map=$MAPS/$key-$MODE.costs
fill_map=""
if [ "$MODE" = hetero ] && [ "$FILL" = on ]; then
    ensure_map homo
    fill_map=$MAPS/$key-homo.costs
fi

# 2. the simulation
work=$(mktemp -d)
trap 'rm -rf "$work" ${rec:+"$rec"}' EXIT
if [ "$NETWORK" = local ]; then # every rank on this machine's one host
    for _ in $(seq 0 $((WORKERS + RELAYS))); do echo node-0; done >"$work/hosts"
else
    seq 0 $((WORKERS + RELAYS)) | sed 's/^/node-/' >"$work/hosts"
fi
# Per-message costs: a poll (MPI_Iprobe, MPI_Test) 0.1 us; sending or
# receiving a message takes its rank 5 us + 0.2 ns a byte; messages up to
# 64 KiB are eager (Open MPI's TCP eager limit): they travel before the
# receive is posted (bench/SCALE.md).
# GigE keeps SMPI's default latency/bandwidth factors (fitted to MPI over
# TCP on Ethernet); InfiniBand gets none (RDMA).
opts=(--cfg=smpi/simulate-computation:no --cfg=smpi/iprobe:1e-7 --cfg=smpi/test:1e-7
      --cfg=smpi/os:0:5e-6:2e-10 --cfg=smpi/or:0:5e-6:2e-10 --cfg=smpi/host-speed:1Gf
      --cfg=smpi/async-small-thresh:65536 --cfg=smpi/send-is-detached-thresh:65536
      --log=root.thres:error)
[ "$NETWORK" != gige ] && opts+=(--cfg=smpi/lat-factor:0:1 --cfg=smpi/bw-factor:0:1)
batch=()
[ "$BATCH" = auto ] || batch=(--batch "$BATCH")
CSGSIM_MASTER_PART_S=$(echo "$PART_US / 1000000" | bc -l) CSGSIM_MASTER_PIXEL_S=$(echo "$PIXEL_NS / 1000000000" | bc -l) \
CSGSIM_COSTS=$map CSGSIM_FILL_COSTS=$fill_map CSGSIM_PASS_SCALE=$PASS_SCALE CSGSIM_PASS_RATE=$PASS_RATE \
    smpirun -np $((WORKERS + RELAYS + 1)) -platform "$ROOT/bench/sim/$NETWORK.xml" \
    -hostfile "$work/hosts" "${opts[@]}" "$CSGSIM" "$SCENE" --mode "$MODE" --width "$WIDTH" \
    --height "$HEIGHT" --tile "$TILE" --schedule "$SCHEDULE" "${batch[@]}" --pixels "$PIXELS" --fill "$FILL" --relays "$RELAYS" --stats "$work/out.json" \
    >"$work/log" 2>&1 || { cat "$work/log" >&2; exit 1; }
python3 - "$work/out.json" "$NETWORK" "$STATS" "$PASS_SCALE" "$PASS_RATE" "$PART_US" "$PIXEL_NS" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
d["network"] = sys.argv[2]
d["pass_scale"] = float(sys.argv[4])
d["pass_rate_mrays"] = float(sys.argv[5])
d["master_part_us"] = float(sys.argv[6])
d["master_pixel_ns"] = float(sys.argv[7])
with open(sys.argv[3], "w") as f:
    json.dump(d, f)
    f.write("\n")
PY
