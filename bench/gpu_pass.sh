#!/usr/bin/env bash
# bench/gpu_pass.sh — the OpenCL pass inside hetero renders against the
# kernel's own rate, by slice size ($CSGTRACE_CL_SLICE): issue 36's "the
# pass in a 4096x4096 render <= 1.5x the kernel's time", for a session that
# has a GPU (it runs on any OpenCL device: here, PoCL's CPU device).
#
#   bench/gpu_pass.sh [--size 4096] [--np 16] [--rounds 3]
#                     [--slices "default 131072 4194304"] [--count 50]
#                     [--bin build/csgtrace] [--harness build/bench/primary_pass]
#                     [--mpirun "mpirun --oversubscribe --bind-to none"]
#                     [--out build/bench/gpu_pass]
#
# Scene: `csgtrace gen spheres --count N --occupancy 0.5 --seed 1` framed
# for SIZE x SIZE.
#   1. The kernel alone (the harness, when given and built: its scalar and
#      packet variants over the whole image, one launch; the C worker is
#      its reference): Mrays/s of the device's wall clock, median of 3.
#   2. Hetero renders with `--pass always --fill off` (every tile waits for
#      its slice: the pass is on the critical path, nothing hides it) under
#      mpirun -np NP, for each slice setting ("default": the device's own,
#      one tile row on a CPU device, 2^22 records on a GPU; a number: that
#      many records at least), ROUNDS rounds interleaved (each setting once
#      a round); medians (min-max) of pass_s, its Mrays/s, the slices, the
#      tile phase and the frame, pass_s over the kernel's own time, and
#      the pass on the device's clock (kernels, copies, span).
# Every render's image is compared with the first one's (cmp).
# Writes OUT/summary.md, OUT/kernel.json, OUT/render-SLICE-ROUND.json; prints
# the summary.  On the device machine: pack with ../shared/node/pack.sh
# build/bench/primary_pass, then run it through .node/run.sh with --bin
# .node/bin/csgtrace --harness .node/bin/primary_pass --mpirun "mpirun
# --bind-to none" --out "$OUT/gpu" (and tar $OUT/gpu: the device tool
# brings back few files).
set -euo pipefail

ROOT=$(cd "$(dirname "$0")/.." && pwd)
SIZE=4096
NP=16
ROUNDS=3
SLICES="default 131072 4194304"
COUNT=50
BIN=$ROOT/build/csgtrace
HARNESS=$ROOT/build/bench/primary_pass
MPIRUN="mpirun --oversubscribe --bind-to none"
OUT=$ROOT/build/bench/gpu_pass
while [ $# -gt 0 ]; do
    case "$1" in
    --size) SIZE=${2:?}; shift ;;
    --np) NP=${2:?}; shift ;;
    --rounds) ROUNDS=${2:?}; shift ;;
    --slices) SLICES=${2:?}; shift ;;
    --count) COUNT=${2:?}; shift ;;
    --bin) BIN=${2:?}; shift ;;
    --harness) HARNESS=${2:?}; shift ;;
    --mpirun) MPIRUN=${2:?}; shift ;;
    --out) OUT=${2:?}; shift ;;
    -h|--help) sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    *) echo "bench/gpu_pass.sh: unknown option '$1' (try --help)" >&2; exit 2 ;;
    esac
    shift
done
[ -x "$BIN" ] || { echo "bench/gpu_pass.sh: no $BIN (make build/csgtrace)" >&2; exit 1; }
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
mkdir -p "$OUT"
scene=$OUT/spheres_$COUNT.pov
"$BIN" gen spheres --count "$COUNT" --occupancy 0.5 --seed 1 --width "$SIZE" --height "$SIZE" \
    -o "$scene" >/dev/null

# 1. the kernel alone
rm -f "$OUT/kernel.json"
if [ -x "$HARNESS" ]; then
    "$HARNESS" "$scene" --width "$SIZE" --height "$SIZE" --repeat 3 \
        --variants c,scalar,packet >"$OUT/kernel.json" || echo "the harness failed" >&2
fi

# 2. the pass inside renders, the settings interleaved
for r in $(seq "$ROUNDS"); do
    for s in $SLICES; do
        out=$OUT/render-$s-$r
        if [ "$s" = default ]; then
            env -u CSGTRACE_CL_SLICE $MPIRUN -np "$NP" "$BIN" render "$scene" --mode hetero \
                --pass always --fill off --width "$SIZE" --height "$SIZE" -o "$out.png" \
                --stats "$out.json" >/dev/null 2>"$out.err"
        else
            CSGTRACE_CL_SLICE=$s $MPIRUN -x CSGTRACE_CL_SLICE -np "$NP" "$BIN" render "$scene" \
                --mode hetero --pass always --fill off --width "$SIZE" --height "$SIZE" \
                -o "$out.png" --stats "$out.json" >/dev/null 2>"$out.err"
        fi || { echo "render $s round $r failed: $(head -c 300 "$out.err")" >&2; exit 1; }
        first=$OUT/render-${SLICES%% *}-1.png
        cmp -s "$first" "$out.png" || { echo "render $s round $r: not the first image" >&2; exit 1; }
    done
done

python3 - "$OUT" "$SIZE" "$NP" "$ROUNDS" $SLICES <<'EOF' | tee "$OUT/summary.md"
import json, os, statistics, sys
out, size, np_, rounds, slices = sys.argv[1], int(sys.argv[2]), sys.argv[3], int(sys.argv[4]), sys.argv[5:]
rays = size * size
kernel = {}
kpath = os.path.join(out, "kernel.json")
if os.path.exists(kpath) and os.path.getsize(kpath) > 0:
    k = json.load(open(kpath))
    kernel = {v: k["variants"][v] for v in ("scalar", "packet") if v in k["variants"]}
    device = k.get("device", "")
def med(xs):
    return "%.4f (%.4f-%.4f)" % (statistics.median(xs), min(xs), max(xs))
runs = {s: [json.load(open(os.path.join(out, "render-%s-%d.json" % (s, r))))
            for r in range(1, rounds + 1)] for s in slices}
j0 = runs[slices[0]][0]
print("The pass inside hetero renders (`--pass always --fill off`), %dx%d, %s ranks, %d rounds "
      "interleaved; device: %s; program: %s; records %s.\n"
      % (size, size, np_, rounds, j0["device"], j0["cl_program"], j0["cl_records"] or "-"))
if kernel:
    print("The kernel alone (build/bench/primary_pass, one launch over the image, median of 3, "
          "device wall clock): " + "; ".join("%s %.1f Mrays/s (%.4f s)"
          % (v, rays / kernel[v]["median_s"] / 1e6, kernel[v]["median_s"]) for v in kernel) + ".\n")
best = min(kernel[v]["median_s"] for v in kernel) if kernel else None
print("| CSGTRACE_CL_SLICE | slices | pass_s | pass Mrays/s | pass / kernel | device: kernels s "
      "| device: copies s | device: span s | tile phase s | frame s |")
print("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
for s in slices:
    js = runs[s]
    p = [j["pass_s"] for j in js]
    ratio = "%.2fx" % (statistics.median(p) / best) if best else "-"
    dev = [med([j.get(k, float("nan")) for j in js])
           for k in ("pass_kernel_s", "pass_copy_s", "pass_device_s")]
    print("| %s | %d | %s | %.1f | %s | %s | %s | %s | %s | %s |" % (
        s, js[0]["slices"], med(p), rays / statistics.median(p) / 1e6, ratio, *dev,
        med([j["tile_phase_s"] for j in js]), med([j["wall_s"] for j in js])))
print("\nEvery render's image equals the first one's (cmp). pass / kernel: the median pass_s "
      "over the faster kernel variant's own time (issue 36: <= 1.5x). device: the pass on "
      "the device's clock (the stats' pass_kernel_s, pass_copy_s, pass_device_s): its "
      "kernels, the records' copies after them, and the first kernel's start to the last "
      "copy's end; span - kernels - copies: the device idle between slices; pass_s - span: "
      "the host before the first kernel (buffers, the scene's upload) and after the last copy.")
EOF
