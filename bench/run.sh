#!/usr/bin/env bash
# bench/run.sh — the benchmark suite: the paper's three experiments and beyond.
#
#   bench/run.sh --quick          what `make bench` runs (about 5 minutes on 2 cores)
#   bench/run.sh --full           `make bench-full` (about 40 minutes on 2 cores, estimated)
#   bench/run.sh --quick --only objects,size     run some experiments, keep the other CSVs
#   bench/run.sh --report         rebuild summaries, plots and RESULTS.md from the CSVs
#
# Experiments (each writes bench/results/<name>.csv, one row per run):
#   objects      10..50 spheres x occupancy 20/50/80 % at 384x384 (Figures 1 and 2)
#   size         192/256/320 (+ the 384 runs of `objects`), averaged (Figure 3)
#   big_objects  up to 300 (quick) / 1000 (full) spheres
#   big_size     up to 768 (quick) / 1536 (full) pixels square
#   occ_sweep    occupancy 5..95 %
#   tile         tile size 8..128, both modes: the best tile per mode
#   schedule     --schedule raster / cost / static / tail, both modes: busy
#                fraction, tail, how well the estimate ranks the tiles
#   povray       bench/vs_povray.sh: one core, trace to trace, against POV-Ray 3.7 +WT1
#
# Method: scenes come from `csgtrace gen spheres` (cached in build/bench/scenes);
# one warm-up render per mode fills the PoCL kernel cache (POCL_CACHE_DIR) before
# any timing.  Each configuration is JOBS separate `csgtrace compare` jobs (MPI
# jobs: a fresh start, placement and memory each time); within a job, a warm-up
# render per mode, then REPEATS rounds of one homo and one hetero render,
# interleaved, so a disturbance of the shared machine falls on both modes.  The
# OpenCL context and program are set up in the warm-up and kept, so the timed
# hetero renders include neither the kernel build nor the OpenCL set-up, and no
# figure includes process start.  compare also checks the two images are
# identical.  The compared figure is time_s = wall_s - compile_s - cl_setup_s
# (both 0 in compare's timed runs) from the per-run stats compare writes.  The
# advantage (homo - hetero)/homo is taken per round (a homo and a hetero render
# of the same job, next to each other), and bench/collect.py reports its median
# over the JOBS x REPEATS rounds with the spread (min .. max, and the range of
# the per-job medians: what a single job could have shown).
#
# Environment: RANKS (3: 1 master + 2 workers), JOBS (3), REPEATS (quick 2,
# full 3), CSGTRACE (build/csgtrace), BENCH_OUT (bench/results,
# bench/results-full for --full), BENCH_WORK (build/bench, build/bench-full for
# --full).
set -euo pipefail

ROOT=$(cd "$(dirname "$0")/.." && pwd)
SUITE=quick
ONLY=""
REPORT_ONLY=0
EXPERIMENTS=(objects size big_objects big_size occ_sweep tile schedule povray)
# --only LIST: comma-separated names of EXPERIMENTS, nothing else (the list is
# data: it is checked here and never pasted into code).
check_only() {
    local name
    [[ "$1" =~ ^[a-z_]+(,[a-z_]+)*$ ]] || { echo "bench/run.sh: --only expects names like objects,size" >&2; exit 2; }
    IFS=, read -r -a names <<<"$1"
    for name in "${names[@]}"; do
        [[ " ${EXPERIMENTS[*]} " == *" $name "* ]] ||
            { echo "bench/run.sh: --only: unknown experiment '$name' (known: ${EXPERIMENTS[*]})" >&2; exit 2; }
    done
}
while [ $# -gt 0 ]; do
    case "$1" in
    --quick) SUITE=quick ;;
    --full) SUITE=full ;;
    --only) [ $# -ge 2 ] || { echo "bench/run.sh: --only needs a list" >&2; exit 2; }
            ONLY=$2; check_only "$ONLY"; shift ;;
    --report) REPORT_ONLY=1 ;;
    -h|--help) sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    *) echo "bench/run.sh: unknown option '$1' (try --help)" >&2; exit 2 ;;
    esac
    shift
done

BIN=${CSGTRACE:-$ROOT/build/csgtrace}
RANKS=${RANKS:-3}
JOBS=${JOBS:-3}
# The full suite keeps its own results (and scene cache) beside the quick one's.
SUFFIX=""
[ "$SUITE" = full ] && SUFFIX=-full
OUT=${BENCH_OUT:-$ROOT/bench/results$SUFFIX}
WORK=${BENCH_WORK:-$ROOT/build/bench$SUFFIX}
COLLECT="python3 $ROOT/bench/collect.py"
export POCL_CACHE_DIR=${POCL_CACHE_DIR:-$ROOT/build/pocl-cache}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_pml=ob1
MPIRUN=(mpirun -np "$RANKS" --oversubscribe --bind-to none)

# ---- the two suites ---------------------------------------------------------------
if [ "$SUITE" = quick ]; then
    REPEATS=${REPEATS:-2}
    SEEDS=(1)
    GEN_SIZE=192              # occupancy fitted at 192 (4x cheaper); measured again at render size
    COUNTS=(10 30 50); OCCS=(20 50 80)
    SIZE_COUNTS=(30); SIZE_OCCS=(50); SIZES=(192 256 320)
    BIG_COUNTS=(100 300); BIG_COUNTS_SIZE=192
    BIG_SIZES=(512 768)
    SWEEP_OCCS=(5 95); SWEEP_SIZE=256     # the paper's range (20-80) is in objects
    TILES=(8 16 64); TILE_SIZE=384        # tile 32: the runs of objects (30, 50)
    SCHED_SIZE=384
    POV_COUNTS=(30); POV_SIZE=384
else
    REPEATS=${REPEATS:-3}
    COUNTS=(10 20 30 40 50); OCCS=(20 50 80)
    SEEDS=(1 2 3)
    GEN_SIZE=384
    SIZE_COUNTS=(10 20 30 40 50); SIZE_OCCS=(20 50 80); SIZES=(192 256 320)
    BIG_COUNTS=(50 100 300 1000); BIG_COUNTS_SIZE=384
    BIG_SIZES=(384 512 768 1024 1536)
    SWEEP_OCCS=(5 15 25 35 45 55 65 75 85 95); SWEEP_SIZE=384
    TILES=(8 16 32 64 128); TILE_SIZE=384
    SCHED_SIZE=768
    POV_COUNTS=(10 30 50); POV_SIZE=384
fi
PAPER_SIZE=384
SCHEDULES=(raster cost static tail); SCHED_COUNT=30; SCHED_OCC=50
BIG_OCC=50; BIG_SIZE_COUNT=30; SWEEP_COUNT=30; TILE_COUNT=30; TILE_OCC=50; DEFAULT_TILE=32

die() { echo "bench/run.sh: $*" >&2; exit 1; }
want() { [ -z "$ONLY" ] || [[ ",$ONLY," == *",$1,"* ]]; }

COMMIT=$(git -C "$ROOT" rev-parse --short HEAD 2>/dev/null || echo unknown)
if [ -n "$(git -C "$ROOT" status --porcelain --untracked-files=no -- csg host workers simd_kernels 2>/dev/null)" ]; then
    COMMIT="$COMMIT+dirty"
fi
CPU=$(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo | head -1 | tr -s ' ,' ' ')
CORES=$(nproc)
loadavg() { cut -d' ' -f1-3 /proc/loadavg; }

# scene COUNT OCC SEED -> prints the path of the cached generated scene.
scene() {
    local n=$1 occ=$2 seed=$3
    local f="$WORK/scenes/spheres-n$n-o$occ-s$seed-g$GEN_SIZE.pov"
    if [ ! -s "$f" ]; then
        mkdir -p "$WORK/scenes"
        "$BIN" gen spheres --count "$n" --occupancy "$(awk -v o="$occ" 'BEGIN{print o/100}')" \
            --seed "$seed" --width "$GEN_SIZE" --height "$GEN_SIZE" -o "$f.tmp.pov" \
            >"$f.gen.txt" || die "gen failed for $f"
        mv "$f.tmp.pov" "$f"
        sed -i "s|$f.tmp.pov|$f|" "$f.gen.txt"
    fi
    echo "$f"
}

# The occupancy gen measured at GEN_SIZE (its one-line report), in %.
gen_occ() { sed -n 's/.*occupancy \([0-9.]*\)%.*/\1/p' "$1.gen.txt"; }

# render MODE SCENE SIZE TILE JSON: one render, stats to JSON (the image is kept
# in WORK for inspection, one per mode).
render() {
    local mode=$1 sc=$2 size=$3 tile=$4 json=$5
    local cmd=("$BIN" render "$sc" -o "$WORK/last-$mode.png" --mode "$mode"
               --width "$size" --height "$size" --tile "$tile" --stats "$json")
    if [ "$mode" = serial ]; then "${cmd[@]}" >"$WORK/log.txt" 2>&1
    else "${MPIRUN[@]}" "${cmd[@]}" >"$WORK/log.txt" 2>&1; fi \
        || { cat "$WORK/log.txt" >&2; die "render failed: ${cmd[*]}"; }
}

# compare_runs SCENE SIZE TILE SCHED: one `csgtrace compare` job (SCHED "default":
# each mode's own scheduler), its runs split into $WORK/run-MODE-R.json (one
# stats object each, as `render --stats` writes).
compare_runs() {
    local sc=$1 size=$2 tile=$3 sched=$4 json="$WORK/compare.json"
    local extra=()
    [ "$sched" = default ] || extra=(--schedule "$sched")
    rm -f "$json" "$WORK"/run-*.json
    "${MPIRUN[@]}" "$BIN" compare "$sc" --width "$size" --height "$size" --tile "$tile" \
        --repeat "$REPEATS" "${extra[@]}" --stats "$json" >"$WORK/log.txt" 2>&1 \
        || { cat "$WORK/log.txt" >&2; die "compare failed on $sc at ${size}x${size}, tile $tile"; }
    python3 - "$json" "$WORK" <<'PY'
import json, sys
runs = json.load(open(sys.argv[1]))
for mode in ("homo", "hetero"):
    for r, stats in enumerate(runs[mode], 1):
        with open(f"{sys.argv[2]}/run-{mode}-{r}.json", "w") as f:
            json.dump(stats, f)
PY
}

# config EXP COUNT OCC SEED SIZE TILE [SCHED]: JOBS compare jobs of REPEATS
# rounds each, one CSV row per render.
config() {
    local exp=$1 n=$2 occ=$3 seed=$4 size=$5 tile=$6 sched=${7:-default}
    local sc; sc=$(scene "$n" "$occ" "$seed")
    local gocc; gocc=$(gen_occ "$sc")
    local j r mode json
    for j in $(seq 1 "$JOBS"); do
        compare_runs "$sc" "$size" "$tile" "$sched"
        for r in $(seq 1 "$REPEATS"); do
            for mode in homo hetero; do
                json="$WORK/run-$mode-$r.json"
                $COLLECT append "$OUT/$exp.csv" "$json" experiment="$exp" suite="$SUITE" \
                    commit="$COMMIT" date="$(date -u +%Y-%m-%dT%H:%M:%SZ)" cpu="$CPU" \
                    cores="$CORES" count="$n" occ_target="$occ" occ_gen="$gocc" \
                    gen_size="$GEN_SIZE" seed="$seed" sched_arg="$sched" job="$j" repeat="$r" \
                    loadavg="$(loadavg)" scene="$(basename "$sc")"
            done
        done
    done
    printf '  %-12s n=%-5s occ=%-3s seed=%s %sx%s tile=%-4s %-8s done (%ds)\n' \
        "$exp" "$n" "$occ" "$seed" "$size" "$size" "$tile" "$sched" "$SECONDS"
}

# fresh EXP: start the experiment's CSV afresh.
fresh() { rm -f "$OUT/$1.csv"; echo "== $1"; }

# report: summaries, RESULTS.md (bench/RESULTS.md for bench/results, else
# next to the CSVs), one PNG per plot_NAME.gp whose NAME.dat has data.
report() {
    local md="$OUT/RESULTS.md"
    [ "$(cd "$OUT" && pwd)" = "$ROOT/bench/results" ] && md="$ROOT/bench/RESULTS.md"
    $COLLECT report "$OUT" "$ROOT/bench/RESULTS.template.md" "$md"
    local term=png
    gnuplot -e 'set terminal pngcairo' >/dev/null 2>&1 && term=pngcairo
    local gp name
    for gp in "$ROOT"/bench/plot_*.gp; do
        name=$(basename "$gp" .gp); name=${name#plot_}
        [ "$name" != common ] || continue
        if [ ! -f "$OUT/$name.dat" ] || [ "$(wc -l <"$OUT/$name.dat")" -lt 2 ]; then
            rm -f "$OUT/$name.png"; continue
        fi
        (cd "$OUT" && gnuplot -e "term='$term'; bench='$ROOT/bench'" "$gp") || echo "bench/run.sh: $gp failed" >&2
    done
    echo "bench: report in $md"
}

# ---- main ------------------------------------------------------------------------
mkdir -p "$OUT" "$WORK"
if [ "$REPORT_ONLY" = 1 ]; then report; exit 0; fi
[ -x "$BIN" ] || die "$BIN not found: run 'make build/csgtrace' first"
SECONDS=0
LOAD_START=$(loadavg)
START=$(date -u +%Y-%m-%dT%H:%M:%SZ)
echo "bench: $SUITE suite, $RANKS ranks, $JOBS jobs x $REPEATS rounds per configuration, commit $COMMIT, $CPU"

# Scenes first (not timed; generation is the slow part for big counts).
echo "== scenes (cached in $WORK/scenes)"
for seed in "${SEEDS[@]}"; do
    for n in "${COUNTS[@]}"; do for occ in "${OCCS[@]}"; do scene "$n" "$occ" "$seed" >/dev/null; done; done
done
for n in "${BIG_COUNTS[@]}"; do scene "$n" "$BIG_OCC" 1 >/dev/null; done
for occ in "${SWEEP_OCCS[@]}"; do scene "$SWEEP_COUNT" "$occ" 1 >/dev/null; done
echo "  scenes ready (${SECONDS}s)"

# Warm-up: fills the PoCL kernel cache and the file cache; not recorded.
WARM=$(scene 30 50 1)
for mode in homo hetero; do render "$mode" "$WARM" 128 "$DEFAULT_TILE" "$WORK/warmup.json"; done
echo "  warm-up done (${SECONDS}s)"

if want objects; then
    fresh objects
    for seed in "${SEEDS[@]}"; do for n in "${COUNTS[@]}"; do for occ in "${OCCS[@]}"; do
        config objects "$n" "$occ" "$seed" "$PAPER_SIZE" "$DEFAULT_TILE"
    done; done; done
    # Figure 2 averages the same runs over objects.
    cp "$OUT/objects.csv" "$OUT/occupancy.csv"
fi

if want size; then
    fresh size
    for seed in "${SEEDS[@]}"; do for size in "${SIZES[@]}"; do
        for n in "${SIZE_COUNTS[@]}"; do for occ in "${SIZE_OCCS[@]}"; do
            config size "$n" "$occ" "$seed" "$size" "$DEFAULT_TILE"
        done; done
    done; done
    # The 384 point: the runs of `objects` with the same configurations.
    [ -f "$OUT/objects.csv" ] || die "size needs objects.csv (run objects first)"
    $COLLECT copy "$OUT/objects.csv" "$OUT/size.csv" size "${SIZE_COUNTS[*]}" "${SIZE_OCCS[*]}"
fi

if want big_objects; then
    fresh big_objects
    for n in "${BIG_COUNTS[@]}"; do config big_objects "$n" "$BIG_OCC" 1 "$BIG_COUNTS_SIZE" "$DEFAULT_TILE"; done
fi

if want big_size; then
    fresh big_size
    for size in "${BIG_SIZES[@]}"; do config big_size "$BIG_SIZE_COUNT" "$BIG_OCC" 1 "$size" "$DEFAULT_TILE"; done
fi

if want occ_sweep; then
    fresh occ_sweep
    for occ in "${SWEEP_OCCS[@]}"; do config occ_sweep "$SWEEP_COUNT" "$occ" 1 "$SWEEP_SIZE" "$DEFAULT_TILE"; done
fi

if want tile; then
    fresh tile
    for tile in "${TILES[@]}"; do config tile "$TILE_COUNT" "$TILE_OCC" 1 "$TILE_SIZE" "$tile"; done
    if [[ " ${TILES[*]} " != *" $DEFAULT_TILE "* ]]; then # the default tile: objects' runs
        [ -f "$OUT/objects.csv" ] || die "tile needs objects.csv (run objects first)"
        $COLLECT copy "$OUT/objects.csv" "$OUT/tile.csv" tile "$TILE_COUNT" "$TILE_OCC"
    fi
fi

if want schedule; then
    fresh schedule
    for sched in "${SCHEDULES[@]}"; do
        config schedule "$SCHED_COUNT" "$SCHED_OCC" 1 "$SCHED_SIZE" "$DEFAULT_TILE" "$sched"
    done
fi

if want povray; then
    echo "== povray"
    for n in "${POV_COUNTS[@]}"; do scene "$n" 50 1 >/dev/null; done
    POV_SCENES=()
    for n in "${POV_COUNTS[@]}"; do POV_SCENES+=("$(scene "$n" 50 1)"); done
    REPEATS=$REPEATS SIZE=$POV_SIZE SUITE=$SUITE CSGTRACE=$BIN BENCH_OUT=$OUT BENCH_WORK=$WORK \
        "$ROOT/bench/vs_povray.sh" "${POV_SCENES[@]}"
fi

# Values go to Python as arguments (data), never into its source.
python3 - "$OUT/run_info.json" "$SUITE" "$START" "$SECONDS" "$COMMIT" "$CPU" "$CORES" "$RANKS" \
    "$JOBS" "$REPEATS" "$ONLY" "$LOAD_START" "$(loadavg)" <<'PY'
import json, sys
keys = ("suite", "start", "elapsed_s", "commit", "cpu", "cores", "ranks", "jobs", "repeats",
        "only", "load_start", "load_end")
info = dict(zip(keys, sys.argv[2:]))
for k in ("elapsed_s", "cores", "ranks", "jobs", "repeats"):
    info[k] = int(info[k])
with open(sys.argv[1], "w") as f:
    json.dump(info, f, indent=1)
PY
report
echo "bench: done in ${SECONDS}s; CSV and PNG in $OUT"
