#!/usr/bin/env bash
# bench/accuracy.sh — speed versus accuracy: every quality knob of
# `csgtrace render` measured against a reference render.
#
# For each test scene (scenes/showcase.pov, glass.pov, mirrors.pov and two
# generated random-sphere scenes) it renders
#   - a reference: --precision double --depth 32 --threshold 1e-6 (and
#     --spp 16 when the binary has --spp).  Threshold 1e-6, not 0: with 0
#     every glass ray tree is traced to depth 32 (2^k tiny branches; 14 s
#     for 80x60 of spheres30), while 1e-6 moves no pixel by more than
#     2e-5 against 1e-7 (measured on glass, spheres30 and mirrors);
#   - a grid: precision {float, double} x depth {1,2,3,5,8} x threshold
#     {0, 0.001, 0.01, 0.1} at spp 1, and, when --spp exists, the same
#     at spp 4 with threshold 0.01 only.  Depth 1 traces primary rays
#     only, so the threshold does not matter there: one setting per
#     precision/spp.
# Every grid setting runs ACC_REPS times (3) in serial mode (one process,
# no MPI, no OpenCL): the time is the median of the `wall_s` fields of the
# --stats JSON (the render only: no process start, no scene parse).  The
# reference runs ACC_REF_REPS times (1: it takes seconds, so one run's
# noise is small against it).  The
# error is oiiotool --diff of the linear EXR against the reference:
# RMSE, PSNR (peak 1), max abs difference over channels, and the share of
# pixels with a channel off by more than 1/255 (linear values).
#
# Output: bench/results/accuracy.csv (one row per scene x setting, the
# reference rows included) and, through bench/accuracy.py,
# bench/results/accuracy.png (time versus RMSE, Pareto front marked) and
# bench/results/accuracy_summary.md (tables quoted in bench/ACCURACY.md).
#
#   bench/accuracy.sh              the full run: 200x150, about 8 minutes
#   ACC_WIDTH=120 ACC_HEIGHT=90 ACC_REPS=1 bench/accuracy.sh   a quick look
#   ACC_SCENES="showcase glass" bench/accuracy.sh             some scenes only
set -euo pipefail
cd "$(dirname "$0")/.."

BIN=${CSGTRACE:-build/csgtrace}
W=${ACC_WIDTH:-200}
H=${ACC_HEIGHT:-150}
REPS=${ACC_REPS:-3}
REF_REPS=${ACC_REF_REPS:-1}
REF_THR=1e-6
SCENES=${ACC_SCENES:-"showcase glass mirrors spheres30 spheres60"}
WORK=${ACC_WORK:-build/bench-accuracy}
RESULTS=bench/results
CSV=$RESULTS/accuracy.csv
export OMPI_MCA_pml=ob1 OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1

for tool in "$BIN" oiiotool python3; do
    command -v "$tool" >/dev/null 2>&1 || [ -x "$tool" ] || {
        echo "accuracy.sh: $tool not found (make build/csgtrace; make deps)" >&2
        exit 77
    }
done
mkdir -p "$WORK" "$RESULTS"

# The scene file of a scene name (generated ones are made once per size).
scene_file() {
    case $1 in
    spheres30)
        "$BIN" gen spheres --count 30 --occupancy 0.5 --seed 1 --width "$W" --height "$H" \
            -o "$WORK/spheres30.pov" >/dev/null
        echo "$WORK/spheres30.pov" ;;
    spheres60)
        "$BIN" gen spheres --count 60 --occupancy 0.8 --seed 2 --width "$W" --height "$H" \
            -o "$WORK/spheres60.pov" >/dev/null
        echo "$WORK/spheres60.pov" ;;
    *) echo "scenes/$1.pov" ;;
    esac
}

# Does this binary know --spp?
HAVE_SPP=0
if "$BIN" render scenes/primitives.pov -o "$WORK/probe.exr" --width 8 --height 6 --spp 1 \
    --no-progress >/dev/null 2>&1; then
    HAVE_SPP=1
fi

# render SCENEFILE OUT.exr PREC DEPTH THRESH SPP REPS -> prints the median wall_s
render() {
    local scene=$1 out=$2 prec=$3 depth=$4 thr=$5 spp=$6 reps=$7 i times=()
    local sppopt=()
    [ "$HAVE_SPP" = 1 ] && sppopt=(--spp "$spp")
    for ((i = 0; i < reps; i++)); do
        "$BIN" render "$scene" -o "$out" --mode serial --width "$W" --height "$H" \
            --precision "$prec" --depth "$depth" --threshold "$thr" "${sppopt[@]}" \
            --stats "$WORK/stats.json" --no-progress >/dev/null
        times+=("$(sed -n 's/^ *"wall_s": *\([0-9.eE+-]*\).*/\1/p' "$WORK/stats.json")")
    done
    printf '%s\n' "${times[@]}" | sort -g | awk '{v[NR]=$1} END {print v[int((NR+1)/2)]}'
}

# diff A.exr REF.exr -> "rmse,psnr,max_abs,share_over_1_255"
diff_exr() {
    local log
    log=$(oiiotool "$1" "$2" --fail 0.00392157 --warn 0 --diff 2>&1 || true)
    awk '
        /RMS error/ {rmse = $4}
        /Peak SNR/ {psnr = $4}
        /Max error/ {maxe = $4}
        /over 0.0039/ {gsub(/[()%]/, "", $3); over = $3 / 100}
        END {
            if (rmse == "") { print "0,inf,0,0"; exit }
            printf "%s,%s,%s,%s\n", rmse, psnr, maxe, (over == "" ? 0 : over)
        }' <<<"$log"
}

echo "scene,precision,depth,threshold,spp,wall_s,rmse,psnr,max_abs,over_1_255,ref_wall_s,speedup,reference" >"$CSV"
start=$(date +%s)
for name in $SCENES; do
    scene=$(scene_file "$name")
    ref_spp=1
    [ "$HAVE_SPP" = 1 ] && ref_spp=16
    ref_exr=$WORK/$name-ref.exr
    ref_t=$(render "$scene" "$ref_exr" double 32 "$REF_THR" "$ref_spp" "$REF_REPS")
    echo "$name,double,32,$REF_THR,$ref_spp,$ref_t,0,inf,0,0,$ref_t,1,1" >>"$CSV"
    echo "accuracy: $name reference ${ref_t}s (double, depth 32, threshold $REF_THR, spp $ref_spp)"
    spps="1"
    [ "$HAVE_SPP" = 1 ] && spps="1 4"
    for spp in $spps; do
        for prec in float double; do
            for depth in 1 2 3 5 8; do
                thrs="0 0.001 0.01 0.1"
                [ "$spp" != 1 ] && thrs="0.01"
                [ "$depth" = 1 ] && thrs="0"
                for thr in $thrs; do
                    exr=$WORK/$name-$prec-d$depth-t$thr-s$spp.exr
                    t=$(render "$scene" "$exr" "$prec" "$depth" "$thr" "$spp" "$REPS")
                    err=$(diff_exr "$exr" "$ref_exr")
                    speed=$(awk -v r="$ref_t" -v t="$t" 'BEGIN {printf "%.3f", r / t}')
                    echo "$name,$prec,$depth,$thr,$spp,$t,$err,$ref_t,$speed,0" >>"$CSV"
                done
            done
        done
    done
    echo "accuracy: $name done ($(($(date +%s) - start)) s so far)"
done

python3 bench/accuracy.py "$CSV" "$RESULTS/accuracy.png" "$RESULTS/accuracy_summary.md"
echo "accuracy: wrote $CSV, $RESULTS/accuracy.png, $RESULTS/accuracy_summary.md" \
    "in $(($(date +%s) - start)) s"
