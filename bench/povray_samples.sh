#!/usr/bin/env bash
# bench/povray_samples.sh — csgtrace on the sample scenes that ship with
# POV-Ray 3.7 (Debian's povray-examples): how many render, how close to
# POV-Ray, and the roadmap of what to support next.
#
#   bench/povray_samples.sh [--out FILE.md] [--jobs N] [SCENE.pov ...]
#
# The sample tree is copied once into the work folder (the scenes that
# #write files need a folder they may write), and each scene is run from its
# own folder there.  For every scene (default: every .pov of povray-examples):
#   1. csgtrace check SCENE (WIDTH x HEIGHT, clock 0, the standard include
#      library): parses or not; when not, the first unsupported construct its
#      message names (or the error);
#   2. the full image: POV-Ray 3.7 and csgtrace render the scene as written
#      (PNG, no antialiasing, POV-Ray's default gamma handling, the scene's
#      folder as a library path; csgtrace serial) and tests/compare_images.py
#      gives the share of pixels whose colours agree within 3/255 in every
#      channel;
#   3. the flat image (geometry and pigments only): csgtrace export --flat,
#      both programs render that (-A, File_Gamma 1; csgtrace to EXR) and the
#      pixels are compared as tests/crosscheck_povray.sh compares them
#      (hit/miss alike, colours within 2.5/255);
#   4. bench/povray_samples.py writes the table (scene, status, first
#      unsupported construct, full and flat agreement) and the counts by
#      construct into FILE.md (default bench/POVRAY_SAMPLES.md).
# A scene "renders" when csgtrace renders it; it "agrees" when its full
# image agrees on >= MIN_AGREEMENT % (default 99) of its pixels.
#
# Nothing read from a scene or an argument is pasted into code: each scene's
# results are files in its own folder, which the Python report reads as
# data.
# Environment: CSGTRACE (build/csgtrace), POVRAY (povray), WIDTH (160),
#   HEIGHT (120), MIN_AGREEMENT (99), TIMEOUT (seconds a step, 120),
#   JOBS (scenes at once, 1; --jobs), BENCH_WORK (the folder of the
#   per-scene results, build/bench/samples).
# Exit status: 0 the report was written; 77 POV-Ray, its samples or
# oiiotool missing; 1 other failures.
set -u

ROOT=$(cd "$(dirname "$0")/.." && pwd)
CSGTRACE=${CSGTRACE:-$ROOT/build/csgtrace}
POVRAY=${POVRAY:-povray}
WIDTH=${WIDTH:-160}
HEIGHT=${HEIGHT:-120}
MIN_AGREEMENT=${MIN_AGREEMENT:-99}
TIMEOUT=${TIMEOUT:-120}
JOBS=${JOBS:-1}
WORK=${BENCH_WORK:-$ROOT/build/bench/samples}
OUT=$ROOT/bench/POVRAY_SAMPLES.md
SAMPLES=/usr/share/doc/povray/examples

scenes=()
while [ $# -gt 0 ]; do
    case "$1" in
        --out) [ $# -ge 2 ] || { echo "povray_samples: --out needs a file" >&2; exit 2; }
               OUT=$2; shift 2 ;;
        --jobs) [ $# -ge 2 ] || { echo "povray_samples: --jobs needs a number" >&2; exit 2; }
                JOBS=$2; shift 2 ;;
        -h|--help) sed -n '2,/^set -u/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
        -*) echo "povray_samples: unknown option $1" >&2; exit 2 ;;
        *) scenes+=("$1"); shift ;;
    esac
done
case "$JOBS" in ''|*[!0-9]*|0) echo "povray_samples: --jobs needs a positive number" >&2; exit 2 ;; esac

for tool in "$POVRAY" oiiotool python3 timeout; do
    command -v "$tool" >/dev/null 2>&1 || { echo "povray_samples: $tool not found: skipped"; exit 77; }
done
[ -x "$CSGTRACE" ] || { echo "povray_samples: $CSGTRACE not built" >&2; exit 1; }
if [ ${#scenes[@]} -eq 0 ]; then
    mapfile -t scenes < <(dpkg -L povray-examples 2>/dev/null | grep '\.pov$' | sort)
    [ ${#scenes[@]} -gt 0 ] || { echo "povray_samples: povray-examples not installed: skipped"; exit 77; }
fi

rm -rf "$WORK"
mkdir -p "$WORK/results" || exit 1
# The writable copy of the samples (scenes outside the tree are run in place).
if [ -d "$SAMPLES" ]; then
    cp -r "$SAMPLES" "$WORK/tree" || exit 1
fi
TOL=0.013725490196 # 3.5/255: codes within 3 of each other

# Step 3 for one scene folder $1 (flat.pov written): the flat agreement.
compare_flat() {
    local dir=$1
    (cd "$dir" && timeout "$TIMEOUT" "$POVRAY" +Iflat.pov +Opov_flat.png +FN +W"$WIDTH" +H"$HEIGHT" \
        -D -A File_Gamma=1.0 -P) >"$dir/povray_flat.log" 2>&1 && [ -s "$dir/pov_flat.png" ] ||
        { echo "povray" >"$dir/flat_failed"; return; }
    timeout "$TIMEOUT" "$CSGTRACE" render "$dir/flat.pov" -o "$dir/ours_flat.exr" --mode serial \
        --width "$WIDTH" --height "$HEIGHT" >"$dir/render_flat.log" 2>&1 ||
        { echo "render" >"$dir/flat_failed"; return; }
    local bg
    bg=$(sed -n 's/^background { color rgb <\([^>]*\)>.*/\1/p' "$dir/flat.pov" | head -n 1 | tr -d ' ')
    python3 "$ROOT/tests/compare_images.py" "$dir/pov_flat.png" "$dir/ours_flat.exr" --name scene \
        --encoding-a linear --encoding-b linear --background "${bg:-0,0,0}" --min 0 \
        >"$dir/compare_flat.log" 2>&1 || echo "compare" >"$dir/flat_failed"
}

# One scene: $1 its number, $2 its path.
run_scene() {
    local dir scene=$2 run sdir base
    dir=$WORK/results/$(printf '%03d' "$1")
    mkdir -p "$dir"
    printf '%s' "$scene" >"$dir/scene"
    run=$scene
    case "$scene" in "$SAMPLES"/*) [ -d "$WORK/tree" ] && run=$WORK/tree/${scene#"$SAMPLES"/} ;; esac
    sdir=$(dirname "$run")
    base=$(basename "$run")
    if ! (cd "$sdir" && timeout "$TIMEOUT" "$CSGTRACE" check "$base" --width "$WIDTH" \
            --height "$HEIGHT") >"$dir/check.log" 2>"$dir/check.err"; then
        echo "check" >"$dir/failed"
        return
    fi
    # step 2: the full image
    if ! (cd "$sdir" && timeout "$TIMEOUT" "$CSGTRACE" render "$base" -o "$dir/ours.png" \
            --mode serial --width "$WIDTH" --height "$HEIGHT") >"$dir/render.log" 2>&1; then
        echo "render" >"$dir/failed"
        return
    fi
    if (cd "$sdir" && timeout "$TIMEOUT" "$POVRAY" +I"$base" +O"$dir/pov.png" +FN +W"$WIDTH" \
            +H"$HEIGHT" -D -A +L"$sdir" -P) >"$dir/povray.log" 2>&1 && [ -s "$dir/pov.png" ]; then
        python3 "$ROOT/tests/compare_images.py" "$dir/pov.png" "$dir/ours.png" --name scene \
            --encoding-a linear --encoding-b linear --background none --tolerance "$TOL" \
            --min 0 >"$dir/compare.log" 2>&1 || echo "compare" >"$dir/full_failed"
    else
        echo "povray" >"$dir/full_failed"
    fi
    # step 3: the flat image
    if (cd "$sdir" && timeout "$TIMEOUT" "$CSGTRACE" export "$base" --flat -o "$dir/flat.pov" \
            --width "$WIDTH" --height "$HEIGHT") >"$dir/export.log" 2>&1; then
        compare_flat "$dir"
    else
        echo "export" >"$dir/flat_failed"
    fi
}

n=0
for scene in "${scenes[@]}"; do
    n=$((n + 1))
    while [ "$(jobs -rp | wc -l)" -ge "$JOBS" ]; do
        wait -n
    done
    { run_scene "$n" "$scene"; printf '.' >&2; } &
done
wait
echo >&2

python3 "$ROOT/bench/povray_samples.py" "$WORK/results" "$OUT" "$MIN_AGREEMENT" "$WIDTH" "$HEIGHT"
