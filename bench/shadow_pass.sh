#!/usr/bin/env bash
# bench/shadow_pass.sh — the shadow rays of the primary hits on the device
# (--simd shadows, #36 item 3) against the C worker, and what the split
# does to homo vs hetero.
#
#   bench/shadow_pass.sh [--counts "10 50 1000"] [--size 512] [--repeat 7]
#                        [--jobs 3] [--out bench/results/shadow_pass]
#
# Part 1 (build/bench/shadow_pass, see its header): on `csgtrace gen
# spheres --count N --occupancy 0.5 --seed 1` scenes at SIZE x SIZE, the
# device's answers (ocl_shadow_answers, packet program: csg_shadows is a
# one-ray kernel in both programs) per CPU-second of the process, against
#   - the same code in C on one thread (csg_shadow_masks: kernel_ratio),
#   - the C worker's CPU saved by the answers (shade - shade_answered over
#     32 x 32 tiles: ratio, noisy: a difference of two shading times);
# medians of REPEAT interleaved rounds with min-max.
# Part 2: `csgtrace compare` (3 ranks) at N = 50, 384 x 384, occupancy
# 0.2 / 0.5 / 0.8, JOBS jobs of 2 rounds each, --simd primary and
# --simd shadows; per round the homo and hetero times (wall_s - compile_s -
# cl_setup_s), the paired advantage (homo - hetero) / homo, the workers'
# busy fraction and whether compare withheld the advantage (< 90 % busy).
# Writes OUT/N<count>.json, OUT/compare.csv and OUT/summary.md.
set -euo pipefail

ROOT=$(cd "$(dirname "$0")/.." && pwd)
COUNTS="10 50 1000"
SIZE=512
REPEAT=7
JOBS=3
OUT=$ROOT/bench/results/shadow_pass
while [ $# -gt 0 ]; do
    case "$1" in
    --counts) COUNTS=${2:?}; shift ;;
    --size) SIZE=${2:?}; shift ;;
    --repeat) REPEAT=${2:?}; shift ;;
    --jobs) JOBS=${2:?}; shift ;;
    --out) OUT=${2:?}; shift ;;
    -h|--help) sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    *) echo "bench/shadow_pass.sh: unknown option '$1' (try --help)" >&2; exit 2 ;;
    esac
    shift
done

BIN=$ROOT/build/csgtrace
HARNESS=$ROOT/build/bench/shadow_pass
WORK=$ROOT/build/bench/shadow
export POCL_CACHE_DIR=${POCL_CACHE_DIR:-$ROOT/build/pocl-cache}
export OMPI_MCA_pml=${OMPI_MCA_pml:-ob1}
[ -x "$BIN" ] && [ -x "$HARNESS" ] || { echo "build first: make build/csgtrace build/bench/shadow_pass" >&2; exit 1; }
mkdir -p "$WORK" "$OUT"
MPIRUN=(mpirun -np 3 --oversubscribe --bind-to none)
LOAD_START=$(cut -d' ' -f1-3 /proc/loadavg)

for n in $COUNTS; do
    scene=$WORK/spheres_$n.pov
    [ -s "$scene" ] || "$BIN" gen spheres --count "$n" --occupancy 0.5 --seed 1 --width 256 \
        --height 256 -o "$scene" >/dev/null
    "$HARNESS" "$scene" --width "$SIZE" --height "$SIZE" --repeat "$REPEAT" >"$OUT/N$n.json"
done

echo "occ,simd,job,round,homo_s,hetero_s,advantage_pct,homo_busy,hetero_busy,withheld,answered" >"$OUT/compare.csv"
for occ in 0.2 0.5 0.8; do
    scene=$WORK/c50_$occ.pov
    [ -s "$scene" ] || "$BIN" gen spheres --count 50 --occupancy "$occ" --seed 1 --width 384 \
        --height 384 -o "$scene" >/dev/null
    for job in $(seq 1 "$JOBS"); do
        for simd in primary shadows; do
            "${MPIRUN[@]}" "$BIN" compare "$scene" --width 384 --height 384 --repeat 2 \
                --simd "$simd" --stats "$WORK/compare.json" >"$WORK/compare.log" 2>&1 ||
                { cat "$WORK/compare.log" >&2; exit 1; }
            python3 - "$WORK/compare.json" "$occ" "$simd" "$job" >>"$OUT/compare.csv" <<'PY'
import json, sys
c = json.load(open(sys.argv[1]))
t = lambda s: s["wall_s"] - s["compile_s"] - s["cl_setup_s"]
busy = lambda s: round(s["busy_fraction"], 3)
for r, (h, x) in enumerate(zip(c["homo"], c["hetero"]), 1):
    print(f"{sys.argv[2]},{sys.argv[3]},{sys.argv[4]},{r},{t(h):.4f},{t(x):.4f},"
          f"{100 * (t(h) - t(x)) / t(h):.1f},{busy(h)},{busy(x)},"
          f"{1 if c.get('advantage_withheld') else 0},{x['rays']['shadow_answered']}")
PY
        done
    done
done

python3 - "$OUT" "$COUNTS" "$LOAD_START" "$(cut -d' ' -f1-3 /proc/loadavg)" >"$OUT/summary.md" <<'PY'
import csv, json, statistics, sys
out, counts = sys.argv[1], sys.argv[2].split()
print(f"load average: {sys.argv[3]} at the start, {sys.argv[4]} at the end\n")
print("| N | hits | answers | shadow rays taken over / traced before | device CPU s | C same code CPU s | kernel ratio | worker CPU saved s | saved / device |")
print("|---|---|---|---|---|---|---|---|---|")
sp = lambda s: f"{s['median']:.4f} ({s['min']:.4f}-{s['max']:.4f})"
for n in counts:
    j = json.load(open(f"{out}/N{n}.json"))
    print(f"| {n} | {j['hits']} | {j['answers']} | {j['taken']} / {j['traced_plain']} | "
          f"{sp(j['device_cpu_s'])} | {sp(j['c_masks_cpu_s'])} | {j['kernel_ratio']:.2f} | "
          f"{sp(j['saved_cpu_s'])} | {j['ratio']:.2f} |")
rows = list(csv.DictReader(open(f"{out}/compare.csv")))
print("\n| occupancy | --simd | homo s (median, min-max) | hetero s | advantage % (median, min-max) | withheld jobs | answers taken |")
print("|---|---|---|---|---|---|---|")
for occ in ("0.2", "0.5", "0.8"):
    for simd in ("primary", "shadows"):
        rs = [r for r in rows if r["occ"] == occ and r["simd"] == simd]
        if not rs:
            continue
        f = lambda k: [float(r[k]) for r in rs]
        m = lambda v: f"{statistics.median(v):.4f} ({min(v):.4f}-{max(v):.4f})"
        a = f("advantage_pct")
        print(f"| {occ} | {simd} | {m(f('homo_s'))} | {m(f('hetero_s'))} | "
              f"{statistics.median(a):.1f} ({min(a):.1f}-{max(a):.1f}) | "
              f"{sum(int(r['withheld']) for r in rs if r['round'] == '1')} of "
              f"{sum(1 for r in rs if r['round'] == '1')} | {rs[0]['answered']} |")
PY
cat "$OUT/summary.md"
