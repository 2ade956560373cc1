#!/usr/bin/env bash
# bench/povray_samples.sh — csgtrace on the sample scenes that ship with
# POV-Ray 3.7 (Debian's povray-examples): the roadmap of what to support next.
#
#   bench/povray_samples.sh [--out FILE.md] [SCENE.pov ...]
#
# For every scene (default: every .pov of povray-examples):
#   1. csgtrace check SCENE (WIDTH x HEIGHT, clock 0, the standard include
#      library): parses or not; when not, the first unsupported construct its
#      message names (or the error);
#   2. a scene that parses: csgtrace export --flat (every surface shows its
#      pigment), POV-Ray 3.7 renders the flat scene (-A, File_Gamma 1),
#      csgtrace renders it (serial, EXR), and tests/compare_images.py gives
#      the share of pixels that agree (hit/miss alike, colours within
#      2.5/255), as tests/crosscheck_povray.sh does;
#   3. bench/povray_samples.py writes the table (scene, status, first
#      unsupported construct, agreement %) and the counts by construct into
#      FILE.md (default bench/POVRAY_SAMPLES.md).
# A scene "renders" when it parses, renders and agrees on >= MIN_AGREEMENT %
# (default 99) of its pixels.
#
# Nothing read from a scene or an argument is pasted into code: each scene's
# results are files in its own folder, which the Python report reads as
# data.
# Environment: CSGTRACE (build/csgtrace), POVRAY (povray), WIDTH (160),
#   HEIGHT (120), MIN_AGREEMENT (99), TIMEOUT (seconds a step, 120),
#   BENCH_WORK (the folder of the per-scene results, build/bench/samples).
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
WORK=${BENCH_WORK:-$ROOT/build/bench/samples}
OUT=$ROOT/bench/POVRAY_SAMPLES.md

scenes=()
while [ $# -gt 0 ]; do
    case "$1" in
        --out) [ $# -ge 2 ] || { echo "povray_samples: --out needs a file" >&2; exit 2; }
               OUT=$2; shift 2 ;;
        -h|--help) sed -n '2,/^set -u/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
        -*) echo "povray_samples: unknown option $1" >&2; exit 2 ;;
        *) scenes+=("$1"); shift ;;
    esac
done

for tool in "$POVRAY" oiiotool python3 timeout; do
    command -v "$tool" >/dev/null 2>&1 || { echo "povray_samples: $tool not found: skipped"; exit 77; }
done
[ -x "$CSGTRACE" ] || { echo "povray_samples: $CSGTRACE not built" >&2; exit 1; }
if [ ${#scenes[@]} -eq 0 ]; then
    mapfile -t scenes < <(dpkg -L povray-examples 2>/dev/null | grep '\.pov$' | sort)
    [ ${#scenes[@]} -gt 0 ] || { echo "povray_samples: povray-examples not installed: skipped"; exit 77; }
fi

rm -rf "$WORK"
mkdir -p "$WORK" || exit 1

# Step 2 for one scene folder $1 (flat.pov written): the agreement line.
compare_flat() {
    local dir=$1
    (cd "$dir" && timeout "$TIMEOUT" "$POVRAY" +Iflat.pov +Opov.png +FN +W"$WIDTH" +H"$HEIGHT" \
        -D -A File_Gamma=1.0 -P) >"$dir/povray.log" 2>&1 && [ -s "$dir/pov.png" ] ||
        { echo "povray" >"$dir/failed"; return; }
    timeout "$TIMEOUT" "$CSGTRACE" render "$dir/flat.pov" -o "$dir/ours.exr" --mode serial \
        --width "$WIDTH" --height "$HEIGHT" >"$dir/render.log" 2>&1 ||
        { echo "render" >"$dir/failed"; return; }
    local bg
    bg=$(sed -n 's/^background { color rgb <\([^>]*\)>.*/\1/p' "$dir/flat.pov" | head -n 1 | tr -d ' ')
    python3 "$ROOT/tests/compare_images.py" "$dir/pov.png" "$dir/ours.exr" --name scene \
        --encoding-a linear --encoding-b linear --background "${bg:-0,0,0}" --min 0 \
        >"$dir/compare.log" 2>&1 || echo "compare" >"$dir/failed"
}

n=0
for scene in "${scenes[@]}"; do
    n=$((n + 1))
    dir=$WORK/$(printf '%03d' "$n")
    mkdir -p "$dir"
    printf '%s' "$scene" >"$dir/scene"
    if ! timeout "$TIMEOUT" "$CSGTRACE" check "$scene" --width "$WIDTH" --height "$HEIGHT" \
            >"$dir/check.log" 2>"$dir/check.err"; then
        echo "check" >"$dir/failed"
        continue
    fi
    if ! timeout "$TIMEOUT" "$CSGTRACE" export "$scene" --flat -o "$dir/flat.pov" \
            --width "$WIDTH" --height "$HEIGHT" >"$dir/export.log" 2>&1; then
        echo "export" >"$dir/failed"
        continue
    fi
    compare_flat "$dir"
    printf '.' >&2
done
echo >&2

python3 "$ROOT/bench/povray_samples.py" "$WORK" "$OUT" "$MIN_AGREEMENT" "$WIDTH" "$HEIGHT"
