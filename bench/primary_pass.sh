#!/usr/bin/env bash
# bench/primary_pass.sh — throughput of the primary pass: the OpenCL pass in
# both kernel variants (packet, scalar) against the C worker's own primary
# rays, on random-sphere scenes of N = 10 .. 10^4 spheres; the packet kernel
# also with its records copied out of device buffers (packet+copy: what a
# discrete GPU does, and what a CPU device did before the records were
# written in place).
#
#   bench/primary_pass.sh [--counts "10 50 200 1000 10000"] [--size 1024]
#                         [--repeat 7] [--occupancy 0.5] [--seed 1]
#                         [--out bench/results/primary_pass]
#
# Method: scenes from `csgtrace gen spheres` (occupancy fitted at 256 x 256,
# cached in build/bench/primary), traced at SIZE x SIZE by
# build/bench/primary_pass, which flattens the scene once and runs the three
# variants in one process: an untimed round, then REPEAT rounds, each running
# every variant once in a rotated order (interleaved), every record compared
# with the C records bit for bit.  Kernel builds stay outside every timing.
# Per variant and scene: the median of the rounds and their min-max, as
#   - Mrays/s per core: rays / median wall time / cores (1 for the C worker,
#     the device's compute units for OpenCL);
#   - Mrays per CPU-second: rays / median CPU time of the process (PoCL's
#     threads included), the per-core figure that a machine shared with other
#     work does not distort (it stretches wall time, not CPU time).
# Writes OUT/N<count>.json (the harness's output) and OUT/summary.md (the
# table), and prints the table.
set -euo pipefail

ROOT=$(cd "$(dirname "$0")/.." && pwd)
COUNTS="10 50 200 1000 10000"
SIZE=1024
REPEAT=7
OCC=0.5
SEED=1
OUT=$ROOT/bench/results/primary_pass
while [ $# -gt 0 ]; do
    case "$1" in
    --counts) COUNTS=${2:?}; shift ;;
    --size) SIZE=${2:?}; shift ;;
    --repeat) REPEAT=${2:?}; shift ;;
    --occupancy) OCC=${2:?}; shift ;;
    --seed) SEED=${2:?}; shift ;;
    --out) OUT=${2:?}; shift ;;
    -h|--help) sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    *) echo "bench/primary_pass.sh: unknown option '$1' (try --help)" >&2; exit 2 ;;
    esac
    shift
done

BIN=$ROOT/build/csgtrace
HARNESS=$ROOT/build/bench/primary_pass
WORK=$ROOT/build/bench/primary
export POCL_CACHE_DIR=${POCL_CACHE_DIR:-$ROOT/build/pocl-cache}
[ -x "$BIN" ] && [ -x "$HARNESS" ] || { echo "build first: make build/csgtrace build/bench/primary_pass" >&2; exit 1; }
mkdir -p "$WORK" "$OUT"
LOAD_START=$(cut -d' ' -f1-3 /proc/loadavg)

for n in $COUNTS; do
    scene=$WORK/spheres_${n}_occ${OCC}_seed${SEED}.pov
    if [ ! -s "$scene" ]; then
        "$BIN" gen spheres --count "$n" --occupancy "$OCC" --seed "$SEED" --width 256 --height 256 \
            -o "$scene" >/dev/null
    fi
    echo "N = $n: $SIZE x $SIZE, $REPEAT rounds" >&2
    "$HARNESS" "$scene" --width "$SIZE" --height "$SIZE" --repeat "$REPEAT" \
        --variants c,scalar,packet,packet+copy >"$OUT/N$n.json"
done

LOAD_END=$(cut -d' ' -f1-3 /proc/loadavg)
python3 - "$OUT" "$OCC" "$(nproc)" "$LOAD_START" "$LOAD_END" $COUNTS <<'EOF' | tee "$OUT/summary.md"
import json, sys, os
out, occ, cpus, load0, load1, counts = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4], sys.argv[5], sys.argv[6:]
rows = [json.load(open(os.path.join(out, "N%s.json" % n))) for n in counts]
j0 = rows[0]
print("Primary pass, %d x %d, %s, random spheres (gen spheres --occupancy %s), %d interleaved "
      "rounds;" % (j0["width"], j0["height"], j0["precision"], occ, j0["repeat"]))
print("device: %s; packet kernel: %s." % (j0["device"], j0["variants"]["packet"]["kernel"]))
print("Machine: %s CPUs, load average (1, 5, 15 min) %s at the start, %s at the end: wall-clock"
      % (cpus, load0, load1))
print("figures shrink with other work on the machine, CPU-time figures much less.\n")
print("Mrays/s per core, wall clock: median (min-max over the rounds)\n")
print("| N | C worker (1 core) | scalar kernel | packet kernel | packet / C | packet / scalar |")
print("| ---: | ---: | ---: | ---: | ---: | ---: |")
def wall(v, rays):
    c = v["cores"]
    return "%.2f (%.2f-%.2f)" % (v["mrays_per_core"], rays / v["max_s"] / 1e6 / c,
                                 rays / v["min_s"] / 1e6 / c)
for n, j in zip(counts, rows):
    v = j["variants"]
    print("| %s | %s | %s | %s | %.1fx | %.1fx |" % (
        n, wall(v["c"], j["rays"]), wall(v["scalar"], j["rays"]), wall(v["packet"], j["rays"]),
        v["packet"]["mrays_per_core"] / v["c"]["mrays_per_core"],
        v["packet"]["mrays_per_core"] / v["scalar"]["mrays_per_core"]))
print("\nMrays per CPU-second (CPU time of the whole process): median (min-max); packet / C "
      "also paired round by round (the rounds are interleaved): median (min-max)\n")
print("| N | C worker | scalar kernel | packet kernel | packet, records copied | packet / C "
      "| paired | packet / copied, paired | records in place | records identical |")
print("| ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | :---: | :---: |")
def cpu(v, rays):
    return "%.2f (%.2f-%.2f)" % (v["mrays_per_cpu_s"], rays / v["cpu_max_s"] / 1e6,
                                 rays / v["cpu_min_s"] / 1e6)
def paired(num, den):
    r = sorted(d / n for n, d in zip(num["cpu_rounds_s"], den["cpu_rounds_s"]))
    m = len(r) // 2
    med = r[m] if len(r) % 2 else (r[m - 1] + r[m]) / 2
    return "%.2fx (%.2f-%.2f)" % (med, r[0], r[-1])
for n, j in zip(counts, rows):
    v = j["variants"]
    same = all(v[k]["identical"] for k in v)
    print("| %s | %s | %s | %s | %s | %.1fx | %s | %s | %s | %s |" % (
        n, cpu(v["c"], j["rays"]), cpu(v["scalar"], j["rays"]), cpu(v["packet"], j["rays"]),
        cpu(v["packet+copy"], j["rays"]),
        v["packet"]["mrays_per_cpu_s"] / v["c"]["mrays_per_cpu_s"], paired(v["packet"], v["c"]),
        paired(v["packet"], v["packet+copy"]),
        "yes" if v["packet"]["records_in_place"] else "no", "yes" if same else "NO"))
EOF
