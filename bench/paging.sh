#!/usr/bin/env bash
# paging.sh — a worker's scene below a memory budget (--scene-memory,
# workers/pager.h), swept from the whole scene down to 1/64 of its blob:
# homo, hetero with the pass's prefetch and without it (and with the shadow
# rays' pages too: --page-prefetch shadows), the pages read one-sided
# (--page-fetch get, the default) and asked of rank 0 (ask), LRU and FIFO; the
# tile phase and the frame against the in-memory render's, the pages
# faulted, fetched, the hit rate and the time waiting for pages.  Every
# paged image is compared with the in-memory one (cmp: bit for bit).
#
# Usage: bench/paging.sh [--scene FILE] [--size N] [--ranks K] [--runs R]
#                        [--fractions "2 4 8 16 32 64"] [--out DIR]
#   --scene   the scene (default: the SPD's tetra9, 262 144 triangles, made
#             from ../shared/nff/tetra8.nff by bench/spd_subdivide.py)
#   --size    the image's edge (default 512)
#   --ranks   mpirun -np (default 3: rank 0 and two workers)
#   --runs    rounds; each round runs every configuration once, in turn
#             (interleaved), and the medians are taken over the rounds
# Writes DIR/paging.csv (one row a render) and prints the table of medians
# (bench/PAGING.md holds the figures and their reading).
set -u
cd "$(dirname "$0")/.."
SCENE="" SIZE=512 RANKS=3 RUNS=3 FRACTIONS="2 4 8 16 32 64" OUT=bench/results-paging
while [ $# -gt 0 ]; do
    case $1 in
    --scene) SCENE=$2; shift 2 ;;
    --size) SIZE=$2; shift 2 ;;
    --ranks) RANKS=$2; shift 2 ;;
    --runs) RUNS=$2; shift 2 ;;
    --fractions) FRACTIONS=$2; shift 2 ;;
    --out) OUT=$2; shift 2 ;;
    *) echo "paging.sh: unknown option $1" >&2; exit 2 ;;
    esac
done
BIN=$PWD/build/csgtrace
[ -x "$BIN" ] || { echo "paging.sh: build first (make)" >&2; exit 2; }
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_pml=ob1
export POCL_CACHE_DIR=${POCL_CACHE_DIR:-$PWD/build/pocl-cache}
export CSGTRACE_CL_CACHE=${CSGTRACE_CL_CACHE:-$PWD/build/cl-cache}
mkdir -p "$OUT"
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
if [ -z "$SCENE" ]; then
    NFF=${SPD_NFF:-../shared/nff}
    [ -f "$NFF/tetra8.nff" ] || { echo "paging.sh: $NFF/tetra8.nff not found (--scene FILE)" >&2; exit 2; }
    mkdir -p build/bench
    SCENE=build/bench/tetra9.nff
    [ -f "$SCENE" ] || python3 bench/spd_subdivide.py "$NFF/tetra8.nff" 1 "$SCENE" ||
        { echo "paging.sh: cannot make tetra9" >&2; exit 2; }
fi
MPI=(mpirun --bind-to none --oversubscribe -np "$RANKS")
COMMON=(--width "$SIZE" --height "$SIZE" --no-progress)

# The blob's size, from an in-memory render (its image: the reference).
"$BIN" render "$SCENE" "${COMMON[@]}" -o "$WORK/ref.png" --stats "$WORK/ref.json" >/dev/null ||
    { echo "paging.sh: the reference render failed" >&2; exit 1; }
BLOB=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['blob_bytes'])" "$WORK/ref.json")

# The configurations: NAME MODE FRACTION (0: in memory) EXTRA...
configs=("memory-homo homo 0" "memory-hetero hetero 0")
for f in $FRACTIONS; do
    configs+=("homo-1/$f homo $f" "homo-ask-1/$f homo $f --page-fetch ask"
        "homo-noprefetch-1/$f homo $f --page-prefetch off"
        "homo-shadows-1/$f homo $f --page-prefetch shadows"
        "hetero-1/$f hetero $f" "hetero-ask-1/$f hetero $f --page-fetch ask"
        "hetero-noprefetch-1/$f hetero $f --page-prefetch off"
        "hetero-shadows-1/$f hetero $f --page-prefetch shadows")
done
configs+=("homo-fifo-1/8 homo 8 --page-policy fifo" "hetero-fifo-1/8 hetero 8 --page-policy fifo")

CSV=$OUT/paging.csv
echo "config,mode,fraction,round,wall_s,tile_phase_s,faults,requests,pages,prefetched,touches,hit_rate,wait_s,bytes,peak_bytes,over_budget_bytes,memory_peak_bytes,identical" >"$CSV"
for ((round = 1; round <= RUNS; round++)); do
    for c in "${configs[@]}"; do
        read -r name mode frac extra <<<"$c"
        args=(--mode "$mode" --pass always --fill off)
        [ "$mode" = homo ] && args=(--mode homo)
        budget=""
        if [ "$frac" != 0 ]; then
            budget=$(python3 -c "print($BLOB / $frac / 1e6)")
            args+=(--scene-memory "$budget")
        fi
        # shellcheck disable=SC2206
        [ -n "${extra:-}" ] && args+=($extra)
        out=$WORK/$round-${name//\//_}
        if ! "${MPI[@]}" "$BIN" render "$SCENE" "${COMMON[@]}" "${args[@]}" -o "$out.png" \
            --stats "$out.json" >/dev/null 2>"$out.err"; then
            echo "$name,$mode,$frac,$round,failed: $(head -c 120 "$out.err" | tr ',\n' ';;')" >>"$CSV"
            continue
        fi
        same=false
        cmp -s "$WORK/ref.png" "$out.png" && same=true
        python3 - "$out.json" "$name" "$mode" "$frac" "$round" "$same" >>"$CSV" <<'EOF'
import json, sys
j = json.load(open(sys.argv[1]))
p = j.get("paging", {})
g = lambda k: p.get(k, 0)
print(",".join(str(x) for x in [sys.argv[2], sys.argv[3], sys.argv[4], sys.argv[5], j["wall_s"],
      j["tile_phase_s"], g("faults"), g("requests"), g("pages"), g("prefetched"), g("touches"),
      g("hit_rate") if p else 1, g("wait_s"), g("bytes"), g("peak_bytes"),
      g("over_budget_bytes"), g("memory_peak_bytes"), sys.argv[6]]))
EOF
    done
done

python3 - "$CSV" "$BLOB" <<'EOF'
import csv, statistics, sys
rows = [r for r in csv.DictReader(open(sys.argv[1])) if not r["wall_s"].startswith("failed")]
blob = int(sys.argv[2])
by = {}
for r in rows:
    by.setdefault(r["config"], []).append(r)
def med(rs, k):
    v = sorted(float(r[k]) for r in rs)
    return statistics.median(v), v[0], v[-1]
base = {m: med(by["memory-" + m], "tile_phase_s")[0] for m in ("homo", "hetero") if "memory-" + m in by}
print("blob: %.1f MB" % (blob / 1e6))
print("| config | budget | tile phase (median, min-max) | vs in memory | frame | faults | requests | pages fetched | prefetched | hit rate | wait s | peak MB (cache) | memory MB | identical |")
print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|")
for name, rs in by.items():
    t, lo, hi = med(rs, "tile_phase_s")
    w = med(rs, "wall_s")[0]
    f = rs[0]["fraction"]
    speed = base[rs[0]["mode"]] / t if t > 0 else 0
    print("| %s | %s | %.3f s (%.3f-%.3f) | %.0f %% | %.3f s | %d | %d | %d | %d | %.3f | %.3f | %.1f | %.1f | %s |" % (
        name, "whole" if f == "0" else "%.2f MB" % (blob / float(f) / 1e6), t, lo, hi, 100 * speed, w,
        statistics.median(int(r["faults"]) for r in rs), statistics.median(int(r["requests"]) for r in rs),
        statistics.median(int(r["pages"]) for r in rs),
        statistics.median(int(r["prefetched"]) for r in rs),
        statistics.median(float(r["hit_rate"]) for r in rs), med(rs, "wait_s")[0],
        max(int(r["peak_bytes"]) for r in rs) / 1e6, max(int(r["memory_peak_bytes"]) for r in rs) / 1e6,
        "yes" if all(r["identical"] == "true" for r in rs) else "NO"))
EOF
