#!/usr/bin/env bash
# spd.sh — the SPD benchmark: every Eric Haines SPD scene of ../shared/nff
# (relative to the repository; not part of a clean clone, so `make test`
# never reads it) rendered at 512x512 by
#   csgtrace serial, homo and hetero (the scene's own view, 45 degrees;
#   hetero twice: --pass auto, the default, and --pass always),
#   csgtrace homo on Tachyon's view (the file with angle 53.130102),
#   Tachyon (tachyon-bin-nox, reads NFF natively, 2 threads),
#   POV-Ray 3.7 on `csgtrace export SCENE.nff` (2 threads),
# in R interleaved rounds (every scene and renderer once per round), then
# bench/spd_report.py writes the medians, ratios and the contact sheet
# into bench/SPD.md and bench/spd/sheet.png.
#
# Times: csgtrace's `wall_s` (--stats: parse, flatten, trace, write; not
# the mpirun launch) and `trace_s` = primary_s + secondary_s; Tachyon's
# parse + preprocessing + ray tracing + image I/O and its ray tracing
# alone; POV-Ray's parse + bounding + trace and its trace alone.
#
# Usage: bench/spd.sh [--runs R] [--nff DIR] [--out DIR] [--size N] [--append] [--pairs] [SCENE ...]
#   (--append: add rows to OUT/raw.csv instead of starting it again, its
#   rounds numbered after the file's last (more rounds of the same runs); the
#   report, the identity check and the sheet then cover every scene of DIR
#   that has images in OUT)
#   (--pairs: the rounds run csgtrace homo and hetero only, side by side,
#   for more rounds of the hetero / homo comparison in the same time; with
#   --append the other renderers keep the rounds they had)
#   (DIR: --nff, else $SPD_NFF, else ../shared/nff beside the repository)
#   (SCENE: base names such as balls4; default every *.nff of DIR)
# Needs: build/csgtrace, mpirun, tachyon, povray, oiiotool, python3.
set -u
ROOT=$(cd "$(dirname "$0")/.." && pwd)
BIN=$ROOT/build/csgtrace
RUNS=3
NFF=${SPD_NFF:-$ROOT/../shared/nff}
[ -d "$NFF" ] || NFF=$ROOT/../../shared/nff # a git worktree one level deeper
OUT=$ROOT/bench/spd
SIZE=512
names=()
append=0
pairs=0
while [ $# -gt 0 ]; do
    case "$1" in
        --runs) RUNS=$2; shift 2 ;;
        --nff) NFF=$2; shift 2 ;;
        --out) OUT=$2; shift 2 ;;
        --size) SIZE=$2; shift 2 ;;
        --append) append=1; shift ;;
        --pairs) pairs=1; shift ;;
        -h|--help) sed -n '2,/^set -u/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
        -*) echo "spd.sh: unknown option $1" >&2; exit 2 ;;
        *) names+=("$1"); shift ;;
    esac
done
[ "$pairs" = 0 ] || [ "$append" = 1 ] ||
    { echo "spd.sh: --pairs adds rounds to a full run's: use it with --append" >&2; exit 2; }
for tool in mpirun tachyon povray oiiotool python3; do
    command -v "$tool" >/dev/null || { echo "spd.sh: $tool not found" >&2; exit 1; }
done
[ -x "$BIN" ] || { echo "spd.sh: build $BIN first (make)" >&2; exit 1; }
if [ ${#names[@]} -eq 0 ]; then
    for f in "$NFF"/*.nff; do names+=("$(basename "$f" .nff)"); done
fi
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_pml=ob1
export OMPI_MCA_rmaps_base_oversubscribe=1
export POCL_CACHE_DIR=${POCL_CACHE_DIR:-$ROOT/build/pocl-cache}
mkdir -p "$OUT/img" "$OUT/work" "$POCL_CACHE_DIR"
RAW=$OUT/raw.csv
[ "$append" = 1 ] && [ -s "$RAW" ] ||
    echo "scene,renderer,run,frame_s,trace_s,rays,cl_open,culled,own_s,tiles_s" >"$RAW"
MPI=(mpirun -np 3 --bind-to none)

# Inputs made once: the POV-Ray export and the file on Tachyon's view.
for n in "${names[@]}"; do
    "$BIN" export "$NFF/$n.nff" -o "$OUT/work/$n.pov" >/dev/null ||
        { echo "spd.sh: export of $n failed" >&2; exit 1; }
    sed 's/^angle .*/angle 53.130102/' "$NFF/$n.nff" >"$OUT/work/$n-tview.nff"
done

# csgtrace: one render, its stats appended as a row.
# (an mpirun that fails to start, as Open MPI's shared-memory set-up
# sometimes does on this machine, is tried once more)
run_csg() { # name renderer run scene mode image [option...]
    local json=$OUT/work/$1-$2.json name=$1 renderer=$2 run=$3 scene=$4 mode=$5 image=$6
    shift 6
    if [ "$mode" = serial ]; then
        "$BIN" render "$scene" -o "$image" --mode serial --stats "$json" "$@" >/dev/null
    else
        "${MPI[@]}" "$BIN" render "$scene" -o "$image" --mode "$mode" --stats "$json" "$@" >/dev/null 2>&1 ||
            "${MPI[@]}" "$BIN" render "$scene" -o "$image" --mode "$mode" --stats "$json" "$@" >/dev/null
    fi || { echo "spd.sh: csgtrace $mode failed on $name" >&2; return 1; }
    python3 "$ROOT/bench/spd_report.py" row "$json" "$name" "$renderer" "$run" >>"$RAW"
}

run_tachyon() { # name run
    local log=$OUT/work/$1-tachyon.log
    (cd "$OUT/work" && tachyon "$NFF/$1.nff" -o "$OUT/img/$1-tachyon.tga" -format TARGA \
        -res "$SIZE" "$SIZE" -numthreads 2 >"$log" 2>&1) ||
        { echo "spd.sh: tachyon failed on $1" >&2; return 1; }
    python3 "$ROOT/bench/spd_report.py" tachyon "$log" "$1" "$2" >>"$RAW"
}

run_povray() { # name run
    local log=$OUT/work/$1-povray.log
    (cd "$OUT/work" && povray +I"$1.pov" +O"$OUT/img/$1-povray.png" +FN +W"$SIZE" +H"$SIZE" \
        -D -A +WT2 -P >"$log" 2>&1) ||
        { echo "spd.sh: povray failed on $1" >&2; return 1; }
    python3 "$ROOT/bench/spd_report.py" povray "$log" "$1" "$2" >>"$RAW"
}

# A warm-up hetero render builds the OpenCL program into the cache.
"$BIN" render "$NFF/${names[0]}.nff" -o "$OUT/work/warm.png" --mode hetero --width 16 >/dev/null

# (--append: the rounds go on from the file's last)
first=$(awk -F, 'NR > 1 && $3 + 0 > m { m = $3 + 0 } END { print m + 1 }' "$RAW")
for r in $(seq "$first" $((first + RUNS - 1))); do
    for n in "${names[@]}"; do
        echo "round $r/$((first + RUNS - 1)): $n" >&2
        [ "$pairs" = 1 ] || run_csg "$n" serial "$r" "$NFF/$n.nff" serial "$OUT/img/$n-serial.png"
        # (homo and hetero side by side, each first in every other round)
        if [ $((r % 2)) = 1 ]; then
            run_csg "$n" homo "$r" "$NFF/$n.nff" homo "$OUT/img/$n-homo.png"
            run_csg "$n" hetero "$r" "$NFF/$n.nff" hetero "$OUT/img/$n-hetero.png"
        else
            run_csg "$n" hetero "$r" "$NFF/$n.nff" hetero "$OUT/img/$n-hetero.png"
            run_csg "$n" homo "$r" "$NFF/$n.nff" homo "$OUT/img/$n-homo.png"
        fi
        [ "$pairs" = 1 ] && continue
        run_csg "$n" hetero-always "$r" "$NFF/$n.nff" hetero "$OUT/img/$n-always.png" --pass always
        run_csg "$n" homo-tview "$r" "$OUT/work/$n-tview.nff" homo "$OUT/img/$n-tview.png"
        run_tachyon "$n" "$r"
        run_povray "$n" "$r"
    done
done

# The final steps cover every scene of the folder rendered so far.
names=()
for f in "$NFF"/*.nff; do
    n=$(basename "$f" .nff)
    [ -f "$OUT/img/$n-serial.png" ] && names+=("$n")
done

# Bit-identical across modes: serial, homo and hetero images of each scene.
: >"$OUT/identical.txt"
for n in "${names[@]}"; do
    if idiff -fail 0 -warn 0 "$OUT/img/$n-serial.png" "$OUT/img/$n-homo.png" >/dev/null 2>&1 &&
       idiff -fail 0 -warn 0 "$OUT/img/$n-serial.png" "$OUT/img/$n-hetero.png" >/dev/null 2>&1 &&
       idiff -fail 0 -warn 0 "$OUT/img/$n-serial.png" "$OUT/img/$n-always.png" >/dev/null 2>&1; then
        echo "$n identical" >>"$OUT/identical.txt"
    else
        echo "$n DIFFERENT" >>"$OUT/identical.txt"
    fi
done

# The contact sheet: csgtrace, Tachyon, POV-Ray, a row each per scene group.
sheet=()
for n in "${names[@]}"; do
    sheet+=("$OUT/img/$n-serial.png" "$OUT/img/$n-tachyon.tga" "$OUT/img/$n-povray.png")
done
oiiotool "${sheet[@]}" --mosaic:pad=4 6x$(( (${#names[@]} + 1) / 2 )) --resize 25% \
    -o "$OUT/sheet.png" || echo "spd.sh: contact sheet failed" >&2

python3 "$ROOT/bench/spd_report.py" report "$RAW" "$OUT/identical.txt" "${SPD_REPORT:-$ROOT/bench/SPD.md}"
