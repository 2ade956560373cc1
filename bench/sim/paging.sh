#!/usr/bin/env bash
# bench/sim/paging.sh — issue 37's page traffic at 16 to 256 workers: the
# simulated build (make sim) with --scene-memory, each item naming the
# pages its real one named (sim/page_trace.h), through the workers' real
# caches and rank 0's real answers over the simulated network.
#
#   bench/sim/paging.sh [--scene FILE] [--size N] [--tile T] [--fractions "8 32"]
#                       [--workers "1 16 64 256"] [--network ib] [--runs R]
#                       [--pass-rate M] [--schedule S] [--page-home H] [--page-fetch F]
#                       [--reuse] [--out DIR]
#
# 1. Real renders on this machine (R rounds, interleaved): serial in
#    memory, and serial at each budget (the blob / fraction) with pages of
#    16 KiB; the first paged one writes the homo page trace
#    ($CSGTRACE_PAGE_TRACE), a hetero render (-np 2, --pass always, --fill
#    off) the hetero one.  From them, a fetched byte's costs: rank 0's
#    packing (the serial fetch is that copy: wait_s / bytes) and the
#    worker's install (the pager's install_s / bytes: making room, copying
#    into place, the kernel's faults on fresh memory pages), medians over
#    the rounds, per budget; beside them the items' CPU seconds (the tile
#    log's cpu_s summed, user and system), paged against in memory: on a
#    shared machine the tile phase's wall clock is stretched by others.
#    The cost maps the simulation reads come from these renders too, at
#    this size and tile (bench/sim/costmap.py, each tile's least CPU
#    seconds over the rounds), and for hetero from one more render in
#    memory (-np 2, --pass always, --fill off): not bench/simulate.sh's
#    384x384 maps scaled up, which cost a pixel of tetra9 at 4096x4096
#    1.9 times what it costs (fewer coherent rays a tile at 384x384).
# 2. The check: the simulated single worker, homo, at each budget, must
#    fault, fetch and evict exactly as the real serial render did (the
#    same items in the same order through the same cache); its makespan
#    beside the real tile phase, and in memory beside the real one (the
#    cost map's scaling from 384x384: bench/simulate.sh).
# 3. The points: bench/simulate.sh at each worker count, homo and hetero
#    (the pass at --pass-rate Mrays/s, default 300: bench/GPU.md's H100
#    figure for spheres, a hypothesis for this scene), in memory and at each
#    budget (the prefetch on; off too at 64 workers).
# --schedule S: the points with csgtrace's --schedule S (default: raster
# in homo, cost in hetero), into DIR/points-S.csv; --page-home H: the
# points with csgtrace's --page-home H (auto, master, spread; default auto),
# into DIR/points[-S]-H.csv when given; --page-fetch F: the calibration
# renders and the points with csgtrace's --page-fetch F (get, the default:
# a worker's install is then making room and mapping fresh memory pages,
# the copy being the one-sided read's, and rank 0 packs nothing, the
# "packs" column the serial read's copy; ask: as before the window), into
# DIR/points[-S][-H]-ask.csv for ask; --reuse: steps 1 and 2
# taken from an earlier run into DIR (its calibration, traces and maps).
# Writes DIR/calibration.csv, DIR/check.csv, DIR/points.csv and prints the
# tables (bench/PAGING.md holds them and their reading).
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
cd "$ROOT"
SCENE="" SIZE=4096 TILE=32 FRACTIONS="8 32" WORKERS="1 16 64 256" NETWORK=ib RUNS=5
PASS_RATE=300 OUT=bench/results-paging/sim SCHEDULE="" PAGE_HOME="" PAGE_FETCH=get REUSE=no
die() { echo "bench/sim/paging.sh: $*" >&2; exit 2; }
while [ $# -gt 0 ]; do
    [ "$1" = --reuse ] || [ $# -ge 2 ] || die "$1 needs a value"
    case $1 in
    --scene) SCENE=$2 ;;
    --size) SIZE=$2 ;;
    --tile) TILE=$2 ;;
    --fractions) FRACTIONS=$2 ;;
    --workers) WORKERS=$2 ;;
    --network) NETWORK=$2 ;;
    --runs) RUNS=$2 ;;
    --pass-rate) PASS_RATE=$2 ;;
    --out) OUT=$2 ;;
    --schedule) SCHEDULE=$2 ;;
    --page-home) PAGE_HOME=$2 ;;
    --page-fetch) PAGE_FETCH=$2 ;;
    --reuse) REUSE=yes; shift; continue ;;
    *) die "unknown option '$1'" ;;
    esac
    shift 2
done
[[ "$SCHEDULE" =~ ^(|raster|cost|static|tail|region)$ ]] || die "--schedule: raster, cost, static, tail or region"
[[ "$PAGE_HOME" =~ ^(|auto|master|spread)$ ]] || die "--page-home: auto, master or spread"
[[ "$PAGE_FETCH" =~ ^(get|ask)$ ]] || die "--page-fetch: get or ask"
[[ "$SIZE" =~ ^[1-9][0-9]{1,4}$ ]] || die "--size: 10..99999"
[[ "$TILE" =~ ^[1-9][0-9]{0,3}$ ]] || die "--tile: 1..9999"
[[ "$FRACTIONS" =~ ^[0-9\ ]+$ ]] || die "--fractions: numbers"
[[ "$WORKERS" =~ ^[0-9\ ]+$ ]] || die "--workers: numbers"
[[ "$NETWORK" =~ ^(ib|gige|local|node)$ ]] || die "--network: ib, gige, local or node"
[[ "$RUNS" =~ ^[1-9][0-9]?$ ]] || die "--runs: 1..99"
[[ "$PASS_RATE" =~ ^[1-9][0-9]{0,5}$ ]] || die "--pass-rate: Mrays/s, an integer"
BIN=$ROOT/build/csgtrace
[ -x "$BIN" ] || die "build first (make)"
[ -x "$ROOT/build/sim/csgsim" ] || die "build the simulator first (make sim)"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_pml=ob1
export POCL_CACHE_DIR=${POCL_CACHE_DIR:-$ROOT/build/pocl-cache}
export CSGTRACE_CL_CACHE=${CSGTRACE_CL_CACHE:-$ROOT/build/cl-cache}
if [ -z "$SCENE" ]; then
    NFF=${SPD_NFF:-../shared/nff}
    SCENE=build/bench/tetra9.nff
    if [ ! -f "$SCENE" ]; then
        [ -f "$NFF/tetra8.nff" ] || die "$NFF/tetra8.nff not found (--scene FILE)"
        mkdir -p build/bench
        python3 bench/spd_subdivide.py "$NFF/tetra8.nff" 1 "$SCENE" || die "cannot make tetra9"
    fi
fi
mkdir -p "$OUT"
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
COMMON=(--width "$SIZE" --height "$SIZE" --tile "$TILE" --no-progress)
PAGE_KB=16

# 1. the real renders
"$BIN" render "$SCENE" "${COMMON[@]}" -o "$WORK/ref.png" --stats "$WORK/ref.json" >/dev/null ||
    die "the reference render failed"
BLOB=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['blob_bytes'])" "$WORK/ref.json")
budget_mb() { python3 -c "print($BLOB / $1 / 1e6)"; }
smallest=$(for f in $FRACTIONS; do echo "$f"; done | sort -n | tail -1)
CAL=$OUT/calibration.csv
HOMO_TRACE=$OUT/homo-1_$smallest.trace.0
HETERO_TRACE=$OUT/hetero.trace.1
if [ "$REUSE" = yes ]; then
    for f in "$CAL" "$HOMO_TRACE" "$HETERO_TRACE" "$OUT/homo.costs" "$OUT/hetero.costs"; do
        [ -f "$f" ] || die "--reuse: no $f"
    done
    cp "$OUT/homo.costs" "$OUT/hetero.costs" "$WORK/"
else
maps=()
echo "config,fraction,round,tile_phase_s,items_cpu_s,bytes,wait_s,install_s,faults,pages,evictions,identical" >"$CAL"
for ((round = 1; round <= RUNS; round++)); do
    for f in 0 $FRACTIONS; do
        args=() env=()
        if [ "$f" != 0 ]; then
            args=(--scene-memory "$(budget_mb "$f")" --page-size $PAGE_KB --page-fetch "$PAGE_FETCH")
            [ "$round" = 1 ] && env=(CSGTRACE_PAGE_TRACE="$OUT/homo-1_$f.trace")
        fi
        out=$WORK/serial-$f-$round
        [ "$f" = 0 ] && maps+=("$out.json" "$out.log")
        env "${env[@]}" "$BIN" render "$SCENE" "${COMMON[@]}" "${args[@]}" -o "$out.png" \
            --stats "$out.json" --tile-log "$out.log" >/dev/null 2>"$out.err" ||
            die "serial 1/$f failed: $(head -c 200 "$out.err")"
        same=false
        cmp -s "$WORK/ref.png" "$out.png" && same=true
        python3 - "$out.json" "$f" "$round" "$same" "$out.log" >>"$CAL" <<'EOF'
import json, sys
j = json.load(open(sys.argv[1]))
p = j.get("paging", {})
cpu = sum(json.loads(l)["cpu_s"] for l in open(sys.argv[5]) if l.strip())
print(",".join(str(x) for x in ["serial", sys.argv[2], sys.argv[3], j["tile_phase_s"], cpu,
      p.get("bytes", 0), p.get("wait_s", 0), p.get("install_s", 0), p.get("faults", 0), p.get("pages", 0),
      p.get("evictions", 0), sys.argv[4]]))
EOF
    done
done
python3 bench/sim/costmap.py "$WORK/homo.costs" "${maps[@]}" || die "the homo cost map failed"
mpirun --bind-to none --oversubscribe -np 2 "$BIN" render "$SCENE" "${COMMON[@]}" --mode hetero \
    --pass always --fill off -o "$WORK/hetero-map.png" --stats "$WORK/hetero-map.json" \
    --tile-log "$WORK/hetero-map.log" >/dev/null 2>"$WORK/hetero-map.err" ||
    die "the hetero map's render failed: $(head -c 200 "$WORK/hetero-map.err")"
python3 bench/sim/costmap.py "$WORK/hetero.costs" "$WORK/hetero-map.json" "$WORK/hetero-map.log" ||
    die "the hetero cost map failed"
cp "$WORK/homo.costs" "$WORK/hetero.costs" "$OUT/"
# (the trace is the same at every budget: the items name pages, whatever is cached)
mpirun --bind-to none --oversubscribe -np 2 env CSGTRACE_PAGE_TRACE="$OUT/hetero.trace" \
    "$BIN" render "$SCENE" "${COMMON[@]}" --mode hetero --pass always --fill off \
    --scene-memory "$(budget_mb "$smallest")" --page-size $PAGE_KB -o "$WORK/hetero.png" \
    --stats "$WORK/hetero.json" >/dev/null 2>"$WORK/hetero.err" ||
    die "the hetero trace's render failed: $(head -c 200 "$WORK/hetero.err")"
cmp -s "$WORK/ref.png" "$WORK/hetero.png" || die "the hetero render's image differs from the serial one"
fi

# A byte's costs per budget: "FRACTION PACK_NS INSTALL_NS" lines.
python3 - "$CAL" >"$WORK/costs" <<'EOF'
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1])))
for f in sorted({r["fraction"] for r in rows if r["fraction"] != "0"}, key=int):
    rs = [r for r in rows if r["fraction"] == f]
    pack = statistics.median(float(r["wait_s"]) / float(r["bytes"]) for r in rs) * 1e9
    install = statistics.median(float(r["install_s"]) / float(r["bytes"]) for r in rs) * 1e9
    print(f, "%.4f" % pack, "%.4f" % max(install, 0))
EOF
declare -A PACK INSTALL
while read -r f pack install; do PACK[$f]=$pack INSTALL[$f]=$install; done <"$WORK/costs"

# point NAME WORKERS MODE FRACTION [EXTRA...]: one simulation into $WORK/NAME.json
point() {
    local name=$1 workers=$2 mode=$3 f=$4
    shift 4
    local args=(--workers "$workers" --mode "$mode" --network "$NETWORK" --size "${SIZE}x$SIZE"
        --tile "$TILE" --stats "$WORK/$name.json")
    args+=(--map "$WORK/$mode.costs")
    [ "$mode" = hetero ] && args+=(--pass-rate "$PASS_RATE" --fill-map "$WORK/homo.costs")
    [ -n "$SCHEDULE" ] && args+=(--schedule "$SCHEDULE")
    [ "$f" = 0 ] || args+=(--scene-memory "$(budget_mb "$f")" --page-size $PAGE_KB
        --page-trace "$HOMO_TRACE:$HETERO_TRACE" --page-install-ns "${INSTALL[$f]}"
        --master-page-ns "${PACK[$f]}" --page-home "${PAGE_HOME:-auto}" --page-fetch "$PAGE_FETCH")
    bench/simulate.sh "$SCENE" "${args[@]}" "$@" >/dev/null 2>"$WORK/$name.err" ||
        { echo "point $name failed: $(tail -3 "$WORK/$name.err")" >&2; return 1; }
}
row() { # NAME FRACTION: a CSV row of the point's figures
    python3 - "$WORK/$1.json" "$1" "$2" <<'EOF'
import json, sys
d = json.load(open(sys.argv[1]))
p, m = d.get("paging", {}), d.get("scene_memory", {})
print(",".join(str(x) for x in [sys.argv[2], d["workers"], d["mode"], sys.argv[3],
      m.get("prefetch", ""), "%.6f" % d["makespan_s"], "%.4f" % d["efficiency"],
      "%.3f" % d["master_busy"], p.get("faults", 0), p.get("requests", 0), p.get("pages", 0),
      p.get("prefetched", 0), p.get("touches", 0), p.get("bytes", 0), "%.6f" % p.get("wait_s", 0),
      m.get("asks_answered", 0), m.get("trace_tiles_missing", 0), m.get("homes", 0),
      m.get("bytes_served", 0), p.get("served_bytes", 0)]))
EOF
}

# 2. the check: one simulated worker against the serial renders
CHECK=$OUT/check.csv
if [ "$REUSE" = no ]; then
point check-0 1 homo 0 --network local
echo "0,$(python3 -c "
import csv, statistics, sys
print(statistics.median(float(r['tile_phase_s']) for r in csv.DictReader(open(sys.argv[1])) if r['fraction'] == '0'))" "$CAL"),$(python3 -c "
import json, sys; print('%.6f' % json.load(open(sys.argv[1]))['makespan_s'])" "$WORK/check-0.json"),0,0,0,0,0,0,0,0,True" >"$WORK/check0"
echo "fraction,real_tile_phase_s,sim_makespan_s,real_faults,sim_faults,real_pages,sim_pages,real_evictions,sim_evictions,real_bytes,sim_bytes,same_counts" >"$CHECK"
cat "$WORK/check0" >>"$CHECK"
for f in $FRACTIONS; do
    point check-$f 1 homo "$f" --network local
    python3 - "$CAL" "$f" "$WORK/check-$f.json" >>"$CHECK" <<'EOF'
import csv, json, statistics, sys
f = sys.argv[2]
rs = [r for r in csv.DictReader(open(sys.argv[1])) if r["fraction"] == f]
real = rs[0]
d = json.load(open(sys.argv[3]))
p = d["paging"]
same = all(int(real[k]) == int(p[k]) for k in ("faults", "pages", "evictions", "bytes"))
print(",".join(str(x) for x in [f, statistics.median(float(r["tile_phase_s"]) for r in rs),
      "%.6f" % d["makespan_s"], real["faults"], p["faults"], real["pages"], p["pages"],
      real["evictions"], p["evictions"], real["bytes"], p["bytes"], same]))
EOF
done

fi

# 3. the points
fetch_suffix=""
[ "$PAGE_FETCH" = ask ] && fetch_suffix=-ask
POINTS=$OUT/points${SCHEDULE:+-$SCHEDULE}${PAGE_HOME:+-$PAGE_HOME}$fetch_suffix.csv
echo "name,workers,mode,fraction,prefetch,makespan_s,efficiency,master_busy,faults,requests,pages,prefetched,touches,bytes,wait_s,asks,trace_tiles_missing,homes,master_bytes_served,workers_bytes_served" >"$POINTS"
for w in $WORKERS; do
    [ "$w" = 1 ] && continue
    for mode in homo hetero; do
        for f in 0 $FRACTIONS; do
            name=$mode-$w-$f
            point "$name" "$w" "$mode" "$f" && row "$name" "$f" >>"$POINTS"
            if [ "$w" = 64 ] && [ "$f" != 0 ]; then
                point "$name-noprefetch" "$w" "$mode" "$f" --page-prefetch off &&
                    row "$name-noprefetch" "$f" >>"$POINTS"
            fi
        done
    done
done

python3 - "$CAL" "$CHECK" "$POINTS" "$BLOB" "$WORK/costs" <<'EOF'
import csv, statistics, sys
cal, check, points = (list(csv.DictReader(open(p))) for p in sys.argv[1:4])
blob = int(sys.argv[4])
costs = {l.split()[0]: l.split()[1:] for l in open(sys.argv[5])}
print("blob: %.1f MB" % (blob / 1e6))
print("\n| budget | real serial tile phase (median, min-max) | items' CPU s (median, min-max) | vs in memory (CPU) | MB fetched | rank 0 packs (ns/byte) | a worker installs (ns/byte) | images identical |")
print("|---|---:|---:|---:|---:|---:|---:|---|")
cpu0 = statistics.median(float(r["items_cpu_s"]) for r in cal if r["fraction"] == "0")
for f in sorted({r["fraction"] for r in cal}, key=int):
    rs = [r for r in cal if r["fraction"] == f]
    t = sorted(float(r["tile_phase_s"]) for r in rs)
    u = sorted(float(r["items_cpu_s"]) for r in rs)
    c = costs.get(f, ["-", "-"])
    print("| %s | %.3f s (%.3f-%.3f) | %.3f s (%.3f-%.3f) | %.0f %% | %.1f | %s | %s | %s |" % (
          "whole" if f == "0" else "1/" + f, statistics.median(t), t[0], t[-1],
          statistics.median(u), u[0], u[-1], 100 * cpu0 / statistics.median(u),
          int(rs[0]["bytes"]) / 1e6, c[0], c[1],
          "yes" if all(r["identical"] == "True" or r["identical"] == "true" for r in rs) else "NO"))
print("\n| budget | real tile phase | simulated, 1 worker | faults real / sim | pages | evictions | bytes | same counts |")
print("|---|---:|---:|---:|---:|---:|---:|---|")
for r in check:
    print("| %s | %.3f s | %.3f s | %s / %s | %s / %s | %s / %s | %s / %s | %s |" % (
          "whole" if r["fraction"] == "0" else "1/" + r["fraction"], float(r["real_tile_phase_s"]),
          float(r["sim_makespan_s"]), r["real_faults"],
          r["sim_faults"], r["real_pages"], r["sim_pages"], r["real_evictions"], r["sim_evictions"],
          r["real_bytes"], r["sim_bytes"], r["same_counts"]))
print("\n| workers | mode | budget | prefetch | makespan | efficiency | vs in memory | master busy | faults | requests | pages | MB fetched | wait s (all workers) | tiles not traced |")
print("|---:|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
memory = {(r["workers"], r["mode"]): float(r["makespan_s"]) for r in points if r["fraction"] == "0"}
for r in points:
    base = memory.get((r["workers"], r["mode"]))
    print("| %s | %s | %s | %s | %.4f s | %.1f %% | %s | %.1f %% | %s | %s | %s | %.1f | %.3f | %s |" % (
          r["workers"], r["mode"], "whole" if r["fraction"] == "0" else "1/" + r["fraction"],
          r["prefetch"] or "-", float(r["makespan_s"]), 100 * float(r["efficiency"]),
          "%.0f %%" % (100 * base / float(r["makespan_s"])) if base else "-",
          100 * float(r["master_busy"]), r["faults"], r["requests"], r["pages"],
          int(r["bytes"]) / 1e6, float(r["wait_s"]), r["trace_tiles_missing"]))
EOF
