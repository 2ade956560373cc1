#!/usr/bin/env bash
# e2e_image.sh — PNG, PPM and PFM written by csgtrace itself, band by band
# (host/output/stream.c):
#   - on every example scene and a random one (80x60): the PNG holds the
#     pixels of the file the image module writes ($CSGTRACE_IMAGE_WRITER=oiio,
#     idiff), and is a valid PNG to it; the PPM of one scene is the module's
#     byte for byte (a PPM has no freedom); the PFM (linear floats) of a
#     random scene holds the EXR's pixels (idiff reads both);
#   - a render to PNG, PPM or PFM maps neither csgtrace-image.so nor OpenImageIO
#     (LD_DEBUG=files) and works without the module; to EXR it needs it, and
#     says so;
#   - EXR and TIFF go to the module band by band too (every band through
#     the stream, the render's pixels), and one over the file-size limit on
#     the way exits 1 with the limit named and leaves no image nor temporary
#     file (its journal keeps the finished tiles);
#   - a folder in a PNG's place: refused before the first tile (exit 1,
#     the output named), nothing made, no journal, no temporary file (a
#     write that fails at the end: e2e_resume.sh's file-size limit).
# Usage: tests/e2e_image.sh   (CSGTRACE_BIN: the binary, default build/csgtrace)
set -u
source "$(dirname "$0")/lib_e2e.sh"

SZ=(--width 80 --height 60 --mode serial)

# failed_leaving DIR LEFT PATTERN WHAT CMD...: CMD exits 1 with a line of
# PATTERN on stderr, and DIR then holds LEFT ("NAME NAME ", ls -A's).
failed_leaving() {
    local dir=$1 want=$2 pattern=$3 what=$4 rc left
    shift 4
    "$@" >/dev/null 2>"$T/err"
    rc=$?
    left=$(ls -A "$dir" | tr '\n' ' ')
    [ $rc -eq 1 ] && grep -q "$pattern" "$T/err" && [ "$left" = "$want" ] && ok "$what" ||
        ko "$what: exit $rc, $(head -c 300 "$T/err"), left: $left"
}
"$BIN" gen spheres --count 30 --occupancy 0.4 --seed 11 --width 80 --height 60 \
    --materials opaque,reflective,transparent -o "$T/random.pov" >/dev/null || ko "gen"

bad=""
for scene in scenes/*.pov "$T/random.pov"; do
    name=$(basename "$scene" .pov)
    "$BIN" render "$scene" "${SZ[@]}" -o "$T/$name.png" >/dev/null 2>&1 &&
        CSGTRACE_IMAGE_WRITER=oiio "$BIN" render "$scene" "${SZ[@]}" -o "$T/$name-oiio.png" \
            >/dev/null 2>&1 || { bad+=" $name:failed"; continue; }
    same "$T/$name.png" "$T/$name-oiio.png" || bad+=" $name:pixels"
done
[ -z "$bad" ] && ok "every example scene and a random one: the PNG holds the module's pixels" ||
    ko "csgtrace's PNG against the module's:$bad"

"$BIN" render scenes/showcase.pov "${SZ[@]}" -o "$T/showcase.ppm" >/dev/null 2>&1 &&
    CSGTRACE_IMAGE_WRITER=oiio "$BIN" render scenes/showcase.pov "${SZ[@]}" \
        -o "$T/showcase-oiio.ppm" >/dev/null 2>&1 && cmp -s "$T/showcase.ppm" "$T/showcase-oiio.ppm" &&
    ok "the PPM is the module's, byte for byte" || ko "direct PPM differs from the module's"

"$BIN" render "$T/random.pov" "${SZ[@]}" -o "$T/random.pfm" >/dev/null 2>&1 &&
    "$BIN" render "$T/random.pov" "${SZ[@]}" -o "$T/random.exr" >/dev/null 2>&1 &&
    idiff -fail 0 -warn 0 "$T/random.exr" "$T/random.pfm" >/dev/null 2>&1 &&
    ok "the PFM holds the EXR's float pixels" || ko "the PFM differs from the EXR"

# --- the module's formats streamed: every band through the stream, the same pixels; a
# write that fails on the way (the file-size limit) leaves nothing and says why ---
for ext in pfm png; do
    "$BIN" render "$T/random.pov" --width 80 --height 200 --mode serial -o "$T/tall.$ext" \
        >/dev/null 2>&1 || ko "tall .$ext"
done
for ext in exr tif; do
    "$BIN" render "$T/random.pov" --width 80 --height 200 --mode serial -o "$T/tall.$ext" \
        --stats "$T/tall-$ext.json" >/dev/null 2>"$T/err"
    bands=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['write_bands'])" \
        "$T/tall-$ext.json" 2>/dev/null)
    own=$([ $ext = exr ] && echo pfm || echo png) # (the floats, or the 8-bit pixels)
    [ "$bands" = 4 ] && same "$T/tall.$ext" "$T/tall.$own" &&
        ok "a .$ext written band by band (4 bands of 64 rows) holds the render's pixels" ||
        ko ".$ext streamed: bands '$bands', $(head -c 300 "$T/err")"
done
mkdir -p "$T/limit"
failed_leaving "$T/limit" "o.exr.journal " \
    "^csgtrace: error: $T/limit/o.exr: .*file-size limit (ulimit -f) of 16384 bytes" \
    "an EXR over the file-size limit on the way: exit 1, the limit named, no image nor temporary file (the journal kept)" \
    bash -c 'ulimit -f 16 && exec "$@"' _ "$BIN" render "$T/random.pov" --width 400 --height 300 \
    --mode serial -o "$T/limit/o.exr"

# --- no module for PNG, PPM or PFM ---
for ext in png ppm pfm; do
    LD_DEBUG=files "$BIN" render "$T/random.pov" "${SZ[@]}" -o "$T/mapped.$ext" \
        >/dev/null 2>"$T/ld.err"
    if [ -s "$T/mapped.$ext" ] && grep -q "file=.*libz" "$T/ld.err" &&
        ! grep -q -e "file=.*csgtrace-image.so" -e "file=.*OpenImageIO" "$T/ld.err"; then
        ok "a render to .$ext maps neither the image module nor OpenImageIO"
    else
        ko "a render to .$ext: $(grep -o -m 3 "file=[^ ]*\(image\|OpenImageIO\)[^ ]*" "$T/ld.err")"
    fi
done
NOMOD=$T/none/csgtrace-image.so
CSGTRACE_IMAGE_MODULE=$NOMOD "$BIN" render "$T/random.pov" "${SZ[@]}" -o "$T/nomod.png" \
    >/dev/null 2>"$T/err" && cmp -s "$T/nomod.png" "$T/random.png" &&
    ok "a PNG render without the image module" || ko "PNG without the module: $(head -c 300 "$T/err")"
CSGTRACE_IMAGE_MODULE=$NOMOD "$BIN" render "$T/random.pov" "${SZ[@]}" -o "$T/nomod.exr" \
    >/dev/null 2>"$T/err"
rc=$?
[ $rc -eq 1 ] && grep -q "^csgtrace: error: $T/nomod.exr: .*image module.*none/csgtrace-image.so" "$T/err" &&
    [ ! -e "$T/nomod.exr" ] && ok "an EXR render without the module: exit 1, the module named" ||
    ko "EXR without the module: exit $rc, $(head -c 300 "$T/err")"

# --- a folder in the image's place: refused before any tile ---
mkdir -p "$T/out/dir.png"
failed_leaving "$T/out" "dir.png " "^csgtrace: error: the output (-o) '$T/out/dir.png' is a folder" \
    "a folder in a PNG's place: exit 1, the output named, nothing made (no journal, no temporary file)" \
    "$BIN" render "$T/random.pov" "${SZ[@]}" -o "$T/out/dir.png"

e2e_finish
