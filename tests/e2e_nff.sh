#!/usr/bin/env bash
# e2e_nff.sh — NFF scenes end to end, on the small files of tests/nff/
# (never ../shared/nff: CI has no such folder): the scene's resolution as
# the default image size, serial == homo == hetero bit for bit in float and
# double, `check` and `export` (the export parses again), and malformed
# files: exit 2, one `file:line:col: error:` line, no image.
set -u
source "$(dirname "$0")/lib_e2e.sh"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_pml=ob1
export POCL_CACHE_DIR=${POCL_CACHE_DIR:-$(pwd)/build/pocl-cache}
MPIRUN=(mpirun --oversubscribe --bind-to none -np 3)

render() { # render NAME MODE SCENE EXTRA... -> $T/NAME.exr, $T/NAME.json
    local name=$1 mode=$2 scene=$3
    shift 3
    if [ "$mode" = serial ]; then
        "$BIN" render "$scene" -o "$T/$name.exr" --mode serial --stats "$T/$name.json" "$@" >/dev/null 2>"$T/$name.err"
    else
        "${MPIRUN[@]}" "$BIN" render "$scene" -o "$T/$name.exr" --mode "$mode" \
            --stats "$T/$name.json" "$@" >/dev/null 2>"$T/$name.err"
    fi
}

# --- every mode, both precisions: the same image, at the file's resolution ---
for scene in tests/nff/*.nff; do
    n=$(basename "$scene" .nff)
    for prec in float double; do
        render "s_$n$prec" serial "$scene" --precision $prec --tile 16
        render "h_$n$prec" homo "$scene" --precision $prec --tile 16
        render "x_$n$prec" hetero "$scene" --precision $prec --tile 16
        if same "$T/s_$n$prec.exr" "$T/h_$n$prec.exr" && same "$T/s_$n$prec.exr" "$T/x_$n$prec.exr"; then
            ok "$n ($prec): serial == homo == hetero"
        else
            ko "$n ($prec): the modes differ"
        fi
    done
done
if json "$T/s_shapesfloat.json" "j['width'] == 80 and j['height'] == 60" &&
    json "$T/s_gearfloat.json" "j['width'] == 64 and j['height'] == 64"; then
    ok "resolution: the file's image size when none is given"
else
    ko "resolution: not the file's image size"
fi
render w serial tests/nff/shapes.nff --width 40
json "$T/w.json" "j['width'] == 40 and j['height'] == 30" &&
    ok "--width alone: the height keeps the file's aspect" || ko "--width alone: wrong height"

# --- check and export ---
if "$BIN" check tests/nff/shapes.nff >"$T/check.out" 2>&1 &&
    grep -q "polygon 2" "$T/check.out" && grep -q "at 80x60" "$T/check.out"; then
    ok "check: the NFF scene's summary at its own size"
else
    ko "check on an NFF scene"
fi
# runs of triangles (p 3, pp 3) of one material: one mesh each, each
# triangle still a primitive and a root of its own
if "$BIN" check tests/nff/terrain.nff >"$T/terrain.out" 2>&1 &&
    grep -q "^  sphere 1 mesh 3 (148 triangles)$" "$T/terrain.out" &&
    grep -q "^flat scene: 149 primitives in 149 roots," "$T/terrain.out" &&
    "$BIN" export tests/nff/terrain.nff -o "$T/terrain.pov" >/dev/null 2>&1 &&
    [ "$(grep -c "mesh {" "$T/terrain.pov")" = 3 ] &&
    [ "$(grep -c "triangle {" "$T/terrain.pov")" = 148 ]; then
    ok "check and export: 148 triangles in 3 runs are 3 meshes, 149 roots"
else
    ko "runs of triangles: $(head -c 300 "$T/terrain.out")"
fi
if "$BIN" export tests/nff/shapes.nff -o "$T/shapes.pov" >/dev/null 2>&1 &&
    "$BIN" check "$T/shapes.pov" >/dev/null 2>&1; then
    ok "export: the NFF scene as POV-Ray SDL that parses again"
else
    ko "export of an NFF scene"
fi

# --- malformed files: one message, exit 2, no image ---
bad() { # bad NAME TEXT PATTERN
    printf '%b' "$2" >"$T/$1.nff"
    "$BIN" render "$T/$1.nff" -o "$T/$1.png" >/dev/null 2>"$T/$1.err"
    local rc=$?
    if [ "$rc" = 2 ] && [ "$(wc -l <"$T/$1.err")" = 1 ] && grep -q "$3" "$T/$1.err" &&
        [ ! -e "$T/$1.png" ]; then
        ok "malformed NFF ($1): exit 2, one line: $(cat "$T/$1.err")"
    else
        ko "malformed NFF ($1): status $rc, message $(cat "$T/$1.err")"
    fi
}
bad word 'b 0 0 0\nv\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 45\nhither 1\nresolution 8 8\nsphere 0 0 0 1\n' \
    "word.nff:9:1: error: an NFF entity"
bad trunc 'b 0 0 0\np 4\n0 0 0\n1 0 0\n' "trunc.nff:5:1: error: a number (polygon vertex x y z) expected, got end of file"
bad count 'p 1e12\n' "count.nff:1:3: error: polygon vertex count must be"
bad noview 's 0 0 0 1\n' "noview.nff:2:1: error: no view"

# --- big files: one of 80 MiB reads (the SPD scaled up: tetra10 is 103 MB),
# one over 2 GiB (CSG_PARSE_MAX_FILE: csg_loc's int lines and columns) is
# refused before a byte is read (a sparse file: no disk taken) ---
{ cat tests/nff/shapes.nff; printf '#'; head -c $((80 << 20)) /dev/zero | tr '\0' x; echo; } \
    >"$T/big.nff"
render big serial "$T/big.nff" --width 40
render small serial tests/nff/shapes.nff --width 40
if [ -s "$T/big.exr" ] && same "$T/big.exr" "$T/small.exr"; then
    ok "an 80 MiB NFF file (a comment line of 80 MiB) renders as the small one"
else
    ko "an 80 MiB NFF file: $(cat "$T/big.err")"
fi
rm -f "$T/big.nff"
truncate -s $((2 << 30)) "$T/huge.nff"
"$BIN" render "$T/huge.nff" -o "$T/huge.png" >/dev/null 2>"$T/huge.err"
rc=$?
if [ "$rc" = 2 ] && [ "$(wc -l <"$T/huge.err")" = 1 ] && [ ! -e "$T/huge.png" ] &&
    grep -q "cannot read scene '.*huge.nff': larger than 2147483647 bytes" "$T/huge.err"; then
    ok "a file over 2 GiB: exit 2, $(cat "$T/huge.err")"
else
    ko "a file over 2 GiB: status $rc, $(cat "$T/huge.err")"
fi
rm -f "$T/huge.nff"

e2e_finish
