#!/usr/bin/env bash
# e2e_wide.sh — wide CSG nodes (issue #39): a box and 2000 small spheres
# as a difference (a run of complemented spheres under intersection), an
# intersection with their union (a union run) and a nested run (an inverse
# union between two operands).  The runs' hierarchies (flat.h,
# CSG_OP_WIDE) must not change a byte: each serial PNG's sha256 is the one
# the linear evaluation gave (the build before the hierarchy, main at
# ba2f09d), and homo and hetero (3 ranks, the OpenCL pass forced) are
# byte-identical to serial.
# Usage: tests/e2e_wide.sh   (CSGTRACE_BIN: the binary, default build/csgtrace)
set -u
source "$(dirname "$0")/lib_e2e.sh"

mpi_sandbox
export POCL_CACHE_DIR=${POCL_CACHE_DIR:-$PWD/build/pocl-cache}
MPI=(timeout -s KILL 300 mpirun --bind-to none --oversubscribe -np 3)
SZ=(--width 64 --height 48)
declare -A EXPECT=(
    [difference]=866bdac619cd7d0e5aee5d494396bceb01ed3c9e11b921139cb1be60e23e413f
    [intersection]=da642013b540906b6410c2c5fcf0185ef4784734cceb94b672527a9112051bea
    [nested]=c71849f2f25db8e0418c7c2cf2d1bc8cb9e4150302b72f7b530da6fd584eb93b
)
for op in difference intersection nested; do
    python3 tests/wide_scene.py $op 2000 "$T/$op.pov" || { ko "$op: scene"; continue; }
    "$BIN" render "$T/$op.pov" "${SZ[@]}" -o "$T/$op-serial.png" >/dev/null 2>&1 ||
        { ko "$op: serial render"; continue; }
    sum=$(sha256sum "$T/$op-serial.png" | cut -d' ' -f1)
    [ "$sum" = "${EXPECT[$op]}" ] && ok "$op: serial as the linear evaluation" ||
        ko "$op: serial $sum, the linear evaluation ${EXPECT[$op]}"
    for mode in homo hetero; do
        "${MPI[@]}" "$BIN" render "$T/$op.pov" "${SZ[@]}" --mode $mode --pass always \
            -o "$T/$op-$mode.png" >/dev/null 2>&1 || { ko "$op: $mode render"; continue; }
        cmp -s "$T/$op-serial.png" "$T/$op-$mode.png" && ok "$op: $mode == serial" ||
            ko "$op: $mode differs from serial"
    done
done

e2e_finish
