#!/usr/bin/env bash
# e2e_cli.sh — the command line contract (docs/cli.md), end to end:
# exit statuses (0 ok, 2 bad input, 1 other failure), one-line
# `file:line:col: error:` messages, no output file left behind on failure,
# image formats by extension, `check` and `export`.
set -u
source "$(dirname "$0")/lib_e2e.sh"

# expect STATUS DESCRIPTION CMD...: runs CMD, checks its exit status.
expect() {
    local want=$1 what=$2
    shift 2
    "$@" >"$T/out" 2>"$T/err"
    local got=$?
    if [ "$got" -eq "$want" ]; then ok "$what (exit $got)"; else
        ko "$what: exit $got, wanted $want; stderr: $(head -c 300 "$T/err")"
    fi
}

# errmsg REGEX DESCRIPTION: the last stderr is one line matching REGEX.
errmsg() {
    local lines
    lines=$(wc -l <"$T/err")
    if [ "$lines" -eq 1 ] && grep -Eq "$1" "$T/err"; then ok "$2"; else
        ko "$2: stderr was: $(head -c 300 "$T/err")"
    fi
}

cat >"$T/good.pov" <<'POV'
camera { location <0, 0, -4> look_at 0 }
light_source { <2, 4, -3> color rgb 1 }
sphere { 0, 1 pigment { color rgb <1, 0.5, 0.2> } }
POV
printf 'sphere { 0, 1\n  pigment { color rgb 1 }\n  torus { 1, 0.2 }\n}\n' >"$T/bad.pov"
printf 'sphere { <0,0,0>, -1 }\n' >"$T/negative.pov"
printf 'sphere { 0, 1\n  scale 1e200 scale 1e200 }\n' >"$T/overflow.pov"
printf 'sphere { 0, 1\n  pigment { bozo noise_generator 4 } }\n' >"$T/noisegen.pov"
printf 'sphere { 0, 1\n  pigment { wood turbulence 0.1 octaves -1 } }\n' >"$T/octaves.pov"

# --- arguments ---
expect 2 "no command" "$BIN"
expect 2 "unknown command" "$BIN" frobnicate x.pov
expect 2 "render without -o" "$BIN" render "$T/good.pov"
expect 2 "bad --width" "$BIN" render "$T/good.pov" -o "$T/x.png" --width 0
errmsg '^csgtrace: error: --width expects' "bad --width message"
expect 2 "bad --mode" "$BIN" render "$T/good.pov" -o "$T/x.png" --mode fast
expect 2 "bad --precision" "$BIN" render "$T/good.pov" -o "$T/x.png" --precision half
expect 2 "bad --max-rays-per-pixel" "$BIN" render "$T/good.pov" -o "$T/x.png" --max-rays-per-pixel 0
expect 2 "unknown option" "$BIN" render "$T/good.pov" -o "$T/x.png" --frobnicate
expect 2 "bad --store-threads" "$BIN" render "$T/good.pov" -o "$T/x.png" --store-threads 9
errmsg '^csgtrace: error: --store-threads expects a whole number from 1 to 8' "bad --store-threads message"
expect 0 "--help" "$BIN" --help

# --- bad scenes: exit 2, one file:line:col message, no output ---
expect 2 "missing scene file" "$BIN" render "$T/none.pov" -o "$T/x.png"
errmsg 'none.pov' "missing scene file message names the file"
expect 2 "unsupported construct" "$BIN" render "$T/bad.pov" -o "$T/bad.png"
errmsg "^$T/bad.pov:3:3: error: .*torus" "unsupported construct message with line:col"
[ ! -e "$T/bad.png" ] && ok "no image after a scene error" || ko "image written after a scene error"
expect 2 "negative radius" "$BIN" check "$T/negative.pov"
errmsg "^$T/negative.pov:1:[0-9]+: error: " "negative radius message"
# a combined transform beyond double's range is an error, not a vanished object
expect 2 "overflowing transform" "$BIN" check "$T/overflow.pov"
errmsg "^$T/overflow.pov:1:1: error: .*overflows" "overflowing transform message"
expect 2 "unknown noise_generator" "$BIN" render "$T/noisegen.pov" -o "$T/noise.png"
errmsg "^$T/noisegen.pov:2:34: error: noise_generator must be 0, 1, 2 or 3, got 4" \
    "unknown noise_generator message with line:col"
[ ! -e "$T/noise.png" ] && ok "no image after a noise_generator error" || ko "image written"
expect 2 "negative octaves" "$BIN" check "$T/octaves.pov"
errmsg "^$T/octaves.pov:2:41: error: octaves must be from 1 to 10, got -1" "negative octaves message"

# Temporary files cannot be planted: links at the names a render, gen or
# --stats once used (beside the output, the process id in the name) are
# never followed, and the victim they point to keeps its content.
P=$(mktemp -d "${TMPDIR:-/tmp}/csgtrace-plant.XXXXXX")
mkdir -p "$P/plant"
printf 'precious\n' >"$P/victim"
pid_next=$(sh -c 'echo $$')
for p in $(seq "$pid_next" $((pid_next + 300))); do
    ln -sf "$P/victim" "$P/plant/.out.png.tmp$p.png"
    ln -sf "$P/victim" "$P/plant/out.png.tmp$p"
    ln -sf "$P/victim" "$P/plant/gen.pov.tmp$p"
done
"$BIN" render "$T/good.pov" -o "$P/plant/out.png" --width 16 --height 12 --mode serial \
    --stats "$P/plant/out.json" >/dev/null 2>&1
"$BIN" gen spheres --count 3 --occupancy 0.3 --seed 1 --width 32 --height 32 \
    -o "$P/plant/gen.pov" >/dev/null 2>&1
if [ "$(cat "$P/victim")" = precious ] && [ -s "$P/plant/out.png" ] && [ ! -L "$P/plant/out.png" ] &&
    [ -s "$P/plant/out.json" ] && [ -s "$P/plant/gen.pov" ] && [ ! -L "$P/plant/gen.pov" ]; then
    ok "planted links at the old temporary names: not followed, outputs written"
else
    ko "planted links: the victim holds '$(head -c 40 "$P/victim")'"
fi
want_mode=$(printf '%o' $((0666 & ~0$(umask))))
modes="$(stat -c %a "$P/plant/out.png" "$P/plant/out.json" "$P/plant/gen.pov" 2>/dev/null | sort -u)"
if [ "$modes" = "$want_mode" ]; then
    ok "image, stats and scene have fopen's mode under this umask ($want_mode)"
else
    ko "output modes '$modes', wanted $want_mode (umask $(umask))"
fi
# (regular files only: the planted links' own names match the pattern
# where the process ids have 3 digits, as on a fresh machine)
left=$(find "$P/plant" -maxdepth 1 -type f -printf '%f\n' |
    grep -E '\.[A-Za-z0-9]{6}(\.png)?$|tmp\.[A-Za-z0-9]{6}$')
if [ -n "$left" ]; then
    ko "a temporary file was left behind: $(echo "$left" | head -3)"
else
    ok "no temporary file left behind"
fi
rm -rf "$P"

# a colour of 1e38 under a bright light, in double: the EXR holds finite
# values (saturated at float's largest), never an infinity
cat >"$T/huge_colour.pov" <<'POV'
camera { location <0, 0, -4> look_at 0 }
light_source { <1, 1, -3> color rgb 100 }
sphere { 0, 1 pigment { color rgb 1e38 } }
POV
"$BIN" render "$T/huge_colour.pov" -o "$T/huge_colour.exr" --precision double --width 8 \
    --height 8 >/dev/null 2>&1
if oiiotool --stats "$T/huge_colour.exr" 2>/dev/null | grep -q 'InfCount: 0 0 0' &&
    oiiotool --stats "$T/huge_colour.exr" 2>/dev/null | grep -q 'NanCount: 0 0 0'; then
    ok "a colour of 1e38 in double: no Inf or NaN pixel"
else
    ko "a colour of 1e38 in double: $(oiiotool --stats "$T/huge_colour.exr" 2>&1 | grep -i 'count' | head -2)"
fi
rm -f "$T/huge_colour.exr"

# no output may overwrite the scene or another output
cp "$T/good.pov" "$T/self.pov"
expect 2 "-o naming the scene" "$BIN" render "$T/self.pov" -o "$T/self.pov" --width 8 --height 6
errmsg "^csgtrace: error: the output \(-o\) and the scene are the same file" "-o naming the scene: message"
expect 2 "--stats naming the image" "$BIN" render "$T/self.pov" -o "$T/same.png" --stats "$T/./same.png"
expect 2 "--stats naming the scene (another path)" "$BIN" render "$T/self.pov" -o "$T/o.png" \
    --stats "$T/../$(basename "$T")/self.pov"
cmp -s "$T/good.pov" "$T/self.pov" && [ ! -e "$T/same.png" ] && [ ! -e "$T/o.png" ] &&
    ok "refused outputs: the scene unchanged, nothing written" || ko "a refused output wrote something"
rm -f "$T/self.pov"

# no output may overwrite a file the scene includes (found while parsing)
printf '#include "part.inc"\n' >"$T/inc.pov"
cat "$T/good.pov" >"$T/part.inc"
expect 2 "-o naming an include" "$BIN" render "$T/inc.pov" -o "$T/part.inc" --width 8 --height 6
errmsg "^csgtrace: error: the output \(-o\) is '.*part.inc', a file the scene includes" \
    "-o naming an include: the message"
expect 2 "--stats naming an include (another path)" "$BIN" render "$T/inc.pov" -o "$T/inc.png" \
    --width 8 --height 6 --stats "$T/../$(basename "$T")/part.inc"
expect 2 "--tile-log naming an include" "$BIN" render "$T/inc.pov" -o "$T/inc.png" \
    --width 8 --height 6 --tile-log "$T/part.inc"
cmp -s "$T/good.pov" "$T/part.inc" && [ ! -e "$T/inc.png" ] &&
    ok "outputs naming an include: it is unchanged, nothing written" ||
    ko "an output naming an include wrote something"
rm -f "$T/inc.pov" "$T/part.inc"

# a stats file that cannot be written fails the render, and leaves no image;
# a folder that is not there is found before the first tile (it once was
# after the last, and the finished image was deleted): one line, no journal
expect 1 "unwritable --stats" "$BIN" render "$T/good.pov" -o "$T/nostats.png" --width 8 --height 6 \
    --stats "$T/no-such-folder/s.json"
[ ! -e "$T/nostats.png" ] && ok "unwritable --stats: no image left" || ko "unwritable --stats left the image"
errmsg "^csgtrace: error: cannot write the stats \(--stats\) '$T/no-such-folder/s.json': its folder $T/no-such-folder: No such file or directory$" \
    "unwritable --stats: refused before the first tile, naming its folder"
[ ! -e "$T/nostats.png.journal" ] && ok "unwritable --stats: no journal (no tile rendered)" ||
    ko "unwritable --stats: a journal was made"
# ... one that fails as it is written (here: over the file-size limit) keeps
# the finished tiles, and the line says so: --resume with a log path that
# works writes both without rendering a tile again
expect 1 "a tile log over the file-size limit" bash -c 'ulimit -f 4 && exec "$@"' _ "$BIN" render \
    "$T/good.pov" -o "$T/nostats.png" --width 8 --height 6 --tile 1 --tile-log "$T/log.jsonl"
[ ! -e "$T/nostats.png" ] && ok "a tile log over the limit: no image left" ||
    ko "a tile log over the limit left the image"
grep -q "finished tiles are kept in $T/nostats.png.journal" "$T/err" &&
    ok "a tile log over the limit: the journal kept, and named" ||
    ko "a tile log over the limit: no journal named: $(head -c 300 "$T/err")"
expect 0 "a tile log over the limit, then --resume" "$BIN" render "$T/good.pov" -o "$T/nostats.png" \
    --width 8 --height 6 --tile 1 --stats "$T/resumed.json" --tile-log "$T/log.jsonl" --resume
json "$T/resumed.json" "j['tiles_resumed'] == j['tiles_total'] and j['tiles_rendered'] == 0" &&
    [ -f "$T/nostats.png" ] && [ -s "$T/log.jsonl" ] && [ ! -e "$T/nostats.png.journal" ] &&
    ok "--resume after the tile log failed: every tile resumed, image and log written, journal gone" ||
    ko "--resume after the tile log failed: $(cat "$T/resumed.json" 2>/dev/null | head -c 300)"
rm -f "$T/nostats.png" "$T/resumed.json" "$T/log.jsonl"

# a render that cannot fit says so before allocating anything (here under a
# 1 GiB address-space limit: 12000x12000 needs 1.6 GiB), and writes nothing
expect 1 "render beyond the memory it may allocate" \
    bash -c 'ulimit -v 1048576 && exec "$@"' _ "$BIN" render "$T/good.pov" -o "$T/huge.png" \
    --width 12000 --height 12000 --mode serial
errmsg "^csgtrace: error: a 12000x12000 render in serial mode needs about 2.03 GiB of memory .*the tiles' bookkeeping 19.45 MiB\); .*may allocate" \
    "memory estimate message"
if [ -e "$T/huge.png" ] || ls "$T"/.huge* >/dev/null 2>&1; then ko "memory refusal wrote a file"; else
    ok "memory refusal wrote no file"
fi
# hetero adds the hit records (8 bytes a pixel in float) and one slice's
# OpenCL buffers; the PNG encoder holds 64 rows, never a copy of the image
expect 1 "hetero render beyond the memory it may allocate" \
    bash -c 'ulimit -v 1048576 && exec "$@"' _ "$BIN" render "$T/good.pov" -o "$T/huge.png" \
    --width 12000 --height 12000 --mode hetero
errmsg "^csgtrace: error: a 12000x12000 render in hetero mode needs about 3.11 GiB of memory \(the image 1.61 GiB, its encoding 411.99 MiB, the hit records of the OpenCL pass 1.08 GiB, the tiles' bookkeeping 22.66 MiB\)" \
    "hetero memory estimate message"

# the tiles' bookkeeping is in the estimate (~100 bytes a tile: --tile 1 at
# 2000x2000 once peaked at 458 MB against an estimate of 48 MB): the peak
# of a --tile 1 render is within the estimate (and a little for the
# process itself), and the estimate counts at least 100 bytes a tile
python3 - "$BIN" "$T/good.pov" "$T/tiles1.png" "$T/tiles1.json" >"$T/out" 2>"$T/err" <<'EOF'
import json, resource, subprocess, sys
binary, scene, out, stats = sys.argv[1:]
w = h = 500
subprocess.run([binary, "render", scene, "--width", str(w), "--height", str(h), "--tile", "1",
                "-o", out, "--stats", stats], check=True, stdout=subprocess.DEVNULL)
peak = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss * 1024
est = json.load(open(stats)).get("memory_estimate", 0)
image = w * h * 3 * 4
print(f"peak {peak >> 20} MiB, estimate {est >> 20} MiB")
sys.exit(0 if peak <= est + (32 << 20) and est >= image + w * h * 100 else 1)
EOF
[ $? = 0 ] && ok "--tile 1: the peak within the estimate, which counts the tiles ($(cat "$T/out"))" ||
    ko "--tile 1: the peak beyond the estimate: $(cat "$T/out" "$T/err" | head -c 300)"
rm -f "$T/tiles1.png" "$T/tiles1.json"

# more tiles than the counts can hold (2^32 at --tile 1, 65536 x 65536): a bad
# request, exit 2, before any allocation (the tile count overflowed int)
expect 2 "2^32 tiles" "$BIN" render "$T/good.pov" -o "$T/huge.png" --width 65536 --height 65536 \
    --tile 1
errmsg "^csgtrace: error: a 65536x65536 image in tiles of 1x1 pixels is 4294967296 tiles, more than a render may have \(134217727\): use a larger --tile$" \
    "2^32 tiles: the message"

# --- a failed render never leaves a partial file: existing output untouched ---
echo "previous" >"$T/keep.png"
expect 2 "scene error keeps an existing output" "$BIN" render "$T/bad.pov" -o "$T/keep.png"
[ "$(cat "$T/keep.png")" = previous ] && ok "existing output untouched" || ko "existing output was modified"
expect 1 "unknown image format" "$BIN" render "$T/good.pov" -o "$T/x.unknownformat" --width 8 --height 6
[ -z "$(ls -A "$T" | grep -v -e '\.pov$' -e keep.png -e '^out$' -e '^err$')" ] && ok "no stray temporary files" ||
    ko "stray files: $(ls -A "$T")"

# --- formats by extension ---
for ext in png exr tif ppm; do
    expect 0 "render .$ext" "$BIN" render "$T/good.pov" -o "$T/img.$ext" --width 32 --height 24
    if oiiotool --info "$T/img.$ext" 2>/dev/null | grep -q "32 x  *24"; then ok ".$ext is a 32x24 image"; else
        ko ".$ext is not a 32x24 image: $(oiiotool --info "$T/img.$ext" 2>&1 | head -c 200)"
    fi
done

# --- PNG compression ($CSGTRACE_PNG_LEVEL): other bytes, the same pixels ---
for level in 0 9; do
    expect 0 "render .png at CSGTRACE_PNG_LEVEL=$level" env CSGTRACE_PNG_LEVEL=$level \
        "$BIN" render "$T/good.pov" -o "$T/level$level.png" --width 32 --height 24
    same "$T/img.png" "$T/level$level.png" && ok "the same pixels at level $level" ||
        ko "CSGTRACE_PNG_LEVEL=$level changed the pixels"
done
rm -f "$T"/level*.png

# --- the image module: only a process that reads an image or writes one other
#     than PNG or PPM loads OpenImageIO (build/csgtrace-image.so); without it,
#     one message, exit 1 ---
if ldd "$BIN" | grep -q OpenImageIO; then ko "the program links OpenImageIO"; else
    ok "the program does not link OpenImageIO"
fi
NOMOD=$T/none/csgtrace-image.so
expect 0 "check needs no image module" env CSGTRACE_IMAGE_MODULE="$NOMOD" "$BIN" check "$T/good.pov"
expect 1 "render without the image module" env CSGTRACE_IMAGE_MODULE="$NOMOD" \
    "$BIN" render "$T/good.pov" -o "$T/nomod.exr" --width 8 --height 6
errmsg "^csgtrace: error: .*image module.*none/csgtrace-image.so" "missing module message names it"
expect 1 "render with a broken image module" env CSGTRACE_IMAGE_MODULE="$T/good.pov" \
    "$BIN" render "$T/good.pov" -o "$T/nomod.exr" --width 8 --height 6
errmsg "^csgtrace: error: .*image module.*good.pov" "broken module message names it"
[ ! -e "$T/nomod.exr" ] && ok "no image without a module" || ko "image written without a module"
# PNG and PPM need no module (host/output/stream.c; tests/e2e_image.sh)
expect 0 "render to PNG without the image module" env CSGTRACE_IMAGE_MODULE="$NOMOD" \
    "$BIN" render "$T/good.pov" -o "$T/nomod.png" --width 8 --height 6
rm -f "$T/nomod.png"
mkdir -p "$T/moved"
cp "$BIN" "$(dirname "$BIN")/csgtrace-image.so" "$T/moved/"
LD_DEBUG=files "$T/moved/csgtrace" render "$T/good.pov" -o "$T/moved.exr" --width 8 --height 6 \
    >/dev/null 2>"$T/err"
grep -q "file=$T/moved/csgtrace-image.so " "$T/err" && ok "a moved program loads the module beside it" ||
    ko "a moved program did not load $T/moved/csgtrace-image.so"
rm -rf "$T/moved" "$T/moved.exr"

# --- check and export ---
expect 0 "check" "$BIN" check "$T/good.pov"
grep -qi "sphere" "$T/out" && ok "check summary lists the sphere" || ko "check summary: $(head -c 300 "$T/out")"
grep -qx "specialised: sphere; no csg (the scene also: no transforms; opaque; no reflection)" "$T/out" &&
    ok "check: the specialised line of a lone opaque sphere" ||
    ko "check specialised line: $(grep specialised "$T/out")"
cat >"$T/rich.pov" <<'POV'
camera { location <0, 0, -4> look_at 0 }
light_source { <2, 4, -3> color rgb 1 shadowless }
difference { box { -1, 1 } sphere { 0, 1.2 } rotate y * 30
  pigment { color rgbf <1, 1, 1, 0.5> } finish { reflection 0.3 } }
cylinder { <0, -1, 0>, <0, 1, 0>, 0.2 no_shadow pigment { color rgb 1 } }
triangle { <0, 0, 0>, <1, 0, 0>, <0, 1, 0> pigment { color rgb 1 } }
POV
expect 0 "check (CSG, transforms, glass, mirror, triangle)" "$BIN" check "$T/rich.pov"
grep -qx "specialised: sphere box cone triangle; csg (the scene also: transforms; transparent; reflective; no_shadow objects; shadowless lights)" "$T/out" &&
    ok "check: the specialised line names every feature" ||
    ko "check specialised line: $(grep specialised "$T/out")"
expect 0 "export" "$BIN" export "$T/good.pov" -o "$T/exported.pov"
expect 0 "exported scene parses again" "$BIN" check "$T/exported.pov"

# --- the test hooks are not in the installed program (comm/test_hooks.h) ---
if grep -qa 'CSGTRACE_TEST_' "$BIN"; then
    ko "$BIN holds a CSGTRACE_TEST_ hook's name"
elif ! grep -qa 'CSGTRACE_TEST_FAIL_WORKER' "$HOOKED_BIN"; then
    ko "$HOOKED_BIN lacks the hooks (the check above would prove nothing)"
else
    ok "the test hooks are in $HOOKED_BIN only, not in $BIN"
fi
(
    mpi_sandbox
    CSGTRACE_TEST_FAIL_WORKER=1 mpirun -np 2 -x CSGTRACE_TEST_FAIL_WORKER "$BIN" render "$T/good.pov" \
        -o "$T/hooked.png" --mode homo --width 8 --height 6 >/dev/null 2>&1
) && [ -s "$T/hooked.png" ] && ok "$BIN ignores CSGTRACE_TEST_FAIL_WORKER" ||
    ko "$BIN obeyed (or failed under) CSGTRACE_TEST_FAIL_WORKER"

e2e_finish
