#!/usr/bin/env bash
# bench/node_session.sh — everything a session with the device machine (16
# cores, an NVIDIA GPU: ../shared/node/README.md) should measure, in one
# run that fits its 15 minutes with time to spare: the questions the 2-core
# machine cannot answer, in the order of what they settle.
#
#   1. bench/gpu_pass.sh: the OpenCL pass inside 4096x4096 hetero renders
#      (--pass always --fill off, NP ranks) against the kernel's own time,
#      with the pass on the device's clock (kernels, copies, span: the
#      stats' pass_kernel_s, pass_copy_s, pass_device_s), by slice size
#      (issue 36: the pass <= 1.5x the kernel).
#   2. csgtrace compare at 4096x4096 with the defaults, then with --simd
#      shadows (the device answers the primary hits' shadow rays too) (issue
#      36: hetero >= 25 % ahead on the node, >= 1.5x homo with the first
#      generation on the GPU; issue 35: busy >= 90 % in both modes).
#   3. bench/node.py (make bench-node's script): serial, homo and hetero at
#      np = 2 .. the node's CPUs, 2048x2048, tile 32 and 64, PNG (issue 35:
#      busy >= 95 %, frame speed-up >= 12x with 15 workers, write tail
#      <= 5 % of the wall).
# Each step has its own time limit; what a step wrote is kept when the next
# fails.  Results: OUT/session.tgz (one file: the device tool brings back
# few), with OUT/session.log, the steps' summaries, bench/NODE.md's table.
#
# Here (tested on 2 cores, small):
#   SIZE=512 NODE_SIZE=256 NP=3 ROUNDS=1 bench/node_session.sh /tmp/session
# On the device machine, after ../shared/node/pack.sh build/bench/primary_pass
# and the libraries the node lacks copied into .node/lib (on 2026-11-29:
# libfreetype.so.6, libbrotlicommon.so.1, libbrotlidec.so.1,
# libnettle.so.8, libpng16.so.16; `ldd build/csgtrace` names them; not
# libz or libzstd), with the device tool (carry [".node"]):
#   bash .node/run.sh bash bench/node_session.sh "$OUT" --packed
set -uo pipefail

ROOT=$(cd "$(dirname "$0")/.." && pwd)
OUT=${1:?usage: bench/node_session.sh OUTDIR [--packed]}
PACKED=${2:-}
SIZE=${SIZE:-4096}
NODE_SIZE=${NODE_SIZE:-2048}
NP=${NP:-16}
ROUNDS=${ROUNDS:-2}
BIN=$ROOT/build/csgtrace
HARNESS=$ROOT/build/bench/primary_pass
MPIRUN="mpirun --oversubscribe --bind-to none"
if [ "$PACKED" = --packed ]; then
    BIN=$ROOT/.node/bin/csgtrace
    HARNESS=$ROOT/.node/bin/primary_pass
    MPIRUN="mpirun --bind-to none"
fi
mkdir -p "$OUT"
W=$(mktemp -d)
LOG=$W/session.log
say() { echo "== $(date -u +%H:%M:%S) $*" | tee -a "$LOG"; }

say "machine"
{
    grep -m1 "model name" /proc/cpuinfo
    nproc
    nvidia-smi -L 2>&1 || true
    "$BIN" --version 2>&1 | head -3
} >>"$LOG" 2>&1

say "1. the pass inside renders (bench/gpu_pass.sh, ${SIZE}x$SIZE, $NP ranks)"
timeout 300 bash "$ROOT/bench/gpu_pass.sh" --bin "$BIN" --harness "$HARNESS" --mpirun "$MPIRUN" \
    --np "$NP" --size "$SIZE" --rounds "$ROUNDS" --slices "default 1048576" \
    --out "$W/gpu_pass" >"$W/gpu_pass.log" 2>&1
say "gpu_pass: exit $?"
rm -f "$W"/gpu_pass/*.png

say "2. compare (${SIZE}x$SIZE, $NP ranks, the defaults)"
scene=$W/s50.pov
"$BIN" gen spheres --count 50 --occupancy 0.5 --seed 1 --width "$SIZE" --height "$SIZE" \
    -o "$scene" >/dev/null 2>&1
timeout 180 $MPIRUN -np "$NP" "$BIN" compare "$scene" --width "$SIZE" --height "$SIZE" \
    --repeat "$ROUNDS" --stats "$W/compare.json" >"$W/compare.txt" 2>&1
say "compare: exit $?"
timeout 180 $MPIRUN -np "$NP" "$BIN" compare "$scene" --width "$SIZE" --height "$SIZE" \
    --repeat "$ROUNDS" --simd shadows --stats "$W/compare-shadows.json" \
    >"$W/compare-shadows.txt" 2>&1
say "compare --simd shadows: exit $?"

say "3. the node (bench/node.py, ${NODE_SIZE}x$NODE_SIZE)"
timeout 240 python3 "$ROOT/bench/node.py" --bin "$BIN" --mpirun "$MPIRUN" --rounds "$ROUNDS" \
    --sizes "$NODE_SIZE" --tiles 32,64 --formats png --out "$W/node" \
    --report "$W/NODE.md" >"$W/node.log" 2>&1
say "node.py: exit $?"
rm -f "$W"/node/*.png "$W"/node/*.ppm

cp "$LOG" "$OUT/session.log"
(cd "$W" && tar czf "$OUT/session.tgz" .)
rm -rf "$W"
echo "results: $OUT/session.tgz"
