#!/usr/bin/env bash
# bench/simulate.sh — one point of the simulated cluster (make sim; bench/SCALE.md).
#
#   bench/simulate.sh SCENE --workers N --mode homo|hetero [--schedule S]
#       [--tile T] [--network gige|ib|local] [--size WxH] [--pass-scale F | --pass-rate M]
#       [--batch N|auto] [--pieces N|auto] [--pixels rgb8|rgb8z|float] [--fill on|off] [--relays K]
#       [--wire-map FILE] [--compress-ns D] [--decompress-ns I] [--hit-records send|retrace]
#       [--master-part-us A --master-pixel-ns B] [--master-message-us M]
#       [--master-store-ns C [--store-threads N]] [--nap-us U] [--map FILE [--fill-map FILE]]
#       [--pass-delay S] [--eager-bytes E] [--sender-progress yes|no] [--runtime current|legacy]
#       [--scene-memory MB --page-trace FILE[:FILE...] [--page-size KB] [--page-policy lru|fifo]
#        [--page-prefetch on|off] [--page-fetch get|ask] [--page-home auto|master|spread]
#        [--page-install-ns I] [--master-page-ns P] [--paged-cost-scale X]] --stats F.json
#
# 1. A cost map of SCENE for the mode, cached in build/sim/maps (keyed by the
#    scene's sha256): three ($SIM_MAP_RENDERS) real renders at 384x384, tile 8, raster, 1 master
#    + 1 worker (mpirun -np 2), their tile logs reduced by bench/sim/costmap.py
#    (each cell's minimum: preemption on a shared machine only adds).
#    Other sizes scale this map (sim/tile_sim.h): a pixel of a 4096x4096
#    image costs what the recorded pixel under it cost, the pass scales with
#    the pixel count.  Not a real 4096x4096 render: an estimate from 384x384.
#    Hetero maps are recorded with --fill off (every cell's cost is its
#    shading); hetero with the fill (the default, --fill on: csgtrace's)
#    also needs the homo map: what a tile rendered whole costs.
# 2. build/sim/csgsim under smpirun on bench/sim/<network>.xml, N + 1 ranks
#    (local: this 2-core machine, every rank on its one host)
#    (N + K + 1 with --relays K: K relays, each the master of N / K of the
#    N workers, comm/relay.h).
# 3. F.json: the driver's object plus network and pass_scale.
# --pass-scale F (default 1) multiplies the measured OpenCL pass (hetero):
# 1 is PoCL on this machine's 2 CPU cores; 0.01 stands for a device 100
# times faster (a GPU-class accelerator): a hypothesis, labelled as such.
# --pass-rate M (Mrays/s) replaces it by a measured device rate: the pass
# takes W x H / (M x 1e6) seconds (bench/GPU.md: the H100's rates).
# --pass-delay S: the device's set-up, seconds before the pass's first slice
# (cl_setup_s of the stats; default 0).
# --batch N|auto: the master's batch limit (csgtrace --batch; default auto).
# --pieces N|auto: the items a tile goes as (csgtrace --pieces; default auto).
# --pixels rgb8|float: what a RESULT carries a pixel: rgb8 (default) is a
# render to an 8-bit file (PNG, ...: 3 bytes), float one to EXR (12 bytes,
# as every render sent before 2026-11-25), rgb8z the 8-bit bytes compressed
# (csgtrace --compress: comm/pixels_z.h).  With rgb8z, --wire-map FILE:
# each part carries the bytes a real render's part of that rectangle
# compressed to (bench/sim/costmap.py --column wire_bytes of a render with
# --compress on; without it, the simulated black pixels compress to almost
# nothing); --compress-ns D: a worker's nanoseconds a raw byte compressed,
# --decompress-ns I: rank 0's a byte decompressed (bench/compress_tiles.c
# measures both; default 0).
# --hit-records retrace (hetero): the records are not sent, each tile with
# hits costs the homo (fill) map's seconds (csgtrace --hit-records).
# --master-part-us A, --master-pixel-ns B: the master's own work on each
# RESULT part of P pixels, A us + P x B ns (checking, storing the pixels,
# queuing the journal), executed on its host; default 0 (only MPI's
# per-message costs below).  --master-message-us M: M us more a RESULT
# message.  --master-store-ns C: the 8-bit parts' pixels are stored by the
# master's store thread (host/store.h), C ns a pixel on a core of its own,
# while its ring has room (A and B are then the loop's part without the
# store); default 0: no store thread, the loop stores them (B).
# --store-threads N|auto: so many store threads (csgtrace --store-threads),
# each on a core of its own at C ns a pixel, a part going to the one that
# is free first; default auto, csgtrace's (one a 64 workers, 1 to 8).
# --nap-us U: every nap that runs out (mpi_link.c's idle wait, any rank) costs
# its rank U us of CPU besides (the timer and the wake-up: 6.4 measured
# here, bench/SCALE.md); default 0.
# --map FILE (and --fill-map FILE, hetero's whole tiles): cost maps made
# elsewhere (bench/sim/costmap.py from a real run's tile log: the node's,
# bench/sim/node_validate.sh) instead of the ones recorded here.
# --network node: one host of 16 cores sharing memory (bench/sim/node.xml).
# --network slow30: gigabit Ethernet's cluster at 30 Mbit/s a link, TCP as
# gige (bench/sim/slow30.xml: bench/slow_link.sh's real link).
# --eager-bytes E: Open MPI's eager limit on the network (its 4.1 defaults:
# shared memory 4096 (btl_vader_eager_limit; node, local), openib 12288 (ib),
# tcp 65536 (gige)); a larger message waits for the receiver to match it.
# --sender-progress yes|no: whether its bytes then also wait for the
# sender's next call into MPI (comm/mpi_link.h, link_model_protocol): yes
# on shared memory without single copy (containers; the node's) and TCP,
# no on InfiniBand (the receiver reads it by RDMA); defaults as said.
# --runtime legacy: the runtime before 2026-11-28 (a message received whole
# before the next, no progress while a worker computes), to check the
# model against the node's runs of that code (bench/sim/node_validate.sh).
# --scene-memory MB: each worker holds the scene within MB megabytes, in
# pages served by rank 0 or their home workers (csgtrace --scene-memory;
# --page-size, --page-policy, --page-prefetch, --page-fetch, --page-home as there); every item names the pages its real one named
# in the --page-trace files (a real render of the same scene, size, tile
# and page size with $CSGTRACE_PAGE_TRACE set: bench/sim/paging.sh records
# them).  --page-install-ns I: a worker's nanoseconds a fetched byte (its
# copies into place, the kernel's faults); --master-page-ns P: rank 0's a
# byte it packs; both measured by bench/sim/paging.sh (default 0).
# --paged-cost-scale X: a paged item's seconds are the map's times X (its
# prefetch walks, which the in-memory map does not have: the instructions'
# ratio, bench/PAGING.md; default 1).
# bench/SCALE.md has the values measured here.
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
SCENE="" WORKERS="" MODE="" SCHEDULE="" TILE=32 NETWORK=gige SIZE=384x384 STATS="" PASS_SCALE=1 PASS_RATE=0 BATCH=auto PIECES=auto PIXELS=rgb8 FILL=on RELAYS=0
PART_US=0 PIXEL_NS=0 MESSAGE_US=0 STORE_NS=0 STORE_THREADS=auto NAP_US=0 GIVEN_MAP="" GIVEN_FILL_MAP=""
EAGER="" SENDER_PROGRESS="" RUNTIME=current PASS_DELAY=0
SCENE_MEMORY="" PAGE_TRACE="" PAGE_SIZE=0 PAGE_POLICY=lru PAGE_PREFETCH=on PAGE_FETCH=get PAGE_HOME=auto PAGE_INSTALL_NS=0 MASTER_PAGE_NS=0 PAGED_COST_SCALE=1
WIRE_MAP="" COMPRESS_NS=0 DECOMPRESS_NS=0 RECORDS=send
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
    --pieces) PIECES=$2 ;;
    --pixels) PIXELS=$2 ;;
    --wire-map) WIRE_MAP=$2 ;;
    --hit-records) RECORDS=$2 ;;
    --compress-ns) COMPRESS_NS=$2 ;;
    --decompress-ns) DECOMPRESS_NS=$2 ;;
    --fill) FILL=$2 ;;
    --relays) RELAYS=$2 ;;
    --master-part-us) PART_US=$2 ;;
    --master-pixel-ns) PIXEL_NS=$2 ;;
    --master-message-us) MESSAGE_US=$2 ;;
    --master-store-ns) STORE_NS=$2 ;;
    --store-threads) STORE_THREADS=$2 ;;
    --nap-us) NAP_US=$2 ;;
    --map) GIVEN_MAP=$2 ;;
    --fill-map) GIVEN_FILL_MAP=$2 ;;
    --eager-bytes) EAGER=$2 ;;
    --pass-delay) PASS_DELAY=$2 ;;
    --sender-progress) SENDER_PROGRESS=$2 ;;
    --runtime) RUNTIME=$2 ;;
    --scene-memory) SCENE_MEMORY=$2 ;;
    --page-trace) PAGE_TRACE=$2 ;;
    --page-size) PAGE_SIZE=$2 ;;
    --page-policy) PAGE_POLICY=$2 ;;
    --page-prefetch) PAGE_PREFETCH=$2 ;;
    --page-fetch) PAGE_FETCH=$2 ;;
    --page-home) PAGE_HOME=$2 ;;
    --page-install-ns) PAGE_INSTALL_NS=$2 ;;
    --master-page-ns) MASTER_PAGE_NS=$2 ;;
    --paged-cost-scale) PAGED_COST_SCALE=$2 ;;
    *) die "unknown option '$1'" ;;
    esac
    shift 2
done
[ -f "$SCENE" ] || die "no scene file '$SCENE'"
[[ "$WORKERS" =~ ^[1-9][0-9]{0,3}$ ]] && [ "$WORKERS" -le 1024 ] || die "--workers: 1..1024"
[[ "$MODE" =~ ^(homo|hetero)$ ]] || die "--mode: homo or hetero"
[ -n "$SCHEDULE" ] || { [ "$MODE" = hetero ] && SCHEDULE=cost || SCHEDULE=raster; }
[[ "$SCHEDULE" =~ ^(raster|cost|static|tail|region)$ ]] || die "--schedule: raster, cost, static, tail or region"
[[ "$TILE" =~ ^[1-9][0-9]{0,3}$ ]] || die "--tile: 1..9999"
[[ "$NETWORK" =~ ^(gige|ib|local|node|slow30)$ ]] || die "--network: gige, ib, local, node or slow30"
[ -z "$GIVEN_MAP" ] || [ -f "$GIVEN_MAP" ] || die "--map: no file '$GIVEN_MAP'"
[ -z "$GIVEN_FILL_MAP" ] || [ -f "$GIVEN_FILL_MAP" ] || die "--fill-map: no file '$GIVEN_FILL_MAP'"
[[ "$SIZE" =~ ^([1-9][0-9]{0,4})x([1-9][0-9]{0,4})$ ]] || die "--size: WxH"
WIDTH=${BASH_REMATCH[1]} HEIGHT=${BASH_REMATCH[2]}
[[ "$PASS_SCALE" =~ ^(0|[1-9][0-9]*)?(\.[0-9]{1,6})?$ && "$PASS_SCALE" =~ [1-9] ]] || die "--pass-scale: a positive decimal number"
[[ "$PASS_RATE" =~ ^(0|[1-9][0-9]*)?(\.[0-9]{1,6})?$ ]] || die "--pass-rate: Mrays/s, a decimal number"
[[ "$BATCH" =~ ^(auto|[1-9][0-9]?)$ ]] || die "--batch: auto or 1..99"
[[ "$PIECES" =~ ^(auto|1|4|16|64)$ ]] || die "--pieces: auto, 1, 4, 16 or 64"
[[ "$PIXELS" =~ ^(rgb8|rgb8z|float)$ ]] || die "--pixels: rgb8, rgb8z or float"
[ -z "$WIRE_MAP" ] || [ -f "$WIRE_MAP" ] || die "--wire-map: no file '$WIRE_MAP'"
[[ "$RECORDS" =~ ^(send|retrace)$ ]] || die "--hit-records: send or retrace"
[[ "$COMPRESS_NS" =~ ^(0|[1-9][0-9]{0,3})(\.[0-9]{1,4})?$ ]] || die "--compress-ns: nanoseconds, 0..9999.9999"
[[ "$DECOMPRESS_NS" =~ ^(0|[1-9][0-9]{0,3})(\.[0-9]{1,4})?$ ]] || die "--decompress-ns: nanoseconds, 0..9999.9999"
[[ "$FILL" =~ ^(on|off)$ ]] || die "--fill: on or off"
[[ "$RELAYS" =~ ^(0|[1-9][0-9]{0,2})$ ]] && [ "$RELAYS" -le 127 ] && [ "$RELAYS" -le "$WORKERS" ] || die "--relays: 0..min(127, workers)"
[[ "$PART_US" =~ ^(0|[1-9][0-9]{0,3})(\.[0-9]{1,3})?$ ]] || die "--master-part-us: microseconds, 0..9999.999"
[[ "$PIXEL_NS" =~ ^(0|[1-9][0-9]{0,3})(\.[0-9]{1,3})?$ ]] || die "--master-pixel-ns: nanoseconds, 0..9999.999"
[[ "$MESSAGE_US" =~ ^(0|[1-9][0-9]{0,3})(\.[0-9]{1,3})?$ ]] || die "--master-message-us: microseconds, 0..9999.999"
[[ "$STORE_NS" =~ ^(0|[1-9][0-9]{0,3})(\.[0-9]{1,3})?$ ]] || die "--master-store-ns: nanoseconds, 0..9999.999"
[[ "$STORE_THREADS" =~ ^([1-8]|auto)$ ]] || die "--store-threads: 1..8 or auto"
[[ "$NAP_US" =~ ^(0|[1-9][0-9]{0,2})(\.[0-9]{1,3})?$ ]] || die "--nap-us: microseconds, 0..999.999"
case $NETWORK in
ib) : "${EAGER:=12288}" "${SENDER_PROGRESS:=no}" ;;
gige | slow30) : "${EAGER:=65536}" "${SENDER_PROGRESS:=yes}" ;;
*) : "${EAGER:=4096}" "${SENDER_PROGRESS:=yes}" ;;
esac
[[ "$PASS_DELAY" =~ ^(0|[1-9][0-9]*)?(\.[0-9]{1,6})?$ ]] || die "--pass-delay: seconds, a decimal number"
[[ "$EAGER" =~ ^[1-9][0-9]{0,8}$ ]] || die "--eager-bytes: 1..999999999"
[[ "$SENDER_PROGRESS" =~ ^(yes|no)$ ]] || die "--sender-progress: yes or no"
[[ "$RUNTIME" =~ ^(current|legacy)$ ]] || die "--runtime: current or legacy"
[ -z "$SCENE_MEMORY" ] || [[ "$SCENE_MEMORY" =~ ^(0|[1-9][0-9]{0,6})(\.[0-9]{1,6})?$ && "$SCENE_MEMORY" =~ [1-9] ]] || die "--scene-memory: megabytes, a positive decimal number"
[[ "$PAGE_SIZE" =~ ^(0|[1-9][0-9]{0,5})$ ]] || die "--page-size: KiB, 0 (auto) .. 999999"
[[ "$PAGE_POLICY" =~ ^(lru|fifo)$ ]] || die "--page-policy: lru or fifo"
[[ "$PAGE_PREFETCH" =~ ^(on|off)$ ]] || die "--page-prefetch: on or off"
[[ "$PAGE_FETCH" =~ ^(get|ask)$ ]] || die "--page-fetch: get or ask"
[[ "$PAGE_HOME" =~ ^(auto|master|spread)$ ]] || die "--page-home: auto, master or spread"
[[ "$PAGED_COST_SCALE" =~ ^[1-9](\.[0-9]{1,4})?$ ]] || die "--paged-cost-scale: 1..9.9999"
[[ "$PAGE_INSTALL_NS" =~ ^(0|[1-9][0-9]{0,3})(\.[0-9]{1,4})?$ ]] || die "--page-install-ns: nanoseconds, 0..9999.9999"
[[ "$MASTER_PAGE_NS" =~ ^(0|[1-9][0-9]{0,3})(\.[0-9]{1,4})?$ ]] || die "--master-page-ns: nanoseconds, 0..9999.9999"
paging=()
if [ -n "$SCENE_MEMORY" ]; then
    [ -n "$PAGE_TRACE" ] || die "--scene-memory needs --page-trace"
    IFS=: read -ra traces <<<"$PAGE_TRACE"
    for f in "${traces[@]}"; do [ -f "$f" ] || die "--page-trace: no file '$f'"; done
    paging=(--scene-memory "$SCENE_MEMORY" --page-policy "$PAGE_POLICY" --page-prefetch "$PAGE_PREFETCH"
            --page-fetch "$PAGE_FETCH" --page-home "$PAGE_HOME")
    [ "$PAGE_SIZE" = 0 ] || paging+=(--page-size "$PAGE_SIZE")
fi
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
if [ -n "$GIVEN_MAP" ]; then
    map=$GIVEN_MAP fill_map=$GIVEN_FILL_MAP
    [ "$MODE$RECORDS" != heteroretrace ] || [ -n "$fill_map" ] ||
        die "--hit-records retrace with --map needs --fill-map (what a whole tile costs)"
else
    ensure_map "$MODE"
    map=$MAPS/$key-$MODE.costs
    fill_map=""
    if [ "$MODE" = hetero ] && { [ "$FILL" = on ] || [ "$RECORDS" = retrace ]; }; then
        ensure_map homo
        fill_map=$MAPS/$key-homo.costs
    fi
fi

# 2. the simulation
work=$(mktemp -d)
trap 'rm -rf "$work" ${rec:+"$rec"}' EXIT
if [ "$NETWORK" = local ] || [ "$NETWORK" = node ]; then # every rank on the one host
    for _ in $(seq 0 $((WORKERS + RELAYS))); do echo node-0; done >"$work/hosts"
else
    seq 0 $((WORKERS + RELAYS)) | sed 's/^/node-/' >"$work/hosts"
fi
# Per-message costs: a poll (MPI_Iprobe, MPI_Test) 0.1 us; sending or
# receiving a message takes its rank 5 us + 0.2 ns a byte across hosts;
# on this machine (local: Open MPI's shared memory) 0.05 us + 0.1 ns a
# byte, so that with local.xml's 0.5 us and 10 GB/s a message takes
# 0.6 us + 0.3 ns a byte end to end, as a ping-pong here measures it
# (0.64 us at 64 bytes, 7.7 us at 16 KiB, 74-80 us at 256 KiB: bench/
# SCALE.md); messages up to the eager limit (--eager-bytes) travel before
# the receive is posted, larger ones once it is (and the sender has
# called in again, with --sender-progress yes).
# GigE keeps SMPI's default latency/bandwidth factors (fitted to MPI over
# TCP on Ethernet); InfiniBand gets none (RDMA).
# A poll that finds nothing costs the same each time, as in MPI (SMPI's
# default makes each one longer than the last until one succeeds: a master
# polling 50 times between naps then spent 127 us polling, 0.1 + 0.2 + ...
# + 5 us, and was slow to see the next result; $SIM_PROBE_GROWTH=yes brings
# that back, as every simulation before 2026-11-26 (fifth) ran).
GROW=${SIM_PROBE_GROWTH:-no}
[[ "$GROW" =~ ^(yes|no)$ ]] || die "SIM_PROBE_GROWTH: yes or no"
overhead=0:5e-6:2e-10 iprobe=1e-7 test=1e-7
[ "$NETWORK" = local ] || [ "$NETWORK" = node ] && overhead=0:5e-8:1e-10 iprobe=8e-8 test=2.6e-8
opts=(--cfg=smpi/simulate-computation:no --cfg=smpi/iprobe:$iprobe --cfg=smpi/test:$test
      --cfg=smpi/os:$overhead --cfg=smpi/or:$overhead --cfg=smpi/host-speed:1Gf
      --cfg=smpi/async-small-thresh:$EAGER --cfg=smpi/send-is-detached-thresh:$EAGER
      --cfg=smpi/grow-injected-times:$GROW --log=root.thres:error)
# $SIM_TCP_FACTORS=none drops SMPI's TCP factors on gige and slow30 too
# (they cut a 3 KB message's bandwidth to 61 %: bench/SCALE.md, "Results
# on a slow link", checks both against a real link).
TCPF=${SIM_TCP_FACTORS:-smpi}
[[ "$TCPF" =~ ^(smpi|none)$ ]] || die "SIM_TCP_FACTORS: smpi or none"
{ { [ "$NETWORK" != gige ] && [ "$NETWORK" != slow30 ]; } || [ "$TCPF" = none ]; } &&
    opts+=(--cfg=smpi/lat-factor:0:1 --cfg=smpi/bw-factor:0:1)
batch=()
[ "$BATCH" = auto ] || batch=(--batch "$BATCH")
[ "$PIECES" = auto ] || batch+=(--pieces "$PIECES")
# (the workers append their lines: sim/tile_run.c, sim_work_log)
[ -z "${CSGSIM_WORK_LOG:-}" ] || echo "rank,x,y,width,height,start_s,end_s" >"$CSGSIM_WORK_LOG"
CSGSIM_MASTER_PART_S=$(echo "$PART_US / 1000000" | bc -l) CSGSIM_MASTER_PIXEL_S=$(echo "$PIXEL_NS / 1000000000" | bc -l) \
CSGSIM_MASTER_MESSAGE_S=$(echo "$MESSAGE_US / 1000000" | bc -l) CSGSIM_MASTER_STORE_S=$(echo "$STORE_NS / 1000000000" | bc -l) \
CSGSIM_MASTER_STORE_THREADS=$([ "$STORE_THREADS" = auto ] && echo 0 || echo "$STORE_THREADS") \
CSGSIM_WORKERS=$WORKERS CSGSIM_NAP_CPU_S=$(echo "$NAP_US / 1000000" | bc -l) \
CSGSIM_EAGER_BYTES=$([ "$SENDER_PROGRESS" = yes ] && echo "$EAGER" || echo 0) \
CSGSIM_PAGES=$PAGE_TRACE CSGSIM_PAGE_INSTALL_S=$(echo "$PAGE_INSTALL_NS / 1000000000" | bc -l) \
CSGSIM_MASTER_PAGE_S=$(echo "$MASTER_PAGE_NS / 1000000000" | bc -l) CSGSIM_PAGED_COST_SCALE=$PAGED_COST_SCALE \
CSGSIM_PASS_DELAY_S=$PASS_DELAY CSGSIM_LEGACY_RUNTIME=$([ "$RUNTIME" = legacy ] && echo 1 || echo 0) \
CSGSIM_WIRE_BYTES=$WIRE_MAP CSGSIM_COMPRESS_S=$(echo "$COMPRESS_NS / 1000000000" | bc -l) \
CSGSIM_MASTER_DECOMPRESS_S=$(echo "$DECOMPRESS_NS / 1000000000" | bc -l) \
CSGSIM_COSTS=$map CSGSIM_FILL_COSTS=$fill_map CSGSIM_PASS_SCALE=$PASS_SCALE CSGSIM_PASS_RATE=$PASS_RATE \
    smpirun -np $((WORKERS + RELAYS + 1)) -platform "$ROOT/bench/sim/$NETWORK.xml" \
    -hostfile "$work/hosts" "${opts[@]}" "$CSGSIM" "$SCENE" --mode "$MODE" --width "$WIDTH" \
    --height "$HEIGHT" --tile "$TILE" --schedule "$SCHEDULE" "${batch[@]}" --pixels "$PIXELS" --hit-records "$RECORDS" --fill "$FILL" --relays "$RELAYS" "${paging[@]}" --stats "$work/out.json" \
    >"$work/log" 2>&1 || { cat "$work/log" >&2; exit 1; }
python3 - "$work/out.json" "$NETWORK" "$STATS" "$PASS_SCALE" "$PASS_RATE" "$PART_US" "$PIXEL_NS" \
    "$MESSAGE_US" "$STORE_NS" "$STORE_THREADS" "$NAP_US" "$EAGER" "$SENDER_PROGRESS" "$RUNTIME" \
    "$COMPRESS_NS" "$DECOMPRESS_NS" "$WIRE_MAP" "$RECORDS" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
d["network"] = sys.argv[2]
d["pass_scale"] = float(sys.argv[4])
d["pass_rate_mrays"] = float(sys.argv[5])
d["master_part_us"] = float(sys.argv[6])
d["master_pixel_ns"] = float(sys.argv[7])
d["master_message_us"] = float(sys.argv[8])
d["master_store_ns"] = float(sys.argv[9])
d["master_store_threads"] = d["store_threads"] if float(sys.argv[9]) > 0 else 0  # (C 0: none)
d["nap_us"] = float(sys.argv[11])
d["eager_bytes"] = int(sys.argv[12])
d["sender_progress"] = sys.argv[13] == "yes"
d["runtime"] = sys.argv[14]
d["compress_ns"] = float(sys.argv[15])
d["decompress_ns"] = float(sys.argv[16])
d["wire_map"] = sys.argv[17]
d["hit_records"] = sys.argv[18]
with open(sys.argv[3], "w") as f:
    json.dump(d, f)
    f.write("\n")
PY
