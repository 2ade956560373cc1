#!/usr/bin/env bash
# crosscheck_povray.sh — geometry cross-check of csgtrace against POV-Ray 3.7.
#
# For every scene (default: scenes/*.pov):
#   1. csgtrace export SCENE --flat -o flat.pov: the parsed scene written back
#      as POV-Ray SDL with every surface showing exactly its pigment colour
#      (finish { ambient 1 diffuse 0 }, ambient_light 1, max_trace_level 1,
#      no filter/transmit; csg/export_pov.h);
#   2. POV-Ray 3.7 renders flat.pov, no antialiasing, File_Gamma=1.0: the PNG
#      holds round(255 * linear colour) (measured: without File_Gamma POV-Ray
#      3.7 encodes its PNGs with the sRGB curve, not a 2.2 power);
#   3. csgtrace renders flat.pov (--mode serial) to EXR (linear floats);
#   4. tests/compare_images.py: a pixel agrees when both call it background or
#      object alike and the colours agree within 2.5/255; the scene fails below
#      99.5% agreement.
# A scene whose first lines say `// crosscheck: full [MIN]` (tests/povray/:
# shading constructs a flat export cannot show: gamma, normals, fog,
# lights, layered textures ...) is instead rendered as written by both
# programs to PNG (POV-Ray's default gamma handling, its folder as the
# library path) and compared by colour alone: a pixel agrees when every
# channel is within 3/255; the scene fails below MIN % (default
# MIN_AGREEMENT).
# Both renderers sample pixel (x, y) at the pixel centre,
# x0 = (x + 0.5)/W - 0.5, y0 = 0.5 - (y + 0.5)/H (checked against POV-Ray).
# The image is 160 pixels wide; its height follows the "Framed for WxH" line
# of the scene's header comment (4:3 when there is none), or for an NFF
# scene (.nff: exported as POV-Ray SDL first, step 1) its `resolution`.
#
# Usage: tests/crosscheck_povray.sh [--keep DIR] [SCENE.pov|SCENE.nff ...]
# Environment: CSGTRACE (build/csgtrace), POVRAY (povray), WIDTH (160),
#   MIN_AGREEMENT (99.5), PRECISION (float|double, default: csgtrace's).
# Exit status: 0 every scene passed, 1 some failed, 77 POV-Ray or oiiotool
# missing (skipped), 2 bad arguments.
set -u

ROOT=$(cd "$(dirname "$0")/.." && pwd)
CSGTRACE=${CSGTRACE:-$ROOT/build/csgtrace}
POVRAY=${POVRAY:-povray}
WIDTH=${WIDTH:-160}
MIN_AGREEMENT=${MIN_AGREEMENT:-99.5}
PRECISION=${PRECISION:-}
COMPARE=$ROOT/tests/compare_images.py

keep=""
scenes=()
while [ $# -gt 0 ]; do
    case "$1" in
        --keep) [ $# -ge 2 ] || { echo "crosscheck: --keep needs a folder" >&2; exit 2; }
                keep=$2; shift 2 ;;
        -h|--help) sed -n '2,/^set -u/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
        -*) echo "crosscheck: unknown option $1" >&2; exit 2 ;;
        *) scenes+=("$1"); shift ;;
    esac
done
[ ${#scenes[@]} -gt 0 ] || scenes=("$ROOT"/scenes/*.pov)

for tool in "$POVRAY" oiiotool python3; do
    if ! command -v "$tool" >/dev/null 2>&1; then
        echo "crosscheck: $tool not found (make deps installs povray and openimageio-tools): skipped"
        exit 77
    fi
done
if [ ! -x "$CSGTRACE" ]; then
    echo "crosscheck: $CSGTRACE not built (make build/csgtrace)" >&2
    exit 1
fi

if [ -n "$keep" ]; then
    work=$keep
    mkdir -p "$work" || exit 1
else
    work=$(mktemp -d "${TMPDIR:-/tmp}/crosscheck.XXXXXX") || exit 1
    trap 'rm -rf "$work"' EXIT
fi

# The height for WIDTH from the scene's "Framed for WxH" comment (4:3 default).
scene_height() {
    local fw fh
    if [ "${1##*.}" = nff ]; then
        read -r fw fh < <(sed -n 's/^resolution  *\([0-9][0-9]*\)  *\([0-9][0-9]*\).*/\1 \2/p' "$1" | head -n 1)
    else
        read -r fw fh < <(sed -n 's/.*[Ff]ramed for \([0-9][0-9]*\)x\([0-9][0-9]*\).*/\1 \2/p' "$1" | head -n 1)
    fi
    if [ -z "${fw:-}" ] || [ -z "${fh:-}" ] || [ "$fw" -eq 0 ]; then
        fw=4; fh=3
    fi
    echo $(( (WIDTH * fh + fw / 2) / fw ))
}

# The background of the flat export as linear "r,g,b".
flat_background() {
    local bg
    bg=$(sed -n 's/^background { color rgb <\([^>]*\)>.*/\1/p' "$1" | head -n 1 | tr -d ' ')
    echo "${bg:-0,0,0}"
}

# Prints the last lines of a log, indented, after a failure.
show_log() {
    tail -n "${2:-8}" "$1" | sed 's/^/    | /'
}

# The full comparison of one scene (see above): $1 scene, $2 name, $3 its
# folder of results, $4 height, $5 the least agreement.
compare_full() {
    local scene=$1 name=$2 dir=$3 height=$4 min=$5 sdir
    sdir=$(cd "$(dirname "$scene")" && pwd)
    cp "$scene" "$dir/scene.pov"
    if ! (cd "$dir" && "$POVRAY" +Iscene.pov +Opov.png +FN +W"$WIDTH" +H"$height" -D -A \
            +L"$sdir" -P) >"$dir/povray.log" 2>&1 || [ ! -s "$dir/pov.png" ]; then
        echo "$name: FAILED (povray)"
        show_log "$dir/povray.log" 12
        return 1
    fi
    if ! "$CSGTRACE" render "$scene" -o "$dir/ours.png" --mode serial \
            --width "$WIDTH" --height "$height" "${prec[@]}" >"$dir/render.log" 2>&1; then
        echo "$name: FAILED (csgtrace render)"
        show_log "$dir/render.log"
        return 1
    fi
    python3 "$COMPARE" "$dir/pov.png" "$dir/ours.png" --name "$name (full)" \
        --encoding-a linear --encoding-b linear --background none --tolerance 0.013725490196 \
        --min "$min" --diff "$dir/diff.ppm"
}

passed=0
failed=0
for scene in "${scenes[@]}"; do
    name=$(basename "$scene")
    name=${name%.*}
    dir=$work/$name
    mkdir -p "$dir"
    height=$(scene_height "$scene")
    prec=()
    [ -n "$PRECISION" ] && prec=(--precision "$PRECISION")
    full=$(head -n 5 "$scene" | sed -n 's|^// *crosscheck: *full *\([0-9.]*\).*|full \1|p' | head -n 1)
    if [ -n "$full" ]; then
        min=${full#full }
        if compare_full "$scene" "$name" "$dir" "$height" "${min:-$MIN_AGREEMENT}"; then
            passed=$((passed + 1))
        else
            failed=$((failed + 1))
        fi
        continue
    fi

    if ! "$CSGTRACE" export "$scene" --flat -o "$dir/flat.pov" >"$dir/export.log" 2>&1; then
        echo "$name: FAILED (csgtrace export)"
        show_log "$dir/export.log"
        failed=$((failed + 1))
        continue
    fi
    if ! (cd "$dir" && "$POVRAY" +Iflat.pov +Opov.png +FN +W"$WIDTH" +H"$height" -D -A \
            File_Gamma=1.0 -P) >"$dir/povray.log" 2>&1 || [ ! -s "$dir/pov.png" ]; then
        echo "$name: FAILED (povray)"
        show_log "$dir/povray.log" 12
        failed=$((failed + 1))
        continue
    fi
    if ! "$CSGTRACE" render "$dir/flat.pov" -o "$dir/ours.pfm" --mode serial \
            --width "$WIDTH" --height "$height" "${prec[@]}" >"$dir/render.log" 2>&1; then
        echo "$name: FAILED (csgtrace render)"
        show_log "$dir/render.log"
        failed=$((failed + 1))
        continue
    fi
    if python3 "$COMPARE" "$dir/pov.png" "$dir/ours.pfm" --name "$name" \
            --encoding-a linear --encoding-b linear \
            --background "$(flat_background "$dir/flat.pov")" \
            --min "$MIN_AGREEMENT" --diff "$dir/diff.ppm"; then
        passed=$((passed + 1))
    else
        failed=$((failed + 1))
    fi
done

echo "$passed passed, $failed failed"
[ -n "$keep" ] && echo "crosscheck: images and logs kept in $work"
[ "$failed" -eq 0 ]
